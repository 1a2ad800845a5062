//! The half-edge mesh of the last refined level, built straight from its parent level's
//! topology.
//!
//! A generic build from a face list ([`Mesh::from_indexed`]) buckets every half-edge by vertex
//! and searches for its twin. Here the twins are known: a parent edge splits into two child
//! edges whose half-edges lie in the children at its ends in the faces on its two sides, and a
//! child's inner edges pair with its siblings' (OpenSubdiv's `Vtr::Refinement` derives the child
//! level's relations from the parent's the same way). One pass over the parent's face corners
//! writes every face half-edge with its twin and crease sharpness; [`Mesh::from_paired_faces`]
//! adds the boundary. The result equals the generic build's, half-edge ids included.

use crate::math::Vec3;
use crate::mesh::Mesh;

use super::topology::{to_mesh_sharpness, Level, NONE};
use super::SubdivError;

/// For each parent edge, the corner (index into `face_verts`) at which each of its faces
/// starts it: the edge of corner `c` runs from `face_verts[c]` to the face's next corner. The
/// second entry of a boundary edge (no second face) is left 0: allocated zeroed, the list needs
/// no fill pass.
fn edge_corners(lv: &Level) -> Vec<[u32; 2]> {
    let mut out = vec![[0u32; 2]; lv.edge_count()];
    for f in 0..lv.face_count() {
        for c in lv.face_range(f) {
            let e = lv.face_edges[c] as usize;
            let slot = usize::from(lv.edge_faces[e][0] != f as u32);
            out[e][slot] = c as u32;
        }
    }
    out
}

/// The corner after `c` in its face (faces of `lv` as CSR; `f` the face of `c`).
#[inline]
fn next_corner(lv: &Level, f: u32, c: u32) -> u32 {
    let f = f as usize;
    if c + 1 == lv.face_start[f + 1] {
        lv.face_start[f]
    } else {
        c + 1
    }
}

/// The sharpness of the two halves of parent edge `e` as mesh tags, `[at edge_verts[e][0], at
/// [1]]` (boundary edges carry none, as [`super::Refiner::to_mesh`] always tagged them).
#[inline]
fn half_sharpness(lv: &Level, e: usize) -> [f64; 2] {
    if lv.edge_sharpness[e] > 0.0 && lv.edge_faces[e][1] != NONE {
        lv.child_sharpness(e).map(to_mesh_sharpness)
    } else {
        [0.0; 2]
    }
}

