//! Moving profiles: translate, rotate, scale and mirror.

use super::construct::cos_sin_degrees;
use super::convert::{check_finite, check_number};
use super::{Profile, ProfileError, Vec2};

impl Profile {
    /// Every point mapped by `f`; contours reversed when `flips` (a mirror), so outer contours
    /// stay counter-clockwise. Refuses a result beyond [`MAX_REACH`](super::MAX_REACH).
    fn mapped(&self, f: impl Fn(Vec2) -> Vec2, flips: bool) -> Result<Profile, ProfileError> {
        let contours = self
            .contours
            .iter()
            .map(|c| {
                let mut c: Vec<Vec2> = c.iter().map(|&p| f(p)).collect();
                if flips {
                    c.reverse();
                }
                c
            })
            .collect::<Vec<Vec<Vec2>>>();
        for c in &contours {
            check_finite(c, "the moved profile")?;
        }
        Ok(Profile { contours })
    }

    /// The profile moved by `offset`.
    ///
    /// # Errors
    /// [`ProfileError::NonFinite`] for a NaN or infinite offset, [`ProfileError::OutOfRange`]
    /// when the result would lie beyond [`MAX_REACH`](super::MAX_REACH).
    pub fn translate(&self, offset: Vec2) -> Result<Profile, ProfileError> {
        check_finite(&[offset], "the offset")?;
        self.mapped(|p| p + offset, false)
    }

    /// The profile turned `degrees` counter-clockwise about the origin (exact at multiples of
    /// 90 degrees).
    ///
    /// # Errors
    /// [`ProfileError::BadValue`] for a non-finite angle.
    pub fn rotate(&self, degrees: f64) -> Result<Profile, ProfileError> {
        check_number("the angle", degrees, false)?;
        let (c, s) = cos_sin_degrees(degrees);
        self.mapped(|p| Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y), false)
    }

    /// The profile scaled by `factor` (x, y) about the origin; a negative factor mirrors.
    ///
    /// # Errors
    /// [`ProfileError::NonFinite`] for a NaN or infinite factor, [`ProfileError::ZeroArea`] for a
    /// zero factor (the result would be flat), [`ProfileError::OutOfRange`] when the result would
    /// lie beyond [`MAX_REACH`](super::MAX_REACH).
    pub fn scale(&self, factor: Vec2) -> Result<Profile, ProfileError> {
        if !factor.is_finite() {
            return Err(ProfileError::NonFinite { what: "the scale".into(), index: 0 });
        }
        if factor.x == 0.0 || factor.y == 0.0 {
            return Err(ProfileError::ZeroArea { what: "the profile scaled by zero".into() });
        }
        self.mapped(|p| p * factor, (factor.x < 0.0) != (factor.y < 0.0))
    }

    /// The profile mirrored across the line through the origin perpendicular to `normal`.
    ///
    /// # Errors
    /// [`ProfileError::NonFinite`] for a NaN or infinite normal, [`ProfileError::BadValue`] for
    /// a zero one.
    pub fn mirror(&self, normal: Vec2) -> Result<Profile, ProfileError> {
        if !normal.is_finite() {
            return Err(ProfileError::NonFinite { what: "the mirror's normal".into(), index: 0 });
        }
        let Some(n) = normal.try_normalize() else {
            return Err(ProfileError::BadValue {
                name: "the mirror's normal length",
                value: 0.0,
                expected: "positive",
            });
        };
        self.mapped(|p| p - 2.0 * p.dot(n) * n, true)
    }
}
