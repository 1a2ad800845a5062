// edge_op_orbits.rs — vertex-orbit scans for `split_pinched_verts` and
// `dedupe_edges` (edge_op.rs): the owner search that lets both run in
// parallel, and the per-orbit duplicate search they share.

use crate::impl_mesh::ManifoldImpl;
use crate::types::{next_halfedge, Halfedge};

// Both scans walk each vertex orbit (stepping `next_halfedge(paired_halfedge)`)
// once, from its smallest eligible halfedge, its owner, using visited flags in
// ascending order. C++ runs both in parallel (edge_op.cpp:722-796, 903-924).
//
// If every orbit is a closed cycle, a halfedge owns its orbit iff its walk
// returns to it without meeting a smaller eligible halfedge. If
// `paired_halfedge` is an involution the step is injective, so a walk either
// returns to its start or reaches a halfedge with no pair, which an open
// orbit's smallest eligible halfedge must do. Otherwise, or on an open orbit,
// the callers fall back to their sequential scans.
//
// Walking a whole orbit from every eligible halfedge costs the sum of the
// squared orbit lengths, Θ(n²) for one high-valence vertex. So the parallel
// walks stop after `ORBIT_WALK_CAP` steps, and the orbits they leave
// unresolved are settled by one sequential visited-flag pass, which walks
// each such orbit once. Why the owners are still exactly the sequential
// scan's, in its order, given closed orbits:
//
// - An orbit of length L <= cap: every walk from an eligible halfedge returns
//   to its start within L steps unless it first meets a smaller eligible one,
//   so the walks alone mark exactly its smallest eligible halfedge owner.
// - An orbit of length L > cap: no walk returns within the cap. A walk from a
//   halfedge that is not the smallest eligible one ends `NOT_OWNER` or
//   `UNRESOLVED`; the walk from the smallest one meets nothing smaller and
//   ends `UNRESOLVED`. So the orbit's `UNRESOLVED` halfedges are eligible and
//   include its smallest eligible halfedge, which is therefore the smallest
//   `UNRESOLVED` one. The ascending pass reaches it first, makes it the owner
//   and marks the whole orbit visited, so no other halfedge of the orbit
//   becomes an owner.
// - The pass walks only from `UNRESOLVED` halfedges, and a walk never leaves
//   its orbit, so short orbits keep the roles their walks gave them.
//
// Every orbit with an eligible halfedge thus has exactly one owner, its
// smallest eligible halfedge, as in the sequential scan, and the owners are
// collected ascending, the order in which that scan reaches them. An open
// orbit with an eligible halfedge is still caught: its smallest eligible
// halfedge's walk meets no smaller one, so it either reaches the open end
// (`OPEN`) or the cap, and then the pass reaches it first and its full walk
// reaches the open end.

/// Halfedge count from which the orbit scans run in parallel. Above C++'s 1e4:
/// every halfedge walks its own orbit, and below 100k that costs more than it saves.
pub(super) const ORBIT_PAR_THRESHOLD: usize = 10_000;

/// Steps after which a parallel orbit walk stops and leaves its orbit to the
/// sequential pass. Vertex valences rarely exceed it, so that pass is usually
/// empty, and it bounds the parallel work at 64 steps per halfedge.
pub(super) const ORBIT_WALK_CAP: usize = 64;

const NOT_OWNER: u8 = 0;
const OWNER: u8 = 1;
const OPEN: u8 = 2;
const UNRESOLVED: u8 = 3;

