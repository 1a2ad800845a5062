// EarClip keyhole index — blocksmith patch (PATCHES.md, 28)
//
// Not in C++, and speed only. `cut_keyhole` and `find_closer_bridge` (polygon_earclip_keyhole.rs)
// walk every outer ring once per hole, so a face with h holes of k verts each costs O(h^2 k): a
// perforated plate of 40 x 40 holes spent 30 % of its boolean there. Each walk is a fold over
// the ring's verts in walk order: a vert that passes tests of its own (the connector-free tests)
// and beats the connector so far becomes the connector. This index finds the verts that can pass
// the connector-free tests without walking, and the searches then fold over those alone, in any
// order, keeping the result only when it is the same in every order: when one candidate beats
// every other candidate (and the connector it starts from) and none beats it. Then the walk,
// whatever its order, takes it when it meets it (the connector it holds is the start or another
// candidate, which it beats) and keeps it (nothing beats it), and a vert that is not a candidate
// never changes the connector. Otherwise (ties, a degenerate ring, a candidate near the hole's
// start, a wide wedge, numbers out of range) the search walks as before. Bridges and triangles
// are therefore the walk's, bit for bit; `ear_clip_with_the_keyhole_index_is_the_walk` compares
// the two on random plates.
//
// The index holds, per row of a uniform grid over the polygons' box, the verts whose edge (vert
// to its right neighbour) spans the row when it was linked (edges are registered again whenever
// `link` changes one; a stale entry is re-read through the current links), and per cell, the
// verts placed in it; and for each vert, the outer ring it belongs to (holes join their ring at
// `join_polygons`).

use crate::linalg::Vec2;
use crate::types::Rect;

use super::super::{dot2d, INVALID};

/// No outer ring (a hole not yet joined, or a polygon that is no outer ring).
const NO_RING: u32 = u32::MAX;

/// The fewest holes for which the keyhole searches use the index.
pub(super) const KEYHOLE_INDEX_MIN_HOLES: usize = 8;

pub(super) struct KeyholeIndex {
    origin: Vec2,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Per row: verts whose edge spanned the row when it was registered.
    row_edges: Vec<Vec<u32>>,
    /// Per cell (row-major): verts placed in it.
    cell_verts: Vec<Vec<u32>>,
    /// Per vert: the `outers` index of its ring, or `NO_RING`.
    pub(super) ring_of: Vec<u32>,
    /// The margin by which an edge's or a vert's rows and cells are widened.
    pub(super) margin: f64,
    /// Last query's mark per vert, so a query meets each vert once.
    seen: Vec<u32>,
    query: u32,
}

impl KeyholeIndex {
    /// An empty index over `bbox`, for about `verts` verts, with `margin` around every entry;
    /// `None` when the box is not finite or degenerate.
    pub(super) fn new(bbox: Rect, verts: usize, margin: f64) -> Option<Self> {
        let size = bbox.max - bbox.min;
        let finite = [bbox.min.x, bbox.min.y, bbox.max.x, bbox.max.y, margin].iter().all(|c| c.is_finite());
        if !finite || !(size.x > 0.0 && size.y > 0.0) {
            return None;
        }
        // About four verts a cell, cells no smaller than four margins (so a vert is placed in
        // at most four), and no more cells than half the verts and 16 (a long thin box).
        let cells = (verts / 4).max(1) as f64;
        let mut cell = (size.x * size.y / cells).sqrt().max(size.x.max(size.y) / 4096.0).max(4.0 * margin);
        let (cols, rows) = loop {
            let (cols, rows) = ((size.x / cell) as usize + 1, (size.y / cell) as usize + 1);
            if cols * rows <= verts / 2 + 16 {
                break (cols, rows);
            }
            cell *= 2.0;
        };
        Some(KeyholeIndex {
            origin: bbox.min,
            cell,
            cols,
            rows,
            row_edges: vec![Vec::new(); rows],
            cell_verts: vec![Vec::new(); rows * cols],
            ring_of: Vec::with_capacity(verts),
            margin,
            seen: Vec::with_capacity(verts),
            query: 0,
        })
    }

