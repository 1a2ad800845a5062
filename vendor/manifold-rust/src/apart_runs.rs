// apart_runs.rs — the parts of a mesh composed of parts apart (blocksmith patch (PATCHES.md,
// 26)), for the boolean's steps that go edge by edge in index order and can then go part by
// part in parallel with the same result.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::impl_mesh::ManifoldImpl;

/// One part of a mesh that shares no vertex and no edge with the others: its triangles and the
/// vertices they use, each a contiguous range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct ApartRun {
    pub faces: Range<usize>,
    pub verts: Range<usize>,
}

/// Half-edges from which a mesh's parts are looked for and worked on in parallel.
const RUNS_PAR_THRESHOLD: usize = 10_000;

/// Set by tests to take the one-run path everywhere, for comparing the two.
static ONE_RUN_ONLY: AtomicBool = AtomicBool::new(false);

/// The parts of `mesh` when it is a composition of parts apart (`Manifold::compose_apart`,
/// patch 16, whose collider keeps each part's first triangle, patch 20) and is large enough to
/// gain from them; `None` otherwise. The collider only suggests where parts start: the mesh's
/// half-edges are checked, in parallel, to stay in their part (vertices and pairs) and the
/// parts' vertices to come in order, so a mesh changed since its composition, or any other,
/// gives `None` or parts that are true.
pub(crate) fn apart_runs(mesh: &ManifoldImpl) -> Option<Vec<ApartRun>> {
    if ONE_RUN_ONLY.load(Ordering::Relaxed) {
        return None;
    }
    parts_apart(mesh)
}

/// [`apart_runs`] whatever tests ask of it (see [`set_one_run_only`]).
fn parts_apart(mesh: &ManifoldImpl) -> Option<Vec<ApartRun>> {
    let n = mesh.halfedge.len();
    if n < RUNS_PAR_THRESHOLD || n % 3 != 0 {
        return None;
    }
    let mut starts = mesh.collider.part_first_leaves()?;
    let num_tri = n / 3;
    if starts.len() < 2 || starts[0] != 0 || starts.iter().any(|&s| s >= num_tri) {
        return None;
    }
    starts.push(num_tri);
    if starts.windows(2).any(|w| w[0] >= w[1]) {
        return None;
    }
    let num_vert = mesh.vert_pos.len();
    // Each part's vertex range, if its half-edges stay in the part.
    let verts: Vec<Option<Range<usize>>> = crate::par::maybe_par_map(starts.len() - 1, 2, |k| {
        let edges = 3 * starts[k]..3 * starts[k + 1];
        let (mut lo, mut hi) = (usize::MAX, 0usize);
        for h in &mesh.halfedge[edges.clone()] {
            let (s, e, p) = (h.start_vert, h.end_vert, h.paired_halfedge);
            if s < 0 || e < 0 || p < 0 || !edges.contains(&(p as usize)) {
                return None;
            }
            let (s, e) = (s as usize, e as usize);
            lo = lo.min(s).min(e);
            hi = hi.max(s).max(e);
        }
        (hi < num_vert).then_some(lo..hi + 1)
    });
    let verts: Vec<Range<usize>> = verts.into_iter().collect::<Option<_>>()?;
    if verts.windows(2).any(|w| w[0].end > w[1].start) {
        return None;
    }
    Some(starts.windows(2).zip(verts).map(|(f, verts)| ApartRun { faces: f[0]..f[1], verts }).collect())
}

/// Makes [`apart_runs`] find none, or find them again; for tests comparing the two paths
/// (both give the same results, so another test running meanwhile is not disturbed).
#[cfg(test)]
pub(crate) fn set_one_run_only(on: bool) {
    ONE_RUN_ONLY.store(on, Ordering::Relaxed);
}

#[cfg(test)]
#[path = "apart_runs_tests.rs"]
mod tests;
