//! Tests of the exact triangle-pair predicates and of the face pairs the BVH finds.

use super::triangle_pair::{is_degenerate, shared_corner_meets, shared_edge_meets, triangles_meet};
use super::{crossings, self_intersections};
use crate::math::{SplitMix64, Vec3};
use crate::mesh::Mesh;

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn flat() -> [Vec3; 3] {
    [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)]
}

#[test]
fn a_triangle_through_another_meets_it_one_beside_does_not() {
    assert!(triangles_meet(flat(), [v(0.5, 0.5, -1.0), v(0.5, 0.5, 1.0), v(0.6, 0.4, 1.0)]));
    assert!(!triangles_meet(flat(), [v(3.0, 3.0, -1.0), v(3.0, 3.0, 1.0), v(3.1, 2.9, 1.0)]));
    // Above the plane: no.
    assert!(!triangles_meet(flat(), [v(0.5, 0.5, 0.1), v(0.5, 0.5, 1.0), v(0.6, 0.4, 1.0)]));
}

#[test]
fn touching_counts_exactly_at_the_last_bit() {
    // A corner resting on the inside of the other triangle meets it; lifted by one unit in the
    // last place it does not (a tolerance would say both or neither).
    let z = 0.0f64;
    assert!(triangles_meet(flat(), [v(0.5, 0.5, z), v(0.5, 0.5, 1.0), v(0.6, 0.4, 1.0)]));
    let up = f64::from_bits(1);
    assert!(!triangles_meet(flat(), [v(0.5, 0.5, up), v(0.5, 0.5, 1.0), v(0.6, 0.4, 1.0)]));
    // A corner exactly on the hypotenuse x + y = 2 (0.5 + 1.5, both exact).
    assert!(triangles_meet(flat(), [v(0.5, 1.5, 0.0), v(0.5, 1.5, 1.0), v(0.9, 1.9, 1.0)]));
}

#[test]
fn coplanar_triangles_meet_when_they_overlap() {
    assert!(triangles_meet(flat(), [v(0.1, 0.1, 0.0), v(1.0, 0.1, 0.0), v(0.1, 1.0, 0.0)]));
    assert!(triangles_meet(flat(), [v(1.0, -1.0, 0.0), v(1.0, 3.0, 0.0), v(5.0, 1.0, 0.0)]));
    assert!(!triangles_meet(flat(), [v(3.0, 3.0, 0.0), v(4.0, 3.0, 0.0), v(3.0, 4.0, 0.0)]));
    // In a vertical plane (the z-projection is degenerate, another one is used).
    let wall = [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 0.0, 2.0)];
    assert!(triangles_meet(wall, [v(0.5, 0.0, 0.5), v(3.0, 0.0, 0.5), v(0.5, 0.0, 3.0)]));
    assert!(!triangles_meet(wall, [v(3.0, 0.0, 3.0), v(4.0, 0.0, 3.0), v(3.0, 0.0, 4.0)]));
}

#[test]
fn neighbours_meet_only_when_they_fold_or_cross() {
    let (s, a, b) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
    // A fan neighbour going up: only the corner.
    assert!(!shared_corner_meets(s, a, b, v(-1.0, 0.0, 0.0), v(0.0, -1.0, 1.0)));
    // Folded flat onto the first: meets beyond the corner.
    assert!(shared_corner_meets(s, a, b, v(1.0, 1.0, 0.0), v(2.0, 0.5, 0.0)));
    // Crossing through the first from the shared corner.
    assert!(shared_corner_meets(s, a, b, v(0.3, 0.3, -1.0), v(0.3, 0.3, 1.0)));
    // Coplanar, on the other side of the corner: no.
    assert!(!shared_corner_meets(s, a, b, v(-1.0, 0.0, 0.0), v(0.0, -1.0, 0.0)));
    // Edge neighbours: a flat pair on both sides does not meet, folded onto one side does.
    assert!(!shared_edge_meets(s, a, b, v(0.5, -1.0, 0.0)));
    assert!(shared_edge_meets(s, a, b, v(0.5, 0.2, 0.0)));
    assert!(!shared_edge_meets(s, a, b, v(0.5, 0.2, 1e-300)));
}

#[test]
fn degenerate_triangles_are_found_exactly() {
    assert!(is_degenerate([v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), v(2.0, 2.0, 2.0)]));
    assert!(is_degenerate([v(1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 5.0, 2.0)]));
    assert!(!is_degenerate([v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), v(2.0, 2.0, 2.0 + 4.0 * f64::EPSILON)]));
}

/// Every pair of faces tested, without the tree: what the tree must find.
fn all_pairs(m: &Mesh) -> Vec<[u32; 2]> {
    // Two faces at a time, as a two-face mesh whose shared corners keep their ids.
    let mut out = Vec::new();
    for f in 0..m.face_count() as u32 {
        for g in f + 1..m.face_count() as u32 {
            let (a, b): (Vec<u32>, Vec<u32>) = (m.face_vertices(f).collect(), m.face_vertices(g).collect());
            let mut ids: Vec<u32> = a.iter().chain(&b).copied().collect();
            ids.sort_unstable();
            ids.dedup();
            let at = |x: u32| ids.binary_search(&x).unwrap() as u32;
            let pos: Vec<Vec3> = ids.iter().map(|&x| m.position(x)).collect();
            let faces = [a.iter().map(|&x| at(x)).collect::<Vec<_>>(), b.iter().map(|&x| at(x)).collect()];
            let two = Mesh::from_polygons(pos, &faces);
            if let Ok(two) = two {
                if !self_intersections(&two).unwrap().is_empty() {
                    out.push([f, g]);
                }
            }
        }
    }
    out
}

