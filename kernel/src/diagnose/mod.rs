//! Diagnosis: what is wrong with a mesh and where.
//!
//! - [`self_intersections`] / [`crossings`]: pairs of faces that cross, by exact predicates over
//!   a bounding-volume hierarchy.
//!
//! Every function here reads a [`Mesh`](crate::mesh::Mesh) and changes nothing.

mod bvh;
mod self_intersections;
mod triangle_pair;

pub use self_intersections::{crossings, self_intersections, Crossing};

#[cfg(test)]
mod tests_self_intersections;
