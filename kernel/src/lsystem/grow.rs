//! Growth as polar operations (seed 004, §11.1): a derived string is carried out module by
//! module as operations on one polar mesh, so that the mesh is the string's implicit
//! representation — every drawn module is one loop or one pole, the backbones the string's
//! order, the nested features its brackets.
//!
//! The symbols (§11 and §10.3; `symbols` defines them and tabulates their parameters):
//! - `L`, `L0`, `F` — move forward and draw a loop: [`PolarMesh::add_refinement`] on a spoke of
//!   the branch's tip pole (§4.1: the new loop lands between the last loop and the pole), then
//!   the low-level moves of §2.4 place it as a circle of the current radius around the turtle,
//!   perpendicular to its heading, and the pole a cap ahead of it;
//! - `P` — move forward and draw the pole: the tip pole moves to the turtle; the branch ends;
//! - `[` — push the turtle; the branch it opens is nested lazily, when it first draws, with
//!   [`PolarMesh::add_feature`] (§4.3) on the current loop of its parent;
//! - `[L`, `[R` — draw a loop (like `L`), roll the parent by the divergence angle, push, and turn
//!   left (`+`) or right (`-`) for a branch nested on that loop;
//! - `]` — pop: return to the parent's turtle and loop; a branch not ended by `P` keeps its
//!   tip pole a cap beyond its last loop;
//! - `f` moves without drawing; `+ - & ^ \ / |` turn (§10.3); `!(r)` sets the radius, `!` alone
//!   shrinks it by 0.7; every other symbol draws nothing.
//!
//! Orientation (the "lack of direction" of §12): a branch opens where the turtle points. Its gap
//! is the run of free consecutive loop vertices whose centroid lies furthest along the turtle's
//! heading projected on the loop's plane, found by a sliding window in time linear in the loop
//! size. A branch keeps its parent's valence when the run fits (a run of valence/2 + 1 vertices,
//! since the pole of a run of |VV| vertices has valence 2(|VV| − 1), §4.3.1) unless its siblings
//! on the same loop need room (c branches get runs of at most valence/c vertices), else the
//! largest run left; runs on one loop never overlap (§4.3.4 d). Siblings share a loop by where
//! they point, not by who comes first: at the first `[` of a group their headings at their
//! first segments are read ahead in the string, and each branch's run is taken from the loop
//! vertices nearest its own heading (its sector) when a run as long as the loop allows fits
//! there; two siblings get their runs chosen together, the pair of disjoint runs whose
//! worse-facing run faces its own heading best (in time linear in the loop size), so that
//! the first does not take a vertex the second needs. A run over 135° of its loop reaches round to the parent's sides, and the branch's
//! first quads at its ends cross the parent's faces beyond them: a lone branch keeps a run of
//! valence/2 + 1 when its loop can be slid so that the run spans 130° — the loop star-shaped
//! about its centre and no loop edge turning over 60° from the edge facing it behind (a circle
//! always can; a branch's first loop, shaped like its gap, seldom can: seen along a heading
//! close to the parent's axis a gap is a crescent). Siblings and runs that cannot slide get at
//! most 3·valence/8 + 1 vertices, so their valence falls by a quarter, compounding with depth.
//! [`GrowOptions::wide_gaps`] lifts that cap, growing every branch at its parent's valence as
//! the thesis does (runs of valence/2 + 1 everywhere; lone runs still slide where they can),
//! at the price of more crossings at branch bases (measured below).
//!
//! A branch's first segment leaves the parent's tube: along a heading at α to the parent's
//! axis it is at least (R + r·cos α) / sin α long (α taken at least 15°), so that its first loop
//! lies outside the parent's radius R, where the parent goes on beyond the loop (as its next
//! segments or its tip's cap) — with a first segment of only R + r, branches at 15° to their
//! parent ran through it (tested).
//!
//! Growth and steps (§11.1, §12, decided here): the string of step n is derived first
//! ([`Lsystem::derive`](super::Lsystem::derive), every module rewritten at once as §10.1 requires)
//! and then carried out in one depth-first pass, each module one polar operation in string order.
//! Growing "after it branches" (§12's shrub limitation) is then the grammar's choice and needs
//! nothing special of the mesh: when the apex survives its branches (`A → L [L A] [R A] A`), the
//! parent's later modules are operations at its own tip pole, drawn after its branches were
//! nested, so the parent's axis grows on, step after step, and so does every branch (tested: the
//! trunk's tip rises by the new segments' lengths every step, while in the thesis's grammar it
//! stays where it branched). A step is not re-applied in place to the previous step's mesh:
//! `F → FF` would insert loops in the middle of grown branches and carry whole sub-trees along,
//! which the polar operations do (add_refinement across a ring, skeleton-based moves) but which
//! costs more than growing the new string afresh, in time linear in the result; so
//! `grow(steps)` grows step `steps` from the axiom's turtle, and the same seed always gives the
//! same string, hence the same mesh.
//!
//! Known limits: a gap's two ends are sharp (the far side meets the loop at the split vertices,
//! §4.3.2), and a branch's first loops keep those corners as creases until they round off; on
//! branches of two or three loops (the thesis's `L0 L P`) the branch stays somewhat flat. No
//! face folds (tests_grow checks that over many seeds). Faces still cross at branch bases
//! (tests_grow, counted with Möller's test): where a branch nests on a branch's first loop at
//! low valence (at the inner gap's far side the parent's next quad and the branch's first quad
//! leave one edge in nearly one direction), where two siblings on a loop of low valence
//! cannot both face their headings (at valence 8 two branches a quarter turn apart share the
//! loop's two halves, whose centroids are opposite: the best pair is 22.5° and 67.5° off,
//! jointly chosen or not), at the two quads of a gap's sharp end for branches within 20° of
//! their parent's axis, and in the recipes' plants (shrub 513 of 1564 faces, tree 791 of 5780,
//! turtle plant 202 of 4528 — 220 before siblings' runs were paired; all
//! within four vertex rings of each other — no two distant branches pass through each other).
//! The Fig. 12.2 benchmark case grows 51k vertices by default, not the thesis's 400k, as its
//! branches nest on crescent-shaped first loops that cannot slide (kernel/benches/lsystem.rs);
//! with wide gaps it grows 393k. Wide gaps cross more: the Fig. 12.2 case at 7 steps in 10,139 of
//! 28,544 faces (1,632 of 6,396 by default), the recipes' plants shrub 1,033 of 2,872, tree 1,709
//! of 9,660, turtle plant 581 of 6,064 (no face folds), and the nested strings of tests_grow at
//! valences 8/12/16: `F F [+F [-F [+F F] F] F] F` 8/6/7 faces (0/0/0 by default),
//! `F F [+F [+F F] F F] F F` 8/5/7 (3/0/0), `F F [&F F] /(90) [&F F] F` 6/16/22 (6/0/8). Gaps made taller for
//! low-angle branches (the far side lifted so that, seen along the heading, the gap is a lens or a
//! half-disc instead of a crescent, so the first loop could round off and slide) folded faces in
//! every plant and gained no valence; capping runs by their angle about the loop's centre instead
//! of their vertex count (135°) doubled the Fig. 12.2 case (98k) but crossed the nested strings and
//! the recipes more (measured, not kept).
//!
//! Skeleton (§7.1): the trunk's base pole is the root; every drawn module adds one node (its loop,
//! or for `P` its pole; a nesting loop and the gaps on it are one node); every branch not ended by
//! `P` adds its tip pole. Every branch end is a leaf.

use std::fmt::Display;

use super::grammar::Module;
use super::turtle::Turtle;
use super::LsystemError;
use crate::math::Vec3;
use crate::polar::PolarMesh;

/// What a size callback is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Size {
    /// The length of a segment.
    Length,
    /// The radius of a loop.
    Radius,
}

/// The sigmoid of Eq. 11.2, `1 − 1 / (1 + e^(2 − step))`: 0.88 at step 0, 0.5 at step 2, 0.05 at
/// step 5 — young segments long and thick, old ones short and thin.
#[must_use]
pub fn sigmoid(step: f64) -> f64 {
    1.0 - 1.0 / (1.0 + (2.0 - step).exp())
}

/// How far a branch's first loop rounds its gap's shape off towards a circle, at most.
const ROUND_FIRST: f64 = 0.35;
/// How far every later loop rounds the previous loop's shape off, at most.
const ROUND: f64 = 0.5;

/// The largest segment length or radius: squared distances of positions this far apart stay
/// finite.
pub const MAX_SIZE: f64 = 1e100;

