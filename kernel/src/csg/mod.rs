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
//! # Speed (release, this 2-core machine with other work paused, 2026-12-01; `cargo bench -p
//! blocksmith-kernel --bench csg`, its `CSG_PROFILE=die|building` mode (best of 100) and
//! `CSG_STRESS=1` mode (one run, peak by `/usr/bin/time -v`); manifold3d 3.5.4 by
//! `../shared/peers/die_manifold.py die|stress` and `tests/data/csg_building/building_peer.py`)
//! | case | blocksmith | manifold3d | ratio |
//! |---|---|---|---|
//! | the die (9.5k triangles), best of runs | 20.2–21.8 ms | 10.2–11.0 ms | 2.0× |
//! | the die, engine only (inputs already imported, as manifold3d's figure), criterion mean vs median | 23.9 ms | 12.6 ms | 1.9× |
//! | the building, 10 storeys, 1,091 blocks (24.6k triangles; manifold3d's 22.3k), best | 101–108 ms | 93–103 ms | 1.05–1.08× |
//! | stress: 10³ cubes ∪, − 1,000 spheres (0.99M triangles), two sittings | 7.2–7.5 s, 1.03 GB peak | 4.3–4.9 s, 1.45 GB | 1.5–1.65×, 0.71× memory |
//! | stress, engine only | 6.9 s | 4.3–4.9 s | 1.4–1.6× |
//!
//! Ours includes importing every input into the engine, provenance and building the result's
//! half-edge [`Mesh`](crate::Mesh); manifold3d's starts from solids it already holds. The
//! engine-only rows time manifold-rust doing exactly manifold3d's work: the gap to the 1.5×
//! target is the port's (its compose and import — vertex normals by `acos`, sorting — cost
//! about as much as the boolean), not this pipeline's, which adds about 10 % (stress) and
//! nothing on the die, where importing the disjoint spheres as one solid saves the compose.
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
