//! The local step: each constraint's projection of its (mean-centred) vertices onto its shape.
//! Every projection takes and returns points relative to their mean (seed 002 Eq. 2), so the
//! mean-centring matrix N of Eq. 1 is applied by the caller.

use super::fit_circle::circle_in_plane;
use super::svd3::{best_rotation, svd3};
use crate::math::{Mat3, Vec3};

/// The rigid (relative shape) projection (Eqs. 5–9): the target shape `target` (centred) turned
/// by the rotation that best maps it onto the current points `current` (centred).
pub(crate) fn rigid(target: &[Vec3], current: &[Vec3]) -> Vec<Vec3> {
    let r = best_rotation(target, current);
    target.iter().map(|p| r * *p).collect()
}

/// The unit normal of the best-fit plane through centred points: the direction of least
/// spread (the last singular vector of their covariance).
pub(crate) fn plane_normal(points: &[Vec3]) -> Vec3 {
    let mut c = Mat3::ZERO;
    for p in points {
        c += Mat3::from_cols(*p * p.x, *p * p.y, *p * p.z);
    }
    let (u, _, _) = svd3(c);
    u.col(2).try_normalize().unwrap_or(Vec3::Z)
}

/// The plane projection: centred points onto their best-fit plane through the mean.
pub(crate) fn plane(points: &[Vec3]) -> Vec<Vec3> {
    let n = plane_normal(points);
    points.iter().map(|p| *p - n * p.dot(n)).collect()
}

/// The circle projection (Shape-Up): the points onto their best-fit plane, then each onto the
/// circle fitted there (least squares on the distances, see `fit_circle`), re-centred on their
/// mean. With `radius`, the circle keeps the fitted centre and plane but has that radius (the
/// size projection of seed 002 Eq. 18, which scales a feature's radial components).
pub(crate) fn circle(points: &[Vec3], radius: Option<f64>) -> Vec<Vec3> {
    let n = plane_normal(points);
    let e1 = n.any_orthonormal_vector();
    let e2 = n.cross(e1);
    let uv: Vec<(f64, f64)> = points.iter().map(|p| (p.dot(e1), p.dot(e2))).collect();
    let (cx, cy, fitted) = circle_in_plane(&uv).unwrap_or_else(|| {
        // Collinear or coincident points: a circle about their mean through the farthest.
        (0.0, 0.0, uv.iter().map(|&(x, y)| (x * x + y * y).sqrt()).fold(0.0, f64::max))
    });
    let radius = radius.unwrap_or(fitted);
    let projected: Vec<Vec3> = uv
        .iter()
        .map(|&(x, y)| {
            let (dx, dy) = (x - cx, y - cy);
            let d = (dx * dx + dy * dy).sqrt();
            let (ux, uy) = if d > 0.0 { (dx / d, dy / d) } else { (1.0, 0.0) };
            e1 * (cx + radius * ux) + e2 * (cy + radius * uy)
        })
        .collect();
    centred(&projected)
}

/// `points` less their mean.
pub(crate) fn centred(points: &[Vec3]) -> Vec<Vec3> {
    let mean = crate::math::mean_point(points.iter().copied());
    points.iter().map(|p| *p - mean).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_noisy_ring_projects_onto_one_circle() {
        let (axis, r) = (Vec3::new(0.3, -0.2, 1.0).normalize(), 0.8);
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        let pts: Vec<Vec3> = (0..12)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 12.0;
                let wobble = 0.05 * (3.0 * a).sin();
                e1 * ((r + wobble) * a.cos()) + e2 * ((r + wobble) * a.sin()) + axis * (0.02 * (5.0 * a).cos())
            })
            .collect();
        let p = circle(&centred(&pts), None);
        let radii: Vec<f64> = p.iter().map(|q| q.length()).collect();
        let mean = radii.iter().sum::<f64>() / radii.len() as f64;
        assert!(radii.iter().all(|x| (x - mean).abs() < 1e-9), "{radii:?}");
        assert!((mean - r).abs() < 0.02, "radius {mean}");
        assert!(p.iter().all(|q| (q.dot(plane_normal(&p))).abs() < 1e-12));
        // With a radius: the same centre and plane, every point at that radius.
        let sized = circle(&centred(&pts), Some(0.5));
        let c = crate::solve::fit_circle(&sized).unwrap();
        assert!((c.radius - 0.5).abs() < 1e-12 && c.deviation < 1e-12, "{c:?}");
    }

    #[test]
    fn rigid_keeps_the_target_shape() {
        let target = centred(&[Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 0.0, 3.0)]);
        let squashed: Vec<Vec3> = target.iter().map(|p| Vec3::new(p.x, 0.5 * p.y, p.z)).collect();
        let p = rigid(&target, &squashed);
        for i in 0..4 {
            for j in 0..4 {
                let (a, b) = ((p[i] - p[j]).length(), (target[i] - target[j]).length());
                assert!((a - b).abs() < 1e-12);
            }
        }
    }
}
