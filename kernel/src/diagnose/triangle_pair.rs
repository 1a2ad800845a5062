//! Whether two triangles intersect, decided exactly: every sign that decides is Shewchuk's
//! adaptive `orient3d` or `orient2d` (the `robust` crate), so no tolerance can hide a crossing
//! or invent one.
//!
//! Notation: triangles are corner positions `[P; 3]`; `o3(a, b, c, d)` is the sign of the
//! orientation of `d` against the plane through `a, b, c`. Triangles are closed sets: touching
//! counts as intersecting, except along what the two triangles share by construction (a common
//! corner or edge), which is what a mesh's neighbouring faces do.
//!
//! Method. Two non-coplanar closed triangles meet on the line where their planes cross; the
//! ends of the meeting segment lie on the boundary of one triangle or the other, so they meet
//! exactly when an edge of one meets the other (Möller 1997, "A fast triangle–triangle
//! intersection test", §2, uses the same fact with floating-point intervals; here each edge
//! test is five exact orientations). Coplanar triangles are tested in the axis-aligned
//! projection in which the first is not degenerate (a projection is exact: it drops a
//! coordinate). Triangles sharing corners meet beyond them only in the cases of
//! [`shared_corner_meets`] and [`shared_edge_meets`].

use robust::{orient2d, orient3d, Coord, Coord3D};

use crate::math::Vec3;

fn c3(p: Vec3) -> Coord3D<f64> {
    Coord3D { x: p.x, y: p.y, z: p.z }
}

