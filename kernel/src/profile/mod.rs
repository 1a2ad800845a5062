//! 2D profiles — regions of outer contours and holes — and the solids made from them: extrude,
//! revolve, sweep and loft, with the 3D hull, Minkowski sum, plane cuts, slices and shadows.
//!
//! - [`Profile`]: the region, built by [`Profile::rect`], [`Profile::circle`] and
//!   [`Profile::polygon`] (with a [`FillRule`]); booleans (`construct`, `boolean`), offsets,
//!   fillets and chamfers (`offset`), hulls (`hull`), transforms (`transform`),
//!   simplification and measures (`measure`).
//! - [`text`]: glyph outlines of a font (the bundled DejaVu Sans or any TTF/OTF) as a profile.
//! - 3D from 2D, each a closed manifold [`Mesh`](crate::Mesh): [`extrude`], [`revolve`],
//!   [`sweep`] (rotation-minimising frames, `frames`), [`loft`].
//! - 3D operations on meshes: [`hull_points`] / [`hull_meshes`], [`minkowski`], [`split`] /
//!   [`trim`], [`slice`] / [`project`] (back to a [`Profile`]).
//! - `error`: [`ProfileError`], naming the input at fault.
//! - Files: SVG and DXF in [`crate::io::svg`] and [`crate::io::dxf`].
//!
//! Regions and the solids of extrude, revolve, hulls, Minkowski sums and cuts come from the
//! boolean engine through its one seam ([`crate::csg::engine`]): Manifold's `CrossSection`
//! (Clipper2, coordinates on a grid of 1e-8) and its constructors. Sweeps and lofts are built
//! here as half-edge meshes, their caps triangulated by the engine.
//!
//! Orientation: outer contours run counter-clockwise and holes clockwise, as the engine returns
//! them; every solid's faces are counter-clockwise seen from outside.

mod boolean;
mod construct;
mod convert;
mod error;
mod extrude;
mod frames;
mod hull;
mod loft;
mod measure;
mod minkowski;
mod offset;
mod revolve;
mod self_crossing;
mod slice;
mod split;
mod sweep;
mod text;
mod transform;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_property;
#[cfg(test)]
mod tests_solids;

pub use construct::FillRule;
pub use error::ProfileError;
pub use extrude::{extrude, ExtrudeOptions};
pub use hull::{hull_meshes, hull_points};
pub use loft::{loft, LoftOptions, Placement};
pub use measure::contour_area;
pub use minkowski::minkowski;
pub use offset::{JoinType, OffsetOptions, MAX_REACH, MAX_SEGMENTS};
pub use revolve::{revolve, RevolveOptions};
pub use slice::{project, slice};
pub use split::{split, trim};
pub use sweep::{sweep, SweepOptions};
pub use text::{text, Font, HAlign, TextDirection, TextOptions, VAlign};

/// A point or direction in 2D, in double precision.
pub type Vec2 = glam::DVec2;

/// A 2D region: outer contours (counter-clockwise) and holes (clockwise), none crossing
/// another.
///
/// Built by [`Profile::rect`], [`Profile::circle`], [`Profile::polygon`] and
/// [`Profile::from_contours`], which resolve overlaps and self-intersections; every operation
/// returns a new profile in the same clean form. A profile may be empty (the difference of a
/// region and a larger one); the solids refuse an empty profile by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    contours: Vec<Vec<Vec2>>,
}

impl Profile {
    /// The empty region.
    #[must_use]
    pub fn empty() -> Profile {
        Profile::default()
    }

    /// Whether the region has no contours.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.contours.is_empty()
    }

    /// The contours: outer ones counter-clockwise, holes clockwise.
    #[must_use]
    pub fn contours(&self) -> &[Vec<Vec2>] {
        &self.contours
    }

    /// The number of points over all contours.
    #[must_use]
    pub fn point_count(&self) -> usize {
        self.contours.iter().map(Vec::len).sum()
    }
}