#[test]
fn a_closed_sphere_has_none_and_a_vertex_pushed_through_makes_some() {
    let mut m = Mesh::icosphere(1.0, 2);
    assert!(self_intersections(&m).unwrap().is_empty());
    let top = (0..m.vertex_count() as u32).max_by(|&a, &b| m.position(a).z.total_cmp(&m.position(b).z)).unwrap();
    m.set_position(top, v(0.0, 0.0, -1.5)).unwrap();
    let pairs = self_intersections(&m).unwrap();
    assert!(!pairs.is_empty());
    assert_eq!(pairs, all_pairs(&m), "the tree finds what testing every pair finds");
    // Each crossing names one of the pushed vertex's faces, and lies inside the sphere's box.
    let around: Vec<u32> = m.vertex_faces(top).collect();
    for c in crossings(&m).unwrap() {
        assert!(around.contains(&c.faces[0]) || around.contains(&c.faces[1]), "{c:?}");
        assert!(c.at.abs().max_element() <= 1.5);
    }
}

#[test]
fn random_triangles_agree_with_every_pair() {
    // 300 random small triangles in a unit box (a soup: no shared corners), some coplanar
    // on z = 0.5 so the coplanar path runs too.
    let mut rng = SplitMix64::new(34);
    let mut r = || rng.next_f64();
    let mut p = Vec::new();
    let mut faces = Vec::new();
    for i in 0..300u32 {
        let c = v(r(), r(), r());
        for _ in 0..3 {
            let mut q = c + v(r() - 0.5, r() - 0.5, r() - 0.5) * 0.2;
            if i % 5 == 0 {
                q.z = 0.5;
            }
            p.push(q);
        }
        faces.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let m = Mesh::from_polygons(p, &faces).unwrap();
    let pairs = self_intersections(&m).unwrap();
    assert!(pairs.len() > 50, "{}", pairs.len());
    assert_eq!(pairs, all_pairs(&m));
}

#[test]
fn sheets_split_at_a_shared_position_do_not_touch_there() {
    // Two triangles meeting at one point through different vertex ids at the same position
    // (as a repair splits a bowtie): not a pair. Moving one so it crosses the other: a pair.
    let p = vec![
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.0, 0.0, 0.0),
        v(-1.0, 0.0, 0.5),
        v(0.0, -1.0, 0.5),
    ];
    let m = Mesh::from_polygons(p.clone(), &[[0, 1, 2], [3, 4, 5]]).unwrap();
    assert!(self_intersections(&m).unwrap().is_empty());
    let mut q = p;
    q[4] = v(0.5, 0.2, -0.5);
    q[5] = v(0.2, 0.5, 0.5);
    let m = Mesh::from_polygons(q, &[[0, 1, 2], [3, 4, 5]]).unwrap();
    assert_eq!(self_intersections(&m).unwrap(), vec![[0, 1]]);
}

#[test]
fn a_stopped_token_stops_the_search() {
    use crate::limits::{install, CancelToken, LimitError};
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;
    let m = Mesh::icosphere(1.0, 6);
    let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
    assert!(matches!(self_intersections(&m), Err(crate::mesh::MeshError::Limit(LimitError::Stopped(_)))));
}

#[test]
fn each_crossing_is_placed_on_both_faces() {
    // Two cubes overlapping in [0, 1]³: every crossing point lies on a face of each cube, so
    // on the boundary of both boxes.
    let a = Mesh::cuboid(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0));
    let b = Mesh::cuboid(v(0.0, 0.0, 0.0), v(2.0, 2.0, 2.0));
    let m = Mesh::combine(&[&a, &b]).unwrap();
    let found = crossings(&m).unwrap();
    assert_eq!(found.len(), 6);
    let on_box = |p: Vec3, lo: f64, hi: f64| {
        let c = [p.x, p.y, p.z];
        c.iter().all(|&x| (lo - 1e-12..=hi + 1e-12).contains(&x))
            && c.iter().any(|&x| (x - lo).abs() < 1e-12 || (x - hi).abs() < 1e-12)
    };
    for c in &found {
        assert!(on_box(c.at, -1.0, 1.0) && on_box(c.at, 0.0, 2.0), "{c:?}");
    }
    // A triangle through another: the point is where the first's edges pierce the second.
    let t = [v(0.5, 0.5, -1.0), v(0.5, 0.5, 1.0), v(0.6, 0.4, 1.0)];
    let p = super::triangle_pair::meeting_point(flat(), t);
    assert!(p.z.abs() < 1e-12 && (p.x - 0.5).abs() < 0.1 && (p.y - 0.5).abs() < 0.1, "{p:?}");
}