    fn row(&self, y: f64) -> usize {
        (((y - self.origin.y) / self.cell).max(0.0) as usize).min(self.rows - 1)
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.origin.x) / self.cell).max(0.0) as usize).min(self.cols - 1)
    }

    /// Makes room for vert `v` (a new vert gets no ring yet).
    pub(super) fn grow(&mut self, v: usize) {
        if self.ring_of.len() <= v {
            self.ring_of.resize(v + 1, NO_RING);
            self.seen.resize(v + 1, 0);
        }
    }

    /// Registers vert `v` at `pos`, in every cell its margin reaches.
    pub(super) fn place(&mut self, v: usize, pos: Vec2) {
        self.grow(v);
        let m = self.margin;
        for r in self.row(pos.y - m)..=self.row(pos.y + m) {
            for c in self.col(pos.x - m)..=self.col(pos.x + m) {
                self.cell_verts[r * self.cols + c].push(v as u32);
            }
        }
    }

    /// Registers the edge from `v` at `from` to `to`, in every row its y range (and margin) reaches.
    pub(super) fn link(&mut self, v: usize, from: Vec2, to: Vec2) {
        self.grow(v);
        let m = self.margin;
        for r in self.row(from.y.min(to.y) - m)..=self.row(from.y.max(to.y) + m) {
            self.row_edges[r].push(v as u32);
        }
    }

    fn next_query(&mut self) {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.seen.iter_mut().for_each(|s| *s = 0);
            self.query = 1;
        }
    }

    /// Every vert whose edge was registered in a row that `[y0, y1]` reaches, each once.
    pub(super) fn edges_across(&mut self, y0: f64, y1: f64, out: &mut Vec<usize>) {
        self.next_query();
        for r in self.row(y0)..=self.row(y1) {
            for &v in &self.row_edges[r] {
                if self.seen[v as usize] != self.query {
                    self.seen[v as usize] = self.query;
                    out.push(v as usize);
                }
            }
        }
    }

    /// Every vert placed in the cells of the columns from `x0` to `x1`, in each column the rows
    /// from `y0` to `y1` that `rows(column's x0, column's x1)` gives, each vert once.
    pub(super) fn verts_in(
        &mut self,
        x0: f64,
        x1: f64,
        mut rows: impl FnMut(f64, f64) -> (f64, f64),
        out: &mut Vec<usize>,
    ) {
        self.next_query();
        for c in self.col(x0)..=self.col(x1) {
            let (cx0, cx1) = (self.origin.x + c as f64 * self.cell, self.origin.x + (c + 1) as f64 * self.cell);
            let (y0, y1) = rows(cx0.max(x0), cx1.min(x1).max(cx0.max(x0)));
            if !(y0 <= y1) {
                continue;
            }
            for r in self.row(y0)..=self.row(y1) {
                for &v in &self.cell_verts[r * self.cols + c] {
                    if self.seen[v as usize] != self.query {
                        self.seen[v as usize] = self.query;
                        out.push(v as usize);
                    }
                }
            }
        }
    }

    /// The right edge of the grid's box.
    pub(super) fn max_x(&self) -> f64 {
        self.origin.x + self.cols as f64 * self.cell
    }
}

/// The fewest verts from which a keyhole search's candidate may be taken without walking: a
/// candidate nearer the hole's start than this many epsilons sends the search to the walk.
const NEAR_START_EPSILONS: f64 = 1e4;

/// The angle (radians) the closer-bridge search's wedge is widened by.
const WEDGE_SLACK: f64 = 1e-3;

/// The angle of `p` seen from `start`, from the ray towards +x, turning towards `above`'s side.
fn angle_from_ray(start: Vec2, above: f64, p: Vec2) -> f64 {
    (above * (p.y - start.y)).atan2(p.x - start.x)
}

