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
//! # Speed
//! [`Csg::evaluate`] runs on a worker of the thread pool: called from the caller's thread, the
//! booleans would run there and hand every parallel step to the pool, sleeping until it was
//! done. Unions are evaluated as Manifold's batch union: operands whose bounds are apart go into
//! the engine together ([`tree`]) or are composed ([`engine::Solid::union_all`]). The imports
//! renumber vertices through a flat map. The `blocksmith` binary and the benches allocate with
//! mimalloc: glibc's malloc hands the engine's many mid-sized arrays back to the system and
//! faults them in again. Times beside manifold3d's, and what each change was worth, are recorded
//! in `kernel/benches/csg.rs`.

pub mod engine;
mod error;
mod shells;
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
#[cfg(test)]
mod tests_colors;
