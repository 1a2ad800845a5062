//! Limit masks: weights over a vertex's one-ring that give its limit position and tangents.
//!
//! A mask weights the centre `c`, the edge neighbours `e_i` and (Catmull–Clark only) the face
//! opposites `f_i` of a [`RingTopo`]. The formulas are OpenSubdiv's `Sdc` limit masks:
//! - position — smooth Catmull–Clark: (n² c + 4 Σ e_i + Σ f_i) / (n (n + 5)) (Halstead et al.
//!   1993); smooth Loop: e-weight 1 / (n + 3 / (8β)) (Loop 1987); crease (both schemes):
//!   (e_a + 4 c + e_b) / 6, the limit of the cubic B-spline crease curve; corner: c.
//! - tangents — smooth: the cosine/sine masks of the subdominant eigenvectors (Halstead et al.
//!   1993 for Catmull–Clark with λ from Stam 1998; Loop 1987); crease and boundary sectors: the
//!   along-crease difference and the cross-crease masks of Biermann et al. (2000), in OpenSubdiv's
//!   scaling and orientation (t1 along the leading edge, t2 into the sector, t1 × t2 outward).
//!
//! At a crease or corner vertex the limit surface has one tangent plane per *sector* (the fan of
//! faces between two consecutive sharp edges). [`limit_normal`] returns the normalised sum of the
//! unit sector normals — on a boundary (one sector) this is exactly OpenSubdiv's normal; at an
//! interior crease it is the bisector of the two sides' normals.

use std::f64::consts::{PI, TAU};

use crate::math::Vec3;

use super::refiner::loop_beta;
use super::ring::RingTopo;
use super::topology::Rule;

/// Weights over a one-ring: centre, edge neighbours, face opposites (empty for Loop).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Mask {
    pub(crate) c: f64,
    pub(crate) e: Vec<f64>,
    pub(crate) f: Vec<f64>,
}

impl Mask {
    fn zeros(n: usize, faces: bool) -> Mask {
        Mask { c: 0.0, e: vec![0.0; n], f: if faces { vec![0.0; n] } else { Vec::new() } }
    }

    /// Σ weight · point. `f` may be shorter than the mask's face weights only where they are 0.
    ///
    /// Summed relative to the centre: a position mask's weights sum to 1 and a tangent mask's to
    /// 0, so Σ w (p − c) + c · Σ w is the same combination, with Σ w taken as exactly 1 or 0 —
    /// coordinates the whole ring shares (a flat sharp face) come out exactly.
    pub(crate) fn apply(&self, c: Vec3, e: &[Vec3], f: &[Vec3]) -> Vec3 {
        // Smaller weights first, as OpenSubdiv does, for precision.
        let mut s = Vec3::ZERO;
        let mut total = self.c;
        for (i, &w) in self.f.iter().enumerate() {
            if w != 0.0 {
                s += (f[i] - c) * w;
                total += w;
            }
        }
        for (i, &w) in self.e.iter().enumerate() {
            if w != 0.0 {
                s += (e[i] - c) * w;
                total += w;
            }
        }
        if total.abs() < 0.5 {
            s
        } else {
            c + s
        }
    }
}

/// Which scheme's masks to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MaskScheme {
    CatmullClark,
    Loop,
}

/// The two sharp edges of a crease vertex, as ring indices.
fn crease_ends(t: &RingTopo) -> [usize; 2] {
    let s = t.sharp_indices();
    [s[0], s[1]]
}

/// The limit-position mask of the ring's centre.
pub(crate) fn position_mask(scheme: MaskScheme, t: &RingTopo) -> Mask {
    let n = t.valence();
    let cc = scheme == MaskScheme::CatmullClark;
    let mut m = Mask::zeros(n, cc);
    match t.rule() {
        Rule::Corner => m.c = 1.0,
        Rule::Crease => {
            let [a, b] = crease_ends(t);
            m.c = 4.0 / 6.0;
            m.e[a] = 1.0 / 6.0;
            m.e[b] = 1.0 / 6.0;
        }
        Rule::Smooth if needs_eigen(scheme, t) => m = eigen_masks(scheme, t).0,
        Rule::Smooth => {
            let nf = n as f64;
            if cc {
                let fw = 1.0 / (nf * (nf + 5.0));
                m.c = nf * fw * nf;
                m.e.iter_mut().for_each(|w| *w = 4.0 * fw);
                m.f.iter_mut().for_each(|w| *w = fw);
            } else {
                let ew = if n == 6 { 1.0 / 12.0 } else { 1.0 / (nf + 3.0 / (8.0 * loop_beta(n))) };
                m.c = 1.0 - nf * ew;
                m.e.iter_mut().for_each(|w| *w = ew);
            }
        }
    }
    m
}

