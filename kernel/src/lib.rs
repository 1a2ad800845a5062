//! blocksmith-kernel: the pure-Rust geometry behind blocksmith.
//!
//! A short tour of the pipeline:
//! - [`math`]: `Vec3` (glam's `DVec3`) and axis-aligned bounds.
//! - [`mesh`]: the half-edge polygon [`Mesh`] every other module produces or consumes — building
//!   from indexed polygons (rejecting non-manifold input), circulators, measures, primitives,
//!   transforms and triangulation.
//! - [`io`]: OBJ, binary STL and glTF 2.0 files.
//! - [`anim`]: skeleton-driven animation of polar meshes (Brazzolotto part II) — skinning, growth,
//!   gravity, script modifiers, rigged glTF export.
//! - [`blocks`]: modeling with blocks (Leblanc et al.) — blocks with sub-face grids and sharp
//!   edges, connections, the control mesh, and its adaptive crack-free tessellation.
//! - [`csg`]: union, difference and intersection of block models and meshes (Leblanc et al.
//!   §2.4.2), with the source of every output face.
//! - [`lsystem`]: L-systems (Brazzolotto part III) — grammars, seeded derivation, and growth
//!   carried out directly as polar-mesh operations.
//!
//! - [`solve`]: Shape-Up constraints (Tsoi & Hui, Bouaziz et al.) — a prefactored local/global
//!   solver, rigid/circle/plane/anchor projections, closeness and Laplacian energies, cylinder fits.
//!
//! The kernel knows nothing of the scripting language: errors are typed here and turned into
//! script errors at the binding edge.

pub mod anim;
pub mod blocks;
pub mod csg;
pub mod io;
pub mod limits;
pub mod lsystem;
pub mod math;
pub mod mesh;
pub mod polar;
pub mod profile;
pub mod solve;
pub mod subdiv;
pub mod voxel;

pub use math::{Aabb, Vec3};
pub use mesh::{Mesh, MeshError};
