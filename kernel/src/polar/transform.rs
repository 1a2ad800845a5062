//! Whole-mesh transforms of a polar mesh, as a [`Mesh`] has them: move, turn, scale and mirror
//! the whole mesh and get a new polar mesh with the same vertex ids, poles and loops (the §2.4
//! low-level moves in `frames` act on a selection in place instead).
//!
//! The markers belong to vertices (poles) and edges (loops), which no transform changes. A
//! transform that keeps orientation keeps every half-edge id, so the markers are copied; a
//! mirroring one (a mirror, a scale with a negative product of factors) reverses the faces so
//! that they keep facing outward, which renumbers half-edges, so the markers are given again as
//! poles and loop edges (vertex pairs) and the marking rebuilt ([`PolarMesh::from_mesh`]). Linear
//! in the mesh's size.

use super::{PolarError, PolarMesh};
use crate::math::Vec3;
use crate::mesh::Mesh;

impl PolarMesh {
    /// This polar mesh moved by `offset`.
    #[must_use]
    pub fn translate(&self, offset: Vec3) -> PolarMesh {
        self.with_mesh(self.mesh.translate(offset))
    }

    /// This polar mesh turned by `degrees` about `axis` through the origin (right-handed). A
    /// zero axis leaves it as it is.
    #[must_use]
    pub fn rotate(&self, axis: Vec3, degrees: f64) -> PolarMesh {
        self.with_mesh(self.mesh.rotate(axis, degrees))
    }

    /// This polar mesh scaled about the origin by `factors` per axis; a negative product of
    /// factors mirrors it, its faces reversed to keep facing outward.
    ///
    /// # Errors
    /// [`PolarError::Internal`] only if the markers could not be rebuilt after a mirroring
    /// scale (they always can: vertices and edges are the same).
    pub fn scale(&self, factors: Vec3) -> Result<PolarMesh, PolarError> {
        let m = self.mesh.scale(factors);
        if factors.x * factors.y * factors.z < 0.0 {
            self.remarked(m)
        } else {
            Ok(self.with_mesh(m))
        }
    }

    /// This polar mesh reflected through the plane through the origin with normal `normal`,
    /// its faces reversed to keep facing outward. A zero normal leaves it as it is.
    ///
    /// # Errors
    /// As [`PolarMesh::scale`].
    pub fn mirror(&self, normal: Vec3) -> Result<PolarMesh, PolarError> {
        if normal == Vec3::ZERO {
            return Ok(self.clone());
        }
        self.remarked(self.mesh.mirror(normal))
    }

    /// `mesh` (this mesh's vertices, faces and half-edges, moved) with this mesh's markers.
    fn with_mesh(&self, mesh: Mesh) -> PolarMesh {
        PolarMesh { mesh, pole: self.pole.clone(), is_loop: self.is_loop.clone() }
    }

    /// `mesh` (this mesh's vertices and faces, half-edges renumbered) marked with this mesh's
    /// poles and loop edges.
    fn remarked(&self, mesh: Mesh) -> Result<PolarMesh, PolarError> {
        let poles: Vec<u32> = (0..self.vertex_count() as u32).filter(|&v| self.pole[v as usize]).collect();
        let loops: Vec<[u32; 2]> = self
            .mesh
            .edges()
            .filter(|&h| self.is_loop[h as usize])
            .map(|h| [self.mesh.origin(h), self.mesh.target(h)])
            .collect();
        PolarMesh::from_mesh(mesh, &poles, &loops)
            .map_err(|e| PolarError::Internal(format!("the mirrored mesh's markers could not be rebuilt: {e}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polar sphere with a feature nested on it, off the origin.
    fn featured() -> PolarMesh {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        pm.add_feature(&[9, 10, 11]).unwrap();
        pm.translate(Vec3::new(1.0, 2.0, 3.0))
    }

    #[test]
    fn transforms_move_the_mesh_and_keep_its_markers() {
        let pm = featured();
        let moved = pm.translate(Vec3::new(0.0, 0.0, 5.0));
        moved.check().unwrap();
        assert_eq!((moved.poles(), moved.loops()), (pm.poles(), pm.loops()));
        assert_eq!(moved.position(0), pm.position(0) + Vec3::new(0.0, 0.0, 5.0));
        let turned = pm.rotate(Vec3::Z, 90.0);
        turned.check().unwrap();
        let p = pm.position(4);
        assert!(turned.position(4).distance(Vec3::new(-p.y, p.x, p.z)) < 1e-12);
        let scaled = pm.scale(Vec3::new(2.0, 2.0, 2.0)).unwrap();
        assert!((scaled.mesh().volume() - 8.0 * pm.mesh().volume()).abs() < 1e-9);
        assert_eq!(scaled.features().len(), pm.features().len());
    }

    #[test]
    fn mirroring_keeps_the_faces_outward_and_the_same_poles_and_loops() {
        let pm = featured();
        for m in [pm.scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap(), pm.mirror(Vec3::Y).unwrap()] {
            m.check().unwrap();
            assert!((m.mesh().volume() - pm.mesh().volume()).abs() < 1e-9, "outward: {}", m.mesh().volume());
            assert_eq!(m.poles(), pm.poles());
            assert_eq!(m.loops().len(), pm.loops().len());
            assert_eq!(m.features().len(), pm.features().len());
            assert_eq!(m.skeleton(None).unwrap().node_count(), pm.skeleton(None).unwrap().node_count());
        }
        assert_eq!(pm.mirror(Vec3::ZERO).unwrap(), pm);
    }
}
