//! The cylinder of a circular feature (seed 002 §5, Eqs. 13–14): its axis and radius, fitted by
//! least squares on the distances of the feature's vertices from the cylinder.
//!
//! The paper takes the axis from a principal component analysis of the vertices: for a ring of a
//! cylinder the covariance spreads equally along the two radial directions, so the axis is the
//! first or the last principal direction, and the centre is the vertices' mean. Both hold only
//! for vertices evenly spaced round the axis. A hole whose vertices crowd on one side (after a
//! boolean, or cut by a seam), a partial arc, or two rings spaced unevenly have their mean pulled
//! off the axis and their spreads unequal, so the principal directions are not the axis either
//! (a first attempt that kept the PCA axis and fitted only the circle in its plane measured a
//! tube of radius 5 made of two crowded rings as 2.14). So the fit here is geometric: minimise
//! Σ (dist(pᵢ, axis) − R)² over the axis direction, a point on it and R, by Levenberg–Marquardt
//! from each principal direction in turn (with the least-squares circle of the points projected
//! on the plane across it as the start), keeping the best. A cylinder through exact points is
//! found to rounding; for a single flat ring it is the circle of [`fit_circle`](super::fit_circle)
//! with the ring's normal as axis (no tilted cylinder passes through a circle).
//!
//! Radius. Eq. 14 takes the minimum vertex–axis distance ([`RadiusRule::Minimum`], the default,
//! as the paper); the mean is offered too ([`RadiusRule::Mean`]). Both are measured from the
//! fitted axis; for vertices on the cylinder they equal its radius.

use super::fit_circle::circle_in_plane;
use super::svd3::svd3;
use super::SolveError;
use crate::math::{Mat3, Vec3};

/// How the radius is taken from the vertex–axis distances.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RadiusRule {
    /// The smallest distance (Eq. 14).
    #[default]
    Minimum,
    /// The mean distance.
    Mean,
}

/// A fitted cylinder: a point on its axis (the foot of the points' mean, so the middle of the
/// feature along the axis), the unit axis and the radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    pub center: Vec3,
    pub axis: Vec3,
    pub radius: f64,
}

/// An axis through `point` along unit `axis`, and the cost Σ rᵢ² of the best radius about it.
#[derive(Clone, Copy, Debug)]
struct Fit {
    point: Vec3,
    axis: Vec3,
    cost: f64,
}

fn cost(points: &[Vec3], point: Vec3, axis: Vec3, radius: f64) -> f64 {
    points
        .iter()
        .map(|q| {
            let w = *q - point;
            let r = (w - axis * w.dot(axis)).length() - radius;
            r * r
        })
        .sum()
}

