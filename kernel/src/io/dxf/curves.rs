//! The curves a DXF draws, as points: arcs and polyline bulges, ellipses, NURBS splines and
//! splines through fit points, and the entity coordinate system (OCS) they are given in.

use std::f64::consts::TAU;

use glam::{DAffine2, DMat2, DVec3};

use super::ARC_SEGMENTS;
use crate::profile::Vec2;

/// The fewest points per knot span of a spline read; a span whose control points turn more
/// than an eighth of a turn gets more, twice [`ARC_SEGMENTS`] per full turn of its control
/// polygon (a curve turns no more than its control polygon: Lane & Riesenfeld 1981; twice,
/// as a spline's parameter does not advance evenly along it as an arc's angle does).
pub const SPLINE_SEGMENTS: usize = 16;

/// The points for the span whose control points are `control`: [`SPLINE_SEGMENTS`], or twice
/// [`ARC_SEGMENTS`] per full turn of the control polygon, whichever is more.
fn span_segments(control: &[DVec3]) -> usize {
    let turning: f64 = control
        .windows(3)
        .map(|w| {
            let (a, b) = ((w[1] - w[0]).truncate(), (w[2] - w[1]).truncate());
            if a.length() > 0.0 && b.length() > 0.0 {
                a.angle_to(b).abs()
            } else {
                0.0
            }
        })
        .sum();
    ((turning / TAU * 2.0 * ARC_SEGMENTS as f64).ceil() as usize).clamp(SPLINE_SEGMENTS, 8 * ARC_SEGMENTS)
}

/// The map from an entity's coordinate system (OCS) to the drawing's x and y, for the
/// extrusion direction `n` (unit) and the elevation `z` of the OCS plane: the "arbitrary axis
/// algorithm" of the DXF reference (the OCS x axis is `Wy × n` when `n` is within 1/64 of the
/// world z axis, else `Wz × n`; its y axis `n × x`), the drawing's z dropped. With `n` = +z it
/// is the identity; with `n` = −z (a mirrored arc, as CAD programs write them) x is negated.
#[must_use]
pub fn ocs(n: DVec3, z: f64) -> DAffine2 {
    let ax = if n.x.abs() < 1.0 / 64.0 && n.y.abs() < 1.0 / 64.0 { DVec3::Y.cross(n) } else { DVec3::Z.cross(n) };
    let ax = ax.normalize();
    let ay = n.cross(ax).normalize();
    DAffine2::from_mat2_translation(DMat2::from_cols(ax.truncate(), ay.truncate()), (n * z).truncate())
}

/// Points along the arc about `centre` of `radius` from angle `a0` turning `sweep` (radians,
/// counter-clockwise positive), the start excluded: [`ARC_SEGMENTS`] per full turn.
pub fn arc_points(centre: Vec2, radius: f64, a0: f64, sweep: f64, out: &mut Vec<Vec2>) {
    let n = ((sweep.abs() / TAU * ARC_SEGMENTS as f64).ceil() as usize).clamp(1, ARC_SEGMENTS);
    for k in 1..=n {
        let (s, c) = (a0 + sweep * k as f64 / n as f64).sin_cos();
        out.push(centre + radius * Vec2::new(c, s));
    }
}

/// A polyline's points with its bulges made arcs: the bulge of vertex i (tan of a quarter of
/// the arc's angle, counter-clockwise positive) bends the segment to vertex i + 1.
#[must_use]
pub fn polyline(vertices: &[(Vec2, f64)], closed: bool) -> Vec<Vec2> {
    let n = vertices.len();
    let mut out = Vec::with_capacity(n);
    let Some(&(first, _)) = vertices.first() else { return out };
    out.push(first);
    let segments = if closed { n } else { n - 1 };
    for i in 0..segments {
        let ((p, bulge), (q, _)) = (vertices[i], vertices[(i + 1) % n]);
        let chord = q - p;
        let len = chord.length();
        if bulge != 0.0 && len > 0.0 {
            let theta = 4.0 * bulge.atan();
            let radius = len / (2.0 * (theta / 2.0).sin()).abs();
            let d = len / (2.0 * (theta / 2.0).tan());
            let centre = (p + q) / 2.0 + chord.perp() / len * d;
            let a0 = (p - centre).y.atan2((p - centre).x);
            arc_points(centre, radius, a0, theta, &mut out);
        } else {
            out.push(q);
        }
    }
    if closed {
        out.pop();
    }
    out
}

