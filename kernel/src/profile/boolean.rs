//! 2D booleans: union, difference and intersection of profiles.

use std::ops::{Add, Sub};

use super::Profile;
use crate::csg::engine::Section;
use crate::csg::CsgOp;

impl Profile {
    /// `self op other` (Clipper2 through the engine; exact up to its 1e-8 grid).
    #[must_use]
    pub fn boolean(&self, other: &Profile, op: CsgOp) -> Profile {
        Profile::from_section(&self.to_section().boolean(&other.to_section(), op))
    }

    /// `self ∪ other`.
    #[must_use]
    pub fn union(&self, other: &Profile) -> Profile {
        self.boolean(other, CsgOp::Union)
    }

    /// `self − other` (may be empty).
    #[must_use]
    pub fn difference(&self, other: &Profile) -> Profile {
        self.boolean(other, CsgOp::Difference)
    }

    /// `self ∩ other` (may be empty).
    #[must_use]
    pub fn intersection(&self, other: &Profile) -> Profile {
        self.boolean(other, CsgOp::Intersection)
    }

    /// The union of all `profiles` (empty for none).
    #[must_use]
    pub fn union_all(profiles: &[Profile]) -> Profile {
        let contours: Vec<Vec<super::Vec2>> = profiles.iter().flat_map(|p| p.contours.iter().cloned()).collect();
        // Every profile is clean (outer counter-clockwise, holes clockwise): their union is where
        // the summed winding is positive.
        Profile::from_section(&Section::from_contours(&contours, crate::csg::engine::Fill::Positive))
    }
}

impl Add for &Profile {
    type Output = Profile;
    /// The union.
    fn add(self, other: &Profile) -> Profile {
        self.union(other)
    }
}

impl Sub for &Profile {
    type Output = Profile;
    /// The difference.
    fn sub(self, other: &Profile) -> Profile {
        self.difference(other)
    }
}
