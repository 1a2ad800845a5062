//! The cylinder of a circular feature (seed 002 §5, Eqs. 13–14): the axis by principal component
//! analysis of the feature's vertices, the radius from their distances to it.
//!
//! Axis. The covariance C = VᵀV of the centred vertices has singular vectors A₁, A₂, A₃ with
//! spreads σ₁ ≥ σ₂ ≥ σ₃. A ring of a cylinder spreads equally along its two radial directions, so
//! the axis is A₁ (a tall feature: σ₂ ≈ σ₃) or A₃ (a flat ring: σ₁ ≈ σ₂). The paper decides by
//! the largest vertex distances Dₖ from the lines along Aₖ, taking A₁ when |D₃ − D₂| < |D₁ − D₂|;
//! but for a single flat ring all three D equal the radius and that test is decided by rounding
//! (found by a test). So the same comparison is made on the spreads, which separate the two
//! cases cleanly: A₁ when |σ₂ − σ₃| < |σ₁ − σ₂|, else A₃.
//!
//! Radius. Eq. 14 takes the minimum vertex–axis distance ([`RadiusRule::Minimum`], the default,
//! as the paper); the mean is offered too ([`RadiusRule::Mean`]): on a polygon with n sides the
//! minimum is the inradius of the vertices' ring only if vertices lie on the circle, which they
//! do for the paper's features.

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

/// A fitted cylinder: a point on its axis (the centroid), the unit axis and the radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    pub center: Vec3,
    pub axis: Vec3,
    pub radius: f64,
}

/// Fits the cylinder of `points` (at least 3, finite).
///
/// # Errors
/// [`SolveError::TooFewVertices`] for fewer than 3 points; [`SolveError::NonFinite`].
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
    let center = local.iter().copied().sum::<Vec3>() / points.len() as f64;
    let mut c = Mat3::ZERO;
    for p in &local {
        let q = *p - center;
        c += Mat3::from_cols(q * q.x, q * q.y, q * q.z);
    }
    let (u, spread, _) = svd3(c);
    let distance = |p: Vec3, axis: Vec3| {
        let q = p - center;
        (q - axis * q.dot(axis)).length()
    };
    let axis = if (spread.y - spread.z).abs() < (spread.x - spread.y).abs() { u.col(0) } else { u.col(2) };
    let axis = axis.normalize();
    let dists = local.iter().map(|&p| distance(p, axis));
    let radius = match rule {
        RadiusRule::Minimum => dists.fold(f64::INFINITY, f64::min),
        RadiusRule::Mean => dists.sum::<f64>() / points.len() as f64,
    };
    Ok(Cylinder { center: r + center, axis, radius })
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

    #[test]
    fn too_few_or_broken_points_are_refused() {
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