/// Options of [`grow`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct GrowOptions {
    /// Radius of the trunk's loops at step 0 before the sigmoid. Default value: 0.25.
    pub radius: f64,
    /// Segment length at step 0 before the sigmoid. Default value: 1.
    pub length: f64,
    /// Number of vertices on the trunk's loops (at least 6). Default value: 8.
    pub valence: u32,
    /// Turning angle of `+ - & ^ \ /` without a parameter, and of `[L` / `[R`, in degrees.
    /// Default value: 30.
    pub angle: f64,
    /// Roll of the parent at every `[L` / `[R`, in degrees, spreading branches around it.
    /// Default value: 137.5 (the golden angle).
    pub divergence: f64,
    /// Whether `radius` and `length` are scaled by the sigmoid of Eq. 11.2 of the step (a thesis
    /// symbol's first parameter, else the branch depth). Default value: true.
    pub sigmoid: bool,
    /// Growth stops with an error once the mesh has more vertices. Default value: 4,000,000.
    pub max_vertices: usize,
    /// Growth stops with an error once more branches are nested. Default value: 200,000.
    pub max_features: usize,
    /// Whether every branch may open a gap as wide as keeps its parent's valence (a run of
    /// valence/2 + 1 vertices, §4.3.1), as the thesis's branches do, where by default a run
    /// that cannot be slid spans at most 135° of its loop (3·valence/8 + 1 vertices, so the
    /// branch's valence falls by a quarter). Wide gaps reach round to the parent's sides and
    /// the branches' first quads there cross the parent's faces beyond them (grow's module doc
    /// has the counts); the Fig. 12.2 case keeps the thesis's size with them (393k vertices at
    /// 11 steps, 51k by default). Default value: false.
    pub wide_gaps: bool,
    /// Whether the trunk stands on a flat base: a loop of the trunk's first radius where the
    /// turtle starts, its pole (the root) at that loop's centre, so the plant's foot is a flat
    /// disk (a triangle fan in one plane) instead of the cone from the root pole to the first
    /// loop. The base loop is one more skeleton node, at the root's position (a segment of
    /// length 0, which animations carry as it is). Default value: false.
    pub flat_base: bool,
}

impl GrowOptions {
    /// The defaults.
    pub const DEFAULT: GrowOptions = GrowOptions {
        radius: 0.25,
        length: 1.0,
        valence: 8,
        angle: 30.0,
        divergence: 137.5,
        sigmoid: true,
        max_vertices: 4_000_000,
        max_features: 200_000,
        wide_gaps: false,
        flat_base: false,
    };

    /// With `radius`.
    #[must_use]
    pub fn with_radius(mut self, radius: f64) -> GrowOptions {
        self.radius = radius;
        self
    }

    /// With `length`.
    #[must_use]
    pub fn with_length(mut self, length: f64) -> GrowOptions {
        self.length = length;
        self
    }

    /// With `valence`.
    #[must_use]
    pub fn with_valence(mut self, valence: u32) -> GrowOptions {
        self.valence = valence;
        self
    }

    /// With `angle`.
    #[must_use]
    pub fn with_angle(mut self, angle: f64) -> GrowOptions {
        self.angle = angle;
        self
    }

    /// With `divergence`.
    #[must_use]
    pub fn with_divergence(mut self, divergence: f64) -> GrowOptions {
        self.divergence = divergence;
        self
    }

    /// With or without the sigmoid.
    #[must_use]
    pub fn with_sigmoid(mut self, on: bool) -> GrowOptions {
        self.sigmoid = on;
        self
    }

    /// With or without wide gaps.
    #[must_use]
    pub fn with_wide_gaps(mut self, on: bool) -> GrowOptions {
        self.wide_gaps = on;
        self
    }

    /// With or without a flat base.
    #[must_use]
    pub fn with_flat_base(mut self, on: bool) -> GrowOptions {
        self.flat_base = on;
        self
    }

    /// With caps on vertices and nested branches.
    #[must_use]
    pub fn with_caps(mut self, max_vertices: usize, max_features: usize) -> GrowOptions {
        self.max_vertices = max_vertices;
        self.max_features = max_features;
        self
    }

    fn validate(&self) -> Result<(), LsystemError> {
        let bad = |s: String| Err(LsystemError::InvalidOption(s));
        if !(self.radius.is_finite() && self.radius > 0.0 && self.radius <= MAX_SIZE) {
            return bad(format!("radius must be a positive number up to {MAX_SIZE:e}, got {}", self.radius));
        }
        if !(self.length.is_finite() && self.length > 0.0 && self.length <= MAX_SIZE) {
            return bad(format!("length must be a positive number up to {MAX_SIZE:e}, got {}", self.length));
        }
        if !(6..=100_000).contains(&self.valence) {
            return bad(format!("valence must lie between 6 and 100000, got {}", self.valence));
        }
        if !(self.angle.is_finite() && self.divergence.is_finite()) {
            return bad(format!("angle and divergence must be finite, got {} and {}", self.angle, self.divergence));
        }
        Ok(())
    }
}

impl Default for GrowOptions {
    fn default() -> GrowOptions {
        GrowOptions::DEFAULT
    }
}

/// A grown plant: the polar mesh and the counts that describe its skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct Grown {
    /// The mesh.
    pub mesh: PolarMesh,
    /// The trunk's base pole (the skeleton's root).
    pub root: u32,
    /// Drawn modules (`F L L0 P [L [R`), each one skeleton node.
    pub segments: usize,
    /// Branches drawn, the trunk included: each ends in a pole, a leaf of the skeleton.
    pub branches: usize,
    /// Branches not ended by `P`, whose tip pole is one more node.
    pub open_ends: usize,
    /// Nested features (branches but the trunk).
    pub features: usize,
}

/// A loop drawn by the growth, with what nesting needs.
#[derive(Clone, Debug)]
struct Ring {
    /// Vertices in order, with the side towards the branch tip on the left of `v[j] → v[j+1]`.
    verts: Vec<u32>,
    used: Vec<bool>,
    center: Vec3,
    axis: Vec3,
    radius: f64,
    length: f64,
}

#[derive(Clone, Debug)]
struct Branch {
    tip: u32,
    ring: Option<usize>,
    ended: Option<usize>,
}

#[derive(Clone, Debug)]
struct State {
    turtle: Turtle,
    branch: Option<usize>,
    host: Option<usize>,
    depth: u32,
    radius: Option<f64>,
    /// How many branches (this one included) the parent opens on the same loop.
    siblings: usize,
    /// The loop vertices this branch may open its gap on, when it has siblings there.
    sector: Option<Vec<bool>>,
}

/// The groups of `[` that open branches on one loop of their parent: those at the same depth
/// with no drawn segment of the parent between them (groups of one left out), each in string
/// order.
fn sibling_groups(modules: &[Module]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    // open[d]: the `[` indices of the current group of depth-d branches.
    let mut open: Vec<Vec<usize>> = vec![Vec::new()];
    for (i, m) in modules.iter().enumerate() {
        match m.symbol.as_str() {
            "[" => {
                if let Some(g) = open.last_mut() {
                    g.push(i);
                }
                open.push(Vec::new());
            }
            "[L" | "[R" => {
                if let Some(g) = open.last_mut() {
                    groups.push(std::mem::take(g));
                }
                open.push(Vec::new());
            }
            "]" => {
                if let Some(g) = open.pop() {
                    groups.push(g);
                }
            }
            "F" | "L" | "L0" | "P" => {
                if let Some(g) = open.last_mut() {
                    groups.push(std::mem::take(g));
                }
            }
            _ => {}
        }
    }
    groups.extend(open);
    groups.retain(|g| g.len() > 1);
    groups
}

/// The headings sibling branches `group` (indices of their `[`, from [`sibling_groups`]) will
/// have when they first draw, from `parent`, the parent's turtle at the first `[`: each
/// branch's turns before its first segment, and the parent's turns between its `]` and the next
/// `[`. `close[i]` is the `]` of the `[` at i.
fn sibling_headings(modules: &[Module], group: &[usize], close: &[usize], parent: Turtle, angle: f64) -> Vec<Vec3> {
    let turn = |t: &mut Turtle, m: &Module| {
        t.apply(m.symbol.as_str(), m.params.first().copied().unwrap_or(angle));
    };
    let mut t = parent;
    let mut out = Vec::with_capacity(group.len());
    for (j, &open) in group.iter().enumerate() {
        let mut b = t;
        for m in &modules[open + 1..close[open]] {
            match m.symbol.as_str() {
                "F" | "L" | "L0" | "P" | "[" | "[L" | "[R" | "]" => break,
                _ => turn(&mut b, m),
            }
        }
        out.push(b.heading);
        if let Some(&next) = group.get(j + 1) {
            for m in &modules[close[open] + 1..next] {
                turn(&mut t, m);
            }
        }
    }
    out
}

