//! Linear extrusion: a profile pulled up along z, optionally twisted and scaled towards the top
//! (OpenSCAD's `linear_extrude`, Manifold's `Extrude`).

use super::convert::{check_finite, check_number, check_solid_size, mesh_from_surface};
use super::{Profile, ProfileError, Vec2};
use crate::csg::engine::Surface;
use crate::math::Vec3;
use crate::mesh::Mesh;

/// Options of [`extrude`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ExtrudeOptions {
    /// The top's turn relative to the bottom, degrees counter-clockwise seen from above.
    /// Default value: 0.
    pub twist: f64,
    /// The top's scale (x, y) about the z axis relative to the bottom; (0, 0) gives a cone to
    /// the origin. Default value: (1, 1).
    pub scale: Vec2,
    /// Layers from bottom to top (at least 1); `None` for one per 5 degrees of twist (at least
    /// 1). Default value: `None`.
    pub slices: Option<u32>,
    /// Whether the solid spans z from −height/2 to height/2 (else from 0 to height).
    /// Default value: false.
    pub center: bool,
}

impl ExtrudeOptions {
    /// No twist, no scale, one layer per 5 degrees of twist, from z = 0.
    pub const DEFAULT: ExtrudeOptions = ExtrudeOptions { twist: 0.0, scale: Vec2::ONE, slices: None, center: false };

    /// With the top turned `degrees`.
    #[must_use]
    pub fn with_twist(mut self, degrees: f64) -> ExtrudeOptions {
        self.twist = degrees;
        self
    }

    /// With the top scaled by `scale`.
    #[must_use]
    pub fn with_scale(mut self, scale: Vec2) -> ExtrudeOptions {
        self.scale = scale;
        self
    }

    /// With `slices` layers.
    #[must_use]
    pub fn with_slices(mut self, slices: u32) -> ExtrudeOptions {
        self.slices = Some(slices);
        self
    }

    /// Centred on z = 0 or not.
    #[must_use]
    pub fn with_center(mut self, center: bool) -> ExtrudeOptions {
        self.center = center;
        self
    }

    /// The number of layers.
    fn layers(&self) -> u32 {
        self.slices.unwrap_or_else(|| ((self.twist.abs() / 5.0).ceil() as u32).max(1))
    }
}

impl Default for ExtrudeOptions {
    fn default() -> ExtrudeOptions {
        ExtrudeOptions::DEFAULT
    }
}

/// `profile` extruded along z to `height`, a closed manifold triangle mesh. Each layer is the
/// profile turned by its share of `twist` and scaled by the linear blend of 1 and `scale`; side
/// quads are split into two triangles, the caps triangulated by ear clipping.
///
/// With a scale and no twist the solid is a frustum: its volume is
/// h/3 · (A₁ + A₂ + √(A₁A₂)) with A₂ = sx·sy·A₁ exactly (tested).
///
/// # Errors
/// [`ProfileError::Empty`] for an empty profile; [`ProfileError::BadValue`] for a height not
/// positive and finite, a non-finite twist, a negative scale or one with exactly one zero
/// component (a flat top edge), zero slices; [`ProfileError::NonFinite`] for a NaN scale.
pub fn extrude(profile: &Profile, height: f64, options: &ExtrudeOptions) -> Result<Mesh, ProfileError> {
    profile.require_region("the profile to extrude")?;
    check_number("the height", height, true)?;
    check_number("the twist", options.twist, false)?;
    check_finite(&[options.scale], "the scale")?;
    let s = options.scale;
    if s.x < 0.0 || s.y < 0.0 || ((s.x == 0.0) != (s.y == 0.0)) {
        let value = if s.x <= 0.0 { s.x } else { s.y };
        return Err(ProfileError::BadValue {
            name: "the top scale",
            value,
            expected: "positive in x and y (or both 0 for a cone)",
        });
    }
    let layers = options.layers();
    if layers == 0 {
        return Err(ProfileError::BadValue { name: "the number of slices", value: 0.0, expected: "at least 1" });
    }
    let points = profile.point_count() as f64;
    let layers_f = f64::from(layers);
    check_solid_size(
        || format!("an extrusion of {points} points in {layers} layers"),
        points * (layers_f + 1.0),
        2.0 * points * (layers_f + 1.0),
    )?;
    crate::limits::charge(profile.point_count() as u64 * u64::from(layers))?;
    let surface = Surface::extruded(profile.contours(), height, layers - 1, options.twist, s);
    let mesh = mesh_from_surface(surface, "the profile to extrude")?;
    Ok(if options.center { mesh.map_positions(|p| p - Vec3::new(0.0, 0.0, height / 2.0)) } else { mesh })
}
