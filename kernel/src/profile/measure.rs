//! Measures of a profile (area, bounds, outer contours and holes) and its simplification.

use super::convert::check_number;
use super::{Profile, ProfileError, Vec2};

/// The signed area of a closed contour: positive counter-clockwise (the shoelace formula).
#[must_use]
pub fn contour_area(contour: &[Vec2]) -> f64 {
    let n = contour.len();
    if n < 3 {
        return 0.0;
    }
    // Relative to the first point, so far-off contours keep their digits.
    let o = contour[0];
    (1..n - 1).map(|i| (contour[i] - o).perp_dot(contour[i + 1] - o)).sum::<f64>() * 0.5
}

impl Profile {
    /// The region's area (outer contours add, holes subtract).
    #[must_use]
    pub fn area(&self) -> f64 {
        self.contours.iter().map(|c| contour_area(c)).sum()
    }

    /// The smallest axis-aligned box holding the region: `(min, max)`, `None` when empty.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec2, Vec2)> {
        let mut points = self.contours.iter().flatten();
        let first = *points.next()?;
        Some(points.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
    }

    /// Whether contour `i` is a hole (clockwise).
    #[must_use]
    pub fn is_hole(&self, i: usize) -> bool {
        self.contours.get(i).is_some_and(|c| contour_area(c) < 0.0)
    }

    /// The region with every vertex nearer than `epsilon` to the line through its neighbours
    /// removed, and contours smaller than `epsilon` across dropped (Clipper2's
    /// `SimplifyPaths`, Ramer–Douglas–Peucker style).
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for `epsilon` negative or not finite.
    pub fn simplify(&self, epsilon: f64) -> Result<Profile, ProfileError> {
        check_number("the tolerance", epsilon, false)?;
        if epsilon < 0.0 {
            return Err(ProfileError::BadValue { name: "the tolerance", value: epsilon, expected: "at least 0" });
        }
        Ok(Profile::from_section(&self.to_section().simplify(epsilon)))
    }

    /// The centroid of the region, `None` when it has no area.
    #[must_use]
    pub fn centroid(&self) -> Option<Vec2> {
        let mut sum = Vec2::ZERO;
        let mut area = 0.0;
        for c in &self.contours {
            let n = c.len();
            for i in 0..n {
                let (p, q) = (c[i], c[(i + 1) % n]);
                let cross = p.perp_dot(q);
                area += cross;
                sum += (p + q) * cross;
            }
        }
        (area != 0.0).then(|| sum / (3.0 * area))
    }
}