/// The vertices of a loop (`pos` about `center`, across unit `axis`) each sibling may open its
/// gap on: those whose direction from the centre lies nearest its heading's (a vertex midway
/// between two headings goes to both), so that siblings share a loop by where they point, not
/// by who comes first. `None` when some sibling would get fewer than 3 vertices.
fn sibling_sectors(pos: &[Vec3], center: Vec3, axis: Vec3, headings: &[Vec3]) -> Option<Vec<Vec<bool>>> {
    let dirs: Vec<Vec3> =
        headings.iter().map(|&h| across(h, axis).unwrap_or_else(|| axis.any_orthonormal_vector())).collect();
    let mut sectors = vec![vec![false; pos.len()]; dirs.len()];
    for (v, &p) in pos.iter().enumerate() {
        let Some(d) = across(p - center, axis) else { continue };
        let best = dirs.iter().map(|&s| s.dot(d)).fold(f64::NEG_INFINITY, f64::max);
        for (k, &s) in dirs.iter().enumerate() {
            if s.dot(d) >= best - 1e-9 {
                sectors[k][v] = true;
            }
        }
    }
    sectors.iter().all(|s| s.iter().filter(|&&x| x).count() >= 3).then_some(sectors)
}

/// Two siblings' runs on one loop chosen together: of the pairs of disjoint runs of `w` free
/// consecutive vertices, the one whose worse-facing run faces its own heading best (the larger
/// cosine between a run's centroid direction and its heading, seen across the loop's axis;
/// ties to the larger sum), so that neither takes a vertex the other needs to face its way —
/// one after the other, the first may take the tie vertex nearer the second's heading and
/// leave it a run centred far off it. Returned as each sibling's sector (exactly its run);
/// `None` when no two disjoint runs fit. Time linear in the loop size: for each first run the
/// best second run among the starts that do not overlap it (a window of n − 2w + 1 starts that
/// slides with the first) is a sliding-window maximum kept in a deque.
fn paired_runs(
    pos: &[Vec3],
    used: &[bool],
    center: Vec3,
    axis: Vec3,
    headings: [Vec3; 2],
    w: usize,
) -> Option<Vec<Vec<bool>>> {
    let n = pos.len();
    if w < 3 || 2 * w > n {
        return None;
    }
    let dirs = headings.map(|h| across(h, axis).unwrap_or_else(|| axis.any_orthonormal_vector()));
    // fits[s]: the run of w from s is free; facing[k][s]: its cosine to heading k.
    let mut fits = vec![false; n];
    let mut facing = [vec![f64::NEG_INFINITY; n], vec![f64::NEG_INFINITY; n]];
    let mut free_ahead = 0usize;
    let mut sum: Vec3 = (0..w).map(|j| pos[j % n]).sum();
    // Free stretch lengths from each start, capped at w, by one backward pass over 2n.
    let mut stretch = vec![0usize; n];
    for t in (0..2 * n).rev() {
        free_ahead = if used[t % n] { 0 } else { (free_ahead + 1).min(w) };
        if t < n {
            stretch[t] = free_ahead;
        }
    }
    for s0 in 0..n {
        if stretch[s0] >= w {
            fits[s0] = true;
            if let Some(d) = across(sum / w as f64 - center, axis) {
                for k in 0..2 {
                    facing[k][s0] = d.dot(dirs[k]);
                }
            }
        }
        sum += pos[(s0 + w) % n] - pos[s0];
    }
    // For first run s1 the second starts at s1 + w + t, t in 0..=n − 2w (mod n).
    let span = n - 2 * w + 1;
    let second = |x: usize| facing[1][x % n];
    let mut deque: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut next = w; // next index (in 0..2n) to push into the window
    let mut best: Option<(f64, f64, usize, usize)> = None;
    for s1 in 0..n {
        let (lo, hi) = (s1 + w, s1 + w + span); // window [lo, hi) of second starts
        while next < hi {
            while deque.back().is_some_and(|&b| second(b) <= second(next)) {
                deque.pop_back();
            }
            deque.push_back(next);
            next += 1;
        }
        while deque.front().is_some_and(|&f| f < lo) {
            deque.pop_front();
        }
        if !fits[s1] {
            continue;
        }
        let Some(&s2) = deque.front() else { continue };
        let (a, b) = (facing[0][s1], second(s2));
        if !fits[s2 % n] || !a.is_finite() || !b.is_finite() {
            continue;
        }
        let (worse, total) = (a.min(b), a + b);
        if best.is_none_or(|(bw, bt, _, _)| worse > bw + 1e-12 || (worse > bw - 1e-12 && total > bt + 1e-12)) {
            best = Some((worse, total, s1, s2 % n));
        }
    }
    let (_, _, s1, s2) = best?;
    let mut out = vec![vec![false; n]; 2];
    for j in 0..w {
        out[0][(s1 + j) % n] = true;
        out[1][(s2 + j) % n] = true;
    }
    Some(out)
}

/// Grows `modules` as polar operations with lengths and radii `opts.length · S(step)` and
/// `opts.radius · S(step)` (S the [`sigmoid`] of Eq. 11.2, or 1 without it). See
/// [`grow_with`].
///
/// # Errors
/// As [`grow_with`].
pub fn grow(modules: &[Module], opts: &GrowOptions) -> Result<Grown, LsystemError> {
    let o = *opts;
    grow_with(modules, opts, &mut |what, step| -> Result<f64, LsystemError> {
        let s = if o.sigmoid { sigmoid(step) } else { 1.0 };
        Ok(match what {
            Size::Length => o.length * s,
            Size::Radius => o.radius * s,
        })
    })
}

/// Grows `modules` (a derived string) as a sequence of polar operations (§11.1); `size(what,
/// step)` gives each segment's length and radius from its step — the first parameter of a thesis
/// symbol (`L(3)`), else the branch depth (a parameter of `F` is its length, as `F(l)` in L-Py).
/// Time linear in the size of the result. Tells a listener ([`crate::limits::listen`]) the
/// modules drawn.
///
/// # Errors
/// [`LsystemError::InvalidOption`], [`LsystemError::NothingDrawn`],
/// [`LsystemError::UnbalancedBrackets`], [`LsystemError::DrawAfterPole`],
/// [`LsystemError::NoRoomForBranch`], [`LsystemError::GrowthCap`] (the caps on vertices and
/// features), [`LsystemError::SizeCallback`] from `size`, and [`LsystemError::Polar`] for a refused
/// operation (a bug).
pub fn grow_with<E: Display>(
    modules: &[Module],
    opts: &GrowOptions,
    size: &mut dyn FnMut(Size, f64) -> Result<f64, E>,
) -> Result<Grown, LsystemError> {
    match grow_once(modules, opts, size) {
        Err(LsystemError::NoRoomForBranch { module, symbol, valence, works: None }) => {
            let works = valence_that_works(modules, opts, size);
            Err(LsystemError::NoRoomForBranch { module, symbol, valence, works })
        }
        other => other,
    }
}

/// The smallest trunk valence found to grow `modules` (the others options as in `opts`), for
/// the advice of [`LsystemError::NoRoomForBranch`]. Each branch takes a run of at least 3 free
/// vertices of its loop and its own loops get 2(run − 1) vertices (§4.3.1), at most 3/8 of
/// its parent's (or 1/c of it for c siblings on one loop), so the room a deep branching needs
/// shrinks geometrically with depth and depends on where the branches point: rather than a
/// bound that is either loose or wrong, the valence is searched (doubling from the refused
/// one, then halving the interval to within an eighth) and only a valence that grew is named.
/// `None` when none up to the option's limit grows within the caps.
fn valence_that_works<E: Display>(
    modules: &[Module],
    opts: &GrowOptions,
    size: &mut dyn FnMut(Size, f64) -> Result<f64, E>,
) -> Option<u32> {
    const MAX: u32 = 100_000;
    let mut grows = |v: u32| -> Result<bool, ()> {
        match grow_once(modules, &opts.with_valence(v), size) {
            Ok(_) => Ok(true),
            Err(LsystemError::NoRoomForBranch { .. }) => Ok(false),
            // Another refusal (a cap, the memory budget, a cancellation): stop searching.
            Err(_) => Err(()),
        }
    };
    let (mut lo, mut hi) = (opts.valence, None);
    while hi.is_none() && lo < MAX {
        let v = lo.saturating_mul(2).min(MAX);
        match grows(v) {
            Ok(true) => hi = Some(v),
            Ok(false) => lo = v,
            Err(()) => return None,
        }
    }
    let mut hi = hi?;
    while hi - lo > (lo / 8).max(1) {
        let mid = lo + (hi - lo) / 2;
        match grows(mid) {
            Ok(true) => hi = mid,
            Ok(false) => lo = mid,
            Err(()) => break,
        }
    }
    Some(hi)
}

