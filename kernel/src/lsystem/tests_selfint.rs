//! Test support: self-intersecting triangle pairs of a mesh, by the interval test of Möller
//! (1997), "A fast triangle–triangle intersection test", §2: two triangles that share no vertex
//! intersect when each straddles the other's plane and their two intervals on the planes'
//! common line overlap. Candidate pairs come from a uniform grid of cells about the size of a
//! triangle's bounding box: each triangle is listed in the cells its box touches and a pair is
//! tested once, in the cell holding the low corner of the two boxes' overlap — near-linear for
//! meshes whose triangles are of similar size (the recipes' ~10k faces in a debug build).

use std::collections::HashMap;

use crate::math::Vec3;
use crate::mesh::Mesh;

/// Signed distances below this fraction of the triangles' size count as touching, not crossing:
/// triangles meeting along an edge of the mesh, or grazing, are not counted.
const EPS: f64 = 1e-9;

/// Whether triangles `a` and `b` (corner positions) cross each other (Möller 1997, §2): not
/// counted when they only touch or are coplanar.
pub(crate) fn triangles_cross(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    let scale = a.iter().chain(&b).map(|p| p.abs().max_element()).fold(1e-300, f64::max);
    let eps = EPS * scale;
    let plane = |t: [Vec3; 3]| {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        let l = n.length();
        (if l > 0.0 { n / l } else { Vec3::ZERO }, t[0])
    };
    let (na, pa) = plane(a);
    let (nb, pb) = plane(b);
    if na == Vec3::ZERO || nb == Vec3::ZERO {
        return false;
    }
    let db: [f64; 3] = b.map(|p| (p - pa).dot(na));
    let da: [f64; 3] = a.map(|p| (p - pb).dot(nb));
    let one_side = |d: [f64; 3]| d.iter().all(|&x| x > -eps) || d.iter().all(|&x| x < eps);
    if one_side(db) || one_side(da) {
        return false;
    }
    let dir = na.cross(nb);
    if dir.length() < 1e-12 {
        return false;
    }
    // The interval where a triangle meets the other's plane, as parameters along `dir`.
    let interval = |t: [Vec3; 3], d: [f64; 3]| {
        let mut ts = Vec::with_capacity(3);
        for k in 0..3 {
            let (i, j) = (k, (k + 1) % 3);
            if (d[i] > 0.0) != (d[j] > 0.0) {
                let s = d[i] / (d[i] - d[j]);
                ts.push((t[i] + (t[j] - t[i]) * s).dot(dir));
            }
        }
        let lo = ts.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (a0, a1) = interval(a, da);
    let (b0, b1) = interval(b, db);
    a0.max(b0) < a1.min(b1) - eps * dir.length()
}

/// The pairs of triangles of `m` (each face triangulated) that share no vertex and cross each
/// other, as pairs of face ids (a face may appear in several), in increasing order.
pub(crate) fn self_intersections(m: &Mesh) -> Vec<(u32, u32)> {
    let mut tris: Vec<([u32; 3], u32)> = Vec::new();
    for f in 0..m.face_count() as u32 {
        let ts = m.triangulate_face(f).unwrap_or_else(|e| panic!("face {f} does not triangulate: {e}"));
        tris.extend(ts.into_iter().map(|t| (t, f)));
    }
    let pos = |t: [u32; 3]| t.map(|v| m.position(v));
    let bbox = |p: [Vec3; 3]| (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
    let boxes: Vec<(Vec3, Vec3)> = tris.iter().map(|&(t, _)| bbox(pos(t))).collect();
    if tris.is_empty() {
        return Vec::new();
    }
    // Cells twice the mean box extent: a typical triangle touches a few cells.
    let mean = boxes.iter().map(|(lo, hi)| (*hi - *lo).max_element()).sum::<f64>() / boxes.len() as f64;
    let origin = boxes.iter().fold(Vec3::splat(f64::INFINITY), |a, (lo, _)| a.min(*lo));
    let size = if mean > 0.0 { 2.0 * mean } else { 1.0 };
    let cell = |p: Vec3| {
        let c = ((p - origin) / size).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &(lo, hi)) in boxes.iter().enumerate() {
        let (a, b) = (cell(lo), cell(hi));
        for x in a.0..=b.0 {
            for y in a.1..=b.1 {
                for z in a.2..=b.2 {
                    grid.entry((x, y, z)).or_default().push(i);
                }
            }
        }
    }
    let mut out = Vec::new();
    for (&c, list) in &grid {
        for (a, &i) in list.iter().enumerate() {
            for &j in &list[a + 1..] {
                let ((ti, fi), (tj, fj)) = (tris[i], tris[j]);
                if fi == fj || ti.iter().any(|v| tj.contains(v)) {
                    continue;
                }
                let ((lo_i, hi_i), (lo_j, hi_j)) = (boxes[i], boxes[j]);
                if lo_i.cmpgt(hi_j).any() || lo_j.cmpgt(hi_i).any() || cell(lo_i.max(lo_j)) != c {
                    continue;
                }
                if triangles_cross(pos(ti), pos(tj)) {
                    out.push((fi.min(fj), fi.max(fj)));
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// Faces of `m` in at least one crossing pair (what pymeshlab's
/// `compute_selection_by_self_intersections_per_face` selects).
pub(crate) fn self_intersecting_faces(m: &Mesh) -> usize {
    let mut faces: Vec<u32> = self_intersections(m).into_iter().flat_map(|(a, b)| [a, b]).collect();
    faces.sort_unstable();
    faces.dedup();
    faces.len()
}

#[test]
fn crossing_triangles_are_found_and_touching_ones_are_not() {
    let t = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| [Vec3::from(a), Vec3::from(b), Vec3::from(c)];
    let flat = t([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
    // Pierces `flat` through its inside.
    assert!(triangles_cross(flat, t([0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [0.6, 0.4, 1.0])));
    // Straddles the plane but beside the triangle.
    assert!(!triangles_cross(flat, t([3.0, 3.0, -1.0], [3.0, 3.0, 1.0], [3.1, 2.9, 1.0])));
    // Above the plane, touching at a point: not a crossing.
    assert!(!triangles_cross(flat, t([0.5, 0.5, 0.0], [0.5, 0.5, 1.0], [0.6, 0.4, 1.0])));
    // Coplanar: not counted.
    assert!(!triangles_cross(flat, t([0.1, 0.1, 0.0], [1.0, 0.1, 0.0], [0.1, 1.0, 0.0])));
    // A closed mesh that does not self-intersect has no pairs; one with a vertex pushed through
    // the opposite side has some.
    let mut cube = crate::polar::PolarMesh::uv_sphere(1.0, 8, 6).to_mesh();
    assert!(self_intersections(&cube).is_empty());
    let top =
        (0..cube.vertex_count() as u32).max_by(|&a, &b| cube.position(a).z.total_cmp(&cube.position(b).z)).unwrap();
    cube.set_position(top, Vec3::new(0.0, 0.0, -2.0)).unwrap();
    assert!(self_intersecting_faces(&cube) > 0);
}

/// The grid finds exactly the pairs that testing every pair finds, on a plant whose pitched
/// branches overlap (and on the same mesh with a vertex pushed through it).
#[test]
fn the_grid_finds_what_every_pair_finds() {
    let all_pairs = |m: &Mesh| {
        let mut tris: Vec<([u32; 3], u32)> = Vec::new();
        for f in 0..m.face_count() as u32 {
            tris.extend(m.triangulate_face(f).unwrap().into_iter().map(|t| (t, f)));
        }
        let mut out = Vec::new();
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                let ((ti, fi), (tj, fj)) = (tris[i], tris[j]);
                if fi != fj
                    && !ti.iter().any(|v| tj.contains(v))
                    && triangles_cross(ti.map(|v| m.position(v)), tj.map(|v| m.position(v)))
                {
                    out.push((fi.min(fj), fi.max(fj)));
                }
            }
        }
        out.sort_unstable();
        out
    };
    let s = super::parse_modules("test", "F F [&F F] /(60) [&F F] F").unwrap();
    let g = super::grow(&s, &super::GrowOptions::DEFAULT.with_valence(8)).unwrap();
    let mut m = g.mesh.to_mesh();
    // A branch's tip pole (its faces are triangles), to be pushed through the trunk.
    let v = g.mesh.poles().into_iter().max_by(|&a, &b| m.position(a).x.total_cmp(&m.position(b).x)).unwrap();
    for pass in 0..2 {
        let want = all_pairs(&m);
        assert_eq!(self_intersections(&m), want, "pass {pass}");
        if pass == 1 {
            assert!(!want.is_empty(), "the pushed vertex crosses the mesh");
        }
        m.set_position(v, Vec3::new(-1.0, 0.0, 1.2)).unwrap();
    }
}
