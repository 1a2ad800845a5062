// par.rs — determinism-preserving parallel execution helpers
//
// Mirrors the C++ `autoPolicy` pattern (parallel.h): each site opts into
// parallelism above a size threshold, staying sequential for small inputs.
// Unlike upstream MANIFOLD_PAR (which allows nondeterministic vertex order in
// some phases), only sites whose output is provably identical to the
// sequential build are parallelized — per-index maps with indexed writes, and
// collect-then-sort pipelines whose final sort is a total order. This keeps
// the `parallel` feature bit-exact with the sequential reference.
//
// The sites, with the size at which each goes parallel (manifold-sharp's
// Par.cs mirrors this list; keep it current):
//   face_op.rs            `calculate_vert_normals`, per-vertex map    10,000 verts
//   face_op_triangulate.rs `face2tri_ct` triangulation of the faces
//                         of over four edges, map_each_ct           2 faces
//                         `face2tri` writes, runs of 4,096 faces into
//                         disjoint `split_at_mut` slices             2 runs
//   boolean3_kernels.rs   `intersect12` query map_ct; result stable
//                         sort and gathers                           10,000
//                         `winding03` per-vert winding query map_ct  1,000 verts
//   manifold_meshgl_export.rs `get_mesh_halfedges` gathers, runs of
//                         4,096 triangles (`concatenated`)            10,000 triangles
//   boolean3_kernels.rs   `winding03` unions, one task per part of an
//                         operand of parts apart (`apart_runs`)        10,000 halfedges
//   boolean_result.rs     `append_whole_edges_in_parts`, one task
//                         per part, each its own output slices        10,000 halfedges
//   apart_runs.rs         the parts' check, one task per part          10,000 halfedges
//   boolean_result.rs     `EdgeGroups::new` stable sort of the
//                         AddNewEdgeVerts edge lists                 10,000 entries
//   sort.rs               `sort_geometry`: Morton codes, stable sorts,
//                         vertex/face/halfedge/tangent gathers        100,000
//                         (PAR_THRESHOLD; per-call n is verts, tris
//                         or 3 * tris)
//   edge_op.rs            edge-flag scans of `collapse_short_edges`,
//                         `collapse_colinear_edges`, `swap_degenerates`
//                         (filter; collapses/swaps stay sequential)  100,001 halfedges
//                                                                    (FLAG_PAR_THRESHOLD)
//   edge_op_orbits.rs     `orbit_owners` for `split_pinched_verts` and
//                         `dedupe_edges` (walks capped at 64 steps,
//                         then one sequential pass)                  100,001 halfedges
//                                                                    (ORBIT_PAR_THRESHOLD)
//                         `dedupe_edges` per-owner orbit map         12,500 owners
//                         `orbits_clean`: a half-edge per vertex
//                         (relaxed stores, any one will do) and a
//                         walk per vertex, runs of 4,096; a boolean
//                         whichever half-edges the stores kept      2 runs
//   sdf.rs                level-set voxel evaluation                 10,000 voxels
//   minkowski.rs          per-face hull maps                         8
//   robust/intersection_graph.rs (via progress.rs) map_ct stages     64 / 16
//   robust/soup.rs        `compute_self_intersections` rows, any_ct 1,000 triangles
//
// One site is an existential "any" rather than a map: `maybe_par_any_ct`, the
// Auto engine's self-intersection pre-check
// (robust/soup.rs `compute_self_intersections`, rows of 1,000+ triangles).
// It returns no array but a boolean identical to the sequential loop's,
// because "some index hits" does not depend on which index is found first or
// how many ran (see its doc). Shared with manifold-sharp's
// `Par.MaybeParAnyCt` (its commit 1d9162c).

// blocksmith patch (PATCHES.md, 7): every parallel section runs `outside` a
// cancellation scope (see cancel.rs), so a task a waiting thread steals never
// sees the scope of the operation that thread was running. The maps, filters
// and for-eaches hand their items the scope's token instead: once it is
// cancelled the remaining items are skipped, and the section unwinds on its
// calling thread, so nothing reads the skipped items' results.

