//! Building polar meshes: from a mesh and pole/loop markers (completed by propagation), and the
//! primitive starting shapes.

use std::collections::VecDeque;

use super::{PolarError, PolarMesh};
use crate::math::Vec3;
use crate::mesh::Mesh;

const UNKNOWN: u8 = 0;
const LOOP: u8 = 1;
const BACKBONE: u8 = 2;

impl PolarMesh {
    /// The regular octahedron of circumradius 1 with poles at −z (vertex 0) and +z (vertex 5),
    /// and the equator (vertices 1–4, counter-clockwise from +x seen from +z) as its one loop:
    /// the thesis's starting point (§4.8 step 1). 6 vertices, 12 edges, 8 triangles.
    #[must_use]
    pub fn octahedron() -> PolarMesh {
        let positions = vec![Vec3::NEG_Z, Vec3::X, Vec3::Y, Vec3::NEG_X, Vec3::NEG_Y, Vec3::Z];
        let mut faces = Vec::new();
        for i in 0..4u32 {
            let (a, b) = (1 + i, 1 + (i + 1) % 4);
            faces.push([0, b, a]);
            faces.push([a, b, 5]);
        }
        let mesh = Mesh::from_polygons(positions, &faces).expect("the octahedron is manifold by construction");
        PolarMesh::marked(mesh, &[0, 5], &[], false).expect("the octahedron is polar by construction")
    }

    /// A latitude–longitude sphere ([`Mesh::uv_sphere`]) as a polar mesh: poles at −z (vertex 0)
    /// and +z (the last vertex), each latitude a loop, each meridian a backbone. `segments` ≥ 3
    /// edges per loop, `rings` ≥ 2 bands (so `rings − 1` loops); `segments · rings` faces.
    #[must_use]
    pub fn uv_sphere(radius: f64, segments: u32, rings: u32) -> PolarMesh {
        let mesh = Mesh::uv_sphere(radius, segments, rings);
        let north = mesh.vertex_count() as u32 - 1;
        PolarMesh::marked(mesh, &[0, north], &[], false).expect("the UV sphere is polar by construction")
    }

    /// Marks an imported closed mesh as a polar mesh.
    ///
    /// Inputs: `poles` (vertex ids) and `loops` (loop edges as `[a, b]` vertex pairs). The
    /// markers are completed by propagation, which never guesses: around a pole the spokes are
    /// backbones and the opposite edges loops; in a quad with one known edge the opposite edge has
    /// the same role and the other two the other role. So give the poles, plus one loop edge in
    /// every part that no pole reaches (a torus-like part). The completed marking must pass
    /// [`PolarMesh::check`].
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad vertex id; [`PolarError::NotAnEdge`] for a loop
    /// pair that is no edge; [`PolarError::InconsistentMarking`] when markers contradict;
    /// [`PolarError::UnmarkedFace`] when a face's roles stay unknown; any invariant error of
    /// [`PolarMesh::check`].
    pub fn from_mesh(mesh: Mesh, poles: &[u32], loops: &[[u32; 2]]) -> Result<PolarMesh, PolarError> {
        PolarMesh::marked(mesh, poles, loops, true)
    }