/// The owner of every orbit with an eligible halfedge, ascending, or `None`
/// below `threshold` or if an orbit is not a closed cycle.
pub(super) fn orbit_owners<F>(
    halfedge: &[Halfedge],
    threshold: usize,
    eligible: F,
) -> Option<Vec<usize>>
where
    F: Fn(&Halfedge) -> bool + Sync + Send,
{
    let n = halfedge.len();
    if n < threshold || !cfg!(feature = "parallel") {
        return None;
    }
    let paired_back = crate::par::maybe_par_filter(n, threshold, |i| {
        let p = halfedge[i].paired_halfedge;
        p >= 0 && (p as usize >= n || halfedge[p as usize].paired_halfedge != i as i32)
    });
    if !paired_back.is_empty() {
        return None;
    }
    // blocksmith patch (PATCHES.md, 4): with no pinched vertex, in O(n).
    if let Some(owners) = vertex_owners(halfedge, threshold, &eligible) {
        return Some(owners);
    }
    // The step from `current`, or `None` at an open end (no pair, or a count
    // not a multiple of 3): those cases are left to the sequential scan.
    let step = |current: usize| -> Option<usize> {
        let p = halfedge[current].paired_halfedge;
        if p < 0 {
            return None;
        }
        let next = next_halfedge(p) as usize;
        (next < n).then_some(next)
    };
    let mut role: Vec<u8> = crate::par::maybe_par_map(n, threshold, |i| {
        if !eligible(&halfedge[i]) {
            return NOT_OWNER;
        }
        let mut current = i;
        for _ in 0..ORBIT_WALK_CAP {
            let Some(next) = step(current) else {
                return OPEN;
            };
            current = next;
            if current == i {
                return OWNER;
            }
            if current < i && eligible(&halfedge[current]) {
                return NOT_OWNER;
            }
        }
        UNRESOLVED
    });
    if role.contains(&OPEN) {
        return None;
    }
    // The sequential pass over the orbits longer than the cap (see above).
    let unresolved: Vec<usize> = (0..n).filter(|&i| role[i] == UNRESOLVED).collect();
    if !unresolved.is_empty() {
        let mut visited = vec![false; n];
        for i in unresolved {
            if visited[i] {
                role[i] = NOT_OWNER;
                continue;
            }
            role[i] = OWNER;
            let mut current = i;
            loop {
                visited[current] = true;
                current = step(current)?;
                if current == i {
                    break;
                }
            }
        }
    }
    Some((0..n).filter(|&i| role[i] == OWNER).collect())
}

/// blocksmith patch (PATCHES.md, 4). The owners when no vertex is pinched, in
/// O(n) rather than the walks' O(sum of squared valences): each vertex's
/// smallest eligible halfedge, when its orbit is closed and holds every
/// eligible halfedge leaving that vertex, and only those. Then every orbit
/// with an eligible halfedge is such a vertex's orbit (its eligible halfedges
/// all leave one vertex, whose first orbit holds them all), and that vertex's
/// smallest eligible halfedge is the orbit's: the owners the walks find.
/// `None` when any vertex fails the test (a pinched vertex, an open orbit, an
/// eligible halfedge with no start vertex), left to the walks. Called with the
/// pairing already checked to be an involution, so a walk either closes or
/// ends at a halfedge with no pair.
fn vertex_owners<F>(halfedge: &[Halfedge], threshold: usize, eligible: &F) -> Option<Vec<usize>>
where
    F: Fn(&Halfedge) -> bool + Sync + Send,
{
    let n = halfedge.len();
    let num_vert = halfedge.iter().map(|h| h.start_vert).max().unwrap_or(-1) + 1;
    let num_vert = usize::try_from(num_vert).ok()?;
    // Each vertex's smallest eligible halfedge and how many eligible ones leave it.
    let mut first = vec![u32::MAX; num_vert];
    let mut degree = vec![0u32; num_vert];
    for (i, h) in halfedge.iter().enumerate() {
        if eligible(h) {
            let v = usize::try_from(h.start_vert).ok()?;
            if first[v] == u32::MAX {
                first[v] = i as u32;
            }
            degree[v] += 1;
        }
    }
    let one_orbit = crate::par::maybe_par_map(num_vert, threshold / 4, |v| {
        let start = first[v] as usize;
        if first[v] == u32::MAX {
            return true;
        }
        let mut count = 0u32;
        let mut current = start;
        for _ in 0..n {
            let h = &halfedge[current];
            if eligible(h) {
                if h.start_vert as usize != v {
                    return false;
                }
                count += 1;
            }
            let p = h.paired_halfedge;
            if p < 0 {
                return false;
            }
            current = next_halfedge(p) as usize;
            if current >= n {
                return false;
            }
            if current == start {
                return count == degree[v];
            }
        }
        false
    });
    if !one_orbit.iter().all(|&ok| ok) {
        return None;
    }
    let mut owner = vec![false; n];
    for &f in first.iter().filter(|&&f| f != u32::MAX) {
        owner[f as usize] = true;
    }
    Some((0..n).filter(|&i| owner[i]).collect())
}

/// Halfedges, or vertices, per parallel piece of [`orbits_clean`]'s scatter and walks.
const CLEAN_RUN: usize = 4096;

