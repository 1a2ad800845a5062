//! Options of [`load_with`](super::load_with) and [`save_with`](super::save_with): the up axis
//! of the file, how corners are welded ([`Weld`], defined with the welding) and how PLY is encoded.
//!
//! blocksmith is Z-up (as OpenSCAD, Manifold and Blender are). glTF is Y-up by specification
//! (glTF 2.0 §3.4 "Coordinate System and Units"), so glTF files are always converted: kernel
//! `(x, y, z)` is written as glTF `(x, z, −y)` and read back the other way — a rotation by
//! −90° about x, exact in floating point (a swap and a negation), so a round trip keeps every
//! bit. OBJ, STL and PLY have no convention: they are written and read as they are unless the
//! `up` option says the file is Y-up.

use super::ply::PlyEncoding;
use super::weld::Weld;
use crate::math::{Quat, Vec3};

/// The axis that points up in a file's coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// +Z up: blocksmith's own axes, written verbatim.
    #[default]
    Z,
    /// +Y up (glTF's convention): kernel `(x, y, z)` is file `(x, z, −y)`.
    Y,
}

impl UpAxis {
    /// The axis named `"z"` or `"y"` (case-insensitive); `None` for any other name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<UpAxis> {
        match name.to_ascii_lowercase().as_str() {
            "z" => Some(UpAxis::Z),
            "y" => Some(UpAxis::Y),
            _ => None,
        }
    }

    /// A kernel (Z-up) point or direction in the file's axes.
    #[must_use]
    #[inline]
    pub fn to_file(self, p: Vec3) -> Vec3 {
        match self {
            UpAxis::Z => p,
            UpAxis::Y => Vec3::new(p.x, p.z, -p.y),
        }
    }

    /// A point or direction of the file, in kernel (Z-up) axes: the inverse of [`UpAxis::to_file`].
    #[must_use]
    #[inline]
    pub fn from_file(self, p: Vec3) -> Vec3 {
        match self {
            UpAxis::Z => p,
            UpAxis::Y => Vec3::new(p.x, -p.z, p.y),
        }
    }

    /// A kernel rotation in the file's axes: the change of axes is itself a rotation, so the
    /// rotation's axis turns like a direction and its angle stays.
    #[must_use]
    pub fn rotation_to_file(self, q: Quat) -> Quat {
        let axis = self.to_file(Vec3::new(q.x, q.y, q.z));
        Quat::from_xyzw(axis.x, axis.y, axis.z, q.w)
    }
}

/// Options of [`load_with`](super::load_with).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct LoadOptions {
    /// The file's up axis; `None` takes the format's convention (glTF Y, 3MF Z, others Z).
    /// Only OBJ, STL and PLY accept another axis. Default value: `None`.
    pub up: Option<UpAxis>,
    /// How corners at one place are welded. OBJ and 3MF, which name their shared vertices,
    /// join only corners at equal coordinates under the default ([`Weld::for_named_vertices`]);
    /// an OBJ with subdivision tags is never welded. Default value: [`Weld::DEFAULT`].
    pub weld: Weld,
    /// Whether a file that is not a manifold surface as written is repaired (vertices split
    /// per fan, faces beyond two on an edge separated, components re-oriented, faces repeating
    /// a vertex dropped; no vertex moved) rather than refused. Default value: `true`.
    pub repair: bool,
}

impl LoadOptions {
    /// The defaults (see each field).
    pub const DEFAULT: LoadOptions = LoadOptions { up: None, weld: Weld::DEFAULT, repair: true };

    /// With repair on or off.
    #[must_use]
    pub fn with_repair(mut self, repair: bool) -> Self {
        self.repair = repair;
        self
    }

    /// With the file's up axis.
    #[must_use]
    pub fn with_up(mut self, up: UpAxis) -> Self {
        self.up = Some(up);
        self
    }

    /// With a weld rule.
    #[must_use]
    pub fn with_weld(mut self, weld: Weld) -> Self {
        self.weld = weld;
        self
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions::DEFAULT
    }
}

/// Options of [`save_with`](super::save_with).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[non_exhaustive]
pub struct SaveOptions {
    /// The file's up axis; `None` takes the format's convention (glTF Y, 3MF Z, others Z).
    /// Only OBJ, STL and PLY accept another axis. Default value: `None`.
    pub up: Option<UpAxis>,
    /// How a PLY file stores its data. Default value: binary little-endian.
    pub ply: PlyEncoding,
}

impl SaveOptions {
    /// The defaults (see each field).
    pub const DEFAULT: SaveOptions = SaveOptions { up: None, ply: PlyEncoding::BinaryLittleEndian };

    /// With a PLY encoding.
    #[must_use]
    pub fn with_ply(mut self, ply: PlyEncoding) -> Self {
        self.ply = ply;
        self
    }

    /// With the file's up axis.
    #[must_use]
    pub fn with_up(mut self, up: UpAxis) -> Self {
        self.up = Some(up);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_up_is_a_rotation_and_round_trips_bit_exactly() {
        let p = Vec3::new(0.1, -2.5e-300, 7.0);
        assert_eq!(UpAxis::Y.from_file(UpAxis::Y.to_file(p)), p);
        // Kernel up (+Z) is glTF up (+Y); kernel +Y (away) is glTF −Z (into the screen).
        assert_eq!(UpAxis::Y.to_file(Vec3::Z), Vec3::Y);
        assert_eq!(UpAxis::Y.to_file(Vec3::Y), -Vec3::Z);
        // A proper rotation: x × y = z holds in the file too.
        let (x, y) = (UpAxis::Y.to_file(Vec3::X), UpAxis::Y.to_file(Vec3::Y));
        assert_eq!(x.cross(y), UpAxis::Y.to_file(Vec3::Z));
    }

    #[test]
    fn rotations_turn_with_the_axes() {
        // Rotating then converting equals converting then rotating by the converted rotation.
        let q = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let p = Vec3::new(0.3, -1.0, 2.0);
        let a = UpAxis::Y.to_file(q * p);
        let b = UpAxis::Y.rotation_to_file(q) * UpAxis::Y.to_file(p);
        assert!((a - b).length() < 1e-15, "{a} vs {b}");
    }

    #[test]
    fn names() {
        assert_eq!(UpAxis::from_name("Y"), Some(UpAxis::Y));
        assert_eq!(UpAxis::from_name("z"), Some(UpAxis::Z));
        assert_eq!(UpAxis::from_name("x"), None);
    }
}