/// How many modules are drawn between two reports of a growth's progress.
const REPORT_EVERY: usize = 256;

fn grow_once<E: Display>(
    modules: &[Module],
    opts: &GrowOptions,
    size: &mut dyn FnMut(Size, f64) -> Result<f64, E>,
) -> Result<Grown, LsystemError> {
    opts.validate()?;
    super::grammar::check_balance("the string", modules.iter().map(|m| m.symbol.as_str()))?;
    let mut g =
        Grower { opts: *opts, mesh: None, root: 0, rings: Vec::new(), branches: Vec::new(), segments: 0, features: 0 };
    let groups = sibling_groups(modules);
    let mut group_of = vec![usize::MAX; modules.len()];
    for (k, gr) in groups.iter().enumerate() {
        for &i in gr {
            group_of[i] = k;
        }
    }
    let mut close = vec![0; modules.len()];
    let mut opens = Vec::new();
    for (i, m) in modules.iter().enumerate() {
        match m.symbol.as_str() {
            "[" | "[L" | "[R" => opens.push(i),
            "]" => {
                if let Some(o) = opens.pop() {
                    close[o] = i;
                }
            }
            _ => {}
        }
    }
    // Sectors of the siblings of the group being opened, by their `[` index.
    let mut sectors: Vec<(usize, Vec<bool>)> = Vec::new();
    let mut stack: Vec<State> = Vec::new();
    let mut st = State {
        turtle: Turtle::default(),
        branch: None,
        host: None,
        depth: 0,
        radius: None,
        siblings: 1,
        sector: None,
    };
    // Progress: the modules drawn (a search for a valence that grows reports each try).
    let work = crate::limits::Work::start(modules.len() as u64);
    for (i, m) in modules.iter().enumerate() {
        if i.is_multiple_of(REPORT_EVERY) {
            work.set(i as u64);
        }
        let s = m.symbol.as_str();
        match s {
            "[" => {
                let mut child = g.child_of(&st);
                if let Some(gr) = groups.get(group_of[i]) {
                    child.siblings = gr.len();
                    if gr[0] == i {
                        sectors.clear();
                        if let Some(ring) = child.host.map(|h| &g.rings[h]) {
                            let pm = g.mesh.as_ref();
                            let pos: Vec<Vec3> =
                                ring.verts.iter().map(|&v| pm.map_or(Vec3::ZERO, |pm| pm.position(v))).collect();
                            let hs = sibling_headings(modules, gr, &close, st.turtle, opts.angle);
                            let n = pos.len();
                            let wmax = (n / 2 + 1).min(n / gr.len()).clamp(3, n - 1);
                            let w = if opts.wide_gaps { wmax } else { wmax.min(3 * n / 8 + 1).max(3) };
                            let paired = if hs.len() == 2 {
                                paired_runs(&pos, &ring.used, ring.center, ring.axis, [hs[0], hs[1]], w)
                            } else {
                                None
                            };
                            if let Some(sec) = paired.or_else(|| sibling_sectors(&pos, ring.center, ring.axis, &hs)) {
                                sectors.extend(gr.iter().copied().zip(sec));
                            }
                        }
                    }
                    child.sector = sectors.iter().position(|(o, _)| *o == i).map(|k| sectors.swap_remove(k).1);
                }
                stack.push(std::mem::replace(&mut st, child));
            }
            "]" => {
                st = stack.pop().ok_or_else(|| LsystemError::Internal("unbalanced string after the check".into()))?;
            }
            "[L" | "[R" => {
                let (len, r) = g.sizes(m, &st, size)?;
                g.draw(i, m, &mut st, len, r, false)?;
                st.turtle.roll(opts.divergence);
                let mut child = g.child_of(&st);
                child.turtle.yaw(if s == "[L" { opts.angle } else { -opts.angle });
                stack.push(std::mem::replace(&mut st, child));
            }
            "F" | "L" | "L0" | "P" => {
                let (len, r) = g.sizes(m, &st, size)?;
                g.draw(i, m, &mut st, len, r, s == "P")?;
            }
            "f" => {
                let (len, _) = g.sizes(m, &st, size)?;
                st.turtle.position += st.turtle.heading * len;
            }
            "!" => {
                let cur = match st.radius {
                    Some(r) => r,
                    None => g.sizes(m, &st, size)?.1,
                };
                st.radius = Some(m.params.first().copied().unwrap_or(cur * super::symbols::SHRINK));
            }
            _ => {
                let deg = m.params.first().copied().unwrap_or(opts.angle);
                st.turtle.apply(s, deg);
            }
        }
    }
    work.finish();
    let mesh = g.mesh.take().ok_or(LsystemError::NothingDrawn)?;
    let open_ends = g.branches.iter().filter(|b| b.ended.is_none()).count();
    Ok(Grown { mesh, root: g.root, segments: g.segments, branches: g.branches.len(), open_ends, features: g.features })
}

struct Grower {
    opts: GrowOptions,
    mesh: Option<PolarMesh>,
    root: u32,
    rings: Vec<Ring>,
    branches: Vec<Branch>,
    segments: usize,
    features: usize,
}

/// How far the tip pole stands beyond a branch's last loop.
fn cap(radius: f64, length: f64) -> f64 {
    0.5 * radius.max(length)
}

/// `v` without its component along unit `axis`, normalised; `None` when (nearly) parallel.
fn across(v: Vec3, axis: Vec3) -> Option<Vec3> {
    (v - axis * v.dot(axis)).try_normalize().filter(|d| d.is_finite())
}

/// Per-vertex weights `w[j] ≤ w_max` of `circle` against `shape` (offsets of a new loop's
/// vertices, in ring order): vertex j goes to `(1 − w[j])·shape[j] + w[j]·circle[j]`. Every
/// edge of the new loop then turns at most 60° from the previous loop's edge between `prev`
/// (same order), or no more than the shape's own edge does, so each quad between the loops
/// stays a trapezoid instead of folding; the weights start at `w_max` and are halved at both
/// ends of an edge that turns too far, and zeroed if halving does not settle it. Each vertex
/// rounds off as far as its own edges allow, so a loop's sharp corners (a gap's narrow ends)
/// do not hold back the rest of the loop. Near-linear in the loop size.
fn rounding(prev: &[Vec3], shape: &[Vec3], circle: &[Vec3], w_max: f64) -> Vec<f64> {
    let n = prev.len();
    let edges: Vec<Vec3> = (0..n).map(|j| prev[(j + 1) % n] - prev[j]).collect();
    blend_weights(&edges, shape, circle, w_max)
}

/// [`rounding`] with the previous cycle given by its edges: `prev_edges[j]` is the edge facing
/// the new loop's edge from vertex j to j + 1 across their face (zero across a pole's
/// triangle, which cannot fold).
fn blend_weights(prev_edges: &[Vec3], shape: &[Vec3], circle: &[Vec3], w_max: f64) -> Vec<f64> {
    let n = prev_edges.len();
    let mut w = vec![w_max; n];
    let at = |w: &[f64], j: usize| shape[j] * (1.0 - w[j]) + circle[j] * w[j];
    let cosine = |a: Vec3, b: Vec3| {
        let l = a.length() * b.length();
        if l > 0.0 {
            a.dot(b) / l
        } else {
            1.0
        }
    };
    let turns_too_far = |w: &[f64], j: usize| {
        let k = (j + 1) % n;
        let d = prev_edges[j];
        let floor = cosine(shape[k] - shape[j], d).min(0.5);
        cosine(at(w, k) - at(w, j), d) < floor - 1e-12
    };
    for pass in 0..=12 {
        let mut settled = true;
        for j in 0..n {
            if turns_too_far(&w, j) {
                settled = false;
                let k = (j + 1) % n;
                let f = if pass < 12 { 0.5 } else { 0.0 };
                w[j] *= f;
                w[k] *= f;
            }
        }
        if settled {
            return w;
        }
    }
    // Zeroing settles: an edge between two zero weights is the shape's own.
    while (0..n).any(|j| turns_too_far(&w, j)) {
        for j in 0..n {
            if turns_too_far(&w, j) {
                w[j] = 0.0;
                w[(j + 1) % n] = 0.0;
            }
        }
    }
    w
}