/// The sign (−1, 0, 1) of the orientation of `d` against the plane through `a, b, c`.
pub(crate) fn o3(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    sign(orient3d(c3(a), c3(b), c3(c), c3(d)))
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// A projection onto a coordinate plane: the axis dropped.
#[derive(Clone, Copy)]
struct Proj(usize);

impl Proj {
    fn at(self, p: Vec3) -> Coord<f64> {
        match self.0 {
            0 => Coord { x: p.y, y: p.z },
            1 => Coord { x: p.z, y: p.x },
            _ => Coord { x: p.x, y: p.y },
        }
    }

    /// The sign of the 2D orientation of `a, b, c` in this projection.
    fn o2(self, a: Vec3, b: Vec3, c: Vec3) -> i8 {
        sign(orient2d(self.at(a), self.at(b), self.at(c)))
    }
}

/// The projection in which triangle `t` is not degenerate, with the sign of its orientation
/// there; `None` when `t` is degenerate (its corners collinear) in every projection, which is
/// degenerate in space.
fn projection(t: [Vec3; 3]) -> Option<(Proj, i8)> {
    (0..3).map(Proj).map(|p| (p, p.o2(t[0], t[1], t[2]))).find(|&(_, s)| s != 0)
}

/// Whether triangle `t` is degenerate: its corners collinear (or two equal), exactly.
#[must_use]
pub(crate) fn is_degenerate(t: [Vec3; 3]) -> bool {
    projection(t).is_none()
}

/// Whether closed 2D segments `ab` and `cd` meet (projected by `p`; collinear overlaps count).
fn segments_meet_2d(p: Proj, a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> bool {
    let (d1, d2) = (p.o2(a, b, c), p.o2(a, b, d));
    let (d3, d4) = (p.o2(c, d, a), p.o2(c, d, b));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    // Touching or collinear: some point of one lies on the other.
    let on = |s: i8, q: Vec3, e0: Vec3, e1: Vec3| s == 0 && within_box(p, q, e0, e1);
    on(d1, c, a, b) || on(d2, d, a, b) || on(d3, a, c, d) || on(d4, b, c, d)
}

/// Whether `q` (collinear with `e0 e1` in projection `p`) lies within the segment's box.
fn within_box(p: Proj, q: Vec3, e0: Vec3, e1: Vec3) -> bool {
    let (q, a, b) = (p.at(q), p.at(e0), p.at(e1));
    q.x >= a.x.min(b.x) && q.x <= a.x.max(b.x) && q.y >= a.y.min(b.y) && q.y <= a.y.max(b.y)
}

/// Whether `q` lies in the closed triangle `t` of orientation `s` (non-zero) in projection `p`.
fn inside_2d(p: Proj, s: i8, q: Vec3, t: [Vec3; 3]) -> bool {
    (0..3).all(|i| p.o2(t[i], t[(i + 1) % 3], q) * s >= 0)
}

/// Whether the closed segment `de` meets the closed triangle `t` (not degenerate), both in
/// one plane, tested in `t`'s projection.
fn segment_meets_coplanar(d: Vec3, e: Vec3, t: [Vec3; 3], p: Proj, s: i8) -> bool {
    inside_2d(p, s, d, t) || inside_2d(p, s, e, t) || (0..3).any(|i| segments_meet_2d(p, d, e, t[i], t[(i + 1) % 3]))
}

/// Whether the closed segment `de` meets the closed triangle `t` (not degenerate).
fn segment_meets(d: Vec3, e: Vec3, t: [Vec3; 3]) -> bool {
    let (sd, se) = (o3(t[0], t[1], t[2], d), o3(t[0], t[1], t[2], e));
    if sd == se && sd != 0 {
        return false;
    }
    if sd == 0 && se == 0 {
        let Some((p, s)) = projection(t) else { return false };
        return segment_meets_coplanar(d, e, t, p, s);
    }
    // The segment crosses (or ends on) the plane at one point; it lies in the triangle when the
    // line de passes on the same side of (or through) each edge.
    let s = [o3(d, e, t[0], t[1]), o3(d, e, t[1], t[2]), o3(d, e, t[2], t[0])];
    !(s.contains(&1) && s.contains(&-1))
}

/// Whether closed triangles `a` and `b`, neither degenerate and sharing no corner, meet.
#[must_use]
pub(crate) fn triangles_meet(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    let sb = b.map(|q| o3(a[0], a[1], a[2], q));
    if (sb[0] == sb[1] && sb[1] == sb[2]) && sb[0] != 0 {
        return false;
    }
    let sa = a.map(|q| o3(b[0], b[1], b[2], q));
    if (sa[0] == sa[1] && sa[1] == sa[2]) && sa[0] != 0 {
        return false;
    }
    if sb == [0, 0, 0] {
        let Some((p, s)) = projection(a) else { return false };
        // b lies in a's plane, which this projection keeps one-to-one.
        let sb2 = p.o2(b[0], b[1], b[2]);
        return (0..3).any(|i| inside_2d(p, s, b[i], a))
            || (sb2 != 0 && (0..3).any(|i| inside_2d(p, sb2, a[i], b)))
            || (0..3).any(|i| (0..3).any(|j| segments_meet_2d(p, a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])));
    }
    (0..3).any(|i| segment_meets(a[i], a[(i + 1) % 3], b)) || (0..3).any(|i| segment_meets(b[i], b[(i + 1) % 3], a))
}

/// Whether the closed segment from `s` to `x` meets triangle `t = [s, p, q]` (not degenerate)
/// anywhere but at `s`: only when `x` lies in `t`'s plane, in the angle of `t` at `s`.
fn edge_enters_at_corner(s: Vec3, x: Vec3, p: Vec3, q: Vec3) -> bool {
    if o3(s, p, q, x) != 0 {
        return false;
    }
    let Some((pr, o)) = projection([s, p, q]) else { return false };
    pr.o2(s, p, x) * o >= 0 && pr.o2(s, x, q) * o >= 0
}

/// Whether triangles `[s, a, b]` and `[s, p, q]` (neither degenerate), sharing exactly the
/// corner `s`, meet anywhere else. Their meeting set is convex and holds `s`; if it holds more,
/// one of its corners other than `s` lies on an edge of one triangle: on the edge opposite `s`
/// (an edge test), or on an edge from `s`, which then runs into the other triangle's angle at
/// `s` within its plane.
#[must_use]
pub(crate) fn shared_corner_meets(s: Vec3, a: Vec3, b: Vec3, p: Vec3, q: Vec3) -> bool {
    segment_meets(a, b, [s, p, q])
        || segment_meets(p, q, [s, a, b])
        || edge_enters_at_corner(s, a, p, q)
        || edge_enters_at_corner(s, b, p, q)
        || edge_enters_at_corner(s, p, a, b)
        || edge_enters_at_corner(s, q, a, b)
}

/// Whether triangles `[u, v, a]` and `[u, v, b]` (neither degenerate), sharing the edge `uv`,
/// meet anywhere off it: only when they are coplanar and fold onto the same side of `uv`.
#[must_use]
pub(crate) fn shared_edge_meets(u: Vec3, v: Vec3, a: Vec3, b: Vec3) -> bool {
    if o3(u, v, a, b) != 0 {
        return false;
    }
    let Some((p, s)) = projection([u, v, a]) else { return false };
    p.o2(u, v, b) == s
}

/// A point where triangles `a` and `b` (found to meet) meet, for showing the crossing: the mean
/// of the points where an edge of either crosses the other (each found by the exact test,
/// placed in floating point along the edge by its distances to the plane), else — in-plane
/// overlaps — the mean of the corners of either inside the other, else the mean of the two
/// triangles' centres.
#[must_use]
pub(crate) fn meeting_point(a: [Vec3; 3], b: [Vec3; 3]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut n = 0.0;
    for (s, t) in [(a, b), (b, a)] {
        let normal = (t[1] - t[0]).cross(t[2] - t[0]);
        for i in 0..3 {
            let (d, e) = (s[i], s[(i + 1) % 3]);
            if !segment_meets(d, e, t) {
                continue;
            }
            let (hd, he) = (normal.dot(d - t[0]), normal.dot(e - t[0]));
            if hd == he {
                // In the plane: its ends inside t stand for it.
                let Some((p, sign)) = projection(t) else { continue };
                for q in [d, e] {
                    if inside_2d(p, sign, q, t) {
                        sum += q;
                        n += 1.0;
                    }
                }
            } else {
                sum += d + (e - d) * (hd / (hd - he)).clamp(0.0, 1.0);
                n += 1.0;
            }
        }
    }
    if n > 0.0 {
        sum / n
    } else {
        (a[0] + a[1] + a[2] + b[0] + b[1] + b[2]) / 6.0
    }
}
