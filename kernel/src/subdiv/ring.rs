//! The one-ring of a vertex in counter-clockwise order, as limit masks need it.
//!
//! Layout (the same for rings read from a [`Mesh`] and for the evaluator's corner fans): edges
//! `e_0 … e_{n-1}` in counter-clockwise order seen from outside; face slot `i` lies between `e_i`
//! and `e_{i+1}` (indices mod n) and may be empty (a boundary gap). On a boundary the single gap is
//! the last slot, so the faces run from `e_0` to `e_{n-1}`. For quad faces `f_i` is the vertex of
//! face slot `i` opposite the centre.

use crate::mesh::{Mesh, NONE};

use super::topology::Rule;

/// Topology of a one-ring: enough to choose and weight a limit mask.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct RingTopo {
    /// Edge `i` is sharp (a crease or a boundary edge).
    pub(crate) sharp: Vec<bool>,
    /// Face slot `i` holds a face.
    pub(crate) face: Vec<bool>,
    /// The centre vertex is marked as a corner.
    pub(crate) corner: bool,
}

impl RingTopo {
    /// Number of edges.
    pub(crate) fn valence(&self) -> usize {
        self.sharp.len()
    }

    /// The indices of the sharp edges, in ring order.
    pub(crate) fn sharp_indices(&self) -> Vec<usize> {
        (0..self.valence()).filter(|&i| self.sharp[i]).collect()
    }

    /// The vertex rule, as [`super::topology::Level`] classifies it.
    pub(crate) fn rule(&self) -> Rule {
        let s = self.sharp.iter().filter(|&&x| x).count();
        if self.corner || s >= 3 || self.valence() == 0 {
            Rule::Corner
        } else if s == 2 {
            Rule::Crease
        } else {
            Rule::Smooth
        }
    }
}

/// A one-ring read from a mesh: topology plus vertex ids.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshRing {
    pub(crate) topo: RingTopo,
    /// Neighbour vertex ids, counter-clockwise.
    pub(crate) edges: Vec<u32>,
    /// For quad face slots, the vertex opposite the centre; [`NONE`] for empty or non-quad slots.
    pub(crate) opposite: Vec<u32>,
    /// Face id of each face slot, [`NONE`] for a gap.
    pub(crate) faces: Vec<u32>,
    /// Whether every face of the ring is a quad.
    pub(crate) all_quads: bool,
}

/// The counter-clockwise one-ring of vertex `v` of `mesh`.
pub(crate) fn mesh_ring(mesh: &Mesh, v: u32) -> MeshRing {
    // `outgoing` turns counter-clockwise seen from outside: the face of half-edge h = v→a lies to
    // the left of h, between a and the next neighbour (twin(prev(h)) = v→b with b after a).
    let hs: Vec<u32> = mesh.outgoing(v).collect();
    let n = hs.len();
    // A boundary vertex starts with its boundary half-edge (face slot 0 empty): rotate by one so
    // the gap comes last.
    let shift = usize::from(n > 0 && mesh.is_boundary_halfedge(hs[0]));
    let mut ring = MeshRing {
        topo: RingTopo { sharp: Vec::with_capacity(n), face: Vec::with_capacity(n), corner: mesh.is_corner(v) },
        edges: Vec::with_capacity(n),
        opposite: Vec::with_capacity(n),
        faces: Vec::with_capacity(n),
        all_quads: true,
    };
    for i in 0..n {
        let h = hs[(i + shift) % n];
        ring.edges.push(mesh.target(h));
        let boundary_edge = mesh.is_boundary_halfedge(h) || mesh.is_boundary_halfedge(mesh.twin(h));
        ring.topo.sharp.push(mesh.is_crease(h) || boundary_edge);
        let f = mesh.face(h);
        ring.faces.push(f);
        ring.topo.face.push(f != NONE);
        if f == NONE {
            ring.opposite.push(NONE);
        } else if mesh.face_arity(f) == 4 {
            ring.opposite.push(mesh.target(mesh.next(h)));
        } else {
            ring.all_quads = false;
            ring.opposite.push(NONE);
        }
    }
    ring
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn grid3() -> Mesh {
        // 3×3 vertices, 2×2 quads in the xy-plane, counter-clockwise seen from +z.
        let p = (0..9).map(|i| Vec3::new(f64::from(i % 3), f64::from(i / 3), 0.0)).collect();
        Mesh::from_polygons(p, &[[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]).unwrap()
    }

    #[test]
    fn interior_ring_turns_counter_clockwise_seen_from_outside() {
        let m = grid3();
        let r = mesh_ring(&m, 4);
        let angle = |w: u32| {
            let d = m.position(w) - m.position(4);
            d.y.atan2(d.x)
        };
        // Consecutive neighbours are a quarter turn apart counter-clockwise (seen from +z).
        for i in 0..4 {
            let a = angle(r.edges[i]);
            let b = angle(r.edges[(i + 1) % 4]);
            let turn = (b - a).rem_euclid(std::f64::consts::TAU);
            assert!((turn - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "turn {turn}");
            // The opposite vertex of face slot i is the diagonal between e_i and e_{i+1}.
            let diag = m.position(r.opposite[i]) - m.position(4);
            let sum = m.position(r.edges[i]) + m.position(r.edges[(i + 1) % 4]) - 2.0 * m.position(4);
            assert!((diag - sum).length() < 1e-12);
        }
        assert!(r.topo.face.iter().all(|&f| f) && r.all_quads);
        assert_eq!(r.topo.rule(), Rule::Smooth);
    }

    #[test]
    fn boundary_ring_puts_the_gap_last() {
        let m = grid3();
        let r = mesh_ring(&m, 1);
        assert_eq!(r.topo.face, vec![true, true, false]);
        assert_eq!(r.topo.sharp, vec![true, false, true]);
        // e_0 is the boundary neighbour the faces start from, e_2 the one they end at.
        assert_eq!((r.edges[0], r.edges[2]), (2, 0));
        assert_eq!(r.topo.rule(), Rule::Crease);
    }
}