/// The widest a branch's run may span about its loop's centre once slid ([`slide_run`]).
const SPAN: f64 = 130.0 * std::f64::consts::PI / 180.0;

/// The angles of a planar loop's vertices `pos` about `center` across unit `axis`, unwrapped
/// from the first vertex in the loop's own turning direction: `(sign, basis, angles)` with
/// `angles[0] = 0` and every step forwards, or `None` unless the loop is star-shaped about the
/// centre (each step turns forwards by less than half a turn and the loop winds once).
fn star_angles(pos: &[Vec3], center: Vec3, axis: Vec3) -> Option<(f64, [Vec3; 2], Vec<f64>)> {
    use std::f64::consts::{PI, TAU};
    let n = pos.len();
    let b1 = across(pos[0] - center, axis)?;
    let b2 = axis.cross(b1);
    let angle = |p: Vec3| (p - center).dot(b2).atan2((p - center).dot(b1));
    let step = |j: usize| (angle(pos[(j + 1) % n]) - angle(pos[j]) + PI).rem_euclid(TAU) - PI;
    let sign = if step(0) < 0.0 { -1.0 } else { 1.0 };
    let mut angles = Vec::with_capacity(n + 1);
    angles.push(0.0);
    for j in 0..n {
        let d = sign * step(j);
        if !(d > 1e-9 && d < PI) {
            return None;
        }
        angles.push(angles[j] + d);
    }
    ((angles[n] - TAU).abs() < 1e-6).then(|| {
        angles.pop();
        (sign, [b1, b2], angles)
    })
}

/// New positions for the vertices of a loop without branches (star-shaped about `center`, in
/// the plane across `axis`) so that the run of `w` vertices from `s` spans at most `span` about
/// the centre, centred where it was, and the others share the rest of the turn evenly: each
/// vertex slides along the loop's own polygon (the low-level moves of §2.4), so the loop keeps
/// its shape — a circle stays that circle. A run over half a loop wraps round to the parent's
/// sides, where the surface faces along the branch and the branch's first quads at the run's
/// ends would fold or cross the parent's faces beyond them; slid, it keeps the valence
/// (|VV| = n/2 + 1, §4.3.1) on a cap of 130°. `None` when the run spans no more than `span`
/// already or the loop is not star-shaped. Linear in the loop size.
fn slide_run(pos: &[Vec3], center: Vec3, axis: Vec3, s: usize, w: usize, span: f64) -> Option<Vec<Vec3>> {
    use std::f64::consts::TAU;
    let n = pos.len();
    let (sign, [b1, b2], raw) = star_angles(pos, center, axis)?;
    // Angles from the run's first vertex, in [0, 2π).
    let from = |j: usize| (raw[j] - raw[s]).rem_euclid(TAU);
    let natural = from((s + w - 1) % n);
    if natural <= span {
        return None;
    }
    let mid = natural / 2.0;
    let rest = (TAU - span) / (n - w + 1) as f64;
    let target = |t: usize| {
        if t < w {
            mid + span * (t as f64 / (w - 1) as f64 - 0.5)
        } else {
            mid + span / 2.0 + (t - w + 1) as f64 * rest
        }
    };
    // Walk the loop once from the run's first vertex (angles from it rise from 0 to 2π): the
    // edge holding each target angle, then the point at that angle whose distance from the
    // centre interpolates the edge's ends' by angle (so a circle stays that circle).
    let radius = |p: Vec3| across(p - center, axis).map_or(0.0, |d| (p - center).dot(d));
    // Targets rise from above 0 to below 2π past the run's start: edges are walked twice round.
    let a_end = |e: usize| from((s + e + 1) % n) + TAU * ((e + 1) / n) as f64;
    let mut e = 0; // edge from vertex s + e to s + e + 1 (mod n)
    let mut out = vec![Vec3::ZERO; n];
    for t in 0..n {
        let phi = target(t);
        while e + 1 < 2 * n && a_end(e) < phi {
            e += 1;
        }
        let (p, q) = (pos[(s + e) % n], pos[(s + e + 1) % n]);
        let a0 = if e == 0 { 0.0 } else { a_end(e - 1) };
        let k = ((phi - a0) / (a_end(e) - a0)).clamp(0.0, 1.0);
        let rho = radius(p) + (radius(q) - radius(p)) * k;
        let th = raw[s] + sign * phi;
        out[(s + t) % n] = center + (b1 * th.cos() + b2 * th.sin()) * rho;
    }
    Some(out)
}

/// The run of consecutive free vertices of a cyclic loop (`pos`, `used`) where a branch opens
/// towards `dir` (§12's "lack of direction", solved without brute force): the longest run
/// length `w ≤ w_max` that fits among the free vertices, then, of the runs of that length, the
/// one whose centroid lies furthest along `dir` from `center`. Returns `(start, w)`, or `None`
/// when no 3 consecutive vertices are free.
///
/// Time linear in the loop size `n`: one backward pass gives the free stretch from every
/// vertex, one sliding window gives every run's centroid (a running sum updated in O(1) per
/// start) — not a centroid per run (O(n·w)) nor a pass per candidate length.
fn facing_run(pos: &[Vec3], used: &[bool], center: Vec3, dir: Vec3, w_max: usize) -> Option<(usize, usize)> {
    let n = pos.len();
    // free[s]: how many consecutive free vertices start at s (n on a loop without branches).
    let mut free = vec![n; n];
    if let Some(u0) = used.iter().position(|&u| u) {
        let mut run = 0;
        for t in 1..=n {
            let j = (u0 + n - t) % n;
            run = if used[j] { 0 } else { run + 1 };
            free[j] = run;
        }
    }
    let w = free.iter().copied().max().unwrap_or(0).min(w_max);
    if w < 3 {
        return None;
    }
    let mut sum: Vec3 = pos.iter().take(w).copied().sum();
    let mut top: Option<(f64, usize)> = None;
    for s in 0..n {
        if free[s] >= w {
            let score = (sum / w as f64 - center).dot(dir);
            if top.is_none_or(|(t, _)| score > t + 1e-12) {
                top = Some((score, s));
            }
        }
        sum += pos[(s + w) % n] - pos[s];
    }
    top.map(|(_, s)| (s, w))
}

impl Grower {
    fn child_of(&self, st: &State) -> State {
        let host = match st.branch {
            Some(b) => self.branches[b].ring,
            None => st.host,
        };
        State {
            turtle: st.turtle,
            branch: None,
            host,
            depth: st.depth + 1,
            radius: st.radius,
            siblings: 1,
            sector: None,
        }
    }

    fn sizes<E: Display>(
        &self,
        m: &Module,
        st: &State,
        size: &mut dyn FnMut(Size, f64) -> Result<f64, E>,
    ) -> Result<(f64, f64), LsystemError> {
        let thesis = super::symbols::STEP_SYMBOLS.contains(&m.symbol.as_str());
        let step = match m.params.first() {
            Some(&p) if thesis => p,
            _ => f64::from(st.depth),
        };
        let call = |what: Size, size: &mut dyn FnMut(Size, f64) -> Result<f64, E>| -> Result<f64, LsystemError> {
            let name = if what == Size::Length { "length" } else { "radius" };
            let v = size(what, step).map_err(|e| LsystemError::SizeCallback {
                place: format!("{name} at step {step} for `{m}`"),
                message: e.to_string(),
            })?;
            if !(v.is_finite() && v > 0.0) {
                return Err(LsystemError::InvalidOption(format!(
                    "the {name} at step {step} for `{m}` must be a positive number, got {v}"
                )));
            }
            Ok(v)
        };
        let len = match m.params.first() {
            Some(&l) if !thesis && super::symbols::LENGTH_SYMBOLS.contains(&m.symbol.as_str()) => l,
            _ => call(Size::Length, size)?,
        };
        let r = match st.radius {
            Some(r) => r,
            None => call(Size::Radius, size)?,
        };
        if !(len.is_finite() && len >= 0.0 && r.is_finite() && r > 0.0) {
            return Err(LsystemError::InvalidOption(format!("`{m}`: length {len} and radius {r} must be positive")));
        }
        if len > MAX_SIZE || r > MAX_SIZE {
            return Err(LsystemError::InvalidOption(format!(
                "`{m}`: length {len:e} and radius {r:e} must be at most {MAX_SIZE:e} (positions would overflow)"
            )));
        }
        Ok((len, r))
    }