/// Smooth tangent masks (t1 toward e_0, t2 toward e_1).
fn smooth_tangents(scheme: MaskScheme, n: usize) -> (Mask, Mask) {
    let cc = scheme == MaskScheme::CatmullClark;
    let mut t1 = Mask::zeros(n, cc);
    let mut t2 = Mask::zeros(n, cc);
    if cc {
        let th = TAU / n as f64;
        let lambda = 5.0 / 16.0 + (th.cos() + (th * 0.5).cos() * (2.0 * (9.0 + th.cos())).sqrt()) / 16.0;
        let fs = 1.0 / (4.0 * lambda - 1.0);
        for i in 0..n {
            let (ci, cn) = ((i as f64 * th).cos(), ((i + 1) as f64 * th).cos());
            t1.e[i] = 4.0 * ci;
            t1.f[i] = fs * (ci + cn);
        }
        // t2 is t1 turned by one slot.
        for i in 0..n {
            t2.e[i] = t1.e[(i + n - 1) % n];
            t2.f[i] = t1.f[(i + n - 1) % n];
        }
    } else {
        let a = TAU / n as f64;
        for i in 0..n {
            t1.e[i] = (a * i as f64).cos();
            t2.e[i] = (a * i as f64).sin();
        }
    }
    (t1, t2)
}

/// Tangent masks of the sector running counter-clockwise from sharp edge `s` to sharp edge `t`
/// (`t` may wrap past `n`; the sector has `t - s` faces): t1 along the crease (toward e_s), t2
/// across the sector, inward.
fn sector_tangents(scheme: MaskScheme, n: usize, s: usize, t: usize) -> (Mask, Mask) {
    let cc = scheme == MaskScheme::CatmullClark;
    let mut t1 = Mask::zeros(n, cc);
    let mut t2 = Mask::zeros(n, cc);
    let k = t - s; // faces in the sector
    let ix = |j: usize| (s + j) % n; // the j-th edge (or face slot) of the sector
    let (es, et) = (ix(0), ix(k));
    if cc {
        t1.e[es] += 0.5;
        t1.e[et] -= 0.5;
        if k == 1 {
            t2.c = -6.0;
            t2.e[es] += 3.0;
            t2.e[et] += 3.0;
        } else if k == 2 {
            t2.c = -4.0 / 6.0;
            t2.e[es] += -1.0 / 6.0;
            t2.e[ix(1)] += 4.0 / 6.0;
            t2.e[et] += -1.0 / 6.0;
            t2.f[ix(0)] += 1.0 / 6.0;
            t2.f[ix(1)] += 1.0 / 6.0;
        } else {
            let kf = k as f64;
            let th = PI / kf;
            let (ct, st) = (th.cos(), th.sin());
            let d = 1.0 / (kf * (3.0 + ct));
            let r = (ct + 1.0) / st;
            t2.c = 4.0 * r * (ct - 1.0) * d;
            t2.e[es] += -r * (1.0 + 2.0 * ct) * d;
            t2.e[et] += -r * (1.0 + 2.0 * ct) * d;
            t2.f[ix(0)] += st * d;
            for i in 1..k {
                let (si, sn) = ((i as f64 * th).sin(), ((i + 1) as f64 * th).sin());
                t2.e[ix(i)] += 4.0 * si * d;
                t2.f[ix(i)] += (si + sn) * d;
            }
        }
    } else {
        t1.e[es] += 1.5;
        t1.e[et] -= 1.5;
        let interior = k - 1;
        if interior == 0 {
            t2.c = -6.0;
            t2.e[es] += 3.0;
            t2.e[et] += 3.0;
        } else if interior == 1 {
            t2.c = -3.0;
            t2.e[ix(1)] += 3.0;
        } else if interior == 2 {
            let r3 = 3f64.sqrt();
            t2.c = -r3;
            t2.e[es] += -r3 / 2.0;
            t2.e[et] += -r3 / 2.0;
            t2.e[ix(1)] += r3;
            t2.e[ix(2)] += r3;
        } else {
            let th = PI / (interior + 1) as f64;
            t2.e[es] += -3.0 * th.sin();
            t2.e[et] += -3.0 * th.sin();
            let coeff = -6.0 * (th.cos() - 1.0);
            for i in 1..=interior {
                t2.e[ix(i)] += coeff * (i as f64 * th).sin();
            }
        }
    }
    (t1, t2)
}

