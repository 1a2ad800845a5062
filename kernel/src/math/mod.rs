//! Vectors and bounds: glam's f64 types and an axis-aligned box; display colours; the seeded
//! generator ([`SplitMix64`]) and the integer hasher ([`IdHasher`]) the other modules share.

mod aabb;
mod closest_point;
mod color;
mod direction;
mod draw;
mod fmt_num;
mod id_hash;
mod lerp;
mod mean;
mod noise;
mod rng;
mod translation;

pub use aabb::Aabb;
pub use closest_point::closest_on_triangle;
pub use color::hsv_rgba;
pub use direction::direction;
pub use fmt_num::fmt_num;
pub use id_hash::{IdHasher, IdMap, IdSet};
pub use lerp::lerp;
pub use mean::mean_point;
pub use noise::{Noise, NoiseError, NoiseKind, NoiseOptions, MAX_LATTICE_COORDINATE, MAX_OCTAVES};
pub use rng::SplitMix64;
pub use translation::translation_between;

/// A point or direction in 3D, in double precision.
pub type Vec3 = glam::DVec3;
/// A 3×3 matrix in double precision.
pub type Mat3 = glam::DMat3;
/// A 4×4 matrix in double precision.
pub type Mat4 = glam::DMat4;
/// A rotation in double precision.
pub type Quat = glam::DQuat;

/// Whether every component of `v` is finite (neither NaN nor infinite).
#[must_use]
pub fn is_finite(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}
