//! Sharp edges by dihedral angle: the tagging that [`super::refine`] keeps sharp.

use crate::mesh::Mesh;

use super::FinishError;

/// The default angle (degrees) between face normals above which an edge is sharp.
pub const DEFAULT_SHARP_ANGLE: f64 = 60.0;

/// A copy of `mesh` whose edges are tagged by angle: an edge whose two faces' normals differ
/// by more than `sharp_angle` degrees becomes an infinitely sharp crease, every other edge
/// smooth (tags replaced). Boundary edges are sharp. Nothing moves; the tags are what
/// [`super::refine`], [`super::remesh`] and subdivision keep sharp. As Manifold's
/// `SharpenEdges` (its `SmoothOut` with `minSmoothness` 0).
///
/// # Errors
/// [`FinishError::BadOption`] for an angle outside 0–180.
pub fn sharp_edges(mesh: &Mesh, sharp_angle: f64) -> Result<Mesh, FinishError> {
    if !(0.0..=180.0).contains(&sharp_angle) {
        return Err(FinishError::bad("sharp_angle", sharp_angle, "between 0 and 180 degrees"));
    }
    let cos_limit = sharp_angle.to_radians().cos();
    let mut out = mesh.clone();
    let normals: Vec<_> = (0..mesh.face_count() as u32).map(|f| mesh.face_normal(f)).collect();
    for h in mesh.edges() {
        let t = mesh.twin(h);
        let sharp = if mesh.is_boundary_halfedge(h) || mesh.is_boundary_halfedge(t) {
            true
        } else {
            let (a, b) = (normals[mesh.face(h) as usize], normals[mesh.face(t) as usize]);
            a.dot(b) < cos_limit
        };
        out.set_crease_halfedge(h, sharp);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cube_has_twelve_sharp_edges_and_a_sphere_none() {
        let c = Mesh::cube(2.0).triangulate().unwrap();
        let s = sharp_edges(&c, 60.0).unwrap();
        assert_eq!(s.crease_count(), 12);
        assert_eq!(sharp_edges(&c, 95.0).unwrap().crease_count(), 0);
        let ball = Mesh::icosphere(1.0, 2);
        assert_eq!(sharp_edges(&ball, 30.0).unwrap().crease_count(), 0);
        assert!(sharp_edges(&c, 200.0).unwrap_err().to_string().contains("`sharp_angle`"));
        assert!(sharp_edges(&c, f64::NAN).is_err());
    }
}