/// The limit normal at the ring's centre (unit length), or `None` where it is undefined
/// (degenerate geometry: zero-area faces, collinear neighbours).
///
/// `e` and `f` are the ring's points in ring order (`f` ignored for Loop; entries of empty face
/// slots are never read).
pub(crate) fn limit_normal(scheme: MaskScheme, t: &RingTopo, c: Vec3, e: &[Vec3], f: &[Vec3]) -> Option<Vec3> {
    normal_impl(scheme, t, c, e, f, None)
}

/// The limit normal of the surface seen from face slot `slot`: at a crease or corner, the normal of
/// the sector holding that face (the surface's one-sided normal there); elsewhere [`limit_normal`].
pub(crate) fn limit_normal_in_slot(
    scheme: MaskScheme,
    t: &RingTopo,
    c: Vec3,
    e: &[Vec3],
    f: &[Vec3],
    slot: usize,
) -> Option<Vec3> {
    normal_impl(scheme, t, c, e, f, Some(slot))
}

fn normal_impl(scheme: MaskScheme, t: &RingTopo, c: Vec3, e: &[Vec3], f: &[Vec3], slot: Option<usize>) -> Option<Vec3> {
    let n = t.valence();
    if n < 2 {
        return None;
    }
    let scale = e.iter().map(|&p| (p - c).length_squared()).fold(0.0, f64::max);
    if scale == 0.0 {
        return None;
    }
    let sharp = t.sharp_indices();
    let smooth_ring = sharp.len() < 2 && t.face.iter().all(|&x| x);
    let mut sum = Vec3::ZERO;
    let mut tangents_ok = true;
    let mut add = |t1: &Mask, t2: &Mask| {
        let (a, b) = (t1.apply(c, e, f), t2.apply(c, e, f));
        let nrm = a.cross(b);
        let len = nrm.length();
        if len <= 1e-12 * a.length() * b.length() || len == 0.0 {
            tangents_ok = false;
        } else {
            sum += nrm / len;
        }
    };
    if smooth_ring {
        // Smooth and dart vertices, and marked corners with fewer than two sharp edges.
        if needs_eigen(scheme, t) {
            let (_, t1, t2) = eigen_masks(scheme, t);
            add(&t1, &t2);
        } else {
            let (t1, t2) = smooth_tangents(scheme, n);
            add(&t1, &t2);
        }
    } else {
        // One normal per sector between consecutive sharp edges (a boundary gap is a sector
        // without faces and is skipped).
        for (j, &s) in sharp.iter().enumerate() {
            let next = sharp[(j + 1) % sharp.len()];
            let tt = if next > s { next } else { next + n };
            if (s..tt).any(|i| !t.face[i % n]) {
                continue;
            }
            if let Some(k) = slot {
                if !(s..tt).any(|i| i % n == k) {
                    continue;
                }
            }
            let (t1, t2) = sector_tangents(scheme, n, s, tt);
            add(&t1, &t2);
        }
    }
    let len = sum.length();
    if !tangents_ok || len < 1e-9 {
        return None;
    }
    Some(sum / len)
}

/// Whether the closed-form smooth masks do not apply: a dart (one sharp edge, whose midpoint rule
/// changes the local subdivision matrix) or a Catmull–Clark vertex of valence 2 — but not a marked
/// corner, which stays put.
fn needs_eigen(scheme: MaskScheme, t: &RingTopo) -> bool {
    let interior = t.face.iter().all(|&x| x);
    let darts = t.sharp.iter().filter(|&&x| x).count() == 1;
    !t.corner && interior && (darts || (scheme == MaskScheme::CatmullClark && t.valence() == 2))
}

