// collider_placed_tests.rs — blocksmith patch (PATCHES.md, 20): a composed collider keeps its
// parts' trees shared and moves each query to them; it must find every leaf the one tree of
// patch 16 (`Collider::flattened`) finds, in the same order, and behave as that tree when
// moved or refitted.

use std::sync::Arc;

use super::*;

/// A tree over a row of `n` small boxes along x, spaced `step` apart, from `start`.
fn row(n: usize, start: Vec3, step: f64) -> Collider {
    let boxes: Vec<BBox> = (0..n)
        .map(|i| {
            let c = start + Vec3::new(i as f64 * step, 0.3 * (i % 3) as f64, 0.0);
            BBox::from_points(c, c + Vec3::new(0.7, 0.5, 0.9))
        })
        .collect();
    Collider::new(boxes, (0..n as u32).collect())
}

/// Every (query, leaf) pair a collider finds for `queries`, in the order found.
fn hits(c: &Collider, queries: &[BBox], self_collision: bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    c.collisions_with_boxes(queries, self_collision, |q, l| out.push((q, l)));
    out
}

/// Queries over and around the parts: small boxes on a grid, long thin ones, rays along z
/// (as the winding number casts), and boxes touching a part's padded box exactly.
fn queries() -> Vec<BBox> {
    let mut q = Vec::new();
    for i in 0..40 {
        for j in 0..6 {
            let c = Vec3::new(-3.0 + 1.37 * i as f64, -1.0 + 0.41 * j as f64, 0.2 * (i % 5) as f64);
            q.push(BBox::from_points(c, c + Vec3::new(0.3, 0.2, 0.4)));
        }
    }
    q.push(BBox::from_points(Vec3::new(-10.0, 0.1, 0.1), Vec3::new(100.0, 0.2, 0.2)));
    for i in 0..20 {
        let x = 0.35 + 2.5 * i as f64;
        q.push(BBox::from_points(Vec3::new(x, 0.25, f64::NEG_INFINITY), Vec3::new(x, 0.25, f64::INFINITY)));
    }
    q.push(BBox::from_points(Vec3::new(0.7 + 1e-3, 0.0, 0.0), Vec3::new(0.9, 0.1, 0.1)));
    q
}

/// Three copies of one tree (shared), one other tree, and a tree of one leaf, placed apart.
fn parts() -> Vec<(Arc<Collider>, Vec3, f64)> {
    let shared = Arc::new(row(9, Vec3::new(0.0, 0.0, 0.0), 1.1));
    let other = Arc::new(row(5, Vec3::new(0.0, 2.0, 0.0), 0.9));
    let single = Arc::new(row(1, Vec3::new(0.0, 0.0, 0.0), 1.0));
    vec![
        (Arc::clone(&shared), Vec3::new(0.0, 0.0, 0.0), 0.0),
        (Arc::clone(&shared), Vec3::new(12.5, 0.0, 0.0), 2e-9),
        (other, Vec3::new(3.0, 0.0, 0.0), 1e-12),
        (single, Vec3::new(-2.0, 0.0, 0.0), 2e-9),
        (shared, Vec3::new(30.0, -0.25, 0.5), 2e-9),
    ]
}

#[test]
fn a_composed_collider_finds_what_its_one_tree_finds() {
    let composed = Collider::compose(&parts()).expect("composed");
    let flat = composed.flattened();
    assert!(composed.placed.is_some() && flat.placed.is_none());
    assert_eq!(composed.num_leaves(), 9 + 9 + 5 + 1 + 9);
    assert_eq!(flat.num_leaves(), composed.num_leaves());
    let q = queries();
    let found = hits(&composed, &q, false);
    assert!(found.len() > 40, "the queries meet the parts: {}", found.len());
    assert_eq!(found, hits(&flat, &q, false));
    // Each leaf's own box finds itself (the flat tree's boxes are the moved leaves).
    let leaf_boxes: Vec<BBox> =
        (0..flat.num_leaves()).map(|l| flat.node_bbox[leaf_to_node(l as i32) as usize]).collect();
    let mine = hits(&composed, &leaf_boxes, true);
    assert_eq!(mine, hits(&flat, &leaf_boxes, true));
    assert!(mine.iter().all(|&(q, l)| q != l), "a leaf is not its own hit in a self-collision");
    let mut found_itself = vec![false; leaf_boxes.len()];
    composed.collisions_with_boxes(&leaf_boxes, false, |q, l| found_itself[q] |= q == l);
    assert!(found_itself.iter().all(|&f| f), "every leaf finds itself");
    // One query at a time, as the parallel callers ask.
    for (k, b) in q.iter().enumerate() {
        let (mut a, mut f) = (Vec::new(), Vec::new());
        composed.collisions_one(b, k, |q, l| a.push((q, l)));
        flat.collisions_one(b, k, |q, l| f.push((q, l)));
        assert_eq!(a, f, "query {k}");
    }
}

#[test]
fn a_composed_collider_moved_or_refitted_is_its_one_tree_moved_or_refitted() {
    let composed = Collider::compose(&parts()).unwrap();
    let flat = composed.flattened();
    let t = crate::linalg::mat4_to_mat3x4(crate::linalg::translation_matrix(Vec3::new(1.0, -2.0, 0.5)));
    let (mut a, mut b) = (composed.clone(), flat.clone());
    a.transform(&t);
    b.transform(&t);
    assert!(a.placed.is_none());
    assert_eq!(format!("{:?}", a.node_bbox), format!("{:?}", b.node_bbox));
    let boxes: Vec<BBox> = (0..flat.num_leaves())
        .map(|l| BBox::from_points(Vec3::splat(l as f64), Vec3::splat(l as f64 + 0.5)))
        .collect();
    let (mut a, mut b) = (composed.clone(), flat);
    a.update_boxes(boxes.clone());
    b.update_boxes(boxes);
    assert_eq!(format!("{:?}", a.node_bbox), format!("{:?}", b.node_bbox));
    assert_eq!(a.internal_children, b.internal_children);
}

#[test]
fn a_part_that_is_not_finite_or_absent_composes_to_none() {
    let mut p = parts();
    p[1].1 = Vec3::new(f64::NAN, 0.0, 0.0);
    assert!(Collider::compose(&p).is_none());
    let mut p = parts();
    p[2].0 = Arc::new(Collider::default());
    assert!(Collider::compose(&p).is_none());
    // One part: its own tree, moved; no parts kept.
    let one = Collider::compose(&parts()[1..2]).unwrap();
    assert!(one.placed.is_none());
    assert_eq!(one.num_leaves(), 9);
}
