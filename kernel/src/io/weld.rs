//! Welding: joining a file's corners that lie at the same place (up to a tolerance) into shared
//! vertices, so that an STL's triangle soup or a glTF split at normal and UV seams reads as the
//! closed surface it draws.
//!
//! Each vertex, in file order, joins the first earlier *kept* vertex within the tolerance in
//! every coordinate (a box, not a ball), or is kept itself. Kept vertices keep their position
//! bit for bit, and a file without near-duplicates is returned unchanged, so round trips stay
//! exact. Lookup goes through a hash grid of cells 256 tolerances wide: a vertex looks in its
//! own cell, and in a neighbouring one only when it lies within the tolerance of that side. A
//! cell holding more than 64 kept vertices splits into fine cells 4 tolerances wide; kept
//! vertices are pairwise more than the tolerance apart, so a fine cell holds at most 125 of
//! them: the cost is linear whatever the positions (a crowded cell made it quadratic).

use crate::limits::LimitError;
use crate::math::{IdMap, Vec3};

/// How corners that a file stores separately are joined into shared vertices.
///
/// Default value: `Weld::Relative(1e-8)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Weld {
    /// Keep every vertex of the file as it is (a glTF's split seams stay open; an STL becomes
    /// separate triangles).
    Off,
    /// Join vertices at most `tol × d` apart in every coordinate, `d` the diagonal of the
    /// bounding box of the file's vertices. `0` joins only equal coordinates (−0 = +0).
    Relative(f64),
}

impl Default for Weld {
    fn default() -> Self {
        Weld::DEFAULT
    }
}

impl Weld {
    /// The default: `Relative(1e-8)`, far below any feature a model draws and far above the
    /// noise of a CAD exporter's arithmetic (1e-17 and below).
    pub const DEFAULT: Weld = Weld::Relative(1e-8);

    /// The rule for a format that names its shared vertices (OBJ, 3MF): by default only
    /// corners at equal coordinates join (an exporter that repeats a corner writes it the same
    /// way each time), so two vertices a file keeps apart at nearly one place stay apart and a
    /// file we wrote reads back as written; a rule other than the default applies as given.
    #[must_use]
    pub(crate) fn for_named_vertices(self) -> Weld {
        if self == Weld::DEFAULT {
            Weld::Relative(0.0)
        } else {
            self
        }
    }
}

/// Fine cell width in tolerances. Kept vertices are more than the tolerance apart in some
/// coordinate, so a fine cell holds at most (CELL + 1)³ = 125 of them whatever the positions
/// (at 256 tolerances, a file whose corners all fell in one cell made the weld quadratic: a
/// minute for a 5 MB STL).
const CELL: f64 = 4.0;

/// Fine cells per coarse cell along an axis: coarse cells are 256 tolerances wide, so that a
/// vertex usually looks up one coarse cell (a neighbour only within the tolerance of its side).
const FINE_PER_COARSE: i64 = 64;

/// Kept vertices a coarse cell lists before its vertices move to fine cells (which cost about
/// 3.4 lookups a vertex: the fine grid is for crowded cells only).
const DENSE: u32 = 64;

/// Cells looked up and kept vertices compared between two polls of the cancellation token:
/// about a millisecond of work.
const POLL_WORK: usize = 1 << 16;