    /// [`PolarMesh::from_mesh`], polling the current cancellation token every
    /// [`crate::limits::POLL_EVERY`] faces of the propagation when `poll` (the primitives, which
    /// cannot fail, do not poll).
    fn marked(mesh: Mesh, poles: &[u32], loops: &[[u32; 2]], poll: bool) -> Result<PolarMesh, PolarError> {
        let mut polled = 0usize;
        let mut tick = || -> Result<(), PolarError> {
            polled += 1;
            if poll {
                crate::limits::poll_at(polled)?;
            }
            Ok(())
        };
        for h in 0..mesh.halfedge_count() as u32 {
            tick()?;
            if mesh.is_boundary_halfedge(h) {
                return Err(PolarError::NotClosed { halfedge: h });
            }
        }
        if !mesh.is_manifold_polling(poll)? {
            return Err(PolarError::NotManifold);
        }
        let nv = mesh.vertex_count();
        let mut pole = vec![false; nv];
        for &p in poles {
            if p as usize >= nv {
                return Err(PolarError::NoSuchElement { what: "vertex", id: i64::from(p), count: nv });
            }
            pole[p as usize] = true;
        }
        let mut kind = vec![UNKNOWN; mesh.halfedge_count()];
        let mut queue: VecDeque<u32> = VecDeque::new();
        let set = |kind: &mut Vec<u8>, queue: &mut VecDeque<u32>, h: u32, k: u8, why: &str| {
            let t = mesh.twin(h);
            if kind[h as usize] == UNKNOWN {
                kind[h as usize] = k;
                kind[t as usize] = k;
                queue.push_back(mesh.face(h));
                queue.push_back(mesh.face(t));
                Ok(())
            } else if kind[h as usize] != k {
                Err(PolarError::InconsistentMarking {
                    face: mesh.face(h),
                    reason: format!(
                        "edge ({}, {}) is {} but {why}",
                        mesh.origin(h),
                        mesh.target(h),
                        if kind[h as usize] == LOOP { "a loop edge" } else { "a backbone" }
                    ),
                })
            } else {
                Ok(())
            }
        };
        for &[a, b] in loops {
            for v in [a, b] {
                if v as usize >= nv {
                    return Err(PolarError::NoSuchElement { what: "vertex", id: i64::from(v), count: nv });
                }
            }
            let h = mesh.find_halfedge(a, b).ok_or(PolarError::NotAnEdge { a, b })?;
            set(&mut kind, &mut queue, h, LOOP, "it is marked as a loop")?;
        }
        for p in (0..nv as u32).filter(|&v| pole[v as usize]) {
            for h in mesh.outgoing(p) {
                let f = mesh.face(h);
                match mesh.face_arity(f) {
                    3 => {}
                    4 => return Err(PolarError::QuadWithPole { face: f, pole: p }),
                    n => return Err(PolarError::FaceArity { face: f, arity: n }),
                }
                set(&mut kind, &mut queue, h, BACKBONE, "it is a spoke of a pole")?;
                set(&mut kind, &mut queue, mesh.next(h), LOOP, "it is opposite a pole")?;
            }
        }
        while let Some(f) = queue.pop_front() {
            tick()?;
            let hs: Vec<u32> = mesh.face_halfedges(f).collect();
            if hs.len() != 4 {
                continue;
            }
            let Some(i0) = (0..4).find(|&i| kind[hs[i] as usize] != UNKNOWN) else { continue };
            let k0 = kind[hs[i0] as usize];
            for (i, &h) in hs.iter().enumerate() {
                let k = if (i + 4 - i0) % 2 == 0 { k0 } else { LOOP + BACKBONE - k0 };
                set(&mut kind, &mut queue, h, k, "the quad's edges must alternate")?;
            }
        }
        for f in 0..mesh.face_count() as u32 {
            tick()?;
            let n = mesh.face_arity(f);
            let poles_in = mesh.face_vertices(f).filter(|&v| pole[v as usize]).count();
            match (n, poles_in) {
                (3, 0) => return Err(PolarError::TriangleWithoutPole { face: f }),
                (3, 1) | (4, 0) => {}
                (3, c) => return Err(PolarError::TriangleWithManyPoles { face: f, count: c }),
                (4, _) => {
                    let p = mesh.face_vertices(f).find(|&v| pole[v as usize]).unwrap_or_default();
                    return Err(PolarError::QuadWithPole { face: f, pole: p });
                }
                _ => return Err(PolarError::FaceArity { face: f, arity: n }),
            }
        }
        if let Some(h) = (0..kind.len()).find(|&h| kind[h] == UNKNOWN) {
            return Err(PolarError::UnmarkedFace { face: mesh.face(h as u32) });
        }
        let is_loop = kind.iter().map(|&k| k == LOOP).collect();
        let pm = PolarMesh { mesh, pole, is_loop };
        pm.check_polling(poll)?;
        Ok(pm)
    }

    /// Wraps a mesh with exact markers (one pole flag per vertex, one loop flag per half-edge),
    /// without propagation.
    ///
    /// # Errors
    /// [`PolarError::InvalidArgument`] for arrays of the wrong length; any invariant error of
    /// [`PolarMesh::check`].
    pub fn from_markers(mesh: Mesh, pole: Vec<bool>, is_loop: Vec<bool>) -> Result<PolarMesh, PolarError> {
        if pole.len() != mesh.vertex_count() || is_loop.len() != mesh.halfedge_count() {
            return Err(PolarError::InvalidArgument(format!(
                "markers have {} pole and {} loop entries for {} vertices and {} half-edges",
                pole.len(),
                is_loop.len(),
                mesh.vertex_count(),
                mesh.halfedge_count()
            )));
        }
        let pm = PolarMesh { mesh, pole, is_loop };
        pm.check()?;
        Ok(pm)
    }