impl super::EarClip {
    /// The index over the polygons as they stand before keyholing: every vert placed, every
    /// edge registered, the outer rings' verts marked. `None` (the searches walk) when the
    /// epsilon is not positive or a position or the box is not finite.
    pub(super) fn new_keyhole_index(&self) -> Option<KeyholeIndex> {
        let eps = self.epsilon;
        let scale = [self.bbox.min.x, self.bbox.min.y, self.bbox.max.x, self.bbox.max.y]
            .iter()
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let all_finite = self.polygon.iter().all(|v| v.pos.x.is_finite() && v.pos.y.is_finite());
        // Below this epsilon, or beyond these magnitudes, the searches' bounds are not argued.
        if !(eps > 1e-20 * scale && eps.is_finite() && scale < 1e60 && scale > 1e-60) || !all_finite {
            return None;
        }
        let margin = 4.0 * eps + 1e-9 * scale;
        let mut index = KeyholeIndex::new(self.bbox, self.polygon.len(), margin)?;
        for (v, vert) in self.polygon.iter().enumerate() {
            index.place(v, vert.pos);
            if vert.right != INVALID {
                index.link(v, vert.pos, self.polygon[vert.right].pos);
            }
        }
        for (k, &outer) in self.outers.iter().enumerate() {
            // A ring the walk finds degenerate gives nothing, so its verts keep no ring.
            if let Some(verts) = self.loop_verts(outer) {
                for v in verts {
                    index.ring_of[v] = k as u32;
                }
            }
        }
        Some(index)
    }

    /// Whether `v`'s ring has fewer than three verts (a ring the walks skip).
    fn in_degenerate_ring(&self, v: usize) -> bool {
        let right = self.polygon[v].right;
        right == self.polygon[v].left || self.polygon[right].right == v
    }

    /// `cut_keyhole`'s edge search from the index: `Some((connector, ring))` (`INVALID` both
    /// when no edge qualifies) when one qualifying edge beats every other and none beats it, as
    /// the walk would find in any order; `None` to walk.
    pub(super) fn keyhole_edge_by_index(&mut self, start: usize, start_pos: Vec2, on_top: i32) -> Option<(usize, usize)> {
        let mut index = self.keyhole_index.take()?;
        let mut verts = Vec::new();
        // An edge with a finite crossing has one end at most y + eps and the other at least
        // y - eps, so its registered rows (widened by the margin, 4 eps and more) meet these.
        index.edges_across(start_pos.y - index.margin, start_pos.y + index.margin, &mut verts);
        let found = self.strict_edge(&index, start, start_pos, on_top, &verts);
        self.keyhole_index = Some(index);
        self.keyhole_searches[usize::from(found.is_none())] += 1;
        found
    }

    fn strict_edge(
        &self,
        index: &KeyholeIndex,
        start: usize,
        start_pos: Vec2,
        on_top: i32,
        verts: &[usize],
    ) -> Option<(usize, usize)> {
        let mut candidates: Vec<(usize, usize, f64)> = Vec::new();
        for &v in verts {
            if self.clipped(v) || index.ring_of[v] == NO_RING {
                continue;
            }
            let x = self.vert_interp_y2x(v, start_pos, on_top);
            if !x.is_finite() || !self.vert_inside_edge(start, v, true) {
                continue;
            }
            if self.in_degenerate_ring(v) {
                return None;
            }
            candidates.push((v, index.ring_of[v] as usize, x));
        }
        let Some(&first) = candidates.first() else {
            return Some((INVALID, INVALID));
        };
        let mut best = first;
        for &c in &candidates[1..] {
            if self.edge_beats(c.0, c.2, start_pos, best.0) {
                best = c;
            }
        }
        for &c in &candidates {
            if c.0 != best.0
                && (!self.edge_beats(best.0, best.2, start_pos, c.0) || self.edge_beats(c.0, c.2, start_pos, best.0))
            {
                return None;
            }
        }
        Some((best.0, best.1))
    }

