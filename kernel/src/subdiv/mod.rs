//! Subdivision surfaces: Catmull–Clark and Loop refinement with semi-sharp and infinitely sharp
//! creases and corners (OpenSubdiv's `Sdc` rules, its boundary modes, creasing methods and
//! triangle option, [`SubdivOptions`]), limit positions and normals, and evaluation of the
//! Catmull–Clark limit surface anywhere.
//!
//! Layout (as OpenSubdiv separates `Sdc`, `Vtr`, `Far` and `Osd`):
//! - `topology`: one level of connectivity as flat arrays, vertex rules (smooth, crease, corner);
//!   `child_level` and `child_adjacency` build the level one step down from it;
//! - [`refiner`]: [`Refiner`] refines the topology once and applies the rules to positions many
//!   times, or hands them out as [`StencilTable`]s; [`Mesh::catmull_clark`] and
//!   [`Mesh::loop_subdivide`] are its one-shot forms;
//! - `masks`, `limit`: limit masks, [`Mesh::catmull_clark_limit`], [`Mesh::loop_limit`], their
//!   normals and stencils;
//! - `patch`, `evaluator`: [`LimitEvaluator`], the Catmull–Clark limit surface at any
//!   (face, u, v) of an all-quad mesh.
//!
//! Boundaries follow the mesh's [`BoundaryInterpolation`], by default "edge only", which Blender's
//! subdivision modifier uses: boundary edges are sharp, and a boundary vertex with two edges (the
//! corner of an open grid) follows the crease rule and moves; "edge and corner" pins it, as does
//! [`Mesh::set_corner`].
//!
//! Sharpness is held as OpenSubdiv holds it during refinement (`f32`, 10 and above infinite), and
//! the rule blends use its values, so refined positions agree with OpenSubdiv's to rounding
//! (`kernel/tests/subdiv_opensubdiv.rs`).

mod catmull_clark;
mod child_adjacency;
mod child_level;
mod child_mesh;
mod error;
mod evaluator;
mod limit;
mod loop_scheme;
mod masks;
mod patch;
#[cfg(test)]
mod reference_tests;
pub mod refiner;
mod ring;
#[cfg(test)]
mod sharpness_tests;
mod stencil;
#[cfg(test)]
mod test_meshes;
mod topology;

pub use error::SubdivError;
pub use evaluator::{LimitEvaluator, LimitSample};
pub use limit::{catmull_clark_limit_stencils, loop_limit_stencils};
// The options are defined with the mesh that carries them (`mesh/subdiv_options.rs`).
pub use crate::mesh::{BoundaryInterpolation, CreaseMethod, SubdivOptions, TriangleSubdivision, SHARPNESS_INFINITE};
pub use refiner::{loop_beta, Refiner, Scheme, MAX_FACES};
pub use stencil::StencilTable;
