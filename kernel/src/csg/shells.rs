//! Which shell each vertex of a triangle soup belongs to, for the flat-shell check of a boolean's
//! result ([`super::tree`]'s `without_flat_shells`): a union–find over the triangles' corners,
//! run on all threads.
//!
//! The forest is one atomic parent per vertex, and a union links the larger of two roots under
//! the smaller (compare-and-swap on the root's parent, retried when another thread linked it
//! first), so every parent is at most its child and the root of a shell, when all unions are
//! done, is its smallest vertex, whatever the threads' interleaving. Finds halve the path (a
//! vertex's parent becomes its grandparent, which is still one of its ancestors, so a lost race
//! only loses a shortcut). This is the lock-free union–find of Anderson & Woll (1991) with
//! linking by index in place of rank; the serial forest it replaces was a tenth of a large
//! boolean's time outside the engine, and its parent array's misses grew faster than the
//! triangles (1.2 ms at 126k result triangles, 20 ms at 950k).

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;

/// Triangles per parallel run of the unions.
const UNION_RUN: usize = 16_384;

/// Each vertex's shell among `vertex_count` vertices joined by the triangles `corners` (three
/// vertex ids each, all below `vertex_count`): the smallest vertex connected to it. The same
/// result on any number of threads.
pub(super) fn vertex_shells(vertex_count: usize, corners: &[u32]) -> Vec<u32> {
    let parent: Vec<AtomicU32> = (0..vertex_count as u32).into_par_iter().map(AtomicU32::new).collect();
    corners.par_chunks(3 * UNION_RUN).for_each(|run| {
        for tri in run.chunks_exact(3) {
            unite(&parent, tri[0], tri[1]);
            unite(&parent, tri[0], tri[2]);
        }
    });
    (0..vertex_count as u32).into_par_iter().map(|v| root(&parent, v)).collect()
}

/// The root of `x`, halving the path on the way.
fn root(parent: &[AtomicU32], mut x: u32) -> u32 {
    loop {
        let p = parent[x as usize].load(Relaxed);
        if p == x {
            return x;
        }
        let grand = parent[p as usize].load(Relaxed);
        if grand != p {
            // Parents only ever move to smaller ancestors: if another thread moved x's parent
            // meanwhile, its value is as good.
            let _ = parent[x as usize].compare_exchange_weak(p, grand, Relaxed, Relaxed);
        }
        x = grand;
    }
}

/// Joins the shells of `a` and `b`: the larger root goes under the smaller.
fn unite(parent: &[AtomicU32], a: u32, b: u32) {
    let (mut a, mut b) = (a, b);
    loop {
        a = root(parent, a);
        b = root(parent, b);
        if a == b {
            return;
        }
        let (small, large) = if a < b { (a, b) } else { (b, a) };
        // Only while `large` is still a root; otherwise look again from its new root.
        if parent[large as usize].compare_exchange(large, small, Relaxed, Relaxed).is_ok() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each vertex's smallest connected vertex by a serial search over the triangles.
    fn shells_by_search(vertex_count: usize, corners: &[u32]) -> Vec<u32> {
        let mut next: Vec<Vec<u32>> = vec![Vec::new(); vertex_count];
        for tri in corners.chunks_exact(3) {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                next[tri[i] as usize].push(tri[j]);
                next[tri[j] as usize].push(tri[i]);
            }
        }
        let mut shell = vec![u32::MAX; vertex_count];
        for first in 0..vertex_count as u32 {
            if shell[first as usize] != u32::MAX {
                continue;
            }
            // Vertices in increasing order reach each shell first at its smallest vertex.
            let mut stack = vec![first];
            shell[first as usize] = first;
            while let Some(v) = stack.pop() {
                for &w in &next[v as usize] {
                    if shell[w as usize] == u32::MAX {
                        shell[w as usize] = first;
                        stack.push(w);
                    }
                }
            }
        }
        shell
    }

    /// Random soups — many small shells, strips that chain across the parallel runs, isolated
    /// vertices — against the serial search, on one thread and on four.
    #[test]
    fn shells_are_the_smallest_connected_vertex_on_any_threads() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut random = move |n: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % u64::from(n)) as u32
        };
        for (vertex_count, triangles, reach) in
            [(10, 3, 10), (2_000, 600, 40), (200_000, 70_000, 3), (60_000, 60_000, 60_000)]
        {
            let mut corners = Vec::with_capacity(3 * triangles);
            for _ in 0..triangles {
                // A triangle's corners near one another (small shells and long strips), or anywhere.
                let a = random(vertex_count);
                for _ in 0..3 {
                    corners.push((a + random(reach)).min(vertex_count - 1));
                }
            }
            let expected = shells_by_search(vertex_count as usize, &corners);
            for threads in [1, 4] {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let shells = pool.install(|| vertex_shells(vertex_count as usize, &corners));
                assert_eq!(shells, expected, "{vertex_count} vertices, {triangles} triangles, {threads} threads");
            }
        }
    }
}