    fn polar<T>(i: usize, r: Result<T, crate::polar::PolarError>) -> Result<T, LsystemError> {
        r.map_err(|source| LsystemError::Polar { module: i, source })
    }

    fn check_caps(&self, i: usize, m: &Module) -> Result<(), LsystemError> {
        let n = self.mesh.as_ref().map_or(0, PolarMesh::vertex_count);
        if n > self.opts.max_vertices {
            return Err(LsystemError::GrowthCap {
                what: "the vertex count",
                count: n,
                cap_name: "max_vertices",
                cap: self.opts.max_vertices,
                module: i,
                symbol: m.to_string(),
            });
        }
        Ok(())
    }

    /// Draws one segment of length `len` and radius `r` for module `i`: a loop, or the pole.
    fn draw(&mut self, i: usize, m: &Module, st: &mut State, len: f64, r: f64, pole: bool) -> Result<(), LsystemError> {
        let b = match st.branch {
            Some(b) => b,
            None => {
                self.segments += 1;
                let b = match st.host {
                    None if self.mesh.is_none() => return self.trunk(st, len, r, pole, i),
                    None => {
                        return Err(LsystemError::InvalidOption(format!(
                            "module {i} (`{m}`): a branch draws before its parent drew a loop to nest it on; start the branch's parent with a segment"
                        )))
                    }
                    Some(host) => self.nest(i, m, st, host, r)?,
                };
                st.branch = Some(b);
                // The first segment leaves the parent's surface: at least the parent's radius
                // plus its own long, clear of the parent's tube (below), and its loop lies at
                // least its radius beyond every vertex of the gap along the heading (a gap on a
                // stretched loop can reach far ahead; a loop behind part of its gap folds the
                // quads).
                let host = &self.rings[st.host.unwrap_or(0)];
                let (o, h) = (st.turtle.position, st.turtle.heading);
                let pm = self.mesh.as_ref().ok_or_else(|| LsystemError::Internal("nesting before the trunk".into()))?;
                let mm = pm.mesh();
                let ahead = mm
                    .outgoing(self.branches[b].tip)
                    .map(|x| (pm.position(mm.target(x)) - o).dot(h))
                    .fold(0.0, f64::max);
                // Clear of the parent's axis: a heading at angle α to the parent's axis moves
                // the turtle len·sin α away from it, and the new circle (radius r, across the
                // heading) reaches r·cos α back towards it, so len·sin α ≥ R + r·cos α keeps the
                // whole first loop outside the parent's tube (which goes on beyond the loop, as
                // the parent's tip or its next segments). Headings within 15° of the parent's
                // axis are taken at 15°, keeping the first segment finite.
                let cos_a = h.dot(host.axis).abs().min(1.0);
                let sin_a = (1.0 - cos_a * cos_a).sqrt().max(15f64.to_radians().sin());
                let clear = (host.radius + r * cos_a) / sin_a;
                let len = len.max(host.radius + r).max(clear).max(ahead + r);
                return self.segment(i, m, st, b, len, r, pole, true);
            }
        };
        self.segments += 1;
        self.segment(i, m, st, b, len, r, pole, false)
    }

    /// The trunk's first segment: a bicone (two poles around one loop of `valence` vertices)
    /// from the turtle's position.
    fn trunk(&mut self, st: &mut State, len: f64, r: f64, pole: bool, i: usize) -> Result<(), LsystemError> {
        let n = self.opts.valence;
        let mut pm = PolarMesh::uv_sphere(1.0, n, 2);
        let t = st.turtle;
        let start = t.position;
        let ring_at = if pole { start + t.heading * (0.5 * len) } else { start + t.heading * len };
        let end = start + t.heading * len;
        let north = n + 1;
        let mut verts = Vec::with_capacity(n as usize);
        for v in 1..=n {
            let p = pm.position(v);
            let a = p.y.atan2(p.x);
            let q = ring_at + (t.left * a.cos() + t.up * a.sin()) * r;
            Self::polar(i, pm.set_position(v, q))?;
            verts.push(v);
        }
        Self::polar(i, pm.set_position(0, start))?;
        let tip = if pole { end } else { ring_at + t.heading * cap(r, len) };
        Self::polar(i, pm.set_position(north, tip))?;
        if self.opts.flat_base {
            // A loop on the root's spokes, laid flat around the root: the foot is a disk.
            let spoke =
                pm.mesh().find_halfedge(0, 1).ok_or_else(|| LsystemError::Internal("no spoke at the root".into()))?;
            let base = Self::polar(i, pm.add_refinement(i64::from(spoke)))?;
            for v in base.vertices {
                let d = pm.position(v) - start;
                let out = (d - t.heading * d.dot(t.heading)).normalize_or_zero();
                Self::polar(i, pm.set_position(v, start + out * r))?;
            }
        }
        st.turtle.position = end;
        let verts = Self::forward_order(&pm, verts, north);
        self.rings.push(Ring {
            used: vec![false; verts.len()],
            verts,
            center: ring_at,
            axis: t.heading,
            radius: r,
            length: len,
        });
        self.branches.push(Branch { tip: north, ring: Some(self.rings.len() - 1), ended: pole.then_some(i) });
        st.branch = Some(self.branches.len() - 1);
        self.root = 0;
        self.mesh = Some(pm);
        Ok(())
    }

    /// Orders a ring so that the side of `tip` lies on the left of `v[j] → v[j + 1]` (the side
    /// [`PolarMesh::add_feature`] opens its gap on).
    fn forward_order(pm: &PolarMesh, mut verts: Vec<u32>, tip: u32) -> Vec<u32> {
        let m = pm.mesh();
        if let Some(h) = m.find_halfedge(verts[0], verts[1]) {
            if !m.face_vertices(m.face(h)).any(|v| v == tip) {
                verts.reverse();
            }
        }
        verts
    }