/// An `ELLIPSE`: `centre + cos t · major + sin t · ratio · (n × major)` for the parameter `t`
/// from `t0` to `t1` (radians, counter-clockwise about `n`), [`ARC_SEGMENTS`] per full turn,
/// the drawing's z dropped. Whether it is the whole ellipse (then the last point, the first
/// again, is left out).
#[must_use]
pub fn ellipse(centre: DVec3, major: DVec3, n: DVec3, ratio: f64, t0: f64, t1: f64) -> (bool, Vec<Vec2>) {
    let minor = n.cross(major) * ratio;
    let mut sweep = (t1 - t0).rem_euclid(TAU);
    if sweep <= 1e-12 || (TAU - sweep) <= 1e-12 {
        sweep = TAU;
    }
    let whole = sweep == TAU;
    let steps = ((sweep / TAU * ARC_SEGMENTS as f64).ceil() as usize).clamp(1, ARC_SEGMENTS);
    let last = if whole { steps - 1 } else { steps };
    let pts = (0..=last)
        .map(|k| {
            let (s, c) = (t0 + sweep * k as f64 / steps as f64).sin_cos();
            (centre + c * major + s * minor).truncate()
        })
        .collect();
    (whole, pts)
}

/// Why a spline cannot be drawn.
pub type SplineError = String;

/// A NURBS curve of `degree` with `knots` (nondecreasing, as many as the control points plus
/// the degree plus one), its `control` points and their `weights` (positive; `None`: all 1),
/// evaluated by de Boor's algorithm in homogeneous coordinates (Piegl & Tiller, *The NURBS
/// Book*, §4.2 and A4.1) at [`SPLINE_SEGMENTS`] or more points per nonempty knot span (see
/// [`SPLINE_SEGMENTS`]) over the curve's domain `[knots[degree], knots[count]]`, the drawing's z dropped (a projection is
/// affine, so it commutes with the rational evaluation).
///
/// # Errors
/// A degree below 1, too few control points for the degree, a knot count other than the
/// control points plus the degree plus one, knots that decrease, weights that are not
/// positive or not one per control point, or an empty domain.
pub fn nurbs(
    degree: usize,
    knots: &[f64],
    control: &[DVec3],
    weights: Option<&[f64]>,
) -> Result<Vec<Vec2>, SplineError> {
    let count = control.len();
    if degree == 0 {
        return Err("its degree is 0".into());
    }
    if count <= degree {
        return Err(format!("it has {count} control points, a degree {degree} spline needs {}", degree + 1));
    }
    if knots.len() != count + degree + 1 {
        return Err(format!(
            "it has {} knots; {count} control points of degree {degree} need {}",
            knots.len(),
            count + degree + 1
        ));
    }
    if knots.windows(2).any(|w| w[1] < w[0]) {
        return Err("its knots decrease".into());
    }
    let weights = match weights {
        Some(w) if !w.is_empty() => {
            if w.len() != count {
                return Err(format!("it has {} weights for {count} control points", w.len()));
            }
            if w.iter().any(|&x| x <= 0.0) {
                return Err("a weight is not positive".into());
            }
            w.to_vec()
        }
        _ => vec![1.0; count],
    };
    let (lo, hi) = (knots[degree], knots[count]);
    if hi <= lo {
        return Err("its domain is empty (the knots it spans are equal)".into());
    }
    // Homogeneous control points: (w·x, w·y, w).
    let homogeneous: Vec<DVec3> = control.iter().zip(&weights).map(|(p, &w)| DVec3::new(p.x * w, p.y * w, w)).collect();
    let at = |span: usize, t: f64| {
        let mut d: Vec<DVec3> = (0..=degree).map(|j| homogeneous[j + span - degree]).collect();
        for r in 1..=degree {
            for j in (r..=degree).rev() {
                let (a, b) = (knots[j + span - degree], knots[j + 1 + span - r]);
                let alpha = if b > a { (t - a) / (b - a) } else { 0.0 };
                d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
            }
        }
        let h = d[degree];
        Vec2::new(h.x / h.z, h.y / h.z)
    };
    let mut out = Vec::new();
    let spans: Vec<usize> = (degree..count).filter(|&k| knots[k + 1] > knots[k]).collect();
    out.push(at(spans[0], lo));
    for &k in &spans {
        let (a, b) = (knots[k], knots[k + 1]);
        let n = span_segments(&control[k - degree..=k]);
        for s in 1..=n {
            out.push(at(k, a + (b - a) * s as f64 / n as f64));
        }
    }
    Ok(out)
}