/// The mesh one Catmull–Clark or Loop step below `lv` (ids as [`super::refiner`] lays them out)
/// with `positions` (one per child vertex), its creases and corners carried down.
pub(crate) fn child_mesh(lv: &Level, loop_scheme: bool, positions: Vec<Vec3>) -> Result<Mesh, SubdivError> {
    let (nv, ne) = (lv.num_vertices as u32, lv.edge_count() as u32);
    let nc = lv.face_verts.len();
    // Catmull–Clark: the child of corner c is quad c, half-edges 4c.. [v → edge point of the
    // corner's edge → face point → edge point of the previous edge → v]. Loop: triangle f's
    // corner k is child 4f + k, half-edges 3(4f + k).. [v_k → m_k → m_k-1 → v_k], and the
    // centre child 4f + 3 runs m_0 → m_1 → m_2.
    let (arity, nfh) = if loop_scheme { (3usize, 12 * lv.face_count()) } else { (4, 4 * nc) };
    // The half-edge leaving a corner's vertex along its edge, and the one arriving there along
    // the previous edge.
    let leave = |c: u32| if loop_scheme { 3 * (c + c / 3) } else { 4 * c };
    let arrive = |c: u32| if loop_scheme { 3 * (c + c / 3) + 2 } else { 4 * c + 3 };
    // Every face half-edge's twin is written below (NONE where the parent edge is a boundary),
    // so the list is allocated zeroed rather than filled first.
    let mut origins = vec![0u32; nfh];
    let mut twins = vec![0u32; nfh];
    let mut sharp = vec![0.0f64; nfh];
    for f in 0..lv.face_count() {
        crate::limits::poll_at(f)?;
        let r = lv.face_range(f);
        let (s, n) = (r.start, r.len());
        let fp = nv + ne + f as u32;
        for k in 0..n {
            let c = (s + k) as u32;
            let kp = if k == 0 { n - 1 } else { k - 1 };
            let kn = if k + 1 == n { 0 } else { k + 1 };
            let (cn, cp) = ((s + kn) as u32, (s + kp) as u32);
            let v = lv.face_verts[c as usize];
            let (mk, mp) = (nv + lv.face_edges[c as usize], nv + lv.face_edges[cp as usize]);
            if loop_scheme {
                let h = leave(c);
                origins[h as usize..h as usize + 3].copy_from_slice(&[v, mk, mp]);
                // m_k → m_k-1 pairs with the centre's m_k-1 → m_k.
                let centre = 3 * (4 * f as u32 + 3);
                let t = centre + kp as u32;
                twins[h as usize + 1] = t;
                twins[t as usize] = h + 1;
                origins[t as usize] = mp;
            } else {
                let h = leave(c);
                origins[h as usize..h as usize + 4].copy_from_slice(&[v, mk, fp, mp]);
                // Edge point → face point pairs with the next corner's face point → edge point.
                let t = 4 * cn + 2;
                twins[h as usize + 1] = t;
                twins[t as usize] = h + 1;
            }
        }
    }
    // The halves of each parent edge: the corner that starts it in face 0 leaves its start,
    // the next corner there arrives at its end; the same in face 1, the other way round.
    let corners = edge_corners(lv);
    for (e, &[c0, c1]) in corners.iter().enumerate() {
        crate::limits::poll_at(e)?;
        let f0 = lv.edge_faces[e][0];
        let n0 = next_corner(lv, f0, c0);
        let [sa, sb] = half_sharpness(lv, e);
        let start = lv.face_verts[c0 as usize];
        let (s_start, s_end) = if start == lv.edge_verts[e][0] { (sa, sb) } else { (sb, sa) };
        let (a0, b0) = (leave(c0) as usize, arrive(n0) as usize);
        // Smooth halves are left as allocated (zero): a mesh without creases never writes, so
        // never touches, its sharpness pages.
        if s_start != 0.0 || s_end != 0.0 {
            sharp[a0] = s_start;
            sharp[b0] = s_end;
        }
        let f1 = lv.edge_faces[e][1];
        if f1 == NONE {
            twins[a0] = NONE;
            twins[b0] = NONE;
        } else {
            let n1 = next_corner(lv, f1, c1);
            let (a1, b1) = (leave(c1) as usize, arrive(n1) as usize);
            // Face 1 leaves the edge's end and arrives at its start.
            twins[a0] = b1 as u32;
            twins[b1] = a0 as u32;
            twins[a1] = b0 as u32;
            twins[b0] = a1 as u32;
            if s_start != 0.0 || s_end != 0.0 {
                sharp[a1] = s_end;
                sharp[b1] = s_start;
            }
        }
    }
    let mut corner = vec![0.0f64; positions.len()];
    for (c, &p) in corner.iter_mut().zip(&lv.vertex_sharpness) {
        if p > 0.0 {
            *c = to_mesh_sharpness(super::topology::decrement(p));
        }
    }
    Mesh::from_paired_faces(positions, arity, origins, twins, sharp, corner)
        .map_err(|e| SubdivError::Internal(format!("refined faces do not form a mesh: {e}")))
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{cube_crease_loop, grid, mixed_torus, tetrahedron};
    use super::super::{BoundaryInterpolation, CreaseMethod, Refiner, Scheme, SubdivOptions};
    use crate::math::Vec3;
    use crate::mesh::Mesh;

    /// Meshes with every kind of topology the build meets: closed and open, n-gons and
    /// triangles, an isolated vertex, infinite and semi-sharp creases and corners, both
    /// creasing methods.
    fn corpus() -> Vec<(&'static str, Mesh)> {
        let mut semi = mixed_torus();
        let pairs: Vec<[u32; 2]> = semi.crease_pairs();
        assert!(pairs.is_empty());
        let hs: Vec<u32> = semi.edges().step_by(5).collect();
        for (i, h) in hs.into_iter().enumerate() {
            semi.set_edge_sharpness_halfedge(h, [0.5, 1.0, 1.5, 2.7, f64::INFINITY][i % 5]);
        }
        semi.set_corner_sharpness(3, 1.5);
        semi.set_corner(7, true);
        let mut chaikin = semi.clone();
        chaikin.set_subdiv_options(SubdivOptions { crease: CreaseMethod::Chaikin, ..SubdivOptions::default() });
        let mut open = grid(4);
        open.crease_edges_sharpness(&[[6, 7], [7, 8]], 2.5).unwrap();
        open.set_subdiv_options(SubdivOptions {
            boundary: BoundaryInterpolation::EdgeAndCorner,
            ..SubdivOptions::default()
        });
        let mut lone = grid(2).to_polygons();
        lone.iter_mut().for_each(|f| f.iter_mut().for_each(|v| *v += 1));
        let mut p = vec![Vec3::new(9.0, 9.0, 9.0)];
        p.extend_from_slice(grid(2).positions());
        let isolated = Mesh::from_polygons(p, &lone).unwrap();
        let mut tri_open = grid(3).triangulate().unwrap();
        tri_open.crease_edges_sharpness(&[[5, 6]], 1.25).unwrap();
        let mut ico = Mesh::icosphere(1.0, 1);
        let hs: Vec<u32> = ico.edges().step_by(3).collect();
        for (i, h) in hs.into_iter().enumerate() {
            ico.set_edge_sharpness_halfedge(h, [0.5, 2.7, f64::INFINITY][i % 3]);
        }
        ico.set_corner_sharpness(0, 2.0);
        vec![
            ("cube", Mesh::cube(2.0)),
            ("cube_crease_loop", cube_crease_loop()),
            ("mixed_torus_semi", semi),
            ("mixed_torus_chaikin", chaikin),
            ("open_grid", open),
            ("isolated_vertex", isolated),
            ("tetrahedron", tetrahedron()),
            ("open_triangles", tri_open),
            ("icosphere_creased", ico),
        ]
    }

    #[test]
    fn the_direct_build_equals_the_generic_build_from_the_face_list() {
        // Same half-edge ids, twins, boundary loops, outgoing half-edges, tags: the whole mesh.
        for (name, m) in corpus() {
            let schemes: &[Scheme] =
                if m.is_triangle_mesh() { &[Scheme::CatmullClark, Scheme::Loop] } else { &[Scheme::CatmullClark] };
            for &scheme in schemes {
                for levels in 1..=3 {
                    let r = Refiner::new(&m, scheme, levels).unwrap();
                    let p = r.refine_positions(m.positions());
                    let direct = r.to_mesh(p.clone()).unwrap();
                    let generic = r.to_mesh_from_faces(p).unwrap();
                    assert!(direct == generic, "{name} {scheme:?} level {levels}");
                    assert!(direct.is_manifold(), "{name} {scheme:?} level {levels}");
                }
            }
        }
    }

    #[test]
    fn the_corpus_carries_tags_down() {
        // The comparison above means something only if the tags survive a level.
        for (name, m) in corpus().into_iter().skip(1) {
            if m.crease_count() > 0 {
                let s = m.catmull_clark(1).unwrap();
                assert!(s.crease_count() >= m.crease_count(), "{name}");
            }
        }
    }
}
