//! blocksmith-kernel: the pure-Rust geometry behind blocksmith.
//!
//! A short tour, foundations first:
//! - [`math`]: `Vec3` and the other glam f64 types, bounds, colours, the seeded RNG and the id hasher.
//! - [`limits`]: the memory budget and the cancellation token long operations check.
//! - [`mesh`]: the half-edge polygon [`Mesh`] — build, circulate, measure, edit, triangulate, tags, provenance.
//! - [`subdiv`]: Catmull–Clark and Loop subdivision with semi-sharp creases, limit points, limit surface.
//! - [`polar`]: polar meshes (Brazzolotto) — rings and poles, the seven operations, the inferred skeleton.
//! - [`blocks`]: modeling with blocks (Leblanc et al.) — blocks, connections, control mesh, tessellation.
//! - [`voxel`]: voxel sculpting (Heurtebise & Thon) — Haar levels of detail, marching cubes, rotated tools.
//! - [`solve`]: Shape-Up constraints (Bouaziz et al.) — the local/global solver, projections, cylinder fits.
//! - [`anim`]: skeleton-driven animation of polar meshes — skinning, growth, gravity, rigged glTF export.
//! - [`lsystem`]: L-systems (Brazzolotto part III) — grammars, seeded derivation, growth as polar operations.
//! - [`diagnose`]: what is wrong with a mesh and where — components, boundaries, self-intersections
//!   (exact predicates over a BVH), handle loops, defects; the repair of non-manifold files.
//! - [`csg`]: union, difference and intersection of block models and meshes, through the one engine seam.
//! - [`profile`]: 2D regions and the solids made from them — extrude, revolve, sweep, loft, hulls, cuts.
//! - [`io`]: files — meshes in OBJ, STL, glTF 2.0 (Draco read too), PLY, 3MF; profiles in SVG, DXF.
//!
//! The kernel knows nothing of the scripting language: errors are typed here and turned into
//! script errors at the binding edge. It is the bottom of the workspace (kernel ← bindings ←
//! studio ← command line) and depends only on geometry and file crates — glam, spade, faer,
//! rayon, the boolean engine (manifold-rust, with Clipper2), gltf, tobj and the format
//! readers — never on Rhai, a terminal, the web or an image crate.

pub mod anim;
pub mod blocks;
pub mod csg;
pub mod diagnose;
pub mod finish;
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
