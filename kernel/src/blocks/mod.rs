//! Modeling with blocks (seed 000, Leblanc, Houle & Poulin, "Modeling with blocks", 2011): the
//! four stages of its pipeline (Fig. 1), one file each.
//!
//! - [`block`]: [`Block`], a generalised cuboid with per-face sub-face grids, sharp or smooth
//!   edges and a group id (§2.1);
//! - [`model`], `connect`: [`BlockModel`] — blocks, allowed group pairs, a scale-invariant
//!   threshold, manual connections — and the ray-cast search for connections with vertex pairing
//!   (§2.2), accelerated by a BVH over sub-faces (`bvh`);
//! - `unconnected`: blocks that touch a block they may connect with but end up in another
//!   piece, with their nearest miss ([`Miss`]);
//! - [`control_mesh`]: exterior sub-faces joined into a watertight, crease-tagged quad mesh (§2.3);
//! - [`tessellate`]: adaptive, anisotropic, crack-free meshing of the limit surface with optional
//!   displacement (§2.4.1, §2.4.3).
//!
//! CSG between groups of blocks (§2.4.2) is not here.

pub mod block;
pub mod building;
mod bvh;
mod connect;
pub mod control_mesh;
mod error;
pub mod model;
pub mod tessellate;
#[cfg(test)]
pub(crate) mod test_models;
#[cfg(test)]
mod tests_fuzz;
#[cfg(test)]
mod tests_random;
mod unconnected;

pub use block::{Block, Edge, Face, MAX_SUBDIVISIONS};
pub use control_mesh::{ControlMesh, PatchSource};
pub use error::BlockError;
pub use model::{BlockModel, Connection, SubFaceRef, DEFAULT_THRESHOLD};
pub use tessellate::{
    tessellate_control, tessellate_control_with_progress, BlockStats, ControlTessellation, Displacement, MeshOptions,
    Progress, Tessellation,
};
pub use unconnected::{Miss, Subdivision};
