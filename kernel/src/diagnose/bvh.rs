//! A bounding-volume hierarchy over boxes, for the pairs of boxes that overlap.
//!
//! Built top-down: each node's items are split at the median of their box centres along the
//! longest side of the centres' box (O(n log n)), down to leaves of at most [`LEAF`] items.
//! The overlapping pairs are found by descending the tree against itself (a node with itself:
//! both children with themselves and with each other; two nodes: the larger against the
//! children of the other), which costs O(n log n + k) for k overlapping pairs when boxes are
//! of similar size, as a mesh's triangles are. Boxes are compared exactly (closed boxes:
//! touching counts), so no pair whose sets meet is missed.

use crate::math::Vec3;

/// Items per leaf at most.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// For an inner node the index of its first child (the second follows it); for a leaf the
    /// start of its items in `order`.
    first: u32,
    /// 0 for an inner node; the number of items for a leaf.
    count: u32,
}

/// The tree: nodes (the root first) and the item ids in leaf order.
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

fn overlap(a_min: Vec3, a_max: Vec3, b_min: Vec3, b_max: Vec3) -> bool {
    a_min.x <= b_max.x
        && b_min.x <= a_max.x
        && a_min.y <= b_max.y
        && b_min.y <= a_max.y
        && a_min.z <= b_max.z
        && b_min.z <= a_max.z
}

impl Bvh {
    /// The tree over `boxes` (each `(min, max)`, finite).
    pub(crate) fn build(boxes: &[(Vec3, Vec3)]) -> Bvh {
        let n = boxes.len();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let centre = |i: u32| {
            let (lo, hi) = boxes[i as usize];
            (lo + hi) * 0.5
        };
        let mut nodes = Vec::with_capacity(2 * n / LEAF + 1);
        if n == 0 {
            return Bvh { nodes, order };
        }
        nodes.push(Node { min: Vec3::ZERO, max: Vec3::ZERO, first: 0, count: 0 });
        // (node, start, end) still to lay out.
        let mut stack = vec![(0usize, 0usize, n)];
        while let Some((node, start, end)) = stack.pop() {
            let items = &mut order[start..end];
            let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
            let (mut clo, mut chi) = (lo, hi);
            for &i in items.iter() {
                let (a, b) = boxes[i as usize];
                lo = lo.min(a);
                hi = hi.max(b);
                let c = centre(i);
                clo = clo.min(c);
                chi = chi.max(c);
            }
            nodes[node].min = lo;
            nodes[node].max = hi;
            if items.len() <= LEAF {
                nodes[node].first = start as u32;
                nodes[node].count = items.len() as u32;
                continue;
            }
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = items.len() / 2;
            items.select_nth_unstable_by(mid, |&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.cmp(&b)));
            let first = nodes.len();
            nodes[node].first = first as u32;
            nodes.push(Node { min: Vec3::ZERO, max: Vec3::ZERO, first: 0, count: 0 });
            nodes.push(Node { min: Vec3::ZERO, max: Vec3::ZERO, first: 0, count: 0 });
            stack.push((first, start, start + mid));
            stack.push((first + 1, start + mid, end));
        }
        Bvh { nodes, order }
    }

    /// Node pairs to descend from, about `want` of them (fewer for a small tree), which
    /// together cover every overlapping pair once: for splitting the work between threads.
    pub(crate) fn tasks(&self, want: usize) -> Vec<(u32, u32)> {
        if self.nodes.is_empty() {
            return Vec::new();
        }
        let mut tasks = vec![(0u32, 0u32)];
        // Expand the largest self-pairs first (breadth first) until there are enough.
        let mut i = 0;
        while tasks.len() < want && i < tasks.len() {
            let (a, b) = tasks[i];
            let na = self.nodes[a as usize];
            if a == b && na.count == 0 {
                let (l, r) = (na.first, na.first + 1);
                tasks[i] = (l, l);
                tasks.push((r, r));
                tasks.push((l, r));
            } else {
                i += 1;
            }
        }
        tasks
    }

    /// Calls `visit(i, j)` (`i ≠ j`) for every pair of items below the node pair `task` whose
    /// boxes overlap, each pair once; stops at the first error `visit` returns.
    pub(crate) fn overlapping_pairs<E>(
        &self,
        task: (u32, u32),
        boxes: &[(Vec3, Vec3)],
        visit: &mut impl FnMut(u32, u32) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut stack = vec![task];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (self.nodes[a as usize], self.nodes[b as usize]);
            if a == b {
                if na.count > 0 {
                    let items = &self.order[na.first as usize..(na.first + na.count) as usize];
                    for (k, &i) in items.iter().enumerate() {
                        for &j in &items[k + 1..] {
                            let ((il, ih), (jl, jh)) = (boxes[i as usize], boxes[j as usize]);
                            if overlap(il, ih, jl, jh) {
                                visit(i, j)?;
                            }
                        }
                    }
                } else {
                    let (l, r) = (na.first, na.first + 1);
                    stack.push((l, l));
                    stack.push((r, r));
                    stack.push((l, r));
                }
                continue;
            }
            if !overlap(na.min, na.max, nb.min, nb.max) {
                continue;
            }
            match (na.count > 0, nb.count > 0) {
                (true, true) => {
                    let ia = &self.order[na.first as usize..(na.first + na.count) as usize];
                    let ib = &self.order[nb.first as usize..(nb.first + nb.count) as usize];
                    for &i in ia {
                        for &j in ib {
                            let ((il, ih), (jl, jh)) = (boxes[i as usize], boxes[j as usize]);
                            if overlap(il, ih, jl, jh) {
                                visit(i, j)?;
                            }
                        }
                    }
                }
                (leaf_a, leaf_b) => {
                    // Descend the inner node, the larger one when both are.
                    let size = |n: Node| (n.max - n.min).max_element();
                    if leaf_b || (!leaf_a && size(na) >= size(nb)) {
                        stack.push((na.first, b));
                        stack.push((na.first + 1, b));
                    } else {
                        stack.push((a, nb.first));
                        stack.push((a, nb.first + 1));
                    }
                }
            }
        }
        Ok(())
    }
}
