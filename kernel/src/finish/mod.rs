//! Surface finishing: sharp edges by angle ([`sharp_edges`]), smooth refinement through
//! Manifold's tangents ([`refine`], [`refine_to_length`]), isotropic remeshing ([`remesh`]),
//! quadric decimation ([`decimate`]) and relaxation ([`relax`]).
//!
//! Every operation takes a closed 2-manifold (relax also a bounded one), returns one and carries
//! each face's part (colour, name, origin) from the input face it came from
//! ([`Mesh::inherit_parts`](crate::Mesh::inherit_parts)). Sizes are estimated and refused
//! before anything is allocated; long loops poll the cancellation token.

mod decimate;
mod error;
mod refine;
mod relax;
mod remesh;
mod sharp;
mod tri_mesh;

pub use decimate::{decimate, DecimateOptions, DecimateReport, DecimateTarget};
pub use error::FinishError;
pub use refine::{refine, refine_to_length, MAX_REFINE};
pub use relax::{relax, RelaxMethod, RelaxOptions};
pub use remesh::{remesh, RemeshOptions, RemeshReport};
pub use sharp::{sharp_edges, DEFAULT_SHARP_ANGLE};

/// The most triangles any finishing operation makes (beyond it the request is refused by
/// name before allocating, whatever the memory budget).
pub const MAX_TRIANGLES: f64 = 50e6;