    /// Nests a branch on ring `host` where the turtle points (sliding window); returns the
    /// branch.
    fn nest(&mut self, i: usize, m: &Module, st: &State, host: usize, r: f64) -> Result<usize, LsystemError> {
        let _ = r;
        if self.features >= self.opts.max_features {
            return Err(LsystemError::GrowthCap {
                what: "the number of nested branches",
                count: self.features,
                cap_name: "max_features",
                cap: self.opts.max_features,
                module: i,
                symbol: m.to_string(),
            });
        }
        let ring = &self.rings[host];
        let pm = self.mesh.as_ref().ok_or_else(|| LsystemError::Internal("nesting before the trunk".into()))?;
        let n = ring.verts.len();
        let dir = across(st.turtle.heading, ring.axis)
            .or_else(|| across(st.turtle.up, ring.axis))
            .unwrap_or_else(|| ring.axis.any_orthonormal_vector());
        let pos: Vec<Vec3> = ring.verts.iter().map(|&v| pm.position(v)).collect();
        // Keep the valence (a run of n/2 + 1) unless the siblings on this loop need room (c
        // siblings get runs of at most n/c, each in its own sector). A run over 135° of its loop
        // wraps round to the parent's sides, where the surface faces along the branch, and the
        // branch's first quads at the gap's ends cross the parent's faces beyond them: a lone
        // branch on a loop without branches gets its run slid to 130° ([`slide_run`]) when the
        // loop allows it; every other run spans at most 3n/8 edges.
        let lone = st.siblings <= 1 && !ring.used.iter().any(|&u| u);
        let wmax = (n / 2 + 1).min(n / st.siblings.max(1)).clamp(3, n - 1);
        let used: Vec<bool> = match &st.sector {
            Some(sec) => ring.used.iter().zip(sec).map(|(&u, &ok)| u || !ok).collect(),
            None => ring.used.clone(),
        };
        // A sector narrower than the run the loop has room for (a sibling took a vertex both
        // could use, or the headings are close): the best-facing free run, as without sectors,
        // so that sectors never cost valence.
        let choose = |wmax: usize| {
            let free = facing_run(&pos, &ring.used, ring.center, dir, wmax);
            facing_run(&pos, &used, ring.center, dir, wmax).filter(|b| free.is_some_and(|f| f.1 == b.1)).or(free)
        };
        // The faces behind the loop, as the edge facing each loop edge across them.
        let behind: Vec<Vec3> = {
            let mm = pm.mesh();
            (0..n)
                .map(|j| {
                    let (a, b) = (ring.verts[j], ring.verts[(j + 1) % n]);
                    mm.find_halfedge(b, a)
                        .map_or(Vec3::ZERO, |h| pm.position(mm.origin(mm.prev(h))) - pm.position(mm.target(mm.next(h))))
                })
                .collect()
        };
        // A lone branch keeps the valence when its run of n/2 + 1 can be slid to 130° with no
        // edge of the loop turning over 60° from the edge facing it behind (as loops round off,
        // [`blend_weights`]): a gap's sharp ends behind a branch's first loop can forbid it.
        let slid = if lone {
            choose(wmax).and_then(|(s, w)| match slide_run(&pos, ring.center, ring.axis, s, w, SPAN) {
                None if star_angles(&pos, ring.center, ring.axis).is_some() => Some((s, w, None)),
                None => None,
                Some(moved) => {
                    let full = blend_weights(&behind, &pos, &moved, 1.0).iter().all(|&x| x == 1.0);
                    full.then_some((s, w, Some(moved)))
                }
            })
        } else {
            None
        };
        // Otherwise a run over 135° would reach round to the parent's sides: at most 3n/8 edges
        // (unless the options ask for wide gaps, as the thesis grew them).
        let narrow = if self.opts.wide_gaps { wmax } else { wmax.min(3 * n / 8 + 1).max(3) };
        let (s, w, moved) = match slid {
            Some(x) => x,
            None => match choose(narrow) {
                Some((s, w)) => (s, w, None),
                None => {
                    return Err(LsystemError::NoRoomForBranch {
                        module: i,
                        symbol: m.to_string(),
                        valence: n,
                        works: None,
                    })
                }
            },
        };
        let run: Vec<u32> = (0..w).map(|j| ring.verts[(s + j) % n]).collect();
        if let Some(moved) = moved {
            let pm = self.mesh.as_mut().ok_or_else(|| LsystemError::Internal("nesting before the trunk".into()))?;
            for (j, p) in moved.into_iter().enumerate() {
                Self::polar(i, pm.set_position(self.rings[host].verts[j], p))?;
            }
        }
        let ring = &self.rings[host];
        let (axis, g) = (ring.axis, 0.3 * ring.radius.min(ring.length));
        let pm = self.mesh.as_mut().ok_or_else(|| LsystemError::Internal("nesting before the trunk".into()))?;
        let pole = Self::polar(i, pm.add_feature(&run))?;
        // The gap's far side. Around the new pole the gap reads v0, v1, …, vk, n(k−1), …, n1
        // (§4.3.2): n_i faces v_i across the gap. Each n_i goes a quarter segment ahead of v_i.
        let far: Vec<(u32, u32)> = {
            let mm = pm.mesh();
            let gap: Vec<u32> = mm.outgoing(pole).map(|h| mm.target(h)).collect();
            let m2 = gap.len();
            let i0 = gap.iter().position(|&v| v == run[0]);
            let Some(i0) = i0.filter(|_| m2 == 2 * (w - 1)) else {
                return Err(LsystemError::Internal(format!(
                    "the gap of the branch at module {i} is not a fan of {} vertices",
                    2 * (w - 1)
                )));
            };
            let fwd = gap[(i0 + 1) % m2] == run[1];
            (1..w - 1)
                .map(|j| {
                    let at = if fwd { (i0 + m2 - j) % m2 } else { (i0 + j) % m2 };
                    (gap[at], run[j])
                })
                .collect()
        };
        let kk = (w - 1) as f64;
        for (j, (v, u)) in far.into_iter().enumerate() {
            // An arch: highest mid-gap, low near the gap's ends, so the gap has no spikes; and
            // never above half the shorter run edge at u, so that no gap edge runs along the
            // axis (where the branch's heading would see it end on and its first loop would
            // get a sliver quad).
            let (a, b) = (pm.position(run[j]), pm.position(run[j + 2]));
            let here = pm.position(u);
            let room = 0.5 * here.distance(a).min(here.distance(b));
            let lift = (g * (std::f64::consts::PI * (j + 1) as f64 / kk).sin()).min(room);
            Self::polar(i, pm.set_position(v, here + axis * lift))?;
        }
        for j in 0..w {
            self.rings[host].used[(s + j) % n] = true;
        }
        self.features += 1;
        self.branches.push(Branch { tip: pole, ring: None, ended: None });
        self.check_caps(i, m)?;
        Ok(self.branches.len() - 1)
    }

