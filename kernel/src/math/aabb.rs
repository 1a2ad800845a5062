//! Axis-aligned bounding boxes.

use super::Vec3;

/// An axis-aligned box `[min, max]`. An empty box has `min > max` on every axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The lowest corner.
    pub min: Vec3,
    /// The highest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box: the identity of [`Aabb::union`] and [`Aabb::grow`].
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f64::INFINITY), max: Vec3::splat(f64::NEG_INFINITY) };

    /// The smallest box holding every point of `points` ([`Aabb::EMPTY`] for none).
    #[must_use]
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grow(*p))
    }

    /// This box enlarged to hold `p`.
    #[must_use]
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box holding both boxes.
    #[must_use]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// Whether the box holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// `max - min` (zero for an empty box).
    #[must_use]
    pub fn size(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// The centre of the box.
    #[must_use]
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Whether `p` lies inside or on the box.
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Whether the two boxes are strictly apart along some axis: a gap between them, not a
    /// shared face, edge or corner.
    #[must_use]
    pub fn is_apart(&self, other: &Aabb) -> bool {
        self.max.cmplt(other.min).any() || other.max.cmplt(self.min).any()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_points_spans_extremes() {
        let b = Aabb::from_points(&[Vec3::new(1.0, -2.0, 3.0), Vec3::new(-1.0, 4.0, 0.0)]);
        assert_eq!(b.min, Vec3::new(-1.0, -2.0, 0.0));
        assert_eq!(b.max, Vec3::new(1.0, 4.0, 3.0));
        assert!(b.contains(Vec3::ZERO));
        assert!(Aabb::EMPTY.is_empty());
        // Touching boxes are not apart; a gap on one axis is enough.
        let unit = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let touching = Aabb { min: Vec3::new(1.0, 0.5, 0.5), max: Vec3::new(2.0, 2.0, 2.0) };
        let beyond = Aabb { min: Vec3::new(0.0, 1.5, 0.0), max: Vec3::new(1.0, 2.0, 1.0) };
        assert!(!unit.is_apart(&touching) && !touching.is_apart(&unit));
        assert!(unit.is_apart(&beyond) && beyond.is_apart(&unit));
        assert_eq!(Aabb::EMPTY.size(), Vec3::ZERO);
    }
}
