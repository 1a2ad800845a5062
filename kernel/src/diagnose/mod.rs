//! Diagnosis: what is wrong with a mesh and where.
//!
//! - [`self_intersections`] / [`crossings`]: pairs of faces that cross, by exact predicates over
//!   a bounding-volume hierarchy.
//! - [`repair_polygons`]: the nearest 2-manifold mesh to polygons that are not one, without
//!   moving a vertex (the loaders' repair).
//!
//! Every function here reads a [`Mesh`](crate::mesh::Mesh) and changes nothing.

mod bvh;
mod repair;
mod self_intersections;
mod triangle_pair;

pub use repair::{repair_polygons, FlippedComponent, RepairOptions, Repaired, Repairs, SeparatedEdge, SplitVertex};
pub use self_intersections::{crossings, self_intersections, Crossing};

#[cfg(test)]
mod tests_repair;
#[cfg(test)]
mod tests_self_intersections;