    /// The pole flags (one per vertex) and loop flags (one per half-edge), e.g. to save them.
    #[must_use]
    pub fn markers(&self) -> (&[bool], &[bool]) {
        (&self.pole, &self.is_loop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_lands_inside_marking_a_large_mesh_and_never_in_the_primitives() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let mesh = Mesh::uv_sphere(1.0, 300, 300);
        let north = mesh.vertex_count() as u32 - 1;
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = PolarMesh::from_mesh(mesh.clone(), &[0, north], &[]).unwrap_err();
            assert!(matches!(e, PolarError::Limit(LimitError::Stopped(StopReason::Interrupted))), "{e}");
            // The primitive's own marking does not poll: it cannot fail, so it cannot stop.
            assert_eq!(PolarMesh::uv_sphere(1.0, 300, 300).mesh().face_count(), 90_000);
        }
        assert_eq!(PolarMesh::from_mesh(mesh, &[0, north], &[]).unwrap().mesh().face_count(), 90_000);
    }

    #[test]
    fn octahedron_is_polar_with_one_loop_of_four() {
        let pm = PolarMesh::octahedron();
        pm.check().unwrap();
        assert_eq!(pm.poles(), vec![0, 5]);
        // The equator: 4 loop edges, 8 loop half-edges; the 8 spokes are backbones.
        assert_eq!((0..24).filter(|&h| pm.is_loop(h)).count(), 8);
        assert!(pm.mesh().volume() > 0.0);
    }

    #[test]
    fn uv_sphere_marks_latitudes_as_loops() {
        let pm = PolarMesh::uv_sphere(1.0, 8, 5);
        pm.check().unwrap();
        // 4 latitude loops of 8 edges: 32 loop edges.
        let loops = (0..pm.halfedge_count() as u32).filter(|&h| pm.is_loop(h)).count();
        assert_eq!(loops, 2 * 32);
    }

    #[test]
    fn torus_needs_one_loop_seed_and_propagates_it() {
        let t = Mesh::torus(2.0, 0.5, 8, 6);
        assert!(matches!(PolarMesh::from_mesh(t.clone(), &[], &[]), Err(PolarError::UnmarkedFace { .. })));
        // Vertices 0 and 1 lie on one tube circle (j = 0, 1 at i = 0).
        let pm = PolarMesh::from_mesh(t, &[], &[[0, 1]]).unwrap();
        assert_eq!((0..pm.halfedge_count() as u32).filter(|&h| pm.is_loop(h)).count(), 2 * 48);
    }

    #[test]
    fn contradicting_markers_and_bad_meshes_are_refused() {
        let t = Mesh::torus(2.0, 0.5, 8, 6);
        // (0, 1) along the tube circle and (0, 6) along the ring meet in one quad as neighbours.
        let e = PolarMesh::from_mesh(t, &[], &[[0, 1], [0, 6]]).unwrap_err();
        assert!(matches!(e, PolarError::InconsistentMarking { .. }), "{e}");
        // A cube has quads only and no pole: a loop seed types all faces... but at each corner
        // three quads meet, so the alternation cannot close.
        let e = PolarMesh::from_mesh(Mesh::cube(1.0), &[], &[[0, 1]]).unwrap_err();
        assert!(matches!(e, PolarError::InconsistentMarking { .. } | PolarError::VertexValence { .. }), "{e}");
        // A pole on a quad.
        let e = PolarMesh::from_mesh(Mesh::cube(1.0), &[0], &[]).unwrap_err();
        assert!(matches!(e, PolarError::QuadWithPole { pole: 0, .. }), "{e}");
        // An icosphere: triangles without poles.
        let e = PolarMesh::from_mesh(Mesh::icosphere(1.0, 0), &[0], &[]).unwrap_err();
        assert!(matches!(e, PolarError::TriangleWithoutPole { .. }), "{e}");
        assert!(matches!(
            PolarMesh::from_mesh(Mesh::cube(1.0), &[99], &[]),
            Err(PolarError::NoSuchElement { id: 99, .. })
        ));
        assert!(matches!(PolarMesh::from_mesh(Mesh::cube(1.0), &[], &[[0, 7]]), Err(PolarError::NotAnEdge { .. })));
    }
}
