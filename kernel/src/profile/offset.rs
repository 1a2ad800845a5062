//! Offsets, fillets and chamfers: a profile grown or shrunk by a distance, its corners rounded
//! or cut.
//!
//! Fillets and chamfers are morphological opening and closing (Serra, *Image Analysis and
//! Mathematical Morphology*, 1982): shrinking by r and growing back rounds every convex corner
//! with radius r; growing and shrinking back rounds every concave one. Parts thinner than 2r
//! (and gaps narrower than 2r) do not survive the round trip — that is what a fillet of that
//! radius means.

use super::convert::check_number;
use super::{Profile, ProfileError};
use crate::csg::engine::Join;

/// How an offset joins the two offset edges at a corner.
///
/// Default value: [`JoinType::Round`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum JoinType {
    /// An arc of the offset distance about the corner.
    #[default]
    Round,
    /// The edges extended until they meet; squared off where that is farther than
    /// `miter_limit × |delta|` from the corner.
    Miter,
    /// Squared off at the offset distance from the corner.
    Square,
}

impl JoinType {
    /// The join by its name: `"round"`, `"miter"` or `"square"`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<JoinType> {
        match name {
            "round" => Some(JoinType::Round),
            "miter" => Some(JoinType::Miter),
            "square" => Some(JoinType::Square),
            _ => None,
        }
    }
}

/// Options of [`Profile::offset`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OffsetOptions {
    /// How corners are joined. Default value: [`JoinType::Round`].
    pub join: JoinType,
    /// For [`JoinType::Miter`]: the farthest a mitred corner may reach, in multiples of the
    /// offset distance (greater than 1). Default value: 2.
    pub miter_limit: f64,
    /// For [`JoinType::Round`]: segments per full turn of an arc (3 to [`MAX_SEGMENTS`]).
    /// Default value: 32.
    pub segments: u32,
}

impl OffsetOptions {
    /// The defaults: round joins, miter limit 2, 32 segments per turn.
    pub const DEFAULT: OffsetOptions = OffsetOptions { join: JoinType::Round, miter_limit: 2.0, segments: 32 };

    /// With `join`.
    #[must_use]
    pub fn with_join(mut self, join: JoinType) -> OffsetOptions {
        self.join = join;
        self
    }

    /// With `miter_limit`.
    #[must_use]
    pub fn with_miter_limit(mut self, miter_limit: f64) -> OffsetOptions {
        self.miter_limit = miter_limit;
        self
    }

    /// With `segments` per full turn.
    #[must_use]
    pub fn with_segments(mut self, segments: u32) -> OffsetOptions {
        self.segments = segments;
        self
    }

    fn check(&self) -> Result<(), ProfileError> {
        // Clipper2 reads a limit of 1 or less as its default 2.
        if !(self.miter_limit.is_finite() && self.miter_limit > 1.0) {
            return Err(ProfileError::BadValue {
                name: "the miter limit",
                value: self.miter_limit,
                expected: "greater than 1",
            });
        }
        check_segments(self.segments)
    }
}

impl Default for OffsetOptions {
    fn default() -> OffsetOptions {
        OffsetOptions::DEFAULT
    }
}

/// The most segments per full turn an arc may have.
pub const MAX_SEGMENTS: u32 = 1_000_000;

/// Refuses fewer than 3 segments per turn, or more than [`MAX_SEGMENTS`].
pub(super) fn check_segments(segments: u32) -> Result<(), ProfileError> {
    if !(3..=MAX_SEGMENTS).contains(&segments) {
        return Err(ProfileError::BadValue {
            name: "the number of segments",
            value: f64::from(segments),
            expected: "from 3 to 1000000",
        });
    }
    Ok(())
}

/// A profile's contours moved a distance along their normals, joined by `join` (no checks).
fn raw_offset(p: &Profile, delta: f64, join: Join, miter_limit: f64, segments: u32) -> Profile {
    Profile::from_section(&p.to_section().offset(delta, join, miter_limit, segments))
}

/// Miter limit for steps whose corners must stay sharp (the first step of a fillet or
/// chamfer): far beyond any corner a later step keeps.
const SHARP: f64 = 1e6;

/// The farthest from the origin an offset may reach, in model units. The engine holds
/// coordinates as integers on a grid of 1e-8 and Clipper2 keeps them below 2⁶¹ ≈ 2.3e18 (so
/// 2.3e10 units); 1e9 leaves room for its intermediate sums.
pub const MAX_REACH: f64 = 1e9;

/// The largest |coordinate| of the profile.
fn extent(p: &Profile) -> f64 {
    p.contours().iter().flatten().map(|q| q.x.abs().max(q.y.abs())).fold(0.0, f64::max)
}

/// Refuses an offset by `delta` whose corners may reach `reach` × |delta| beyond the profile
/// when that passes [`MAX_REACH`]: the engine's integers would overflow.
fn check_reach(p: &Profile, name: &'static str, delta: f64, reach: f64) -> Result<(), ProfileError> {
    if extent(p) + delta.abs() * reach > MAX_REACH {
        return Err(ProfileError::BadValue {
            name,
            value: delta,
            expected: "small enough that the result stays within 1e9 of the origin",
        });
    }
    Ok(())
}

