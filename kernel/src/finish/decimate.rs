//! Quadric-error decimation (Garland and Heckbert, "Surface simplification using quadric error
//! metrics", SIGGRAPH 1997): every vertex carries the sum of the squared-distance quadrics of
//! the planes of its input triangles; the edge whose collapse adds the least error is collapsed
//! first (its vertex placed where the summed quadric is smallest, §4), and the kept vertex takes
//! both quadrics. Collapses that would fold a triangle or break the 2-manifold (the link
//! condition) are skipped. The queue is ordered by error over the quality of the worst
//! triangle a collapse leaves (below 0.3, as MeshLab's quadric collapse weighs it), checked
//! again when a collapse comes up, since collapses around it may have changed its triangles:
//! without that check, slivers of 0.3° survived on a scan-like surface and the largest
//! Hausdorff distance to the input was 1.8× MeshLab's; with it, 7.5° and 1.08× (the
//! `finish` bench and `finish_peer.py`). Crease-tagged edges and the borders between parts (colours) are
//! features: a collapse slides along them and never moves their corners, and their planes are
//! held by an extra perpendicular quadric (§6, as for boundaries).
//!
//! O(n log n) for n triangles: one heap of candidate collapses, refreshed around each collapse.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::limits;
use crate::math::{fmt_num, Mat3, Vec3};
use crate::mesh::Mesh;

use super::tri_mesh::{next, prev, TriMesh};
use super::FinishError;

/// How far [`decimate`] goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DecimateTarget {
    /// Keep this share of the triangles (0 < ratio ≤ 1).
    Ratio(f64),
    /// Keep this many triangles (at least 4).
    Triangles(usize),
    /// Collapse while the next collapse's error (the root of its quadric: about the distance
    /// from the input's planes) stays below this.
    Error(f64),
}

/// What [`decimate`] is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecimateOptions {
    /// How far to go.
    pub target: DecimateTarget,
}

/// What [`decimate`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct DecimateReport {
    /// Triangles before and after.
    pub triangles_before: usize,
    pub triangles_after: usize,
    /// The largest error of a collapse made (the root of its quadric).
    pub max_error: f64,
}

/// A symmetric 4×4 quadric: the upper triangle of [[A, b], [bᵀ, c]].
#[derive(Clone, Copy, Debug, Default)]
struct Quadric([f64; 10]);

impl Quadric {
    /// The squared distance to the plane n·x + d = 0 (n unit), times `w`.
    fn plane(n: Vec3, d: f64, w: f64) -> Quadric {
        let (a, b, c) = (n.x, n.y, n.z);
        Quadric([a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d].map(|x| x * w))
    }

    fn add(&mut self, o: &Quadric) {
        for (x, y) in self.0.iter_mut().zip(o.0) {
            *x += y;
        }
    }

    fn eval(&self, p: Vec3) -> f64 {
        let q = &self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        q[0] * x * x
            + 2.0 * q[1] * x * y
            + 2.0 * q[2] * x * z
            + 2.0 * q[3] * x
            + q[4] * y * y
            + 2.0 * q[5] * y * z
            + 2.0 * q[6] * y
            + q[7] * z * z
            + 2.0 * q[8] * z
            + q[9]
    }

    /// The point where the quadric is least, when A is well conditioned.
    fn minimum(&self) -> Option<Vec3> {
        let q = &self.0;
        let a = Mat3::from_cols(Vec3::new(q[0], q[1], q[2]), Vec3::new(q[1], q[4], q[5]), Vec3::new(q[2], q[5], q[7]));
        let det = a.determinant();
        let scale = q[0].abs() + q[4].abs() + q[7].abs();
        if !det.is_finite() || det.abs() <= 1e-12 * scale.powi(3) {
            return None;
        }
        let p = a.inverse() * -Vec3::new(q[3], q[6], q[8]);
        p.is_finite().then_some(p)
    }
}

/// How many collapses a decimation makes between two reports of its progress.
const REPORT_EVERY: usize = 1024;

