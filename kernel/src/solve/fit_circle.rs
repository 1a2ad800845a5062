//! The circle through a ring of points (issue 35; the measure behind seed 002's circular
//! features): the best-fit plane by principal component analysis, then the circle in that plane
//! by least squares on the distances themselves (geometric fit), started from Kåsa's algebraic
//! fit.
//!
//! Why not the centroid: the mean of a ring's vertices is the circle's centre only when they are
//! evenly spaced round it. A hole whose vertices crowd on one side (as after a boolean, or a
//! feature cut by a seam) has its centroid pulled toward them, so a radius measured from it is
//! wrong by up to the pull. The least-squares circle does not depend on how the points are
//! spread along it.
//!
//! Geometric fit: minimise Σ (‖qᵢ − c‖ − R)² over the centre c and the radius R in the plane, by
//! Gauss–Newton from Kåsa's solution of x² + y² + a·x + b·y + e = 0 (exact for points on a
//! circle, so exact input converges at once).

use super::projections::plane_normal;
use super::SolveError;
use crate::math::{Mat3, Vec3};

/// A fitted circle: its centre, the unit normal of its plane (oriented so that the points run
/// counter-clockwise about it, in the order given), its radius, and the largest distance of a
/// point from the circle (out of the plane and off the radius together).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f64,
    pub deviation: f64,
}

/// The least-squares circle of planar points `uv`: `(cx, cy, r)`, or `None` when they are
/// (nearly) collinear or coincide.
pub(crate) fn circle_in_plane(uv: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = uv.len() as f64;
    let (mx, my) = (uv.iter().map(|p| p.0).sum::<f64>() / n, uv.iter().map(|p| p.1).sum::<f64>() / n);
    let local: Vec<(f64, f64)> = uv.iter().map(|&(x, y)| (x - mx, y - my)).collect();
    let scale = local.iter().map(|&(x, y)| x.abs().max(y.abs())).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    // Kåsa: normal equations of [x y 1]·[a b e]ᵀ = −(x² + y²), in units of `scale`.
    let pts: Vec<(f64, f64)> = local.iter().map(|&(x, y)| (x / scale, y / scale)).collect();
    let mut m = Mat3::ZERO;
    let mut rhs = Vec3::ZERO;
    for &(x, y) in &pts {
        let row = Vec3::new(x, y, 1.0);
        m += Mat3::from_cols(row * x, row * y, row);
        rhs -= row * (x * x + y * y);
    }
    if m.determinant().abs() < 1e-12 * n * n * n {
        return None;
    }
    let abe = m.inverse() * rhs;
    let (mut cx, mut cy) = (-abe.x / 2.0, -abe.y / 2.0);
    let mut r = (cx * cx + cy * cy - abe.z).max(0.0).sqrt();
    if !(r.is_finite() && r < 1e6) {
        return None;
    }
    // Gauss–Newton on the geometric residuals dᵢ − R.
    for _ in 0..50 {
        let mut jtj = Mat3::ZERO;
        let mut jtr = Vec3::ZERO;
        for &(x, y) in &pts {
            let (dx, dy) = (x - cx, y - cy);
            let d = (dx * dx + dy * dy).sqrt();
            if d == 0.0 {
                continue;
            }
            let j = Vec3::new(-dx / d, -dy / d, -1.0);
            jtj += Mat3::from_cols(j * j.x, j * j.y, j * j.z);
            jtr += j * (d - r);
        }
        if jtj.determinant().abs() < 1e-300 {
            break;
        }
        let step = jtj.inverse() * -jtr;
        cx += step.x;
        cy += step.y;
        r += step.z;
        if step.length() < 1e-15 * (1.0 + r) {
            break;
        }
    }
    Some((mx + cx * scale, my + cy * scale, r.abs() * scale))
}

