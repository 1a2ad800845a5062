//! Convex hulls: of a profile, of several profiles, of 3D points and meshes.
//!
//! 2D: Andrew's monotone chain (A. M. Andrew, "Another efficient algorithm for convex hulls in
//! two dimensions", 1979); 3D: quickhull (Barber, Dobkin & Huhdanpaa, 1996), both in the engine.

use super::convert::{check_finite, engine_error, mesh_from_solid};
use super::{Profile, ProfileError, Vec2};
use crate::csg::engine::{Section, Solid};
use crate::math::Vec3;
use crate::mesh::Mesh;

impl Profile {
    /// The convex hull of the region.
    ///
    /// # Errors
    /// [`ProfileError::Empty`] for an empty profile.
    pub fn hull(&self) -> Result<Profile, ProfileError> {
        Profile::hull_all(std::slice::from_ref(self))
    }

    /// The convex hull of all `profiles` together.
    ///
    /// # Errors
    /// [`ProfileError::Empty`] when they have no points at all.
    pub fn hull_all(profiles: &[Profile]) -> Result<Profile, ProfileError> {
        let points: Vec<Vec2> = profiles.iter().flat_map(|p| p.contours.iter().flatten().copied()).collect();
        if points.is_empty() {
            return Err(ProfileError::Empty { what: "the profile to hull".into() });
        }
        Profile::hull_of_points(&points)
    }

    /// The convex hull of 2D `points`.
    ///
    /// # Errors
    /// [`ProfileError::NonFinite`] for a NaN or infinite point, [`ProfileError::TooFewPoints`]
    /// for fewer than 3, [`ProfileError::ZeroArea`] when they are all on a line.
    pub fn hull_of_points(points: &[Vec2]) -> Result<Profile, ProfileError> {
        check_finite(points, "the points")?;
        if points.len() < 3 {
            return Err(ProfileError::TooFewPoints { what: "the points".into(), count: points.len(), needed: 3 });
        }
        let hull = Section::hull(points);
        let p = Profile::from_section(&hull);
        if p.is_empty() || hull.area() <= 0.0 {
            return Err(ProfileError::ZeroArea { what: "the hull of the points (all on one line)".into() });
        }
        Ok(p)
    }
}

/// The convex hull of 3D `points`, a closed triangle mesh.
///
/// # Errors
/// [`ProfileError::NonFinite`] for a NaN or infinite point, [`ProfileError::TooFewPoints`] for
/// fewer than 4, [`ProfileError::ZeroArea`] when they all lie in one plane.
pub fn hull_points(points: &[Vec3]) -> Result<Mesh, ProfileError> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(ProfileError::NonFinite { what: "the points".into(), index });
    }
    if points.len() < 4 {
        return Err(ProfileError::TooFewPoints { what: "the points".into(), count: points.len(), needed: 4 });
    }
    crate::limits::charge(points.len() as u64)?;
    let solid = Solid::hull(points).map_err(engine_error)?;
    let mesh = mesh_from_solid(&solid)?;
    if mesh.face_count() == 0 || mesh.volume() <= 0.0 {
        return Err(ProfileError::ZeroArea { what: "the hull of the points (all in one plane)".into() });
    }
    Ok(mesh)
}

/// The convex hull of every vertex of `meshes` (open meshes and loose points count too).
///
/// # Errors
/// As [`hull_points`].
pub fn hull_meshes(meshes: &[&Mesh]) -> Result<Mesh, ProfileError> {
    let points: Vec<Vec3> = meshes.iter().flat_map(|m| m.positions().iter().copied()).collect();
    hull_points(&points)
}
