//! From solids back to profiles: the section at a height, the shadow on the xy plane.

use super::convert::{check_number, check_range, solid_from_mesh};
use super::{Profile, ProfileError};
use crate::mesh::Mesh;

/// The section of `mesh` by the plane z = `z`, as a profile (empty when the plane misses it).
///
/// # Errors
/// [`ProfileError::NotSolid`] / [`ProfileError::NonFinite`] for a mesh that bounds no solid;
/// [`ProfileError::OutOfRange`] for one reaching beyond [`MAX_REACH`](super::MAX_REACH) in x or
/// y; [`ProfileError::BadValue`] for a non-finite height.
pub fn slice(mesh: &Mesh, z: f64) -> Result<Profile, ProfileError> {
    check_number("the height", z, false)?;
    check_mesh_range(mesh, "the mesh to slice")?;
    let solid = solid_from_mesh(mesh, "the mesh to slice")?;
    Ok(Profile::from_section(&solid.slice(z)))
}

/// The shadow of `mesh` on the xy plane (the union of its triangles projected along z).
///
/// # Errors
/// [`ProfileError::NotSolid`] / [`ProfileError::NonFinite`] for a mesh that bounds no solid.
pub fn project(mesh: &Mesh) -> Result<Profile, ProfileError> {
    check_mesh_range(mesh, "the mesh to project")?;
    let solid = solid_from_mesh(mesh, "the mesh to project")?;
    Ok(Profile::from_section(&solid.project()))
}

/// Refuses a mesh reaching beyond [`MAX_REACH`](super::MAX_REACH) in x or y (its section would
/// overflow the 2D engine's grid).
fn check_mesh_range(mesh: &Mesh, what: &str) -> Result<(), ProfileError> {
    let xy: Vec<super::Vec2> = mesh.positions().iter().filter(|p| p.is_finite()).map(|p| p.truncate()).collect();
    check_range(&xy, what)
}
