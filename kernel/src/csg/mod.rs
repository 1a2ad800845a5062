//! Constructive solid geometry (seed 000 §2.4.2, Figs. 12–13, 18–20): union, difference and
//! intersection of block models and meshes, with the source of every output face.
//!
//! - [`tree`]: [`Csg`], the tree — leaves are block models (tessellated first, so adaptive
//!   tessellation and crease tags come through), meshes or earlier results; independent subtrees
//!   evaluate in parallel; the result is a closed manifold [`Mesh`](crate::Mesh) with a
//!   [`FaceSource`](crate::mesh::FaceSource) per face.
//! - [`engine`]: the one seam to the boolean engine.
//! - `error`: [`CsgError`], naming the operand at fault.
//!
//! # The engine, and why
//! The paper intersects the tessellated surfaces segment by segment and keeps the loops' inside
//! patches. We do not hand-roll that: two pure-Rust ports of Manifold's approach (exact
//! symbolic-perturbation predicates, so coplanar and touching cases have one consistent answer)
//! were evaluated by `kernel/tests/csg_engines.rs` (`cargo test --release -p blocksmith-kernel
//! --test csg_engines -- --ignored --nocapture`):
//!
//! | case | manifold-rust 0.19 | boolmesh 0.2 |
//! |---|---|---|
//! | box − box, coplanar union / flush difference, shared-edge union, through-hole (genus 1), 1e-9 slivers | exact volume, closed, manifold | exact volume, closed, manifold |
//! | touching intersection, identical difference (empty results) | empty solid | **error** ("empty pos matrix") |
//! | identical union, sphere ∩ itself | exact | exact |
//! | sphere − sphere (1,024 triangles each) | 3.4 ms | 5.9 ms |
//! | the die, 21 sequential differences | 156 ms, volume error 4e-15 | 274 ms, 4e-15 |
//!
//! (Medians of 5 in one release run on this 2-core machine.) Both are robust on the hard
//! geometric cases; boolmesh fails on empty results and is 1.6–1.8× slower, so **manifold-rust**
//! (its `parallel` feature on; results are bit-identical to the sequential build) is the engine.
//! We carry it in `vendor/manifold-rust` with three speed patches that leave every result as it
//! was (`vendor/manifold-rust/PATCHES.md`: vertex normals computed once, parallel thresholds
//! near C++'s, linear-time stable sorts), until upstream takes them.
//! Its `faceID` survives booleans and its simplification never merges across two face ids,
//! which gives provenance: each input *face* — a connected flat region of one source (a block
//! sub-face, a polygon of an input mesh, a coplanar region of a plain triangle mesh), see
//! [`tree`] — gets its own id, so the engine re-triangulates a cut face whole (as manifold3d
//! does with its own faces) and every output triangle still names its source. The paper's own
//! segment/loop method would need to beat both on robustness and speed; it is not attempted.
//!
//! # Regularised
//! Solids that only touch over part of a face can leave, in Manifold, a closed shell of no
//! volume there (two coincident sheets facing apart). Such shells bound nothing and are
//! dropped, so `a ∩ b` of touching solids is empty, as in CGAL's Nef polyhedra (OpenSCAD).
//!
//! # Speed (release, this 2-core machine, 2026-12-02, ours and manifold3d's interleaved in one
//! sitting; `cargo bench -p blocksmith-kernel --bench csg`, its `CSG_PROFILE=die|die_engine|building`
//! mode (best and median of 200, of 30 for the building) and `CSG_STRESS=1` mode (one run, peak
//! by `/usr/bin/time -v`); manifold3d 3.5.4 by `../shared/peers/die_manifold.py die --reps 200`
//! and `stress`, and `tests/data/csg_building/building_peer.py` (15 runs))
//! | case | blocksmith | manifold3d | ratio |
//! |---|---|---|---|
//! | the die (9.5k triangles), best | 9.4–10.8 ms | 8.2–9.5 ms | 1.1–1.2× |
//! | the die, median | 9.9–14.1 ms | 9.0–11.3 ms | 1.1–1.3× |
//! | the die, one core (`taskset -c 0`, `RAYON_NUM_THREADS=1`), best / median | 13.8–14.5 / 14.7–16.2 ms | 11.8–12.8 / 12.5–14.0 ms | 1.15× / 1.2× |
//! | the die, engine only (inputs already imported, as manifold3d's figure), best / median | 8.5–9.1 / 9.3–11.5 ms | as above | 1.0× / 0.9–1.2× |
//! | the building, 10 storeys, 1,091 blocks (24.4k triangles; manifold3d's 22.3k), best / median | 68–74 / 71–87 ms | 83–95 / 88–117 ms | 0.8× / 0.75–0.9× |
//! | stress: 10³ cubes ∪, − 1,000 spheres (0.99M triangles), four runs | 5.3–5.8 s, 1.11–1.15 GB peak | 4.11 s (median of 3), 1.71 GB | 1.3–1.4×, 0.67× memory |
//!
//! Ours includes importing every input into the engine (about 2.5 ms of the die: the 21 pips,
//! 10.7k triangles, go in as one solid), provenance and building the result's half-edge
//! [`Mesh`](crate::Mesh) (0.5 ms preparing the leaves, 0.9 ms after the engine); manifold3d's
//! starts from solids it already holds (its compose of the spheres costs about what our import
//! does) and stops at its own lazy result. The machine's speed drifts by a third from minute to
//! minute (other tenants), so only ratios from one sitting are quoted.
//!
//! What made the difference (each measured against the build before it, identical outputs):
//! [`Csg::evaluate`] runs on a worker of the thread pool — called from the script's thread, the
//! booleans ran there and handed every parallel step to the pool, sleeping until it was done
//! (the die: 236 context switches a run, now 30; median −20 %); the engine's patches 3–5
//! (`vendor/manifold-rust/PATCHES.md`: linear-time owner search and sorts, one triangulation
//! task per large face, the collider's radix tree in parallel; −15 %); and the imports'
//! vertex renumbering through a flat map. The binary and the benches allocate with mimalloc:
//! glibc's malloc hands the engine's many mid-sized arrays back to the system and faults them
//! in again (17 % of the die). Before all this (2026-12-01): the die 2.0× by best, the stress
//! case 1.5–1.65×.
//! Unions are evaluated as Manifold's batch union: operands whose bounds are apart go into the
//! engine together ([`tree`]) or are composed ([`engine::Solid::union_all`]).

pub mod engine;
mod error;
pub mod tree;

pub use error::{CsgError, Side};
pub use tree::Csg;

/// A boolean operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CsgOp {
    /// `a ∪ b` (`a + b`).
    Union,
    /// `a − b` (`a - b`).
    Difference,
    /// `a ∩ b`.
    Intersection,
}

#[cfg(test)]
mod tests;