    /// `find_closer_bridge`'s search from the index, from `connector` (not within epsilon of
    /// the ray): `Some((vert, ring))` (`ring` `None` when `connector` stays) when one vert beats
    /// the connector and every other candidate and none beats it; `None` to walk.
    ///
    /// A vert v beats a connector c only if it is not clearly on the far side of the line from
    /// the start s to c: with a = (v - s) x (c - s), `ccw` calls it outside when 4 a^2 exceeds
    /// max(|v - s|, |c - s|)^2 eps^2. Measure angles from the ray (towards `above`): when v and
    /// c are both at least `NEAR_START_EPSILONS` epsilons from s and v's angle exceeds c's by
    /// more than half of `WEDGE_SLACK`, |a| >= |v - s| |c - s| sin(slack / 2), which exceeds
    /// max(|v - s|, |c - s|) eps / 2 by a factor of about 5 (rounding moves a by 1e-15 of
    /// |v - s| |c - s|), so v cannot beat c. The candidates are every qualifying vert in the
    /// wedge up to the connector's angle plus the slack, and in a disc of that radius around s;
    /// the answer is kept when no candidate is in the disc and every candidate's angle is at
    /// most the connector's plus half the slack, so every connector the walk can hold is a
    /// candidate or the start, and a vert outside the wedge beats none of them.
    pub(super) fn closer_bridge_by_index(
        &mut self,
        start_pos: Vec2,
        edge: usize,
        connector: usize,
        above: f64,
    ) -> Option<(usize, Option<usize>)> {
        let near = NEAR_START_EPSILONS * self.epsilon;
        let c0 = self.polygon[connector].pos;
        let angle0 = angle_from_ray(start_pos, above, c0);
        if !(dot2d(c0 - start_pos, c0 - start_pos).sqrt() >= near && angle0 < std::f64::consts::FRAC_PI_2 - 0.01) {
            self.keyhole_searches[1] += 1;
            return None;
        }
        let slope = (angle0 + WEDGE_SLACK).tan();
        let mut index = self.keyhole_index.take()?;
        let m = index.margin;
        let (eps, sx, sy) = (self.epsilon, start_pos.x, start_pos.y);
        let mut verts = Vec::new();
        // Per column from x0 to x1: heights above the ray from -eps to the wedge's at x1, and
        // up to the disc's radius where the column meets the disc.
        index.verts_in(
            sx - eps - m,
            index.max_x(),
            |x0, x1| {
                let mut high = (x1 - sx).max(0.0) * slope + m;
                if x0 <= sx + near + m {
                    high = high.max(near + m);
                }
                let low = -eps - m;
                if above > 0.0 {
                    (sy + low, sy + high)
                } else {
                    (sy - high, sy - low)
                }
            },
            &mut verts,
        );
        let found = self.strict_bridge(&index, start_pos, edge, connector, above, &verts);
        self.keyhole_index = Some(index);
        self.keyhole_searches[usize::from(found.is_none())] += 1;
        found
    }

    fn strict_bridge(
        &self,
        index: &KeyholeIndex,
        start_pos: Vec2,
        edge: usize,
        connector: usize,
        above: f64,
        verts: &[usize],
    ) -> Option<(usize, Option<usize>)> {
        let near = NEAR_START_EPSILONS * self.epsilon;
        let angle0 = angle_from_ray(start_pos, above, self.polygon[connector].pos);
        let mut candidates = Vec::new();
        for &v in verts {
            if self.clipped(v) || index.ring_of[v] == NO_RING || !self.bridge_vert_qualifies(v, start_pos, above, edge) {
                continue;
            }
            let p = self.polygon[v].pos;
            if dot2d(p - start_pos, p - start_pos).sqrt() < near || self.in_degenerate_ring(v) {
                return None;
            }
            let a = angle_from_ray(start_pos, above, p);
            if a > angle0 + WEDGE_SLACK {
                // Outside the wedge, where no connector this search can hold lies.
                continue;
            }
            if !(a <= angle0 + 0.5 * WEDGE_SLACK) {
                return None;
            }
            candidates.push(v);
        }
        let mut best = connector;
        for &v in &candidates {
            if self.bridge_vert_beats(v, start_pos, above, best) {
                best = v;
            }
        }
        for &v in &candidates {
            if v != best
                && (self.bridge_vert_beats(v, start_pos, above, best)
                    || (best != connector && !self.bridge_vert_beats(best, start_pos, above, v)))
            {
                return None;
            }
        }
        if best != connector && !self.bridge_vert_beats(best, start_pos, above, connector) {
            return None;
        }
        Some((best, (best != connector).then(|| index.ring_of[best] as usize)))
    }
}
