//! Building profiles: rectangles, circles, polygons with a fill rule.

use super::convert::{check_finite, check_number};
use super::{Profile, ProfileError, Vec2};
use crate::csg::engine::{Fill, Section};

/// Which parts of overlapping or self-intersecting contours are inside, by winding number (the
/// number of times the contours wind around a point, counter-clockwise counting +1).
///
/// Repair of self-intersecting input: contours are split where they cross and every enclosed
/// piece is kept or dropped by the rule, so the result is always a clean region. A figure-eight
/// (bow-tie) gives both its lobes under either rule; a contour that winds twice around a
/// region fills it under [`FillRule::NonZero`] and leaves it out under [`FillRule::EvenOdd`];
/// a clockwise outline is turned counter-clockwise.
///
/// Default value: [`FillRule::EvenOdd`] — a hole is a hole whichever way it runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FillRule {
    /// Inside where the winding number is odd (SVG `evenodd`).
    #[default]
    EvenOdd,
    /// Inside where the winding number is not zero (SVG `nonzero`).
    NonZero,
}

impl FillRule {
    /// The rule by its name: `"evenodd"` / `"even-odd"` or `"nonzero"` / `"non-zero"`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<FillRule> {
        match name.to_ascii_lowercase().replace(['-', '_', ' '], "").as_str() {
            "evenodd" => Some(FillRule::EvenOdd),
            "nonzero" => Some(FillRule::NonZero),
            _ => None,
        }
    }

    fn engine(self) -> Fill {
        match self {
            FillRule::EvenOdd => Fill::EvenOdd,
            FillRule::NonZero => Fill::NonZero,
        }
    }
}

/// `cos` and `sin` of `degrees`, exact at multiples of 90 degrees.
pub(super) fn cos_sin_degrees(degrees: f64) -> (f64, f64) {
    let d = degrees.rem_euclid(360.0);
    if d % 90.0 == 0.0 {
        return match (d / 90.0) as u32 {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        };
    }
    let r = d.to_radians();
    (r.cos(), r.sin())
}

impl Profile {
    /// The rectangle with corners `min` and `max` (either order per axis).
    ///
    /// # Errors
    /// [`ProfileError::NonFinite`] for a NaN or infinite corner, [`ProfileError::OutOfRange`]
    /// for one beyond [`MAX_REACH`](super::MAX_REACH), [`ProfileError::ZeroArea`] when the two
    /// corners share an x or a y.
    pub fn rect(min: Vec2, max: Vec2) -> Result<Profile, ProfileError> {
        check_finite(&[min, max], "the rectangle's corners")?;
        let (lo, hi) = (min.min(max), min.max(max));
        if lo.x == hi.x || lo.y == hi.y {
            return Err(ProfileError::ZeroArea { what: "the rectangle".into() });
        }
        Ok(Profile { contours: vec![vec![lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)]] })
    }

    /// The regular `segments`-gon inscribed in the circle of `radius` about the origin, its first
    /// corner on +x (exact on the axes), counter-clockwise.
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for a radius not positive and finite, fewer than 3 segments or
    /// more than [`MAX_SEGMENTS`](super::MAX_SEGMENTS); [`ProfileError::OutOfRange`] for a
    /// radius beyond [`MAX_REACH`](super::MAX_REACH).
    pub fn circle(radius: f64, segments: u32) -> Result<Profile, ProfileError> {
        check_number("the radius", radius, true)?;
        check_finite(&[Vec2::new(radius, 0.0)], "the circle")?;
        super::offset::check_segments(segments)?;
        let contour = (0..segments)
            .map(|i| {
                let (c, s) = cos_sin_degrees(360.0 * f64::from(i) / f64::from(segments));
                Vec2::new(radius * c, radius * s)
            })
            .collect();
        Ok(Profile { contours: vec![contour] })
    }

    /// The region inside one closed contour (the last point joins the first) under `fill`.
    ///
    /// # Errors
    /// As [`Profile::from_contours`].
    pub fn polygon(points: &[Vec2], fill: FillRule) -> Result<Profile, ProfileError> {
        Profile::from_contours(&[points.to_vec()], fill)
    }

    /// The region `contours` fill under `fill` (each closed: its last point joins its first).
    /// Overlaps and self-intersections are resolved by the rule (see [`FillRule`]).
    ///
    /// # Errors
    /// [`ProfileError::TooFewPoints`] for a contour of fewer than 3 points,
    /// [`ProfileError::NonFinite`] for a NaN or infinite coordinate and
    /// [`ProfileError::OutOfRange`] for one beyond [`MAX_REACH`](super::MAX_REACH) (each naming
    /// the contour and point), [`ProfileError::ZeroArea`] when the contours enclose nothing
    /// under the rule.
    pub fn from_contours(contours: &[Vec<Vec2>], fill: FillRule) -> Result<Profile, ProfileError> {
        let name = |i: usize| if contours.len() == 1 { "the polygon".to_string() } else { format!("contour {i}") };
        if contours.is_empty() {
            return Err(ProfileError::TooFewPoints { what: "the polygon".into(), count: 0, needed: 3 });
        }
        for (i, c) in contours.iter().enumerate() {
            if c.len() < 3 {
                return Err(ProfileError::TooFewPoints { what: name(i), count: c.len(), needed: 3 });
            }
            check_finite(c, &name(i))?;
        }
        let p = Profile::from_section(&Section::from_contours(contours, fill.engine()));
        if p.is_empty() {
            let what = if contours.len() == 1 { "the polygon".to_string() } else { "the contours".to_string() };
            return Err(ProfileError::ZeroArea { what });
        }
        Ok(p)
    }
}
