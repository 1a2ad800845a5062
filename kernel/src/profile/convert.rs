//! Crossing the engine seam: profiles ⇄ engine sections, meshes ⇄ engine solids.

use super::{Profile, ProfileError};
use crate::csg::engine::{EngineError, Fill, Section, Solid, Stop, Surface};
use crate::mesh::{Mesh, MeshError};

impl Profile {
    /// The region as an engine section (already clean: no fill rule needed).
    pub(super) fn to_section(&self) -> Section {
        Section::from_contours(&self.contours, Fill::Positive)
    }

    /// The engine's region as a profile (degenerate contours of fewer than 3 points dropped).
    pub(super) fn from_section(section: &Section) -> Profile {
        Profile { contours: section.contours() }
    }

    /// Refuses an empty profile, naming it `what`.
    pub(super) fn require_region(&self, what: &str) -> Result<(), ProfileError> {
        if self.is_empty() {
            return Err(ProfileError::Empty { what: what.to_string() });
        }
        Ok(())
    }
}

/// An engine failure as a profile error.
pub(super) fn engine_error(e: EngineError) -> ProfileError {
    match e {
        EngineError::Stopped => ProfileError::Limit(crate::limits::LimitError::Stopped(
            crate::limits::current().stopped().unwrap_or(crate::limits::StopReason::Interrupted),
        )),
        EngineError::Failed(reason) => ProfileError::Engine { reason },
    }
}

/// A mesh error while building a result as a profile error.
pub(super) fn mesh_error(e: MeshError) -> ProfileError {
    match e {
        MeshError::Limit(l) => ProfileError::Limit(l),
        e => ProfileError::Engine { reason: e.to_string() },
    }
}

/// The engine solid's triangles as a half-edge mesh (an empty mesh for an empty solid), built
/// from the engine's own pairing of its half-edges ([`Mesh::from_paired_triangles`]: linear, no
/// search for twins).
///
/// Where the solid pinches to a point (a revolved profile touching the axis at one point, a
/// cut through a vertex) the engine shares one vertex between two fans of triangles; the
/// half-edge mesh gets one vertex per fan there, at the same position, as CSG results keep two
/// vertices where two solids meet along an edge.
pub(super) fn mesh_from_solid(solid: &Solid) -> Result<Mesh, ProfileError> {
    let t = solid.paired_triangles();
    crate::limits::charge(t.tags.len() as u64)?;
    Mesh::from_paired_triangles(t.positions, t.corners, t.pairs).map_err(mesh_error)
}

/// The surface an engine constructor built (`None`: nothing) as a half-edge mesh
/// ([`Mesh::from_closed_triangles`]: linear; a point where the surface pinches gets a vertex per
/// fan, as in [`mesh_from_solid`]); `what` names the profile in the error for an empty result.
///
/// # Errors
/// [`ProfileError::ZeroArea`] for no triangles; the limit's error when the operation limit is
/// reached; a build failure as [`ProfileError::Engine`].
pub(super) fn mesh_from_surface(surface: Option<Surface>, what: &str) -> Result<Mesh, ProfileError> {
    let Some(Surface { positions, corners }) = surface.filter(|s| !s.corners.is_empty()) else {
        return Err(ProfileError::ZeroArea { what: what.into() });
    };
    crate::limits::charge(corners.len() as u64 / 3)?;
    Mesh::from_closed_triangles(positions, corners).map_err(mesh_error)
}

/// A closed mesh as an engine solid; `what` names it in errors.
///
/// # Errors
/// [`ProfileError::NotSolid`] for a mesh with no faces or a boundary, [`ProfileError::NonFinite`]
/// for a NaN or infinite coordinate, the engine's refusal as [`ProfileError::NotSolid`].
pub(super) fn solid_from_mesh(mesh: &Mesh, what: &str) -> Result<Solid, ProfileError> {
    if mesh.face_count() == 0 {
        return Err(ProfileError::NotSolid { what: what.to_string(), reason: "it has no faces".into() });
    }
    if let Some(index) = mesh.positions().iter().position(|p| !p.is_finite()) {
        return Err(ProfileError::NonFinite { what: what.to_string(), index });
    }
    if !mesh.is_closed() {
        let edges: usize = mesh.boundary_loops().iter().map(Vec::len).sum();
        return Err(ProfileError::NotSolid {
            what: what.to_string(),
            reason: format!("it has {edges} boundary edges"),
        });
    }
    let tri = if mesh.is_triangle_mesh() { mesh.clone() } else { mesh.triangulate().map_err(mesh_error)? };
    let triangles: Vec<[u32; 3]> = (0..tri.face_count() as u32)
        .map(|f| {
            let mut it = tri.face_vertices(f);
            [it.next().unwrap_or(0), it.next().unwrap_or(0), it.next().unwrap_or(0)]
        })
        .collect();
    crate::limits::charge(triangles.len() as u64)?;
    let tags: Vec<u32> = (0..triangles.len() as u32).collect();
    Solid::with_id_until(tri.positions(), &triangles, &tags, Solid::reserve_ids(1), &Stop::new()).map_err(|e| match e {
        EngineError::Stopped => engine_error(e),
        EngineError::Failed(reason) => ProfileError::NotSolid { what: what.to_string(), reason },
    })
}

/// Checks `points` are finite and within [`MAX_REACH`](super::MAX_REACH) of the origin, naming
/// them `what`.
pub(super) fn check_finite(points: &[super::Vec2], what: &str) -> Result<(), ProfileError> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(ProfileError::NonFinite { what: what.to_string(), index });
    }
    check_range(points, what)
}

/// Checks `points` are within [`MAX_REACH`](super::MAX_REACH) of the origin in x and y, naming
/// them `what`.
pub(super) fn check_range(points: &[super::Vec2], what: &str) -> Result<(), ProfileError> {
    match points.iter().position(|p| p.abs().max_element() > super::MAX_REACH) {
        Some(index) => {
            let p = points[index];
            let value = if p.x.abs() > super::MAX_REACH { p.x } else { p.y };
            Err(ProfileError::OutOfRange { what: what.to_string(), index, value })
        }
        None => Ok(()),
    }
}

/// Checks a number is finite (and positive when `positive`), naming it `name`.
pub(super) fn check_number(name: &'static str, value: f64, positive: bool) -> Result<f64, ProfileError> {
    if !value.is_finite() {
        return Err(ProfileError::BadValue { name, value, expected: "a finite number" });
    }
    if positive && value <= 0.0 {
        return Err(ProfileError::BadValue { name, value, expected: "positive" });
    }
    Ok(value)
}

/// The engine's memory per triangle while it builds a solid (as the CSG estimate).
const ENGINE_BYTES_PER_TRIANGLE: f64 = 1024.0;

/// Refuses a solid of about `vertices` vertices and `triangles` triangles when building it
/// would pass the memory budget; `what` describes the request.
pub(super) fn check_solid_size(
    what: impl FnOnce() -> String,
    vertices: f64,
    triangles: f64,
) -> Result<(), ProfileError> {
    let bytes = crate::mesh::mesh_bytes(vertices, 3.0 * triangles, triangles) + triangles * ENGINE_BYTES_PER_TRIANGLE;
    crate::limits::check_memory(what, bytes)?;
    Ok(())
}