    /// One segment at the tip of branch `b`: a new loop (add_refinement on a spoke, then placed)
    /// or, for `P`, the pole moved to the segment's end.
    #[allow(clippy::too_many_arguments)]
    fn segment(
        &mut self,
        i: usize,
        m: &Module,
        st: &mut State,
        b: usize,
        len: f64,
        r: f64,
        pole: bool,
        from_gap: bool,
    ) -> Result<(), LsystemError> {
        if let Some(e) = self.branches[b].ended {
            return Err(LsystemError::DrawAfterPole { module: i, symbol: m.to_string(), ended: e });
        }
        let h = st.turtle.heading;
        let end = st.turtle.position + h * len;
        st.turtle.position = end;
        let tip = self.branches[b].tip;
        let pm = self.mesh.as_mut().ok_or_else(|| LsystemError::Internal("a segment before the trunk".into()))?;
        if pole {
            Self::polar(i, pm.set_position(tip, end))?;
            self.branches[b].ended = Some(i);
            return Ok(());
        }
        let spokes: Vec<u32> = pm.mesh().outgoing(tip).collect();
        let prev_center = crate::math::mean_point(spokes.iter().map(|&x| pm.position(pm.mesh().target(x))));
        let refined = Self::polar(i, pm.add_refinement(i64::from(spokes[0])))?;
        let verts = refined.vertices;
        // The far end of each new vertex's spoke (its neighbour on the previous loop or gap),
        // in ring order. The new circle starts at the first one's direction and turns the way
        // they do around the heading (the sign of their polygon's Newell normal along it), so
        // no quad between the two loops folds.
        let ends: Vec<Vec3> = {
            let mm = pm.mesh();
            verts
                .iter()
                .map(|&v| {
                    let w = mm.outgoing(v).filter(|&x| !pm.is_loop(x)).map(|x| mm.target(x)).find(|&u| u != tip);
                    pm.position(w.unwrap_or(tip))
                })
                .collect()
        };
        // The new circle follows the previous cycle (a loop or a branch's gap), seen along the
        // heading: each end is projected on the plane across the heading, then stretched along
        // the direction in which the cycle is foreshortened (the Newell normal's part across the
        // heading) by 1 / cos of the angle between the normal and the heading (at most 4), so a
        // gap on a parent's side is seen face on, not as a sliver. A projection followed by a
        // symmetric positive stretch keeps every edge's direction within 90° of the original
        // edge (e · S P e = |√S P e|² ≥ 0), so the quads between the two cycles never fold —
        // a rotation of the normal onto the heading does not (it reverses edges near the
        // normal at a gap's narrow ends).
        let nn = ends.len();
        let mut newell = Vec3::ZERO;
        for j in 0..nn {
            newell += (ends[j] - prev_center).cross(ends[(j + 1) % nn] - prev_center);
        }
        // The cycle turns about the heading one way or the other (ring order is topology's);
        // the circle turns the same way, at the phase that best matches every end's direction.
        let sign = if newell.dot(h) < 0.0 { -1.0 } else { 1.0 };
        let (squash, stretch) = match (newell * sign).try_normalize() {
            Some(nrm) => (across(nrm, h).unwrap_or(Vec3::ZERO), 1.0 / nrm.dot(h).max(0.25)),
            None => (Vec3::ZERO, 1.0),
        };
        let view = |e: Vec3| {
            let q = e - prev_center;
            let q = q - h * q.dot(h);
            q + squash * (q.dot(squash) * (stretch - 1.0))
        };
        // The new loop blends two placements: the previous cycle seen along the heading and
        // scaled to radius `r` (its "shape": every edge parallel to the previous cycle's edge
        // seen along the heading, so no quad between the two twists, whatever the cycle's
        // shape), and a circle of radius `r` (each vertex at its end's own direction where the
        // seen cycle is star-shaped about its centre, else at its arc-length fraction from the
        // best phase). A branch's first loop takes at most ROUND_FIRST of the circle (it starts
        // from its gap's shape), later loops at most ROUND, each vertex less where a quad would
        // fold ([`rounding`]). So a branch rounds off over a few loops and no quad folds.
        let qs: Vec<Vec3> = ends.iter().map(|&e| view(e)).collect();
        let mean = qs.iter().map(|q| q.length()).sum::<f64>() / nn as f64;
        let b1 = h.any_orthonormal_vector();
        let b2 = h.cross(b1);
        // Star-shaped about the centre, turning the cycle's way: every step turns forwards (by
        // less than half a turn) and the cycle winds once, crossing the ray along b1 once —
        // without an angle (no trigonometry on the common path).
        let turns_on = (0..nn).all(|j| sign * qs[j].cross(qs[(j + 1) % nn]).dot(h) > 0.0);
        let crossings = (0..nn)
            .filter(|&j| {
                let (y0, y1) = (sign * qs[j].dot(b2), sign * qs[(j + 1) % nn].dot(b2));
                y0 < 0.0 && y1 >= 0.0
            })
            .count();
        let circle: Vec<Vec3> = if turns_on && crossings == 1 {
            qs.iter().map(|q| q.normalize() * r).collect()
        } else {
            let mut arc = Vec::with_capacity(nn + 1);
            arc.push(0.0);
            for j in 0..nn {
                arc.push(arc[j] + ends[j].distance(ends[(j + 1) % nn]));
            }
            let total = arc[nn];
            let frac = |j: usize| if total > 0.0 { arc[j] / total } else { j as f64 / nn as f64 };
            // The phase that best matches every end's own direction (a circular mean).
            let (mut sx, mut sy) = (0.0, 0.0);
            for (j, q) in qs.iter().enumerate() {
                let d = q.dot(b2).atan2(q.dot(b1)) - sign * std::f64::consts::TAU * frac(j);
                sx += d.cos();
                sy += d.sin();
            }
            let phase = sy.atan2(sx);
            (0..nn)
                .map(|j| {
                    let a = phase + sign * std::f64::consts::TAU * frac(j);
                    (b1 * a.cos() + b2 * a.sin()) * r
                })
                .collect()
        };
        let shape: Vec<Vec3> = if mean > 0.0 { qs.iter().map(|q| *q * (r / mean)).collect() } else { circle.clone() };
        let w = rounding(&ends, &shape, &circle, if from_gap { ROUND_FIRST } else { ROUND });
        for (j, &v) in verts.iter().enumerate() {
            Self::polar(i, pm.set_position(v, end + shape[j] * (1.0 - w[j]) + circle[j] * w[j]))?;
        }
        Self::polar(i, pm.set_position(tip, end + h * cap(r, len)))?;
        let verts = Self::forward_order(pm, verts, tip);
        self.rings.push(Ring { used: vec![false; nn], verts, center: end, axis: h, radius: r, length: len });
        self.branches[b].ring = Some(self.rings.len() - 1);
        self.check_caps(i, m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::SplitMix64;

    /// The run by brute force: every length from `w_max` down, every start, each centroid summed
    /// afresh (O(n²·w)).
    fn brute_force(pos: &[Vec3], used: &[bool], center: Vec3, dir: Vec3, w_max: usize) -> Option<(usize, usize)> {
        let n = pos.len();
        for w in (3..=w_max).rev() {
            let mut top: Option<(f64, usize)> = None;
            for s in 0..n {
                if (0..w).any(|j| used[(s + j) % n]) {
                    continue;
                }
                let c = (0..w).map(|j| pos[(s + j) % n]).sum::<Vec3>() / w as f64;
                let score = (c - center).dot(dir);
                if top.is_none_or(|(t, _)| score > t + 1e-12) {
                    top = Some((score, s));
                }
            }
            if let Some((_, s)) = top {
                return Some((s, w));
            }
        }
        None
    }

    /// Two siblings' runs by brute force: every pair of disjoint free runs of `w`, the worse
    /// cosine first, then the sum (O(n²·w)).
    fn paired_brute_force(pos: &[Vec3], used: &[bool], dirs: [Vec3; 2], w: usize) -> Option<(f64, f64)> {
        let n = pos.len();
        let cosine = |s: usize, d: Vec3| {
            let c = (0..w).map(|j| pos[(s + j) % n]).sum::<Vec3>() / w as f64;
            across(c, Vec3::Z).map(|c| c.dot(d))
        };
        let free = |s: usize| (0..w).all(|j| !used[(s + j) % n]);
        let mut best: Option<(f64, f64)> = None;
        for s1 in (0..n).filter(|&s| free(s)) {
            for t in 0..=n - 2 * w {
                let s2 = (s1 + w + t) % n;
                let (Some(a), Some(b)) = (cosine(s1, dirs[0]), cosine(s2, dirs[1])) else { continue };
                if !free(s2) {
                    continue;
                }
                let (worse, total) = (a.min(b), a + b);
                if best.is_none_or(|(bw, bt)| worse > bw + 1e-12 || (worse > bw - 1e-12 && total > bt + 1e-12)) {
                    best = Some((worse, total));
                }
            }
        }
        best
    }

    /// `n` vertices around the origin in the xy-plane, radii wobbling by up to 0.3 when `wobbly`,
    /// heights random up to `lift`.
    fn random_loop(rng: &mut SplitMix64, n: usize, wobbly: bool, lift: f64) -> Vec<Vec3> {
        (0..n)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / n as f64;
                let r = 1.0 + 0.3 * rng.next_f64() * f64::from(u8::from(wobbly));
                Vec3::new(a.cos() * r, a.sin() * r, lift * rng.next_f64())
            })
            .collect()
    }

    #[test]
    fn paired_runs_are_the_brute_force_choice() {
        let mut rng = SplitMix64::new(5);
        let mut found = 0;
        for case in 0..400 {
            let n = 6 + (rng.next_u64() % 30) as usize;
            let pos = random_loop(&mut rng, n, case % 2 == 1, 0.0);
            let used: Vec<bool> = (0..n).map(|_| rng.next_f64() < 0.05 * (case % 3) as f64).collect();
            let mut dir = || {
                let a = std::f64::consts::TAU * rng.next_f64();
                Vec3::new(a.cos(), a.sin(), 0.0)
            };
            let dirs = [dir(), dir()];
            let w = 3 + (rng.next_u64() % (n as u64 / 2 - 2)) as usize;
            let got = paired_runs(&pos, &used, Vec3::ZERO, Vec3::Z, dirs, w);
            let want = paired_brute_force(&pos, &used, dirs, w);
            assert_eq!(got.is_some(), want.is_some(), "case {case}: n {n}, w {w}");
            if let (Some(sec), Some((worse, total))) = (got, want) {
                found += 1;
                // Each sector is one free run of w; the pair scores as the brute force's best.
                let score = |k: usize| {
                    assert_eq!(sec[k].iter().filter(|&&x| x).count(), w);
                    assert!((0..n).all(|v| !(sec[k][v] && used[v])));
                    let c = (0..n).filter(|&v| sec[k][v]).map(|v| pos[v]).sum::<Vec3>();
                    across(c, Vec3::Z).unwrap().dot(dirs[k])
                };
                let (a, b) = (score(0), score(1));
                assert!((0..n).all(|v| !(sec[0][v] && sec[1][v])), "case {case}: runs overlap");
                assert!((a.min(b) - worse).abs() < 1e-9 && (a + b - total).abs() < 1e-9, "case {case}");
            }
        }
        assert!(found > 200, "{found} cases with a pair");
    }

    #[test]
    fn the_facing_run_is_the_brute_force_choice() {
        let mut rng = SplitMix64::new(7);
        for case in 0..400 {
            let n = 6 + (rng.next_u64() % 40) as usize;
            // Some vertices used by branches in three cases of four.
            let pos = random_loop(&mut rng, n, case % 2 == 1, 0.2);
            let used: Vec<bool> = (0..n).map(|_| rng.next_f64() < 0.1 * (case % 4) as f64).collect();
            let a = std::f64::consts::TAU * rng.next_f64();
            let dir = Vec3::new(a.cos(), a.sin(), 0.0);
            let w_max = (3 + (rng.next_u64() % (n as u64 - 3))) as usize;
            let got = facing_run(&pos, &used, Vec3::ZERO, dir, w_max);
            assert_eq!(got, brute_force(&pos, &used, Vec3::ZERO, dir, w_max), "case {case}: n {n}, used {used:?}");
            if let Some((s, w)) = got {
                // The run is free; on a round loop without branches it centres on the heading
                // (to within one vertex step).
                assert!((0..w).all(|j| !used[(s + j) % n]));
                if case % 4 == 0 {
                    let c = (0..w).map(|j| pos[(s + j) % n]).sum::<Vec3>();
                    let off = c.y.atan2(c.x) - a;
                    let off = (off + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
                    assert!(
                        off.abs() < 2.0 * std::f64::consts::TAU / n as f64,
                        "case {case}: run centred {off} rad off"
                    );
                }
            }
        }
    }
}
