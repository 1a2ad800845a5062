//! Linear interpolation that keeps what its ends share.

use super::Vec3;

/// The point `t` of the way from `a` to `b`: exactly `a` at 0, exactly `b` at 1, and in every
/// coordinate `a` and `b` share, exactly that coordinate.
///
/// glam's `lerp` (`a (1 − t) + b t`) rounds a shared coordinate — 0.3 at t = 1/3 becomes
/// 0.29999999999999993 — so points meant to lie on one plane (the grid on a sharp block's face, a
/// T-vertex on a straight rim) miss it by an ulp, and solids that should touch leave slivers in a
/// boolean.
#[inline]
#[must_use]
pub fn lerp(a: Vec3, b: Vec3, t: f64) -> Vec3 {
    if t == 1.0 {
        b
    } else {
        a + (b - a) * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_shared_coordinates_are_exact() {
        let (a, b) = (Vec3::new(0.3, -0.1, 0.7), Vec3::new(0.3, 0.3, 1.1));
        assert_eq!(lerp(a, b, 0.0), a);
        assert_eq!(lerp(a, b, 1.0), b);
        for k in 1..100 {
            let t = f64::from(k) / 100.0;
            assert_eq!(lerp(a, b, t).x, 0.3, "t = {t}");
            // glam's form does not keep it for every t.
        }
        assert!((1..100).any(|k| a.lerp(b, f64::from(k) / 100.0).x != 0.3));
        assert!((lerp(a, b, 0.25) - Vec3::new(0.3, 0.0, 0.8)).length() < 1e-15);
    }
}