/// The end vertices [`orbits_clean`] searches for a repeat as it walks an orbit; a longer
/// orbit's are sorted once it closes (a search per step would be quadratic in the valence).
pub(super) const CLEAN_SEARCHED: usize = 32;

/// Whether `cleanup_topology` has nothing to do on `halfedge` (over `num_vert`
/// vertices): every halfedge has both its vertices, the pairing is an
/// involution, the halfedges leaving each vertex form one closed orbit (no
/// pinched vertex to split) and no two of an orbit end at the same vertex (no
/// duplicate edge). Both of its scans are then no-ops, with the same result,
/// so the common case, a boolean's result or an import with nothing to
/// repair, is told in two parallel passes: each vertex is given some halfedge
/// leaving it, and each vertex's orbit is walked once from it, checking as it
/// goes. `false` sends the caller to the scans, which repair what is wrong.
/// blocksmith patch (PATCHES.md, 24): the scans' owner search, their
/// involution check and the duplicate search each walked every orbit.
///
/// Which halfedge a vertex is given depends on the threads (the last store
/// wins), the answer does not: walks that all close, visiting only their own
/// vertex's halfedges, each at most once (a walk that entered a loop not
/// through its start would pass two halfedges with one pair, failing the
/// involution check at one of them), are disjoint, and visit `n` halfedges in
/// all exactly when every halfedge is in its vertex's one orbit, whichever
/// halfedge each started from.
pub(super) fn orbits_clean(halfedge: &[Halfedge], num_vert: usize, threshold: usize) -> bool {
    use std::sync::atomic::{AtomicU32, Ordering};
    let n = halfedge.len();
    if n >= u32::MAX as usize || num_vert >= i32::MAX as usize {
        return false;
    }
    let start: Vec<AtomicU32> = (0..num_vert).map(|_| AtomicU32::new(u32::MAX)).collect();
    let runs = n.div_ceil(CLEAN_RUN);
    let in_range = |v: i32| v >= 0 && (v as usize) < num_vert;
    let scattered = crate::par::maybe_par_map(runs, threshold / CLEAN_RUN, |r| {
        let first = r * CLEAN_RUN;
        halfedge[first..(first + CLEAN_RUN).min(n)].iter().zip(first..).all(|(h, i)| {
            let ok = in_range(h.start_vert) && in_range(h.end_vert);
            if ok {
                start[h.start_vert as usize].store(i as u32, Ordering::Relaxed);
            }
            ok
        })
    });
    if !scattered.iter().all(|&ok| ok) {
        return false;
    }
    let start: Vec<u32> = start.into_iter().map(AtomicU32::into_inner).collect();
    // The halfedges each vertex's walk visits, or `None` if a check fails.
    let walk = |v: usize, end_verts: &mut Vec<i32>| -> Option<usize> {
        let first = start[v] as usize;
        if start[v] == u32::MAX {
            return Some(0);
        }
        end_verts.clear();
        let mut current = first;
        for count in 1..=n {
            let h = &halfedge[current];
            if h.start_vert as usize != v {
                return None;
            }
            // A repeated end vertex, by search up to the usual valences, by sort beyond.
            if end_verts.len() < CLEAN_SEARCHED && end_verts.contains(&h.end_vert) {
                return None;
            }
            end_verts.push(h.end_vert);
            let pair = usize::try_from(h.paired_halfedge).ok().filter(|&p| p < n)?;
            if halfedge[pair].paired_halfedge as usize != current {
                return None;
            }
            current = next_halfedge(pair as i32) as usize;
            if current >= n {
                return None;
            }
            if current == first {
                if end_verts.len() > CLEAN_SEARCHED {
                    end_verts.sort_unstable();
                    if end_verts.windows(2).any(|w| w[0] == w[1]) {
                        return None;
                    }
                }
                return Some(count);
            }
        }
        None
    };
    let vert_runs = num_vert.div_ceil(CLEAN_RUN);
    let visited = crate::par::maybe_par_map(vert_runs, threshold / CLEAN_RUN, |r| {
        let mut end_verts = Vec::with_capacity(16);
        (r * CLEAN_RUN..((r + 1) * CLEAN_RUN).min(num_vert)).try_fold(0usize, |sum, v| Some(sum + walk(v, &mut end_verts)?))
    });
    visited.into_iter().try_fold(0usize, |sum, c| Some(sum + c?)) == Some(n)
}