/// The local subdivision matrix of an interior one-ring (row-major, size m × m): row i gives
/// next-level ring point i from this level's ring points, ordered [c, e_0.., f_0..] (no f for Loop).
/// The next ring is [vertex point, edge points, face points], the same layout one level down.
fn ring_matrix(scheme: MaskScheme, t: &RingTopo) -> (usize, Vec<f64>) {
    let n = t.valence();
    let nf = n as f64;
    let cc = scheme == MaskScheme::CatmullClark;
    let m = if cc { 1 + 2 * n } else { 1 + n };
    let mut s = vec![0.0; m * m];
    let e = |i: usize| 1 + (i % n);
    let f = |i: usize| 1 + n + (i % n);
    if cc {
        // Face points (rows f_i).
        for i in 0..n {
            for col in [0, e(i), f(i), e(i + 1)] {
                s[f(i) * m + col] += 0.25;
            }
        }
        for i in 0..n {
            let r = e(i) * m;
            if t.sharp[i] {
                s[r] += 0.5;
                s[r + e(i)] += 0.5;
            } else {
                s[r] += 0.25;
                s[r + e(i)] += 0.25;
                for k in 0..m {
                    s[r + k] += 0.25 * (s[f(i + n - 1) * m + k] + s[f(i) * m + k]);
                }
            }
        }
        // Vertex point: smooth rule (only smooth rings come here).
        s[0] += (nf - 2.0) / nf;
        for i in 0..n {
            s[e(i)] += 1.0 / (nf * nf);
            for k in 0..m {
                s[k] += s[f(i) * m + k] / (nf * nf);
            }
        }
    } else {
        for i in 0..n {
            let r = e(i) * m;
            if t.sharp[i] {
                s[r] += 0.5;
                s[r + e(i)] += 0.5;
            } else {
                s[r] += 0.375;
                s[r + e(i)] += 0.375;
                s[r + e(i + n - 1)] += 0.125;
                s[r + e(i + 1)] += 0.125;
            }
        }
        let b = loop_beta(n);
        s[0] += 1.0 - nf * b;
        for i in 0..n {
            s[e(i)] += b;
        }
    }
    (m, s)
}

fn to_mask(v: &[f64], n: usize, cc: bool) -> Mask {
    Mask { c: v[0], e: v[1..=n].to_vec(), f: if cc { v[n + 1..=2 * n].to_vec() } else { Vec::new() } }
}

