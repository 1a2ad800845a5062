//! Revolution: a profile turned about the z axis, its x the radius and its y the height
//! (OpenSCAD's `rotate_extrude`, Manifold's `Revolve`).

use super::convert::{check_number, check_solid_size, mesh_from_surface};
use super::offset::check_segments;
use super::{Profile, ProfileError};
use crate::csg::engine::Surface;
use crate::mesh::Mesh;

/// Options of [`revolve`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RevolveOptions {
    /// The angle turned, degrees in (0, 360], counter-clockwise seen from above from the +x
    /// axis; a partial turn is capped at both ends. Default value: 360.
    pub angle: f64,
    /// Segments per full turn (at least 3); a partial turn gets its share, at least 3.
    /// Default value: 32.
    pub segments: u32,
}

impl RevolveOptions {
    /// A full turn in 32 segments.
    pub const DEFAULT: RevolveOptions = RevolveOptions { angle: 360.0, segments: 32 };

    /// With `degrees` turned.
    #[must_use]
    pub fn with_angle(mut self, degrees: f64) -> RevolveOptions {
        self.angle = degrees;
        self
    }

    /// With `segments` per full turn.
    #[must_use]
    pub fn with_segments(mut self, segments: u32) -> RevolveOptions {
        self.segments = segments;
        self
    }

    /// The number of steps over the angle.
    #[must_use]
    pub fn steps(&self) -> u32 {
        ((f64::from(self.segments) * self.angle / 360.0).ceil() as u32).max(3)
    }
}

impl Default for RevolveOptions {
    fn default() -> RevolveOptions {
        RevolveOptions::DEFAULT
    }
}

/// `profile` revolved about the z axis: the profile's point (x, y) sweeps the circle of radius x
/// at height y. A closed manifold triangle mesh; points on the axis (x = 0) stay single
/// vertices there.
///
/// Pappus's theorem for the polygonal solid: revolving a region of area A whose centroid is at
/// radius x̄ in n steps over the full turn gives exactly n·sin(2π/n)·A·x̄ (each step's wedge is
/// sin(2π/n)·∫x dA), which tends to 2π·x̄·A (tested with a revolved disc).
///
/// # Errors
/// [`ProfileError::Empty`] for an empty profile; [`ProfileError::CrossesAxis`] naming the
/// contour and point of the profile that lies at x < 0; [`ProfileError::BadValue`] for an angle
/// outside (0, 360] or fewer than 3 segments.
pub fn revolve(profile: &Profile, options: &RevolveOptions) -> Result<Mesh, ProfileError> {
    profile.require_region("the profile to revolve")?;
    check_number("the angle", options.angle, true)?;
    if options.angle > 360.0 {
        return Err(ProfileError::BadValue { name: "the angle", value: options.angle, expected: "at most 360" });
    }
    check_segments(options.segments)?;
    for (contour, c) in profile.contours().iter().enumerate() {
        if let Some((index, p)) = c.iter().enumerate().filter(|(_, p)| p.x < 0.0).min_by(|a, b| a.1.x.total_cmp(&b.1.x))
        {
            return Err(ProfileError::CrossesAxis { contour, index, x: p.x });
        }
    }
    let steps = options.steps();
    let points = profile.point_count() as f64;
    check_solid_size(
        || format!("a revolution of {points} points in {steps} steps"),
        points * (f64::from(steps) + 1.0),
        2.0 * points * (f64::from(steps) + 1.0),
    )?;
    crate::limits::charge(profile.point_count() as u64 * u64::from(steps))?;
    mesh_from_surface(Surface::revolved(profile.contours(), steps, options.angle), "the profile to revolve")
}