/// Appends the duplicate edges of the orbit walked from `i`, in walk order:
/// halfedges whose end vertex a smaller halfedge of the orbit also ends at.
/// `mark` sees each halfedge the walk visits.
pub(super) fn dedupe_orbit(
    mesh: &ManifoldImpl,
    i: usize,
    n_edges: usize,
    mut mark: impl FnMut(usize),
    duplicates: &mut Vec<usize>,
) {
    // Track all endVerts seen in this vertex's orbit, keeping smallest edge idx.
    // Uses ForVert traversal: current = next_halfedge(halfedge[current].paired_halfedge)
    // blocksmith patch (PATCHES.md, 9): on the stack up to `EndVerts::INLINE` entries.
    let mut end_verts = EndVerts::new(); // (endVert, min_edge_idx)
                                         // Process i itself first
    mark(i);
    let c_ev0 = mesh.halfedge[i].end_vert;
    if c_ev0 >= 0 {
        end_verts.push((c_ev0, i));
    }
    // Then orbit (with safety bound to prevent infinite loops)
    let mut current = i;
    let mut orbit_steps = 0;
    loop {
        let pair = mesh.halfedge[current].paired_halfedge;
        if pair < 0 {
            break;
        }
        current = next_halfedge(pair) as usize;
        if current == i {
            break;
        }
        orbit_steps += 1;
        if orbit_steps > n_edges {
            break;
        } // safety
        mark(current);
        let c_sv = mesh.halfedge[current].start_vert;
        let c_ev = mesh.halfedge[current].end_vert;
        if c_sv >= 0 && c_ev >= 0 {
            if let Some(entry) = end_verts
                .as_mut_slice()
                .iter_mut()
                .find(|(v, _)| *v == c_ev)
            {
                if current < entry.1 {
                    entry.1 = current;
                }
            } else {
                end_verts.push((c_ev, current));
            }
        }
    }

    // Second pass: find edges that aren't the minimum for their endVert
    let c_ev0 = mesh.halfedge[i].end_vert;
    if c_ev0 >= 0 {
        if let Some(&(_, min_edge)) = end_verts.as_mut_slice().iter().find(|(v, _)| *v == c_ev0) {
            if min_edge != i {
                duplicates.push(i);
            }
        }
    }
    current = i;
    orbit_steps = 0;
    loop {
        let pair = mesh.halfedge[current].paired_halfedge;
        if pair < 0 {
            break;
        }
        current = next_halfedge(pair) as usize;
        if current == i {
            break;
        }
        orbit_steps += 1;
        if orbit_steps > n_edges {
            break;
        } // safety
        let c_ev = mesh.halfedge[current].end_vert;
        if c_ev >= 0 {
            if let Some(&(_, min_edge)) = end_verts.as_mut_slice().iter().find(|(v, _)| *v == c_ev) {
                if min_edge != current {
                    duplicates.push(current);
                }
            }
        }
    }
}

/// The (end vertex, smallest halfedge) pairs of one orbit in [`dedupe_orbit`], in the order
/// found: held on the stack up to [`EndVerts::INLINE`] pairs (a vertex's valence; 6 on most
/// meshes) and moved to the heap beyond. blocksmith patch (PATCHES.md, 9): a `Vec` per orbit
/// grew through two reallocations for a vertex of valence 6, an allocation, two copies and a
/// free for every vertex of every import and boolean.
struct EndVerts {
    inline: [(i32, usize); EndVerts::INLINE],
    len: usize,
    heap: Vec<(i32, usize)>,
}

impl EndVerts {
    const INLINE: usize = 32;

    fn new() -> Self {
        EndVerts { inline: [(0, 0); EndVerts::INLINE], len: 0, heap: Vec::new() }
    }

    fn push(&mut self, entry: (i32, usize)) {
        if self.len < EndVerts::INLINE {
            self.inline[self.len] = entry;
        } else {
            if self.len == EndVerts::INLINE {
                self.heap.extend_from_slice(&self.inline);
            }
            self.heap.push(entry);
        }
        self.len += 1;
    }

    fn as_mut_slice(&mut self) -> &mut [(i32, usize)] {
        if self.len <= EndVerts::INLINE {
            &mut self.inline[..self.len]
        } else {
            &mut self.heap
        }
    }
}