/// `mesh` with its triangles collapsed by quadric error to `options.target`, and a report.
/// Tells a listener ([`limits::listen`]) the triangles removed of those to remove.
///
/// # Errors
/// [`FinishError::BadOption`] for a ratio outside (0, 1], fewer than 4 triangles, or an error
/// that is not finite and 0 or more; [`FinishError::NotClosed`] for a mesh with a boundary; a
/// stop of the cancellation token.
pub fn decimate(mesh: &Mesh, options: DecimateOptions) -> Result<(Mesh, DecimateReport), FinishError> {
    let before = mesh.triangle_count();
    let (target, max_error) = match options.target {
        DecimateTarget::Ratio(r) if r > 0.0 && r <= 1.0 => (((before as f64) * r).round() as usize, f64::INFINITY),
        DecimateTarget::Ratio(r) => return Err(FinishError::bad("ratio", r, "above 0 and at most 1")),
        DecimateTarget::Triangles(n) if n >= 4 => (n, f64::INFINITY),
        DecimateTarget::Triangles(n) => return Err(FinishError::bad("triangles", n as f64, "at least 4")),
        DecimateTarget::Error(e) if e.is_finite() && e >= 0.0 => (4, e),
        DecimateTarget::Error(e) => return Err(FinishError::bad("error", e, "a finite number of 0 or more")),
    };
    if !mesh.is_closed() {
        let boundary_edges =
            mesh.edges().filter(|&h| mesh.is_boundary_halfedge(h) || mesh.is_boundary_halfedge(mesh.twin(h))).count();
        return Err(FinishError::NotClosed { what: "decimate", boundary_edges });
    }
    let (t, sources) = mesh.triangulate_with_sources()?;
    let part = |f: u32| mesh.face_part_ids().map(|ids| ids[sources[f as usize] as usize]);
    let is_feature = |h: u32| t.is_crease(h) || part(t.face(h)) != part(t.face(t.twin(h)));
    let mut w = TriMesh::new(&t, &sources, is_feature);
    let quadrics = initial_quadrics(&w);
    let least_cost = 1e-12 * w.mean_edge_length().powi(2);
    let mut d = Decimator {
        w: &mut w,
        q: quadrics,
        least_cost,
        stamp: Vec::new(),
        heap: BinaryHeap::new(),
        ring_a: Vec::new(),
        ring_b: Vec::new(),
    };
    d.stamp = vec![0; d.w.pos.len()];
    for h in 0..d.w.tv.len() as u32 {
        limits::poll_at(h as usize)?;
        if h < d.w.twin[h as usize] {
            d.push(h);
        }
    }
    let mut worst = 0.0f64;
    let mut step = 0usize;
    // Progress: the triangles removed of the `before − target` to remove (an `error` target
    // counts down to 4 triangles and may stop sooner; the whole is then reported at the end).
    let work = limits::Work::start(before.saturating_sub(target) as u64);
    while d.w.alive_tris > target {
        step += 1;
        limits::poll_at(step)?;
        if step.is_multiple_of(REPORT_EVERY) {
            work.set(before.saturating_sub(d.w.alive_tris) as u64);
        }
        let Some((Reverse(queued), h, sa, sb)) = d.heap.pop() else { break };
        if !d.current(h, sa, sb) {
            continue;
        }
        if let Some(error) = d.apply(h, f64::from_bits(queued), max_error) {
            worst = worst.max(error);
        }
    }
    work.finish();
    let (mut out, parents) = w.to_mesh(&|_| true)?;
    out.inherit_parts(mesh, &parents)?;
    let report = DecimateReport { triangles_before: before, triangles_after: out.face_count(), max_error: worst };
    Ok((out, report))
}

fn initial_quadrics(w: &TriMesh) -> Vec<Quadric> {
    let mut q = vec![Quadric::default(); w.pos.len()];
    for t in 0..w.tri_alive.len() as u32 {
        let [a, b, c] = w.corners(t);
        let n = (b - a).cross(c - a);
        let Some(n) = n.try_normalize() else { continue };
        let plane = Quadric::plane(n, -n.dot(a), 1.0);
        for i in 0..3 {
            q[w.tv[(3 * t + i) as usize] as usize].add(&plane);
        }
        // Features hold their place: a heavy plane through the edge, perpendicular to the face.
        for i in 0..3 {
            let h = 3 * t + i;
            if w.feature[h as usize] {
                let (p, r) = (w.pos[w.orig(h) as usize], w.pos[w.dest(h) as usize]);
                if let Some(m) = (r - p).cross(n).try_normalize() {
                    let hold = Quadric::plane(m, -m.dot(p), 1e3);
                    q[w.orig(h) as usize].add(&hold);
                    q[w.dest(h) as usize].add(&hold);
                }
            }
        }
    }
    q
}

/// Below this quality (1 for an equilateral triangle, see [`TriMesh::worst_quality_after`]) a
/// collapse's priority is raised in proportion: MeshLab's default threshold.
const QUALITY_FLOOR: f64 = 0.3;

struct Decimator<'a> {
    w: &'a mut TriMesh,
    q: Vec<Quadric>,
    /// The least cost a priority counts: the square of a millionth of the mean edge length,
    /// far below any curvature's error.
    least_cost: f64,
    stamp: Vec<u32>,
    /// (priority bits, half-edge whose origin goes, stamps of its two ends).
    heap: BinaryHeap<(Reverse<u64>, u32, u32, u32)>,
    ring_a: Vec<u32>,
    ring_b: Vec<u32>,
}