/// Solves the 5×5 system `a x = b` (symmetric positive definite after damping) by Gaussian
/// elimination with partial pivoting; `None` when singular.
fn solve5(mut a: [[f64; 5]; 5], mut b: [f64; 5]) -> Option<[f64; 5]> {
    for k in 0..5 {
        let p = (k..5).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[p][k].abs() < 1e-300 {
            return None;
        }
        a.swap(k, p);
        b.swap(k, p);
        let pivot_row = a[k];
        for i in k + 1..5 {
            let f = a[i][k] / pivot_row[k];
            for (x, y) in a[i][k..].iter_mut().zip(&pivot_row[k..]) {
                *x -= f * y;
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = [0.0; 5];
    for k in (0..5).rev() {
        let s: f64 = (k + 1..5).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Levenberg–Marquardt from the axis direction `start`: the circle of the points projected on the
/// plane across it starts the centre and radius. `None` when the projection has no circle (the
/// points project onto a line: `start` lies in their plane).
fn refine(points: &[Vec3], mean: Vec3, start: Vec3) -> Option<Fit> {
    let mut axis = start.try_normalize()?;
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let uv: Vec<(f64, f64)> = points.iter().map(|p| ((*p - mean).dot(e1), (*p - mean).dot(e2))).collect();
    let (cx, cy, mut radius) = circle_in_plane(&uv)?;
    let mut point = mean + e1 * cx + e2 * cy;
    let mut current = cost(points, point, axis, radius);
    let scale = points.iter().map(|p| (*p - mean).length()).fold(0.0, f64::max).max(1e-300);
    let mut lambda = 1e-6;
    for _ in 0..100 {
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        // Residuals dᵢ − R and their derivatives by (axis tilt toward e1, e2; point along e1,
        // e2; R): with w = q − point, p = w − a(w·a), n = p/|p|: ∂d/∂tilt = −(w·a)(n·e),
        // ∂d/∂point = −n·e, ∂d/∂R = −1.
        let mut jtj = [[0.0; 5]; 5];
        let mut jtr = [0.0; 5];
        for q in points {
            let w = *q - point;
            let along = w.dot(axis);
            let perp = w - axis * along;
            let d = perp.length();
            if d == 0.0 {
                continue;
            }
            let n = perp / d;
            let j = [-along * n.dot(e1), -along * n.dot(e2), -n.dot(e1), -n.dot(e2), -1.0];
            let r = d - radius;
            for a in 0..5 {
                jtr[a] += j[a] * r;
                for b in 0..5 {
                    jtj[a][b] += j[a] * j[b];
                }
            }
        }
        let mut accepted = false;
        while lambda < 1e12 {
            let mut damped = jtj;
            for (k, row) in damped.iter_mut().enumerate() {
                row[k] += lambda * (jtj[k][k] + 1e-30);
            }
            let Some(step) = solve5(damped, jtr.map(|v| -v)) else {
                lambda *= 10.0;
                continue;
            };
            let Some(new_axis) = (axis + e1 * step[0] + e2 * step[1]).try_normalize() else {
                lambda *= 10.0;
                continue;
            };
            let moved = point + e1 * step[2] + e2 * step[3];
            // Keep the point on the axis at the foot of the mean (well conditioned).
            let new_point = moved + new_axis * (mean - moved).dot(new_axis);
            let new_radius = radius + step[4];
            let c = cost(points, new_point, new_axis, new_radius);
            if c <= current {
                let small = step.iter().map(|v| v.abs()).fold(0.0, f64::max) < 1e-15 * (1.0 + scale);
                axis = new_axis;
                point = new_point;
                radius = new_radius;
                current = c;
                lambda = (lambda * 0.1).max(1e-12);
                accepted = !small;
                break;
            }
            lambda *= 10.0;
        }
        if !accepted {
            break;
        }
    }
    Some(Fit { point, axis, cost: current })
}

/// Fits the cylinder of `points` (at least 3, finite, not all on one line).
///
/// # Errors
/// [`SolveError::TooFewVertices`] for fewer than 3 points; [`SolveError::NonFinite`];
/// [`SolveError::NoCircle`] when the points lie on one line or at one place.
pub fn fit_cylinder(points: &[Vec3], rule: RadiusRule) -> Result<Cylinder, SolveError> {
    if points.len() < 3 {
        return Err(SolveError::TooFewVertices { what: "a cylinder fit", needed: 3, got: points.len() });
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(SolveError::NonFinite { what: "the feature" });
    }
    // Everything is computed about the centre of the points' bounds, `r`: differences of
    // nearby coordinates are exact, so a feature far from the origin (1e8) keeps its digits.
    let r = crate::math::Aabb::from_points(points.iter()).center();
    let local: Vec<Vec3> = points.iter().map(|p| *p - r).collect();
    let mean = local.iter().copied().sum::<Vec3>() / points.len() as f64;
    let mut c = Mat3::ZERO;
    for p in &local {
        let q = *p - mean;
        c += Mat3::from_cols(q * q.x, q * q.y, q * q.z);
    }
    let (u, _, _) = svd3(c);
    // The feature as one ring: the circle of its points, its normal the axis.
    let ring = super::fit_circle(&local).map_err(|_| SolveError::NoCircle { what: "the feature" })?;
    let n = local.len() as f64;
    let (mut thickness, mut ring_cost) = (0.0, 0.0);
    for p in &local {
        let q = *p - ring.center;
        let h = q.dot(ring.normal);
        let d = (q - ring.normal * h).length() - ring.radius;
        thickness += h * h;
        ring_cost += h * h + d * d;
    }
    let thickness = (thickness / n).sqrt();
    // The cylinder of a ring is not determined by it: a planar ellipse (a round hole sheared with
    // its part) lies exactly on a tilted cylinder whose radius is its minor semi-axis, and a
    // ring that is not quite planar is fitted a little better by some tilted cylinder of large
    // radius through it; neither is the hole's axis. So a feature within a hundredth of its
    // radius (RMS) of one plane is a ring, its axis the plane's normal, and a thicker one is a
    // tube only where the cylinder explains it ten times better (RMS distance) than the ring:
    // where the points really extend along an axis (rims of a tube, arcs of its side).
    let tube = if thickness <= 0.01 * ring.radius {
        None
    } else {
        // The best of the cylinder fits started from each principal direction.
        [u.col(2), u.col(0), u.col(1)]
            .into_iter()
            .filter_map(|a| refine(&local, mean, a))
            .fold(None, |best: Option<Fit>, f| match best {
                Some(b) if b.cost <= f.cost => Some(b),
                _ => Some(f),
            })
            .filter(|t| t.cost < 0.01 * ring_cost)
    };
    let best = tube.unwrap_or(Fit { point: ring.center, axis: ring.normal, cost: ring_cost });
    let axis = best.axis;
    let dists = local.iter().map(|&p| {
        let q = p - best.point;
        (q - axis * q.dot(axis)).length()
    });
    let radius = match rule {
        RadiusRule::Minimum => dists.fold(f64::INFINITY, f64::min),
        RadiusRule::Mean => dists.sum::<f64>() / points.len() as f64,
    };
    Ok(Cylinder { center: r + best.point, axis, radius })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(n: usize, r: f64, z: f64, axis: Vec3) -> Vec<Vec3> {
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        (0..n)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                e1 * (r * a.cos()) + e2 * (r * a.sin()) + axis * z + Vec3::new(1.0, -2.0, 0.5)
            })
            .collect()
    }

    #[test]
    fn a_flat_ring_and_a_tall_tube_give_their_axes_and_radii() {
        let axis = Vec3::new(0.2, 0.3, 1.0).normalize();
        // A single ring (flat: the axis is the direction of least spread, A₃).
        let c = fit_cylinder(&ring(16, 0.35, 0.0, axis), RadiusRule::Minimum).unwrap();
        assert!(c.axis.dot(axis).abs() > 1.0 - 1e-12, "{}", c.axis);
        assert!((c.radius - 0.35).abs() < 1e-12, "{}", c.radius);
        // A ring whose points are all at the same distance from every principal line (a
        // rounded ring with a 1e-9 wobble): the spreads still tell the axis.
        let wobbly: Vec<Vec3> = ring(16, 0.8, 0.0, Vec3::Z)
            .iter()
            .enumerate()
            .map(|(i, p)| *p + Vec3::Z * (1e-9 * (i % 3) as f64))
            .collect();
        let c = fit_cylinder(&wobbly, RadiusRule::Minimum).unwrap();
        assert!(c.axis.z.abs() > 1.0 - 1e-9, "{}", c.axis);
        assert!((c.radius - 0.8).abs() < 1e-9);
        // Two rings far apart (tall: the axis is the direction of most spread, A₁).
        let mut tube = ring(12, 0.5, -2.0, axis);
        tube.extend(ring(12, 0.5, 2.0, axis));
        let c = fit_cylinder(&tube, RadiusRule::Mean).unwrap();
        assert!(c.axis.dot(axis).abs() > 1.0 - 1e-12);
        assert!((c.radius - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_feature_far_from_the_origin_fits_as_it_does_near_it() {
        // The same tube moved by up to 1e8 (moving back is exact: nearby coordinates subtract
        // without rounding): the same axis and radius, the centre moved by the offset. Summed
        // about the origin the centre was off by ~1e-7 at 1e8, and the minimum radius with it.
        let axis = Vec3::new(0.2, 0.3, 1.0).normalize();
        let mut tube = ring(12, 0.5, -2.0, axis);
        tube.extend(ring(12, 0.5, 2.0, axis));
        for offset in [1e4, 1e6, 1e8] {
            let d = Vec3::new(offset, offset, -offset);
            let far: Vec<Vec3> = tube.iter().map(|p| *p + d).collect();
            let near: Vec<Vec3> = far.iter().map(|p| *p - d).collect();
            for rule in [RadiusRule::Minimum, RadiusRule::Mean] {
                let (a, b) = (fit_cylinder(&far, rule).unwrap(), fit_cylinder(&near, rule).unwrap());
                assert!((a.radius - b.radius).abs() < 1e-12, "{offset}: {} vs {}", a.radius, b.radius);
                assert!(a.axis.dot(b.axis).abs() > 1.0 - 1e-12);
                assert!(((a.center - d) - b.center).length() < 1e-7, "{offset}");
            }
        }
    }

    /// Points at `angles` (radians) round the axis through `c` along unit `axis`, radius `r`,
    /// at each of `heights` along it.
    fn arcs(angles: &[f64], heights: &[f64], r: f64, c: Vec3, axis: Vec3) -> Vec<Vec3> {
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        let mut out = Vec::new();
        for h in heights {
            out.extend(angles.iter().map(|a| c + axis * *h + e1 * (r * a.cos()) + e2 * (r * a.sin())));
        }
        out
    }

    fn assert_cylinder(f: &Cylinder, c: Vec3, axis: Vec3, r: f64, tol: f64, what: &str) {
        assert!(f.axis.dot(axis).abs() > 1.0 - tol.max(1e-12), "{what}: axis {} vs {axis}", f.axis);
        assert!((f.radius - r).abs() < tol * r, "{what}: radius {} vs {r}", f.radius);
        // The fitted centre lies on the true axis.
        let q = f.center - c;
        assert!((q - axis * q.dot(axis)).length() < tol * r, "{what}: centre {} off the axis", f.center);
    }

    #[test]
    fn unevenly_spaced_rings_and_partial_arcs_give_the_cylinder_not_their_centroid() {
        // Each case's points lie exactly on a cylinder of radius 5, so the least-squares fit is
        // that cylinder to rounding, whatever the spread of the points; the centroid is off the
        // axis by up to 3.4 and the principal directions are not the axis.
        let axis = Vec3::new(0.3, -0.4, 1.0).normalize();
        let c = Vec3::new(1.0, 2.0, -3.0);
        let crowded: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.15).chain([2.5, 3.8, 5.0]).collect();
        let quarter: Vec<f64> = (0..7).map(|i| f64::from(i) * std::f64::consts::FRAC_PI_2 / 6.0).collect();
        let third: Vec<f64> = (0..9).map(|i| f64::from(i) * std::f64::consts::TAU / 3.0 / 8.0).collect();
        let cases = [
            ("one crowded ring", arcs(&crowded, &[0.0], 5.0, c, axis)),
            ("two crowded rings, short", arcs(&crowded, &[-1.0, 1.0], 5.0, c, axis)),
            ("two crowded rings, tall", arcs(&crowded, &[-6.0, 6.0], 5.0, c, axis)),
            ("three rings of a quarter arc", arcs(&quarter, &[-2.0, 0.5, 3.0], 5.0, c, axis)),
            ("a quarter arc, one ring", arcs(&quarter, &[0.0], 5.0, c, axis)),
            // Thin across the arc, yet a tube: a circle through both arcs in the plane along
            // them misses by far more than the cylinder.
            ("a third of the side, both rims", arcs(&third, &[-2.0, 2.0], 5.0, c, axis)),
        ];
        for (what, pts) in &cases {
            let centroid = crate::math::mean_point(pts.iter().copied());
            let q = centroid - c;
            assert!((q - axis * q.dot(axis)).length() > 1.0, "{what}: the centroid is off the axis");
            for rule in [RadiusRule::Minimum, RadiusRule::Mean] {
                let f = fit_cylinder(pts, rule).unwrap();
                assert_cylinder(&f, c, axis, 5.0, 1e-8, what);
            }
        }
    }

    #[test]
    fn a_sheared_hole_is_a_ring_not_a_tilted_cylinder() {
        // A round hole squashed to an ellipse of semi-axes 5.3 and 4.8 in the plane z = 1 lies
        // exactly on a cylinder of radius 4.8 tilted by acos(4.8 / 5.3) = 25°; the feature's
        // axis is still the plane's normal (a hole, not a slanted tube).
        let pts: Vec<Vec3> = (0..24)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 24.0;
                Vec3::new(5.3 * a.cos(), 4.8 * a.sin(), 1.0)
            })
            .collect();
        let f = fit_cylinder(&pts, RadiusRule::Mean).unwrap();
        assert!(f.axis.z.abs() > 1.0 - 1e-12, "{f:?}");
        assert!((f.center - Vec3::Z).length() < 1e-9 && f.radius > 4.8 && f.radius < 5.3, "{f:?}");
    }

    #[test]
    fn noisy_partial_arcs_give_the_cylinder_within_the_noise() {
        // Points on 120° of a cylinder of radius 2 at four heights, each moved by up to ±1 % of
        // the radius (seeded): the least-squares radius is within the noise's mean effect, well
        // under 1 % (about 0.3 % measured), the axis within 1°.
        let axis = Vec3::new(-0.2, 0.9, 0.3).normalize();
        let c = Vec3::new(-4.0, 0.5, 7.0);
        let angles: Vec<f64> = (0..16).map(|i| f64::from(i) * std::f64::consts::TAU / 3.0 / 15.0).collect();
        let mut rng = crate::math::SplitMix64::new(35);
        for seed_case in 0..4 {
            let pts: Vec<Vec3> = arcs(&angles, &[-1.5, -0.5, 0.5, 1.5], 2.0, c, axis)
                .into_iter()
                .map(|p| p + Vec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5) * 0.04)
                .collect();
            let f = fit_cylinder(&pts, RadiusRule::Mean).unwrap();
            assert!(f.axis.dot(axis).abs() > 1f64.to_radians().cos(), "case {seed_case}: axis {}", f.axis);
            assert!((f.radius - 2.0).abs() < 0.01 * 2.0, "case {seed_case}: radius {}", f.radius);
            let q = f.center - c;
            assert!((q - axis * q.dot(axis)).length() < 0.02 * 2.0, "case {seed_case}: centre {}", f.center);
        }
    }

    #[test]
    fn too_few_or_broken_points_are_refused() {
        let line = [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)];
        assert!(matches!(fit_cylinder(&line, RadiusRule::Minimum), Err(SolveError::NoCircle { .. })));
        assert!(matches!(fit_cylinder(&[Vec3::ONE; 5], RadiusRule::Mean), Err(SolveError::NoCircle { .. })));
        assert!(matches!(
            fit_cylinder(&[Vec3::ZERO, Vec3::X], RadiusRule::Minimum),
            Err(SolveError::TooFewVertices { needed: 3, got: 2, .. })
        ));
        assert!(matches!(
            fit_cylinder(&[Vec3::ZERO, Vec3::X, Vec3::NAN], RadiusRule::Minimum),
            Err(SolveError::NonFinite { .. })
        ));
    }
}
