//! A bounding-volume hierarchy over quads for nearest ray hits: the acceleration structure of
//! the connection search (seed 000 §2.2), so that casting one ray per sub-face of N blocks costs
//! about O(N log N) instead of O(N²).
//!
//! Built by median splits along the longest axis of the quads' centres; a leaf holds at most
//! [`LEAF_SIZE`] quads. A quad (possibly non-planar) is tested as the four triangles fanned
//! about its centroid, which is the centre of its bilinear patch: two sub-faces with the same
//! corners, listed in any order, are then the same surface through the same centre, so the ray
//! from one centre meets the other at t = 0 however twisted the quad (a split along one diagonal
//! would depend on the corner order and miss a twisted twin by its warp).

use crate::math::Vec3;

const LEAF_SIZE: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf (`count > 0`): its items are `items[start..start + count]`. Inner (`count == 0`): the
    /// left child is the next node, the right child is `right`.
    start: u32,
    count: u32,
    right: u32,
}

/// Quads in a hierarchy of boxes.
#[derive(Clone, Debug)]
pub(super) struct QuadBvh {
    quads: Vec<[Vec3; 4]>,
    items: Vec<u32>,
    nodes: Vec<Node>,
}

impl QuadBvh {
    /// Builds the hierarchy over `quads` (O(n log n)).
    pub(super) fn new(quads: Vec<[Vec3; 4]>) -> QuadBvh {
        let mut bvh = QuadBvh { items: (0..quads.len() as u32).collect(), quads, nodes: Vec::new() };
        if !bvh.quads.is_empty() {
            let n = bvh.items.len();
            bvh.build(0, n);
        }
        bvh
    }

    fn centre(&self, i: u32) -> Vec3 {
        let q = &self.quads[i as usize];
        (q[0] + q[1] + q[2] + q[3]) * 0.25
    }

    /// Builds the node for `items[start..end]`, returning its index.
    fn build(&mut self, start: usize, end: usize) -> u32 {
        let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &i in &self.items[start..end] {
            for p in &self.quads[i as usize] {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            let c = self.centre(i);
            clo = clo.min(c);
            chi = chi.max(c);
        }
        // Pad flat boxes so that slab tests of rays in their plane stay robust.
        let pad = (hi - lo).max_element() * 1e-9 + 1e-300;
        let me = self.nodes.len() as u32;
        self.nodes.push(Node {
            lo: lo - Vec3::splat(pad),
            hi: hi + Vec3::splat(pad),
            start: start as u32,
            count: (end - start) as u32,
            right: 0,
        });
        if end - start > LEAF_SIZE {
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = (start + end) / 2;
            let quads = &self.quads;
            let key = |i: &u32| {
                let q = &quads[*i as usize];
                (q[0][axis] + q[1][axis] + q[2][axis] + q[3][axis]) * 0.25
            };
            self.items[start..end].select_nth_unstable_by(mid - start, |a, b| key(a).total_cmp(&key(b)));
            self.build(start, mid);
            let right = self.build(mid, end);
            let node = &mut self.nodes[me as usize];
            node.count = 0;
            node.right = right;
        }
        me
    }

    /// The quad whose hit along `origin + t·dir` has the smallest |t| with `t ∈ [-back, reach]`,
    /// among the quads `accept` lets through: `(quad, t)`.
    pub(super) fn nearest(
        &self,
        origin: Vec3,
        dir: Vec3,
        back: f64,
        reach: f64,
        accept: impl Fn(u32) -> bool,
    ) -> Option<(u32, f64)> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best: Option<(u32, f64)> = None;
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n as usize];
            let (lo, hi) = best.map_or((-back, reach), |(_, t)| (-t.abs().min(back), t.abs().min(reach)));
            let Some((t0, t1)) = slab(node.lo, node.hi, origin, dir) else { continue };
            // The box's parameter interval must meet [lo, hi].
            if t1 < lo || t0 > hi {
                continue;
            }
            if node.count == 0 {
                stack.push(node.right);
                stack.push(n + 1);
                continue;
            }
            for &i in &self.items[node.start as usize..(node.start + node.count) as usize] {
                if !accept(i) {
                    continue;
                }
                if let Some(t) = ray_quad(&self.quads[i as usize], origin, dir) {
                    let in_range = (-back..=reach).contains(&t);
                    if in_range && best.is_none_or(|(bi, b)| t.abs() < b.abs() || (t.abs() == b.abs() && i < bi)) {
                        best = Some((i, t));
                    }
                }
            }
        }
        best
    }
}