/// The weld of `positions`: for each file vertex its new id, and for each new id the file
/// vertex it keeps (in increasing order). `Weld::Off` keeps every vertex.
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] vertices, or [`POLL_WORK`] cells and comparisons).
pub(crate) fn weld(positions: &[Vec3], rule: Weld) -> Result<(Vec<u32>, Vec<u32>), LimitError> {
    let tol = match rule {
        Weld::Off => return Ok(((0..positions.len() as u32).collect(), (0..positions.len() as u32).collect())),
        Weld::Relative(r) => r.max(0.0) * diagonal(positions),
    };
    let mut map = Vec::with_capacity(positions.len());
    let mut kept: Vec<u32> = Vec::with_capacity(positions.len() / 2);
    if tol.is_nan() || tol <= f64::MIN_POSITIVE || tol.is_infinite() {
        // Equal coordinates only (−0 = +0).
        let key = |p: Vec3| [p.x, p.y, p.z].map(|c| if c == 0.0 { 0u64 } else { c.to_bits() });
        let mut ids: IdMap<[u64; 3], u32> = IdMap::default();
        ids.reserve(positions.len() / 2);
        for (i, &p) in positions.iter().enumerate() {
            crate::limits::poll_at(i)?;
            let id = *ids.entry(key(p)).or_insert_with(|| {
                kept.push(i as u32);
                (kept.len() - 1) as u32
            });
            map.push(id);
        }
        return Ok((map, kept));
    }
    // Cells are measured from the low corner of the box, so that far-off models (o = 1e12 with
    // a diagonal of 1) do not saturate the cell numbers into one cell; and at least 2⁻⁵⁰ of the
    // diagonal wide, so that numbers stay in range for any ratio. Fine cells are CELL
    // tolerances wide; coarse ones FINE_PER_COARSE fine cells (256 tolerances).
    let (lo, diag) = bounds(positions);
    let width = (tol * CELL).max(diag * 2f64.powi(-50));
    let l = [lo.x, lo.y, lo.z];
    let fine_of = |c: f64, a: usize| ((c - l[a]) / width).floor() as i64;
    // The kept vertices of each coarse cell, or of each fine cell of a dense coarse cell, as
    // linked lists through `next` (by new id); each kept vertex is in exactly one list.
    let mut coarse: IdMap<[i64; 3], Coarse> = IdMap::default();
    coarse.reserve(positions.len() / 8);
    let mut fine: IdMap<[i64; 3], u32> = IdMap::default();
    let mut next: Vec<u32> = Vec::with_capacity(positions.len() / 2);
    let near = |a: Vec3, b: Vec3| (a.x - b.x).abs() <= tol && (a.y - b.y).abs() <= tol && (a.z - b.z).abs() <= tol;
    // Work since the last poll: cells looked up and vertices compared.
    let mut work = 0usize;
    for (i, &p) in positions.iter().enumerate() {
        work += 1;
        if work >= POLL_WORK {
            work = 0;
            crate::limits::poll()?;
        }
        let c = [p.x, p.y, p.z];
        let cell = [0, 1, 2].map(|a| fine_of(c[a], a));
        // Fine cells per axis from that of p − tol to that of p + tol: p's own, and its
        // neighbour when p lies within tol of that side; and the coarse cells holding them.
        let range = [0, 1, 2].map(|a| (fine_of(c[a] - tol, a), fine_of(c[a] + tol, a)));
        let up = |f: i64| f.div_euclid(FINE_PER_COARSE);
        // The first (smallest id) kept vertex within tol over all candidate cells.
        let mut found: Option<u32> = None;
        let mut scan = |head: Option<u32>, work: &mut usize| {
            let mut at = head;
            while let Some(k) = at {
                *work += 1;
                if found.is_none_or(|f| k < f) && near(p, positions[kept[k as usize] as usize]) {
                    found = Some(k);
                }
                at = Some(next[k as usize]).filter(|&n| n != u32::MAX);
            }
        };
        for cx in up(range[0].0)..=up(range[0].1) {
            for cy in up(range[1].0)..=up(range[1].1) {
                for cz in up(range[2].0)..=up(range[2].1) {
                    work += 1;
                    match coarse.get(&[cx, cy, cz]) {
                        None => {}
                        Some(&Coarse::Sparse { head, .. }) => scan(Some(head), &mut work),
                        Some(Coarse::Dense) => {
                            // The fine cells of the range inside this coarse cell.
                            let clip = |a: usize, cc: i64| {
                                (
                                    range[a].0.max(cc * FINE_PER_COARSE),
                                    range[a].1.min(cc * FINE_PER_COARSE + FINE_PER_COARSE - 1),
                                )
                            };
                            let (x, y, z) = (clip(0, cx), clip(1, cy), clip(2, cz));
                            for fx in x.0..=x.1 {
                                for fy in y.0..=y.1 {
                                    for fz in z.0..=z.1 {
                                        work += 1;
                                        scan(fine.get(&[fx, fy, fz]).copied(), &mut work);
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        let id = match found {
            Some(k) => k,
            None => {
                let k = kept.len() as u32;
                kept.push(i as u32);
                next.push(u32::MAX);
                let home = cell.map(up);
                let entry = coarse.entry(home).or_insert(Coarse::Sparse { head: u32::MAX, len: 0 });
                match entry {
                    Coarse::Sparse { head, len } => {
                        // Pushed at the head: lists hold decreasing ids.
                        next[k as usize] = *head;
                        *head = k;
                        *len += 1;
                        if *len > DENSE {
                            // Too many for one list: this coarse cell's vertices move to
                            // fine cells, where at most (CELL + 1)³ share one.
                            let mut at = Some(*head);
                            *entry = Coarse::Dense;
                            while let Some(v) = at {
                                at = Some(next[v as usize]).filter(|&n| n != u32::MAX);
                                let q = positions[kept[v as usize] as usize];
                                let f = [fine_of(q.x, 0), fine_of(q.y, 1), fine_of(q.z, 2)];
                                next[v as usize] = fine.insert(f, v).unwrap_or(u32::MAX);
                            }
                        }
                    }
                    Coarse::Dense => next[k as usize] = fine.insert(cell, k).unwrap_or(u32::MAX),
                }
                k
            }
        };
        map.push(id);
    }
    Ok((map, kept))
}

/// A coarse cell of the weld's grid: a list of its kept vertices while it holds at most
/// [`DENSE`], then its vertices in fine cells.
#[derive(Clone, Copy)]
enum Coarse {
    Sparse { head: u32, len: u32 },
    Dense,
}

/// The length of the diagonal of the bounding box of the finite `positions` (0 if none).
fn diagonal(positions: &[Vec3]) -> f64 {
    bounds(positions).1
}

/// The low corner of the bounding box of the finite `positions` and the length of its
/// diagonal (the origin and 0 if none).
fn bounds(positions: &[Vec3]) -> (Vec3, f64) {
    let mut lo = Vec3::splat(f64::INFINITY);
    let mut hi = Vec3::splat(f64::NEG_INFINITY);
    for &p in positions.iter().filter(|p| p.is_finite()) {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    if lo.x > hi.x {
        (Vec3::ZERO, 0.0)
    } else {
        (lo, (hi - lo).length())
    }
}

/// Re-indexes polygons (`indices` split by `arities`) through `map`, dropping repeated
/// consecutive corners that welding made; a polygon left with fewer than three corners is
/// dropped (a sliver thinner than the tolerance), as is a triangle with a repeated corner.
/// Returns the new indices and arities, and for each kept polygon the index of the polygon it
/// comes from.
#[must_use]
pub(crate) fn remap_faces(indices: &[u32], arities: &[u32], map: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let mut out = Vec::with_capacity(indices.len());
    let mut out_arities = Vec::with_capacity(arities.len());
    let mut from = Vec::with_capacity(arities.len());
    // Reused for the rare long polygon, so that no face allocates.
    let mut scratch: Vec<u32> = Vec::new();
    let mut start = 0;
    for (f, &a) in arities.iter().enumerate() {
        let face = &indices[start..start + a as usize];
        start += a as usize;
        let begin = out.len();
        for &v in face {
            let w = map[v as usize];
            if out.len() == begin || out[out.len() - 1] != w {
                out.push(w);
            }
        }
        while out.len() > begin + 1 && out[out.len() - 1] == out[begin] {
            out.pop();
        }
        let n = out.len() - begin;
        if n < 3 || has_repeat(&out[begin..], &mut scratch) {
            // Fewer than three corners, or a corner repeated further apart (a pinched polygon).
            out.truncate(begin);
            continue;
        }
        out_arities.push(n as u32);
        from.push(f as u32);
    }
    (out, out_arities, from)
}

/// Whether some corner of `poly` appears twice: by comparing pairs for the short polygons
/// files are made of, by sorting a copy in `scratch` (reused from face to face) for long ones.
fn has_repeat(poly: &[u32], scratch: &mut Vec<u32>) -> bool {
    if poly.len() <= 16 {
        return poly.iter().enumerate().any(|(i, v)| poly[i + 1..].contains(v));
    }
    scratch.clear();
    scratch.extend_from_slice(poly);
    scratch.sort_unstable();
    scratch.windows(2).any(|w| w[0] == w[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_weld_joins_equal_coordinates_and_signed_zeros() {
        let p = [Vec3::new(0.0, 1.0, 2.0), Vec3::new(-0.0, 1.0, 2.0), Vec3::new(1e-300, 1.0, 2.0)];
        let (map, kept) = weld(&p, Weld::Relative(0.0)).unwrap();
        assert_eq!(map, vec![0, 0, 1]);
        assert_eq!(kept, vec![0, 2]);
    }

    #[test]
    fn relative_weld_joins_cad_noise_and_keeps_the_first_position() {
        // The noise of the CAD files of issue 19: 0 against −3.79e-33, −6.123e-17 against −6.147e-17.
        let p = [
            Vec3::new(0.0, -6.123e-17, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-3.79e-33, -6.147e-17, 1.0),
            Vec3::new(1.0, 1e-9, 0.0),
        ];
        let (map, kept) = weld(&p, Weld::DEFAULT).unwrap();
        assert_eq!(map, vec![0, 1, 0, 1]);
        assert_eq!(kept, vec![0, 1]);
        // 1e-9 apart in a model of diagonal √2 is more than 1e-10 × √2: kept apart.
        let (map, _) = weld(&p, Weld::Relative(1e-10)).unwrap();
        assert_eq!(map, vec![0, 1, 0, 2]);
        let (map, _) = weld(&p, Weld::Off).unwrap();
        assert_eq!(map, vec![0, 1, 2, 3]);
    }

    /// Checks `map` and `kept` against comparing every vertex with every kept one before it:
    /// a vertex joins the first kept vertex within `tol` in every coordinate, else is kept.
    fn assert_welds_as_brute_force(p: &[Vec3], tol: f64, map: &[u32], kept: &[u32]) {
        let mut want_kept: Vec<u32> = Vec::new();
        for (i, &q) in p.iter().enumerate() {
            let hit = want_kept.iter().position(|&k| {
                let r = p[k as usize];
                (r.x - q.x).abs() <= tol && (r.y - q.y).abs() <= tol && (r.z - q.z).abs() <= tol
            });
            match hit {
                Some(h) => assert_eq!(map[i] as usize, h, "vertex {i}"),
                None => {
                    assert_eq!(map[i] as usize, want_kept.len(), "vertex {i}");
                    want_kept.push(i as u32);
                }
            }
        }
        assert_eq!(kept, want_kept);
    }

    #[test]
    fn weld_across_cell_sides_matches_brute_force() {
        // Points on a lattice with jitter straddling cell boundaries: the grid must find the
        // same first-kept neighbour as comparing every pair.
        let tol_rel = 1e-3;
        let mut p = Vec::new();
        let mut rng = crate::math::SplitMix64::new(12345);
        let mut rnd = || rng.next_f64();
        for _ in 0..2000 {
            let base = Vec3::new((rnd() * 8.0).floor(), (rnd() * 8.0).floor(), (rnd() * 8.0).floor()) * 0.05;
            p.push(base + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 0.002);
        }
        let (map, kept) = weld(&p, Weld::Relative(tol_rel)).unwrap();
        let tol = tol_rel * diagonal(&p);
        assert_welds_as_brute_force(&p, tol, &map, &kept);
        assert!(kept.len() < p.len(), "the case must weld something");
    }

    #[test]
    fn a_crowded_cloud_welds_as_brute_force_does() {
        // 3,000 random points within 100 tolerances of each other (and one far point fixing the
        // tolerance): their coarse cell turns dense, and the fine cells must find the same
        // first kept neighbour as comparing every pair.
        let tol = 1e-3 * 3f64.sqrt();
        let mut rng = crate::math::SplitMix64::new(99);
        let mut rnd = || rng.next_f64();
        let mut p: Vec<Vec3> = (0..3000).map(|_| Vec3::new(rnd(), rnd(), rnd()) * (100.0 * tol)).collect();
        p.push(Vec3::ONE);
        let (map, kept) = weld(&p, Weld::Relative(1e-3)).unwrap();
        assert_welds_as_brute_force(&p, tol, &map, &kept);
        assert!(kept.len() > 200 && kept.len() < p.len(), "{}", kept.len());
    }

    #[test]
    fn remap_drops_collapsed_faces() {
        // A quad whose last two corners weld becomes a triangle; a triangle with two welded
        // corners is dropped.
        let map = [0, 1, 2, 2, 0, 0];
        let (idx, ar, from) = remap_faces(&[0, 1, 2, 3, 4, 5, 3], &[4, 3], &map);
        assert_eq!((idx, ar, from), (vec![0, 1, 2], vec![3], vec![0]));
    }

    #[test]
    fn remap_drops_pinched_polygons_short_and_long() {
        // A pentagon whose corners 0 and 2 weld (not consecutive: pinched) is dropped, as is a
        // 20-gon pinched the same way (the sorted path); an unpinched 20-gon is kept whole.
        let map: Vec<u32> = (0..40).map(|v| if v == 2 { 0 } else { v }).collect();
        let (idx, ar, from) = remap_faces(&[0, 1, 2, 3, 4], &[5], &map);
        assert!(idx.is_empty() && ar.is_empty() && from.is_empty());
        let long: Vec<u32> = (0..20).collect();
        let (_, ar, _) = remap_faces(&long, &[20], &map);
        assert!(ar.is_empty());
        let long: Vec<u32> = (20..40).collect();
        let (idx, ar, from) = remap_faces(&long, &[20], &map);
        assert_eq!((idx, ar, from), (long, vec![20], vec![0]));
        assert!(has_repeat(&[5, 1, 2, 5], &mut Vec::new()) && !has_repeat(&[5, 1, 2], &mut Vec::new()));
    }

    /// 64,000 corners on a lattice 2.5 tolerances apart (none within the tolerance of another),
    /// all within 100 tolerances of the origin, and one corner at (1, 1, 1) that sets the
    /// tolerance: the crowded file of issue 33, all in one cell of the old 256-tolerance grid.
    fn crowded() -> Vec<Vec3> {
        let tol = 1e-8 * 3f64.sqrt();
        let mut p: Vec<Vec3> = (0..40 * 40 * 40)
            .map(|i| Vec3::new(f64::from(i % 40), f64::from(i / 40 % 40), f64::from(i / 1600)) * (2.5 * tol))
            .collect();
        p.push(Vec3::ONE);
        p
    }

    #[test]
    fn a_crowded_cell_welds_in_linear_time() {
        // Each corner is compared with at most the 125 kept corners a cell can hold, times the
        // cells it touches: well under a second (comparing all pairs, 2·10⁹ of them, took seconds).
        let p = crowded();
        let t = std::time::Instant::now();
        let (map, kept) = weld(&p, Weld::DEFAULT).unwrap();
        assert!(t.elapsed().as_secs_f64() < 1.0, "{:?}", t.elapsed());
        assert_eq!(kept.len(), p.len(), "nothing is within the tolerance");
        assert!(map.iter().enumerate().all(|(i, &m)| m as usize == i));
        // Every odd corner in x moved 1.6 tolerances back lies 0.9 tolerance from the corner
        // before it, and welds to it: half the lattice goes.
        let mut q = p.clone();
        for v in q.iter_mut().take(64_000).skip(1).step_by(2) {
            v.x -= 1.6 * 1e-8 * 3f64.sqrt();
        }
        let (map, kept) = weld(&q, Weld::DEFAULT).unwrap();
        assert_eq!((kept.len(), map[1]), (32_001, 0));
    }

    #[test]
    fn a_weld_stops_on_the_token() {
        use crate::limits::{install, CancelToken, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
        assert!(matches!(weld(&crowded(), Weld::DEFAULT), Err(LimitError::Stopped(StopReason::Interrupted))));
    }
}