/// A curve through `fit` points, as a spline given only by them is drawn: a centripetal
/// Catmull–Rom curve (Yuksel, Schaefer & Keyser 2011: no cusps or self-crossings within a
/// segment), [`SPLINE_SEGMENTS`] points per segment, through every point in order; `closed`
/// joins the last to the first. AutoCAD fits a cubic B-spline with end tangents through the
/// same points: the two agree at the points and differ slightly between them.
#[must_use]
pub fn through(fit: &[Vec2], closed: bool) -> Vec<Vec2> {
    let n = fit.len();
    if n < 3 {
        return fit.to_vec();
    }
    let get = |i: isize| -> Vec2 {
        if closed {
            fit[i.rem_euclid(n as isize) as usize]
        } else if i < 0 {
            2.0 * fit[0] - fit[1]
        } else if i as usize >= n {
            2.0 * fit[n - 1] - fit[n - 2]
        } else {
            fit[i as usize]
        }
    };
    let segments = if closed { n } else { n - 1 };
    let mut out = vec![fit[0]];
    for i in 0..segments as isize {
        let (p0, p1, p2, p3) = (get(i - 1), get(i), get(i + 1), get(i + 2));
        let knot = |a: Vec2, b: Vec2| a.distance(b).sqrt().max(1e-12);
        let t1 = knot(p0, p1);
        let t2 = t1 + knot(p1, p2);
        let t3 = t2 + knot(p2, p3);
        let lerp = |a: Vec2, b: Vec2, ta: f64, tb: f64, t: f64| a * ((tb - t) / (tb - ta)) + b * ((t - ta) / (tb - ta));
        for s in 1..=SPLINE_SEGMENTS {
            let t = t1 + (t2 - t1) * s as f64 / SPLINE_SEGMENTS as f64;
            let a1 = lerp(p0, p1, 0.0, t1, t);
            let a2 = lerp(p1, p2, t1, t2, t);
            let a3 = lerp(p2, p3, t2, t3, t);
            let b1 = lerp(a1, a2, 0.0, t2, t);
            let b2 = lerp(a2, a3, t1, t3, t);
            out.push(lerp(b1, b2, t1, t2, t));
        }
    }
    if closed {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cubic_bezier_as_a_nurbs_matches_bernstein() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
        ];
        let pts = nurbs(3, &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &p, None).unwrap();
        // The control polygon turns twice atan(2): 0.352 of a turn, 46 segments.
        assert_eq!(pts.len(), 46 + 1);
        for (k, q) in pts.iter().enumerate() {
            let t = k as f64 / 46.0;
            let u = 1.0 - t;
            let b = p[0] * u * u * u + p[1] * 3.0 * u * u * t + p[2] * 3.0 * u * t * t + p[3] * t * t * t;
            assert!(q.distance(b.truncate()) < 1e-12, "t = {t}: {q} vs {b}");
        }
    }

    #[test]
    fn a_rational_quadratic_circle_is_exact() {
        // The nine-point rational quadratic unit circle (The NURBS Book, Ex. 7.2).
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let p: Vec<DVec3> =
            [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.), (1., 0.)]
                .iter()
                .map(|&(x, y)| DVec3::new(x, y, 0.0))
                .collect();
        let weights = [1.0, w, 1.0, w, 1.0, w, 1.0, w, 1.0];
        let knots = [0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0];
        let pts = nurbs(2, &knots, &p, Some(&weights)).unwrap();
        assert_eq!(pts.len(), 4 * 32 + 1, "a quarter turn per span: 32 points");
        assert!(pts.iter().all(|q| (q.length() - 1.0).abs() < 1e-12));
        assert!(pts[0].distance(pts[pts.len() - 1]) < 1e-12);
    }

    #[test]
    fn bad_splines_say_why() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(nurbs(3, &[0.0; 7], &p, None).unwrap_err().contains("needs 4"));
        assert!(nurbs(2, &[0.0; 5], &p, None).unwrap_err().contains("need 6"));
        assert!(nurbs(2, &[0.0, 0.0, 0.0, 1.0, 0.5, 1.0], &p, None).unwrap_err().contains("decrease"));
        assert!(nurbs(2, &[0.0; 6], &p, None).unwrap_err().contains("empty"));
        assert!(nurbs(2, &[0., 0., 0., 1., 1., 1.], &p, Some(&[1.0, 0.0, 1.0])).unwrap_err().contains("positive"));
        assert!(nurbs(2, &[0., 0., 0., 1., 1., 1.], &p, Some(&[1.0])).unwrap_err().contains("1 weights"));
    }

    #[test]
    fn a_span_that_turns_far_gets_more_points() {
        // A cubic Bézier loop (its control polygon turns 0.65 of a turn): 83 segments, and
        // its polygon's area within 0.1% of the exact one (Green's theorem on the Bernstein form:
        // 3/20 of a sum of cross products, here 1.2).
        let p = [
            DVec3::new(22.0, 10.0, 0.0),
            DVec3::new(23.0, 13.0, 0.0),
            DVec3::new(25.0, 11.0, 0.0),
            DVec3::new(22.0, 10.0, 0.0),
        ];
        let pts = nurbs(3, &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &p, None).unwrap();
        assert_eq!(pts.len(), 83 + 1);
        let area = crate::profile::contour_area(&pts[..pts.len() - 1]).abs();
        assert!((area - 1.2).abs() < 1.2e-3, "{area}");
    }

    #[test]
    fn a_curve_through_fit_points_passes_through_each() {
        let fit = [Vec2::new(0.0, 0.0), Vec2::new(2.0, 1.0), Vec2::new(3.0, 4.0), Vec2::new(0.5, 3.0)];
        for closed in [false, true] {
            let pts = through(&fit, closed);
            for (i, f) in fit.iter().enumerate() {
                assert!(pts[i * SPLINE_SEGMENTS].distance(*f) < 1e-12, "closed {closed}: point {i}");
            }
            let segments = if closed { 4 } else { 3 };
            assert_eq!(pts.len(), segments * SPLINE_SEGMENTS + usize::from(!closed));
        }
    }

    #[test]
    fn the_ocs_of_a_downward_extrusion_mirrors_x() {
        let m = ocs(DVec3::NEG_Z, 0.0);
        assert!(m.transform_point2(Vec2::new(2.0, 3.0)).distance(Vec2::new(-2.0, 3.0)) < 1e-15);
        assert!(ocs(DVec3::Z, 5.0).transform_point2(Vec2::new(2.0, 3.0)).distance(Vec2::new(2.0, 3.0)) < 1e-15);
        // Tilted about x by 60°: y is foreshortened by cos 60°.
        let n = DVec3::new(0.0, -(60f64.to_radians().sin()), 60f64.to_radians().cos());
        let q = ocs(n, 0.0).transform_point2(Vec2::new(0.0, 1.0));
        assert!((q.length() - 0.5).abs() < 1e-12, "{q}");
    }

    #[test]
    fn a_whole_ellipse_leaves_out_its_repeated_point() {
        let (whole, pts) = ellipse(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 0.5, 0.0, TAU);
        assert!(whole);
        assert_eq!(pts.len(), ARC_SEGMENTS);
        assert!(pts.iter().all(|p| ((p.x / 3.0).powi(2) + (p.y / 1.5).powi(2) - 1.0).abs() < 1e-12));
        let (whole, pts) = ellipse(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::NEG_Z, 0.5, 0.0, TAU / 4.0);
        assert!(!whole);
        assert!(pts[pts.len() - 1].distance(Vec2::new(0.0, -1.5)) < 1e-12, "a downward ellipse turns clockwise");
    }
}