impl Decimator<'_> {
    /// Where the collapse of `h` (its origin removed) puts the kept vertex and what it costs,
    /// or `None` when the features forbid it.
    fn plan(&self, h: u32) -> Option<(Vec3, f64)> {
        let w = &*self.w;
        let (a, b) = (w.orig(h) as usize, w.dest(h) as usize);
        let g = w.twin[h as usize];
        let side = |e: u32| w.feature[next(e) as usize] && w.feature[prev(e) as usize];
        if side(h) || side(g) {
            return None;
        }
        let mut q = self.q[a];
        q.add(&self.q[b]);
        let p = match (w.feature_degree[a], w.feature_degree[b]) {
            (0, 0) => {
                let mid = (w.pos[a] + w.pos[b]) * 0.5;
                let mut best =
                    [w.pos[a], w.pos[b], mid].into_iter().min_by(|x, y| q.eval(*x).total_cmp(&q.eval(*y)))?;
                if let Some(m) = q.minimum() {
                    // Only within reach of the edge: a far minimum of a flat region is noise.
                    if m.distance(mid) <= 2.0 * w.pos[a].distance(w.pos[b]) && q.eval(m) <= q.eval(best) {
                        best = m;
                    }
                }
                best
            }
            (0, _) => w.pos[b],
            (2, _) if w.feature[h as usize] => w.pos[b],
            _ => return None,
        };
        Some((p, q.eval(p).max(0.0)))
    }

    /// The order in which a collapse of `h` to `p` costing `cost` is made: the cost divided by
    /// the quality of the worst triangle it leaves, when that is below [`QUALITY_FLOOR`] (as
    /// MeshLab's quadric collapse weighs quality): of two collapses of like cost the one that
    /// leaves no sliver goes first, and a sliver's collapse waits until it is the cheap one.
    /// Costs are floored at [`Decimator::least_cost`] so that on flat regions, where every
    /// collapse costs nothing, quality alone orders them.
    fn priority(&self, h: u32, p: Vec3, cost: f64) -> f64 {
        let quality = self.w.worst_quality_after(h, p).clamp(1e-6, QUALITY_FLOOR);
        cost.max(self.least_cost) * QUALITY_FLOOR / quality
    }

    /// Queues the cheaper allowed direction of the edge of `h`.
    fn push(&mut self, h: u32) {
        let g = self.w.twin[h as usize];
        let best = [h, g]
            .into_iter()
            .filter_map(|e| self.plan(e).map(|(p, c)| (self.priority(e, p, c), e)))
            .min_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((cost, e)) = best {
            let (a, b) = (self.w.orig(e) as usize, self.w.dest(e) as usize);
            self.heap.push((Reverse(cost.to_bits()), e, self.stamp[a], self.stamp[b]));
        }
    }

    /// Whether a queued collapse still describes the mesh.
    fn current(&self, h: u32, sa: u32, sb: u32) -> bool {
        let w = &*self.w;
        w.tri_alive[(h / 3) as usize] && {
            let (a, b) = (w.orig(h) as usize, w.dest(h) as usize);
            w.vert_alive[a] && w.vert_alive[b] && self.stamp[a] == sa && self.stamp[b] == sb
        }
    }

    /// Collapses `h` if it is still allowed and its error (the root of its quadric) is at most
    /// `max_error`; requeues the edges around the kept vertex. The error made, if it collapsed.
    ///
    /// A collapse was queued at the priority its neighbourhood gave then; collapses around it
    /// since (which do not touch its two ends, so leave its entry current) can have made the
    /// triangles it would leave worse. If its priority now is above `queued`, it is queued again
    /// at that priority instead.
    fn apply(&mut self, h: u32, queued: f64, max_error: f64) -> Option<f64> {
        let (p, cost) = self.plan(h)?;
        let error = cost.sqrt();
        if error > max_error {
            return None;
        }
        let now = self.priority(h, p, cost);
        if now > queued * (1.0 + 1e-9) {
            let (a, b) = (self.w.orig(h) as usize, self.w.dest(h) as usize);
            self.heap.push((Reverse(now.to_bits()), h, self.stamp[a], self.stamp[b]));
            return None;
        }
        let (a, b) = (self.w.orig(h), self.w.dest(h));
        self.w.ring(a, &mut self.ring_a);
        if !self.w.link_ok(h, &self.ring_a, &mut self.ring_b) {
            return None;
        }
        let moved_b = (self.w.pos[b as usize] != p).then_some((self.ring_b.as_slice(), p));
        if !self.w.keeps_orientation(h, &self.ring_a, p, moved_b) {
            return None;
        }
        let ring_a = std::mem::take(&mut self.ring_a);
        self.w.collapse(h, p, &ring_a);
        self.ring_a = ring_a;
        let qa = self.q[a as usize];
        self.q[b as usize].add(&qa);
        self.stamp[a as usize] += 1;
        self.stamp[b as usize] += 1;
        // Only the edges at b changed cost (b's quadric and place); b's new stamp voids their
        // old entries.
        let mut ring = std::mem::take(&mut self.ring_b);
        self.w.ring(b, &mut ring);
        for &o in &ring {
            self.push(o);
        }
        self.ring_b = ring;
        Some(error)
    }
}

impl std::fmt::Display for DecimateReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} → {} triangles, largest error {}",
            self.triangles_before,
            self.triangles_after,
            fmt_num(self.max_error)
        )
    }
}

#[cfg(test)]
#[path = "tests_decimate.rs"]
mod tests;
