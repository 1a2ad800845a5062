//! Diagnosis: what is wrong with a mesh and where.
//!
//! - [`self_intersections`] / [`crossings`]: pairs of faces that cross, by exact predicates over
//!   a bounding-volume hierarchy.
//! - [`components`], [`boundary_loops`]: the pieces of a mesh, its open boundaries.
//! - [`handle_loops`]: a short loop of edges around each handle; cutting along them all leaves
//!   genus 0.
//! - [`defects`]: one list of all the above, with degenerate faces and touching sheets, each
//!   with its elements and a position.
//! - [`repair_polygons`]: the nearest 2-manifold mesh to polygons that are not one, without
//!   moving a vertex (the loaders' repair).
//!
//! Every function here reads a [`Mesh`](crate::mesh::Mesh) and changes nothing.

mod bvh;
mod components;
mod defects;
mod handle_loops;
mod repair;
mod self_intersections;
mod triangle_pair;

pub use components::{boundary_loops, components};
pub use defects::{defects, Defect, DefectKind};
pub use handle_loops::{handle_loops, HandleLoop, MAX_HANDLES};
pub use repair::{repair_polygons, FlippedComponent, RepairOptions, Repaired, Repairs, SeparatedEdge, SplitVertex};
pub use self_intersections::{crossings, self_intersections, Crossing};

#[cfg(test)]
mod tests_defects;
#[cfg(test)]
mod tests_repair;
#[cfg(test)]
mod tests_self_intersections;