/// Limit position and tangent masks from the local subdivision matrix S: the position mask is the
/// dominant left eigenvector (row 0 of S^k as k → ∞: where the centre goes), the tangent masks span
/// the subdominant left eigenspace (subspace iteration on sum-zero vectors, oriented like the smooth
/// masks). Exact for any interior ring, used where no closed form applies (darts).
fn eigen_masks(scheme: MaskScheme, t: &RingTopo) -> (Mask, Mask, Mask) {
    let n = t.valence();
    let cc = scheme == MaskScheme::CatmullClark;
    let (m, s) = ring_matrix(scheme, t);
    let times = |x: &[f64]| -> Vec<f64> {
        let mut y = vec![0.0; m];
        for (i, &xi) in x.iter().enumerate() {
            if xi != 0.0 {
                for k in 0..m {
                    y[k] += xi * s[i * m + k];
                }
            }
        }
        y
    };
    let mut l = vec![0.0; m];
    l[0] = 1.0;
    for _ in 0..400 {
        let next = times(&l);
        let diff: f64 = next.iter().zip(&l).map(|(a, b)| (a - b).abs()).sum();
        l = next;
        if diff < 1e-17 {
            break;
        }
    }
    let flat = |mk: &Mask| -> Vec<f64> {
        let mut v = vec![mk.c];
        v.extend_from_slice(&mk.e);
        v.extend_from_slice(&mk.f);
        v
    };
    let (s1, s2) = smooth_tangents(scheme, n);
    let (a0, b0) = (flat(&s1), flat(&s2));
    let (mut a, mut b) = (a0.clone(), b0.clone());
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let normalize = |x: &mut Vec<f64>| {
        let len = dot(x, x).sqrt();
        x.iter_mut().for_each(|v| *v /= len);
    };
    // Remove the eigenvalue-1 component (x · 1 along l, as l · 1 = 1): rounding would let it grow.
    let deflate = |x: &mut Vec<f64>| {
        let sum: f64 = x.iter().sum();
        x.iter_mut().zip(&l).for_each(|(v, li)| *v -= sum * li);
    };
    for _ in 0..400 {
        a = times(&a);
        b = times(&b);
        deflate(&mut a);
        deflate(&mut b);
        normalize(&mut a);
        let d = dot(&a, &b);
        b.iter_mut().zip(&a).for_each(|(y, x)| *y -= d * x);
        normalize(&mut b);
    }
    // Keep the orientation of the smooth masks (t1 × t2 outward).
    let det = dot(&a0, &a) * dot(&b0, &b) - dot(&a0, &b) * dot(&b0, &a);
    if det < 0.0 {
        b.iter_mut().for_each(|v| *v = -*v);
    }
    (to_mask(&l, n, cc), to_mask(&a, n, cc), to_mask(&b, n, cc))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn topo(n: usize) -> RingTopo {
        RingTopo { sharp: vec![false; n], face: vec![true; n], corner: false }
    }

    #[test]
    fn position_masks_sum_to_one() {
        for n in 3..10 {
            for scheme in [MaskScheme::CatmullClark, MaskScheme::Loop] {
                let m = position_mask(scheme, &topo(n));
                let s = m.c + m.e.iter().sum::<f64>() + m.f.iter().sum::<f64>();
                assert!((s - 1.0).abs() < 1e-14, "{scheme:?} n={n}: sum {s}");
            }
        }
        // The regular Catmull–Clark mask is 4/9, 1/9, 1/36 (the bicubic B-spline at a knot).
        let m = position_mask(MaskScheme::CatmullClark, &topo(4));
        assert!((m.c - 4.0 / 9.0).abs() < 1e-15 && (m.e[0] - 1.0 / 9.0).abs() < 1e-15);
        assert!((m.f[0] - 1.0 / 36.0).abs() < 1e-15);
        // The regular Loop mask is 1/2 and 1/12 (the quartic box spline at a vertex).
        let m = position_mask(MaskScheme::Loop, &topo(6));
        assert!((m.c - 0.5).abs() < 1e-15 && (m.e[0] - 1.0 / 12.0).abs() < 1e-15);
    }

    #[test]
    fn eigenvector_masks_reproduce_the_closed_forms() {
        // The dominant left eigenvector of the local subdivision matrix is the limit mask: for
        // smooth rings it must equal the closed forms (Halstead et al.; Loop), for darts it differs.
        for scheme in [MaskScheme::CatmullClark, MaskScheme::Loop] {
            for n in 3..9 {
                let (p, t1, t2) = eigen_masks(scheme, &topo(n));
                let q = position_mask(scheme, &topo(n));
                assert!((p.c - q.c).abs() < 1e-13, "{scheme:?} n={n}: {} vs {}", p.c, q.c);
                for i in 0..n {
                    assert!((p.e[i] - q.e[i]).abs() < 1e-13);
                }
                // The tangent masks span the same plane as the closed-form ones: the closed-form
                // t1 has no component outside span(t1, t2).
                let (s1, _) = smooth_tangents(scheme, n);
                let v = |m: &Mask| {
                    let mut x = vec![m.c];
                    x.extend_from_slice(&m.e);
                    x.extend_from_slice(&m.f);
                    x
                };
                let (a, b, c) = (v(&t1), v(&t2), v(&s1));
                let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
                let (ca, cb) = (dot(&c, &a), dot(&c, &b));
                let resid: f64 =
                    c.iter().zip(a.iter().zip(&b)).map(|(ci, (ai, bi))| (ci - ca * ai - cb * bi).powi(2)).sum();
                assert!(resid.sqrt() < 1e-9 * dot(&c, &c).sqrt(), "{scheme:?} n={n}: residual {resid:e}");
            }
            let mut dart = topo(5);
            dart.sharp[2] = true;
            assert!(needs_eigen(scheme, &dart));
            let p = position_mask(scheme, &dart);
            let s = p.c + p.e.iter().sum::<f64>() + p.f.iter().sum::<f64>();
            assert!((s - 1.0).abs() < 1e-13);
            // The sharp edge's neighbour weighs more than the others (its midpoint rule pulls).
            assert!(p.e[2] > p.e[0] + 1e-3, "{scheme:?}: {:?}", p.e);
        }
    }

    #[test]
    fn tangent_masks_ignore_translation() {
        // A tangent is a difference of points: its weights sum to zero, for every sector size.
        for scheme in [MaskScheme::CatmullClark, MaskScheme::Loop] {
            for n in 3..9 {
                let (a, b) = smooth_tangents(scheme, n);
                for m in [a, b] {
                    let s = m.c + m.e.iter().sum::<f64>() + m.f.iter().sum::<f64>();
                    assert!(s.abs() < 1e-12, "{scheme:?} smooth n={n}: {s}");
                }
                for k in 1..n {
                    let (a, b) = sector_tangents(scheme, n, 0, k);
                    for m in [a, b] {
                        let s = m.c + m.e.iter().sum::<f64>() + m.f.iter().sum::<f64>();
                        assert!(s.abs() < 1e-12, "{scheme:?} sector n={n} k={k}: {s}");
                    }
                }
            }
        }
    }
}
