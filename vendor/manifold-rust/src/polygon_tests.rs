use super::*;
use crate::linalg::Vec2;
use crate::types::PolyVert;

fn make_poly(coords: &[(f64, f64)]) -> SimplePolygonIdx {
    coords
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| PolyVert {
            pos: Vec2::new(x, y),
            idx: i as i32,
        })
        .collect()
}

#[test]
fn test_ccw_basic() {
    // CCW triangle
    assert_eq!(
        ccw(
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 1.0),
            1e-10
        ),
        1
    );
    // CW triangle
    assert_eq!(
        ccw(
            Vec2::new(0.0, 0.0),
            Vec2::new(0.5, 1.0),
            Vec2::new(1.0, 0.0),
            1e-10
        ),
        -1
    );
    // Colinear
    assert_eq!(
        ccw(
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(2.0, 0.0),
            1e-10
        ),
        0
    );
}

#[test]
fn test_triangle_ccw() {
    let poly = vec![make_poly(&[(0.0, 0.0), (1.0, 0.0), (0.5, 1.0)])];
    let tris = triangulate_idx(&poly, 1e-10, true);
    assert_eq!(tris.len(), 1);
    assert_eq!(tris[0], IVec3Out::new(0, 1, 2));
}

#[test]
fn test_square_ccw() {
    // Unit square, CCW
    let poly = vec![make_poly(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])];
    let tris = triangulate_idx(&poly, 1e-10, true);
    assert_eq!(tris.len(), 2);
    // Total triangles should cover the whole square
    for tri in &tris {
        assert!(tri.x >= 0 && tri.x < 4);
        assert!(tri.y >= 0 && tri.y < 4);
        assert!(tri.z >= 0 && tri.z < 4);
    }
}

#[test]
fn test_pentagon_ccw() {
    use std::f64::consts::PI;
    let n = 5usize;
    let coords: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            (a.cos(), a.sin())
        })
        .collect();
    let poly = vec![make_poly(&coords)];
    let tris = triangulate_idx(&poly, 1e-10, false);
    assert_eq!(tris.len(), n - 2);
}

#[test]
fn test_convex_fast_path() {
    use std::f64::consts::PI;
    let n = 8usize;
    let coords: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            (a.cos(), a.sin())
        })
        .collect();
    let poly = vec![make_poly(&coords)];
    // is_convex should return true -> triangulate_convex used
    assert!(is_convex(&poly, 1e-10));
    let tris = triangulate_idx(&poly, 1e-10, true);
    assert_eq!(tris.len(), n - 2);
}

#[test]
fn test_triangulate_unindexed() {
    let poly = vec![vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ]];
    let tris = triangulate(&poly, 1e-10, true);
    assert_eq!(tris.len(), 2);
}

#[test]
fn test_kd_tree_query() {
    let mut points: Vec<PolyVert> = (0..20)
        .map(|i| PolyVert {
            pos: Vec2::new(i as f64, (i % 5) as f64),
            idx: i,
        })
        .collect();
    build_two_d_tree(&mut points);

    let query_rect = Rect::from_points(Vec2::new(3.0, 0.0), Vec2::new(8.0, 3.0));
    let mut found = Vec::new();
    query_two_d_tree(&points, query_rect, |p| found.push(p.idx));
    // Points with x in [3,8] and y in [0,3]
    found.sort();
    // i=3: x=3, y=3 yes; i=4: x=4, y=4 no; i=5: x=5, y=0 yes; i=6: x=6, y=1 yes;
    // i=7: x=7, y=2 yes; i=8: x=8, y=3 yes
    // (y = i%5: 3->3, 5->0, 6->1, 7->2, 8->3)
    assert!(found.contains(&3));
    assert!(found.contains(&5));
    assert!(found.contains(&6));
    assert!(found.contains(&7));
    assert!(found.contains(&8));
    assert!(!found.contains(&4)); // y=4 outside
}

/// The triangulation's half-edges paired as C++ pairs them, with a vector of unpaired
/// half-edges per directed edge (the code before blocksmith patch 29).
fn paired_by_vectors(polys: &PolygonsIdx, triangles: &[IVec3]) -> Vec<Halfedge> {
    let mut halfedges: Vec<Halfedge> = Vec::new();
    let mut unpaired: std::collections::HashMap<(i32, i32), Vec<i32>> = std::collections::HashMap::new();
    let mut add = |start: i32, end: i32| {
        let idx = halfedges.len() as i32;
        let mut data = Halfedge { start_vert: start, end_vert: end, paired_halfedge: -1, prop_vert: -1 };
        if let Some(reverse) = unpaired.get_mut(&(end, start)) {
            if let Some(pair) = reverse.pop() {
                data.paired_halfedge = pair;
                halfedges[pair as usize].paired_halfedge = idx;
                if reverse.is_empty() {
                    unpaired.remove(&(end, start));
                }
                halfedges.push(data);
                return;
            }
        }
        unpaired.entry((start, end)).or_default().push(idx);
        halfedges.push(data);
    };
    for poly in polys {
        for i in 0..poly.len() {
            add(poly[(i + 1) % poly.len()].idx, poly[i].idx);
        }
    }
    for t in triangles {
        add(t.x, t.y);
        add(t.y, t.z);
        add(t.z, t.x);
    }
    halfedges
}

/// The pairing by stacks of newest half-edges (blocksmith patch 29) pairs exactly as the vectors
/// did: random faces with holes, and the same faces with a contour given twice or three times
/// (so a directed edge has several unpaired half-edges and the order they pair in shows).
#[test]
fn halfedges_pair_as_with_a_vector_per_edge() {
    let mut seed = 0x2f0b_3c5a_91d7_e643u64;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..30 {
        let mut polys: Vec<Vec<Vec2>> = vec![vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, 10.0),
            Vec2::new(0.0, 10.0),
        ]];
        for k in 0..(case % 6) {
            let (cx, cy) = (1.5 + 1.6 * k as f64, 2.0 + 6.0 * random());
            let n = 3 + (random() * 9.0) as usize;
            let phase = random();
            polys.push(
                (0..n)
                    .rev()
                    .map(|i| {
                        let a = phase + std::f64::consts::TAU * i as f64 / n as f64;
                        Vec2::new(cx + 0.6 * a.cos(), cy + 0.6 * a.sin())
                    })
                    .collect(),
            );
        }
        let repeats = 1 + case % 3;
        let mut idx = 0;
        let mut indexed: PolygonsIdx = polys
            .iter()
            .map(|p| {
                p.iter()
                    .map(|&pos| {
                        idx += 1;
                        PolyVert { pos, idx: idx - 1 }
                    })
                    .collect()
            })
            .collect();
        for _ in 1..repeats {
            indexed.push(indexed[0].clone());
        }
        let paired = triangulate_idx_halfedges(&indexed, 1e-9, true);
        let triangles = triangulate_idx(&indexed, 1e-9, true);
        let expected = paired_by_vectors(&indexed, &triangles);
        let key = |h: &Halfedge| (h.start_vert, h.end_vert, h.paired_halfedge);
        assert_eq!(
            paired.halfedges.iter().map(key).collect::<Vec<_>>(),
            expected.iter().map(key).collect::<Vec<_>>(),
            "case {case}"
        );
    }
}