/// The parameter interval of the line `origin + t·dir` inside the box, if any.
fn slab(lo: Vec3, hi: Vec3, origin: Vec3, dir: Vec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        let (o, d) = (origin[a], dir[a]);
        if d.abs() < 1e-300 {
            if o < lo[a] || o > hi[a] {
                return None;
            }
            continue;
        }
        let (mut ta, mut tb) = ((lo[a] - o) / d, (hi[a] - o) / d);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        t0 = t0.max(ta);
        t1 = t1.min(tb);
        if t0 > t1 {
            return None;
        }
    }
    Some((t0, t1))
}

/// The line parameter where `origin + t·dir` crosses the quad (either side) as four triangles
/// about its centroid, the one of smallest |t| if it crosses several.
fn ray_quad(q: &[Vec3; 4], origin: Vec3, dir: Vec3) -> Option<f64> {
    let c = (q[0] + q[1] + q[2] + q[3]) * 0.25;
    (0..4).filter_map(|k| ray_triangle(q[k], q[(k + 1) % 4], c, origin, dir)).min_by(|x, y| x.abs().total_cmp(&y.abs()))
}

/// Möller–Trumbore, two-sided, with a small tolerance so that hits on shared edges count.
fn ray_triangle(p0: Vec3, p1: Vec3, p2: Vec3, origin: Vec3, dir: Vec3) -> Option<f64> {
    const EPS: f64 = 1e-9;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - p0;
    let u = s.dot(pv) * inv;
    if !(-EPS..=1.0 + EPS).contains(&u) {
        return None;
    }
    let qv = s.cross(e1);
    let v = dir.dot(qv) * inv;
    if v < -EPS || u + v > 1.0 + EPS {
        return None;
    }
    Some(e2.dot(qv) * inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(z: f64, x: f64) -> [Vec3; 4] {
        [Vec3::new(x, 0.0, z), Vec3::new(x + 1.0, 0.0, z), Vec3::new(x + 1.0, 1.0, z), Vec3::new(x, 1.0, z)]
    }

    #[test]
    fn nearest_hit_matches_brute_force() {
        // A 10 × 10 × 5 stack of unit squares; rays straight up and down from assorted points.
        let mut quads = Vec::new();
        for k in 0..5 {
            for i in 0..100 {
                quads.push(square(f64::from(k), f64::from(i)));
            }
        }
        let bvh = QuadBvh::new(quads.clone());
        for i in 0..100 {
            let o = Vec3::new(f64::from(i) + 0.3, 0.6, 2.4);
            let (q, t) = bvh.nearest(o, Vec3::Z, 10.0, 10.0, |_| true).unwrap();
            // The nearest level is z = 2 (|t| = 0.4, below), the square under x = i.
            assert_eq!(q as usize, 2 * 100 + i as usize);
            assert!((t + 0.4).abs() < 1e-12, "{t}");
            // Forbidding level 2 leaves z = 3 at t = 0.6.
            let (q, t) = bvh.nearest(o, Vec3::Z, 10.0, 10.0, |j| j / 100 != 2).unwrap();
            assert_eq!(q as usize, 300 + i as usize);
            assert!((t - 0.6).abs() < 1e-12);
            // Nothing within reach 0.1; forward only, z = 3 at t = 0.6.
            assert!(bvh.nearest(o, Vec3::Z, 0.1, 0.1, |_| true).is_none());
            let (q, _) = bvh.nearest(o, Vec3::Z, 0.0, 10.0, |_| true).unwrap();
            assert_eq!(q as usize, 300 + i as usize);
        }
    }
}