/// Map `f` over `0..n`, in parallel when the `parallel` feature is enabled and
/// `n >= threshold`. Results are returned in index order either way.
#[cfg(feature = "parallel")]
pub fn maybe_par_map<T, F>(n: usize, threshold: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    use rayon::prelude::*;
    if n >= threshold {
        match crate::cancel::scope() {
            None => crate::cancel::outside(|| (0..n).into_par_iter().map(f).collect()),
            // blocksmith patch (PATCHES.md, 10): an item that sees the token cancelled
            // unwinds (rayon carries the unwind to this thread, and on to `cancellable`),
            // so the collect stays indexed: one exact allocation written in place, where
            // collecting `Option<T>`s into an `Option<Vec<T>>` made rayon gather growing
            // pieces and copy them together.
            Some(t) => crate::cancel::outside(|| {
                (0..n)
                    .into_par_iter()
                    .map(|i| {
                        if t.is_cancelled() {
                            crate::cancel::unwind();
                        }
                        f(i)
                    })
                    .collect()
            }),
        }
    } else {
        (0..n).map(f).collect()
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_map<T, F>(n: usize, _threshold: usize, f: F) -> Vec<T>
where
    F: Fn(usize) -> T,
{
    (0..n).map(f).collect()
}

/// The indices in `0..n` where `pred` holds, ascending, testing in parallel
/// when `n >= threshold`: the flag half of C++ `FlagStore::run_par`
/// (edge_op.cpp:54-84). rayon's `collect` keeps the order, so unlike C++ no
/// sort is needed.
#[cfg(feature = "parallel")]
pub fn maybe_par_filter<F>(n: usize, threshold: usize, pred: F) -> Vec<usize>
where
    F: Fn(usize) -> bool + Sync + Send,
{
    use rayon::prelude::*;
    if n >= threshold {
        let scope = crate::cancel::scope();
        let cancelled = || scope.as_ref().is_some_and(|t| t.is_cancelled());
        let kept = crate::cancel::outside(|| (0..n).into_par_iter().filter(|&i| !cancelled() && pred(i)).collect());
        if cancelled() {
            crate::cancel::unwind();
        }
        kept
    } else {
        (0..n).filter(|&i| pred(i)).collect()
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_filter<F>(n: usize, _threshold: usize, pred: F) -> Vec<usize>
where
    F: Fn(usize) -> bool,
{
    (0..n).filter(|&i| pred(i)).collect()
}

/// A stable sort by key, in parallel when `v.len() >= threshold`. A stable
/// sort is determined by the keys and input order, so rayon's gives the same
/// slice, provided `key` is a total order.
#[cfg(feature = "parallel")]
pub fn maybe_par_sort_by_key<T, K, F>(v: &mut [T], threshold: usize, key: F)
where
    T: Send,
    K: Ord,
    F: Fn(&T) -> K + Sync,
{
    use rayon::prelude::*;
    if v.len() >= threshold {
        crate::cancel::outside(|| v.par_sort_by_key(key));
    } else {
        v.sort_by_key(key);
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_sort_by_key<T, K, F>(v: &mut [T], _threshold: usize, key: F)
where
    K: Ord,
    F: Fn(&T) -> K,
{
    v.sort_by_key(key);
}

/// Run `f` on every item, in parallel when `items.len() >= threshold`. Items
/// must own disjoint output, so the run order cannot change what is written.
#[cfg(feature = "parallel")]
pub fn maybe_par_for_each<T, F>(items: Vec<T>, threshold: usize, f: F)
where
    T: Send,
    F: Fn(T) + Sync + Send,
{
    use rayon::prelude::*;
    if items.len() >= threshold {
        let scope = crate::cancel::scope();
        let cancelled = || scope.as_ref().is_some_and(|t| t.is_cancelled());
        crate::cancel::outside(|| {
            items.into_par_iter().for_each(|x| {
                if !cancelled() {
                    f(x)
                }
            })
        });
        if cancelled() {
            crate::cancel::unwind();
        }
    } else {
        items.into_iter().for_each(f);
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_for_each<T, F>(items: Vec<T>, _threshold: usize, f: F)
where
    F: Fn(T),
{
    items.into_iter().for_each(f);
}

/// Apply `f` to every element in place, in parallel when `v.len() >=
/// threshold`. `f` sees only its own element, so the result does not depend on
/// the order.
#[cfg(feature = "parallel")]
pub fn maybe_par_for_each_mut<T, F>(v: &mut [T], threshold: usize, f: F)
where
    T: Send,
    F: Fn(&mut T) + Sync + Send,
{
    use rayon::prelude::*;
    if v.len() >= threshold {
        let scope = crate::cancel::scope();
        let cancelled = || scope.as_ref().is_some_and(|t| t.is_cancelled());
        crate::cancel::outside(|| {
            v.par_iter_mut().for_each(|x| {
                if !cancelled() {
                    f(x)
                }
            })
        });
        if cancelled() {
            crate::cancel::unwind();
        }
    } else {
        v.iter_mut().for_each(f);
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_for_each_mut<T, F>(v: &mut [T], _threshold: usize, f: F)
where
    F: Fn(&mut T),
{
    v.iter_mut().for_each(f);
}

/// [`maybe_par_map`] with cooperative cancellation: `None` means the token was
/// cancelled and the (necessarily incomplete) results were discarded.
///
/// Mirrors the ctx-aware `for_each` overload in C++ `parallel.h:400-437`, whose
/// contract is the same — "only safe when *skip the rest of the range* produces
/// a result the caller will discard via a post-loop `IsCancelled` check".
///
/// Two deliberate differences from the C++:
/// - A `None` token dispatches straight to [`maybe_par_map`], so the
///   uncancellable path is byte-for-byte the code that ran before cancellation
///   existed — stricter than C++, which still branches on `ctx != nullptr`
///   inside the loop.
/// - With a token we check the flag on *every* element rather than once per
///   `kSeqCancelChunk` (1024) elements. The flag is written at most once, so its
///   cache line stays shared and the relaxed load is an L1 hit; paying it per
///   element buys strictly better cancellation latency than the C++ chunking.
#[cfg(feature = "parallel")]
pub fn maybe_par_map_ct<T, F>(
    n: usize,
    threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    f: F,
) -> Option<Vec<T>>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    let Some(token) = token else {
        return Some(maybe_par_map(n, threshold, f));
    };
    cancellable_map(n, threshold, usize::MAX, Some(token), f)
}

/// [`maybe_par_map_ct`] with every index its own task (rayon's `with_max_len(1)`),
/// for a few items of very uneven cost: the default splitting hands out ranges,
/// and a range holding all the costly items runs them on one thread. Same
/// results, in index order. blocksmith patch (PATCHES.md, 5).
#[cfg(feature = "parallel")]
pub fn maybe_par_map_each_ct<T, F>(
    n: usize,
    threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    f: F,
) -> Option<Vec<T>>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    cancellable_map(n, threshold, 1, token, f)
}

/// The body of [`maybe_par_map_ct`] and [`maybe_par_map_each_ct`]: `f` over
/// `0..n`, in rayon tasks of at most `max_len` indices when `n >= threshold`,
/// `None` once `token` is cancelled.
#[cfg(feature = "parallel")]
fn cancellable_map<T, F>(
    n: usize,
    threshold: usize,
    max_len: usize,
    token: Option<&crate::cancel::CancelToken>,
    f: F,
) -> Option<Vec<T>>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    use rayon::prelude::*;
    // blocksmith patch (PATCHES.md, 10): an item that sees the token cancelled
    // unwinds, caught here as `None`, and the remaining items stop as they
    // would have at the first `None` of an `Option` collect; the collect stays
    // indexed (one exact allocation written in place, rather than growing
    // pieces copied together), and the sequential loop writes into a `Vec` of
    // the right capacity.
    if n >= threshold {
        crate::cancel::catching(|| {
            crate::cancel::outside(|| {
                (0..n)
                    .into_par_iter()
                    .with_max_len(max_len)
                    .map(|i| {
                        if crate::cancel::is_cancelled(token) {
                            crate::cancel::unwind();
                        }
                        f(i)
                    })
                    .collect()
            })
        })
    } else {
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            if crate::cancel::is_cancelled(token) {
                return None;
            }
            out.push(f(i));
        }
        Some(out)
    }
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_map_each_ct<T, F>(
    n: usize,
    threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    f: F,
) -> Option<Vec<T>>
where
    F: Fn(usize) -> T,
{
    maybe_par_map_ct(n, threshold, token, f)
}

/// Sequential fallback: identical output to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_map_ct<T, F>(
    n: usize,
    threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    f: F,
) -> Option<Vec<T>>
where
    F: Fn(usize) -> T,
{
    let Some(token) = token else {
        return Some(maybe_par_map(n, threshold, f));
    };
    (0..n)
        .map(|i| {
            if token.is_cancelled() {
                None
            } else {
                Some(f(i))
            }
        })
        .collect()
}

/// Does `predicate` hold for some index in `0..n`? Stops at the first hit, in
/// parallel when the `parallel` feature is enabled and `n >= threshold`.
/// `None` means the token was cancelled before a verdict.
///
/// The one existential site (the Auto engine's self-intersection pre-check,
/// `robust::soup::compute_self_intersections`). Its answer is a single
/// boolean rather than an array, so the index-order argument the maps above
/// rest on becomes this one: the answer is "some index's predicate is true",
/// and an existential does not depend on which index is found first or how
/// many ran. A hit, from any worker, answers `Some(true)`; a run in which
/// every index ran without a hit answers `Some(false)`. Both are exactly what
/// the sequential loop answers, so the verdict is the same in both builds;
/// only *which* hit stops the loop differs, and the caller never learns which.
///
/// `predicate` must be pure apart from its per-job scratch `L`, made by
/// `local_init` (rayon's `*_init`: one per split job in parallel, one for the
/// whole sequential loop).
///
/// Cancellation: a cancel any worker observed answers `None`, unless some
/// worker had already found a hit, which answers `Some(true)` — a real
/// verdict (the hit is a genuine witness), not a cancelled partial result.
/// The sequential loop polls the token before every index.
#[cfg(feature = "parallel")]
pub fn maybe_par_any_ct<L, I, F>(
    n: usize,
    threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    local_init: I,
    predicate: F,
) -> Option<bool>
where
    I: Fn() -> L + Sync + Send,
    F: Fn(usize, &mut L) -> bool + Sync + Send,
{
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    if n < threshold {
        return seq_any_ct(n, token, local_init, predicate);
    }
    // Written only ever from false to true, so two racing hits are benign.
    let found = AtomicBool::new(false);
    let stopped = crate::cancel::outside(|| {
        (0..n)
            .into_par_iter()
            .try_for_each_init(local_init, |local, i| {
                if token.is_some_and(|t| t.is_cancelled()) {
                    return Err(());
                }
                if predicate(i, local) {
                    found.store(true, Ordering::Relaxed);
                    return Err(());
                }
                Ok(())
            })
            .is_err()
    });
    if found.load(Ordering::Relaxed) {
        Some(true)
    } else if stopped {
        // Stopped without a hit means some worker stopped on the cancel.
        None
    } else {
        Some(false)
    }
}

/// Sequential fallback: identical verdict to the parallel version.
#[cfg(not(feature = "parallel"))]
pub fn maybe_par_any_ct<L, I, F>(
    n: usize,
    _threshold: usize,
    token: Option<&crate::cancel::CancelToken>,
    local_init: I,
    predicate: F,
) -> Option<bool>
where
    I: Fn() -> L,
    F: Fn(usize, &mut L) -> bool,
{
    seq_any_ct(n, token, local_init, predicate)
}

/// The sequential loop both builds' [`maybe_par_any_ct`] reduce to.
fn seq_any_ct<L, I, F>(
    n: usize,
    token: Option<&crate::cancel::CancelToken>,
    local_init: I,
    predicate: F,
) -> Option<bool>
where
    I: Fn() -> L,
    F: Fn(usize, &mut L) -> bool,
{
    let mut local = local_init();
    for i in 0..n {
        if token.is_some_and(|t| t.is_cancelled()) {
            return None;
        }
        if predicate(i, &mut local) {
            return Some(true);
        }
    }
    Some(false)
}

/// Pieces laid end to end in one array: piece `k`'s elements, `piece(k)`, from `starts[k]` to
/// `starts[k + 1]`, written in place (no pass to initialise the result first), the pieces in
/// parallel when there are at least `threshold` of them. blocksmith patch (PATCHES.md, 19;
/// shared with the export of patch 22).
pub(crate) fn concatenated<T, I, F>(starts: &[usize], threshold: usize, piece: F) -> Vec<T>
where
    T: Send,
    I: Iterator<Item = T>,
    F: Fn(usize) -> I + Sync + Send,
{
    let total = starts.last().copied().unwrap_or(0);
    let mut out: Vec<T> = Vec::with_capacity(total);
    let mut slices = Vec::with_capacity(starts.len().saturating_sub(1));
    let mut rest = &mut out.spare_capacity_mut()[..total];
    for (k, w) in starts.windows(2).enumerate() {
        let (slice, tail) = std::mem::take(&mut rest).split_at_mut(w[1] - w[0]);
        slices.push((k, slice));
        rest = tail;
    }
    let written = std::sync::atomic::AtomicUsize::new(0);
    maybe_par_for_each(slices, threshold, |(k, slice)| {
        let mut n = 0;
        for (slot, value) in slice.iter_mut().zip(piece(k)) {
            slot.write(value);
            n += 1;
        }
        // A piece that fills less than its slice leaves the count short: nothing is exposed.
        if n == slice.len() {
            written.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        }
    });
    assert_eq!(written.into_inner(), total, "a piece is shorter than its count");
    // SAFETY: the slices partition `0..total` of the capacity, and each was written in
    // full (counted above) before the length covers them.
    unsafe { out.set_len(total) };
    out
}

#[cfg(test)]
#[path = "par_tests.rs"]
mod tests;
