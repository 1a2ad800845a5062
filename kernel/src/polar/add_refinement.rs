//! Add refinement (§4.1): a new loop across a ring of backbones, or a new backbone across a ring
//! of loop edges.

use super::{PolarError, PolarMesh, PolyList};
use crate::math::IdMap;
use crate::math::Vec3;

/// What [`PolarMesh::add_refinement`] created.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Refinement {
    /// The new loop or backbone as a walk ([`PolarMesh::walk`]): closed for a loop, pole to pole
    /// for a backbone (or closed).
    pub halfedges: Vec<u32>,
    /// The new vertices, one per split edge, in ring order.
    pub vertices: Vec<u32>,
}

impl PolarMesh {
    /// Add refinement (seed 004, §4.1) with the new vertices at the edges' midpoints; see
    /// [`PolarMesh::add_refinement_at`].
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad id.
    pub fn add_refinement(&mut self, h: i64) -> Result<Refinement, PolarError> {
        self.add_refinement_at(h, 0.5)
    }

    /// Add refinement (seed 004, §4.1): splits every edge parallel to the edge of `h`
    /// ([`PolarMesh::parallel`]) at fraction `t` along the direction of `h` and joins the new
    /// vertices across the faces between them. On a backbone this adds a loop (a ring becomes two
    /// rings; a pole fan gains a ring of quads); on a loop edge it adds a backbone from pole to
    /// pole, raising the valency of every region it crosses by one.
    ///
    /// Affects only the faces of the ring: time proportional to its length. No limitation
    /// (§4.1.4): every edge can be refined.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`]; [`PolarError::InvalidArgument`] unless `0 < t < 1`.
    pub fn add_refinement_at(&mut self, h: i64, t: f64) -> Result<Refinement, PolarError> {
        let h = self.halfedge_id(h)?;
        if !(t > 0.0 && t < 1.0) {
            return Err(PolarError::InvalidArgument(format!(
                "the split fraction must lie strictly between 0 and 1, got {t}"
            )));
        }
        let m = &self.mesh;
        let ring = self.ring_of(h);
        let nv = m.vertex_count() as u32;
        let mut index: IdMap<u32, u32> = IdMap::with_capacity_and_hasher(ring.edges.len(), Default::default());
        let mut positions: Vec<Vec3> = Vec::with_capacity(ring.edges.len());
        for (j, &d) in ring.edges.iter().enumerate() {
            index.insert(m.edge_key(d), nv + j as u32);
            positions.push(m.position(m.origin(d)).lerp(m.position(m.target(d)), t));
        }
        let chord = !self.is_loop(h);
        // Each ring face, with the new vertices on its enter and leave edges, is split along
        // the chord between them: two polygons straight into one list (no allocation per face).
        let mut polys = PolyList::with_capacity(2 * ring.faces.len(), 6 * ring.faces.len() + 4);
        let mut remove = Vec::with_capacity(ring.faces.len());
        let (mut corners, mut loops): (Vec<u32>, Vec<bool>) = (Vec::with_capacity(8), Vec::with_capacity(8));
        for rf in &ring.faces {
            remove.push(rf.face);
            corners.clear();
            loops.clear();
            let mut leave_at = None;
            for x in m.loop_halfedges(rf.enter) {
                corners.push(m.origin(x));
                loops.push(self.is_loop(x));
                if x == rf.enter || Some(x) == rf.leave {
                    if Some(x) == rf.leave {
                        leave_at = Some(corners.len());
                    }
                    corners.push(index[&m.edge_key(x)]);
                    loops.push(self.is_loop(x));
                }
            }
            // Without a leave edge the face is a pole triangle [a, m, b, pole]: the chord runs
            // from the new vertex to the pole.
            let j = leave_at.unwrap_or(3);
            polys.push_split_side(&corners, &loops, 1, j, chord);
            polys.push_split_rest(&corners, &loops, 1, j, chord);
        }
        let log = self.rebuild_list(&remove, &polys, &positions, &[])?;
        let vertices = log.new_vertices().to_vec();
        let m = &self.mesh;
        let first = m.outgoing(vertices[0]).find(|&x| self.is_loop(x) == chord);
        let first = first.ok_or_else(|| PolarError::Internal("the new refinement has no edge".into()))?;
        Ok(Refinement { halfedges: self.walk_of(first), vertices })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refining_a_spoke_adds_a_loop_around_the_pole() {
        // Octahedron + a loop near pole 0: 4 new vertices, 4 new loop edges + 4 split spokes
        // (V 6→10, E 12→20, F 8→12), Euler characteristic stays 2.
        let mut pm = PolarMesh::octahedron();
        let s = pm.mesh().find_halfedge(0, 1).unwrap();
        let r = pm.add_refinement(i64::from(s)).unwrap();
        pm.check().unwrap();
        let m = pm.mesh();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (10, 20, 12));
        assert_eq!(r.vertices.len(), 4);
        assert_eq!(r.halfedges.len(), 4);
        assert!(r.halfedges.iter().all(|&h| pm.is_loop(h)));
        // Midpoints of the spokes from (0,0,-1) to the equator: z = -0.5.
        for &v in &r.vertices {
            assert!((pm.position(v).z + 0.5).abs() < 1e-15, "z {}", pm.position(v).z);
        }
        assert_eq!(pm.valence(0), 4);
        assert_eq!(pm.loops().len(), 2);
    }

    #[test]
    fn refining_a_loop_edge_adds_a_backbone_pole_to_pole() {
        let mut pm = PolarMesh::octahedron();
        let e = pm.mesh().find_halfedge(1, 2).unwrap();
        let r = pm.add_refinement(i64::from(e)).unwrap();
        pm.check().unwrap();
        // One new vertex on the equator, a backbone of 2 edges from pole to pole.
        assert_eq!(r.vertices.len(), 1);
        assert_eq!(r.halfedges.len(), 2);
        assert!(r.halfedges.iter().all(|&h| !pm.is_loop(h)));
        assert_eq!((pm.valence(0), pm.valence(5)), (5, 5));
        assert_eq!(pm.mesh().euler(), 2);
    }

    #[test]
    fn refinement_fraction_must_be_inside_the_edge() {
        let mut pm = PolarMesh::octahedron();
        let before = pm.clone();
        for t in [0.0, 1.0, -0.5, f64::NAN] {
            assert!(matches!(pm.add_refinement_at(0, t), Err(PolarError::InvalidArgument(_))));
        }
        assert!(matches!(pm.add_refinement(999), Err(PolarError::NoSuchElement { .. })));
        assert_eq!(pm, before);
    }
}
