//! The mean of points, summed about one of them.

use super::Vec3;

/// The mean of `points` (the origin for none), summed as offsets from the first point, a local
/// origin: those differences of nearby coordinates are exact, so points far from the origin
/// (1e8) keep their digits, where a sum of the positions themselves rounds each term to the
/// large coordinates' spacing and grows its error with the count.
#[must_use]
pub fn mean_point<I: IntoIterator<Item = Vec3>>(points: I) -> Vec3 {
    let mut it = points.into_iter();
    let Some(origin) = it.next() else { return Vec3::ZERO };
    let (mut sum, mut n) = (Vec3::ZERO, 1.0);
    for p in it {
        sum += p - origin;
        n += 1.0;
    }
    origin + sum / n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_keeps_its_digits_far_from_the_origin() {
        assert_eq!(mean_point([]), Vec3::ZERO);
        assert_eq!(mean_point([Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 2.0, 1.0)]), Vec3::splat(2.0));
        // 1001 points on a small circle about (1e8, -1e8, 1e8): the mean is that centre to the
        // coordinates' own spacing (1.49e-8 at 1e8); the plain sum misses it by far more.
        let c = Vec3::new(1e8, -1e8, 1e8);
        let pts: Vec<Vec3> = (0..1001)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 1001.0;
                c + Vec3::new(0.3 * a.cos(), 0.3 * a.sin(), 0.0)
            })
            .collect();
        let got = mean_point(pts.iter().copied());
        assert!((got - c).abs().max_element() <= 1.5e-8, "{:e}", (got - c).abs().max_element());
        let naive = pts.iter().copied().sum::<Vec3>() / pts.len() as f64;
        assert!((naive - c).abs().max_element() > 1e-7, "the plain sum is {:e} off", (naive - c).abs().max_element());
    }
}
