//! Unit vectors of any non-zero finite vector.

use super::Vec3;

/// `v` normalised, also when its length squared overflows or underflows (`[1e300, 0, 0]`,
/// `[1e-200, 0, 0]`, a Newell normal of a face 1e100 across): then divided by its largest
/// component first. `None` for the zero vector and non-finite vectors.
#[must_use]
pub fn direction(v: Vec3) -> Option<Vec3> {
    // Ordinary lengths: exactly as `try_normalize`, so results do not move by an ulp.
    let l2 = v.length_squared();
    if l2.is_finite() && l2 >= f64::MIN_POSITIVE {
        return v.try_normalize();
    }
    let big = v.abs().max_element();
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    (v / big).try_normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_vectors_have_directions_zero_and_nan_none() {
        for s in [1e300, f64::MAX, 1e-200, 5e-324, 1.0] {
            assert_eq!(direction(Vec3::new(0.0, 0.0, -s)), Some(Vec3::NEG_Z), "{s}");
        }
        let d = direction(Vec3::new(1e300, 1e300, 0.0)).unwrap();
        assert!((d.length() - 1.0).abs() < 1e-15);
        assert_eq!(direction(Vec3::ZERO), None);
        assert_eq!(direction(Vec3::new(f64::NAN, 1.0, 0.0)), None);
        assert_eq!(direction(Vec3::new(f64::INFINITY, 1.0, 0.0)), None);
    }
}