/// Fits the circle of `points` (at least 3, finite, not all on one line).
///
/// # Errors
/// [`SolveError::TooFewVertices`] for fewer than 3 points; [`SolveError::NonFinite`];
/// [`SolveError::NoCircle`] when the points are collinear or coincide (no circle passes near
/// them).
pub fn fit_circle(points: &[Vec3]) -> Result<Circle, SolveError> {
    if points.len() < 3 {
        return Err(SolveError::TooFewVertices { what: "a circle fit", needed: 3, got: points.len() });
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(SolveError::NonFinite { what: "the ring" });
    }
    // About the centre of the bounds, so a ring far from the origin keeps its digits.
    let origin = crate::math::Aabb::from_points(points.iter()).center();
    let mean = crate::math::mean_point(points.iter().map(|p| *p - origin));
    let local: Vec<Vec3> = points.iter().map(|p| *p - origin - mean).collect();
    let mut normal = plane_normal(&local);
    let e1 = normal.any_orthonormal_vector();
    let e2 = normal.cross(e1);
    let uv: Vec<(f64, f64)> = local.iter().map(|p| (p.dot(e1), p.dot(e2))).collect();
    let (cx, cy, radius) = circle_in_plane(&uv).ok_or(SolveError::NoCircle { what: "the ring" })?;
    let c = e1 * cx + e2 * cy;
    // Orient the normal by the points' turning about the centre (the ring's order).
    let turning: Vec3 = (0..local.len()).map(|i| (local[i] - c).cross(local[(i + 1) % local.len()] - c)).sum();
    if turning.dot(normal) < 0.0 {
        normal = -normal;
    }
    let deviation = local
        .iter()
        .map(|p| {
            let q = *p - c;
            let h = q.dot(normal);
            let d = (q - normal * h).length() - radius;
            (h * h + d * d).sqrt()
        })
        .fold(0.0, f64::max);
    Ok(Circle { center: origin + mean + c, normal, radius, deviation })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn ring_at(angles: &[f64], r: f64, c: Vec3, axis: Vec3) -> Vec<Vec3> {
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        angles.iter().map(|a| c + e1 * (r * a.cos()) + e2 * (r * a.sin())).collect()
    }

    #[test]
    fn unevenly_spaced_points_give_the_circle_not_their_centroid() {
        // Ten points crowded on a quarter of the circle and three spread over the rest: the
        // centroid is 1.6 from the centre, the fit exact.
        let axis = Vec3::new(0.3, -0.4, 1.0).normalize();
        let c = Vec3::new(1.0, 2.0, -3.0);
        let mut angles: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.15).collect();
        angles.extend([2.5, 3.8, 5.0]);
        let pts = ring_at(&angles, 5.0, c, axis);
        let centroid = crate::math::mean_point(pts.iter().copied());
        assert!((centroid - c).length() > 1.0);
        let f = fit_circle(&pts).unwrap();
        assert!((f.radius - 5.0).abs() < 1e-9, "{f:?}");
        assert!((f.center - c).length() < 1e-9, "{f:?}");
        assert!(f.normal.dot(axis) > 1.0 - 1e-12, "counter-clockwise about the axis: {f:?}");
        assert!(f.deviation < 1e-9);
        // Reversed order: the normal flips, nothing else.
        let rev: Vec<Vec3> = pts.iter().rev().copied().collect();
        let g = fit_circle(&rev).unwrap();
        assert!(g.normal.dot(axis) < -1.0 + 1e-12 && (g.radius - 5.0).abs() < 1e-9);
    }

    #[test]
    fn a_noisy_ring_reports_its_deviation_and_far_rings_keep_their_digits() {
        let angles: Vec<f64> = (0..24).map(|i| f64::from(i) * TAU / 24.0).collect();
        let mut pts = ring_at(&angles, 2.0, Vec3::ZERO, Vec3::Z);
        pts[3].z += 0.01;
        pts[7] *= 1.02;
        let f = fit_circle(&pts).unwrap();
        assert!((f.radius - 2.0).abs() < 0.01 && f.deviation > 0.01 && f.deviation < 0.05, "{f:?}");
        for offset in [1e4, 1e8] {
            let d = Vec3::new(offset, -offset, offset);
            let exact = ring_at(&angles, 0.35, d, Vec3::X);
            let f = fit_circle(&exact).unwrap();
            // At 1e8 the coordinates themselves are rounded to 1.5e-8.
            assert!((f.radius - 0.35).abs() < 1e-7, "{offset}: {f:?}");
            assert!((f.center - d).length() < 1e-6, "{offset}: {f:?}");
        }
    }

    #[test]
    fn lines_points_and_too_few_are_refused() {
        let line = [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)];
        assert!(matches!(fit_circle(&line), Err(SolveError::NoCircle { .. })));
        assert!(matches!(fit_circle(&[Vec3::ONE; 4]), Err(SolveError::NoCircle { .. })));
        assert!(matches!(fit_circle(&[Vec3::ZERO, Vec3::X]), Err(SolveError::TooFewVertices { .. })));
        assert!(matches!(fit_circle(&[Vec3::ZERO, Vec3::X, Vec3::NAN]), Err(SolveError::NonFinite { .. })));
    }
}