/// The miter limit of a fillet's or chamfer's sharp steps by `r`: [`SHARP`], or less where a
/// corner that far out would pass [`MAX_REACH`].
fn sharp_for(p: &Profile, r: f64) -> f64 {
    SHARP.min(((MAX_REACH - extent(p)) / r).max(2.0))
}

impl Profile {
    /// The region grown by `delta` (shrunk when negative: every point at distance ≤ |delta| from
    /// the outside removed), corners joined as `options` say. Shrinking may leave nothing (an
    /// empty profile).
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for a non-finite `delta`, a miter limit below 1 or fewer than 3
    /// segments.
    pub fn offset(&self, delta: f64, options: &OffsetOptions) -> Result<Profile, ProfileError> {
        check_number("the offset", delta, false)?;
        options.check()?;
        if delta == 0.0 {
            return Ok(self.clone());
        }
        let reach = match options.join {
            JoinType::Round => 1.0,
            JoinType::Square => std::f64::consts::SQRT_2,
            JoinType::Miter => options.miter_limit.max(1.0),
        };
        check_reach(self, "the offset", delta, reach)?;
        let join = match options.join {
            JoinType::Round => Join::Round,
            JoinType::Miter => Join::Miter,
            JoinType::Square => Join::Square,
        };
        Ok(raw_offset(self, delta, join, options.miter_limit, options.segments))
    }

    /// Every corner, convex and concave, rounded with radius `r` (arcs of `segments` per full
    /// turn): the opening (shrink by r, grow by r) then the closing (grow by r, shrink by r).
    /// Parts thinner than 2r vanish and gaps narrower than 2r close.
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for a radius negative or not finite, fewer than 3 segments.
    pub fn fillet(&self, r: f64, segments: u32) -> Result<Profile, ProfileError> {
        check_number("the fillet radius", r, false)?;
        if r < 0.0 {
            return Err(ProfileError::BadValue { name: "the fillet radius", value: r, expected: "at least 0" });
        }
        check_segments(segments)?;
        if r == 0.0 {
            return Ok(self.clone());
        }
        check_reach(self, "the fillet radius", r, 2.0)?;
        let sharp = sharp_for(self, r);
        let opened = raw_offset(&raw_offset(self, -r, Join::Miter, sharp, segments), r, Join::Round, 2.0, segments);
        let closed = raw_offset(&raw_offset(&opened, r, Join::Miter, sharp, segments), -r, Join::Round, 2.0, segments);
        Ok(closed)
    }

    /// Every corner, convex and concave, cut by a straight chamfer: the opening and closing of
    /// [`Profile::fillet`] with straight (bevel) joins in place of arcs. A right-angled corner
    /// loses a right triangle with legs `d`.
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for a distance negative or not finite.
    pub fn chamfer(&self, d: f64) -> Result<Profile, ProfileError> {
        check_number("the chamfer distance", d, false)?;
        if d < 0.0 {
            return Err(ProfileError::BadValue { name: "the chamfer distance", value: d, expected: "at least 0" });
        }
        if d == 0.0 {
            return Ok(self.clone());
        }
        check_reach(self, "the chamfer distance", d, 2.0)?;
        let sharp = sharp_for(self, d);
        let opened = raw_offset(&raw_offset(self, -d, Join::Miter, sharp, 32), d, Join::Bevel, 2.0, 32);
        let closed = raw_offset(&raw_offset(&opened, d, Join::Miter, sharp, 32), -d, Join::Bevel, 2.0, 32);
        Ok(closed)
    }
}

#[cfg(test)]
mod reach_tests {
    use super::*;
    use crate::profile::Vec2;

    #[test]
    fn an_offset_that_would_leave_the_engine_s_range_is_refused_not_overflowed() {
        // 1e300 passes every finiteness check; the engine's integers (grid 1e-8) would
        // overflow, so each operation refuses it by name instead.
        let p = Profile::rect(Vec2::ZERO, Vec2::new(2.0, 1.0)).unwrap();
        for delta in [1e300, -1e300, 2e9] {
            let e = p.offset(delta, &OffsetOptions::DEFAULT).unwrap_err().to_string();
            assert!(e.contains("the offset") && e.contains("within 1e9"), "{e}");
        }
        assert!(p.fillet(1e300, 32).unwrap_err().to_string().contains("the fillet radius"));
        assert!(p.chamfer(1e300).unwrap_err().to_string().contains("the chamfer distance"));
        // A miter join reaches miter_limit × delta: checked with it.
        let miter = OffsetOptions::DEFAULT.with_join(JoinType::Miter).with_miter_limit(1e6);
        assert!(p.offset(1e4, &miter).is_err());
        // Large but in range: fine, and the sharp steps of a fillet shorten to stay in range.
        assert!(p.offset(1e6, &OffsetOptions::DEFAULT).is_ok());
        let f = p.fillet(1e4, 32).unwrap();
        assert!(f.is_empty() || f.area() <= p.area());
    }
}
