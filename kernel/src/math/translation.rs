//! Whether one list of points is another moved by one vector.

use super::Vec3;

/// The vector that moves `from` onto `to`, when every point of `to` is its point of `from`
/// moved by one vector within `tolerance` per coordinate (the vector taken from the first
/// pair); `None` when they differ in length, are empty, or are not so moved (a non-finite
/// point never is). Linear.
#[must_use]
pub fn translation_between(from: &[Vec3], to: &[Vec3], tolerance: f64) -> Option<Vec3> {
    if from.len() != to.len() || from.is_empty() {
        return None;
    }
    let d = to[0] - from[0];
    // Compared per component, so a NaN fails (a maximum of the components would skip it).
    let within = Vec3::splat(tolerance);
    let moved = from.iter().zip(to).all(|(&p, &q)| (q - p - d).abs().cmple(within).all());
    moved.then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_translate_within_the_tolerance_and_nothing_else() {
        let from = [Vec3::ZERO, Vec3::X, Vec3::new(0.3, 0.7, -2.0)];
        let d = Vec3::new(1e3, -2.5, 0.125);
        let to: Vec<Vec3> = from.iter().map(|&p| p + d).collect();
        assert!((translation_between(&from, &to, 1e-12).unwrap() - d).length() < 1e-12);
        let mut bent = to.clone();
        bent[2].y += 1e-6;
        assert!(translation_between(&from, &bent, 1e-9).is_none());
        assert!(translation_between(&from, &bent, 1e-5).is_some());
        bent[1].x = f64::NAN;
        assert!(translation_between(&from, &bent, 1.0).is_none());
        assert!(translation_between(&from, &to[..2], 1.0).is_none());
        assert!(translation_between(&[], &[], 1.0).is_none());
    }
}
