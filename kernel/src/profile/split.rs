//! Cutting a solid by a plane: both halves, or the half on one side.

use super::convert::{check_number, engine_error, mesh_from_solid, solid_from_mesh};
use super::ProfileError;
use crate::math::Vec3;
use crate::mesh::Mesh;

/// The unit normal, refusing a zero or non-finite one.
fn unit_normal(normal: Vec3) -> Result<Vec3, ProfileError> {
    if !normal.is_finite() {
        return Err(ProfileError::NonFinite { what: "the plane's normal".into(), index: 0 });
    }
    normal.try_normalize().ok_or(ProfileError::BadValue {
        name: "the plane's normal length",
        value: 0.0,
        expected: "positive",
    })
}

/// `mesh` cut by the plane `n · x = offset` (`n` the unit `normal`): `(below, above)`, above on
/// the side `normal` points to. Each half is a closed manifold mesh, capped along the cut; a
/// half is an empty mesh when the plane misses the solid on that side.
///
/// # Errors
/// [`ProfileError::NotSolid`] / [`ProfileError::NonFinite`] for a mesh that bounds no solid;
/// [`ProfileError::BadValue`] for a zero normal or a non-finite offset.
pub fn split(mesh: &Mesh, normal: Vec3, offset: f64) -> Result<(Mesh, Mesh), ProfileError> {
    let n = unit_normal(normal)?;
    check_number("the plane's offset", offset, false)?;
    let solid = solid_from_mesh(mesh, "the mesh to split")?;
    let (below, above) = solid.split_by_plane(n, offset).map_err(engine_error)?;
    Ok((mesh_from_solid(&below)?, mesh_from_solid(&above)?))
}

/// The part of `mesh` on the side of the plane `n · x = offset` that `normal` points to (the
/// `above` of [`split`]), capped along the cut; an empty mesh when there is none.
///
/// # Errors
/// As [`split`].
pub fn trim(mesh: &Mesh, normal: Vec3, offset: f64) -> Result<Mesh, ProfileError> {
    let n = unit_normal(normal)?;
    check_number("the plane's offset", offset, false)?;
    let solid = solid_from_mesh(mesh, "the mesh to trim")?;
    mesh_from_solid(&solid.trim_by_plane(n, offset).map_err(engine_error)?)
}
