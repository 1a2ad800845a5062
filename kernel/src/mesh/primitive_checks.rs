//! What the primitives accept: lengths in a range where areas and volumes stay finite and
//! normalised directions stay exact, and sizes whose mesh fits the memory budget. The `try_`
//! constructors check both, then build.

use super::{check_mesh_size, Mesh, MeshError};
use crate::math::{fmt_num, Vec3};

/// The smallest length (size, radius, height, coordinate magnitude) a primitive takes.
pub const MIN_LENGTH: f64 = 1e-100;
/// The largest length a primitive takes: its cube (a volume) and square (an area, the squared
/// length a normalisation computes) stay far inside `f64`'s range.
pub const MAX_LENGTH: f64 = 1e100;

/// `value` when it is a finite length in [`MIN_LENGTH`]..=[`MAX_LENGTH`].
///
/// # Errors
/// [`MeshError::OutOfRange`] naming `name`, the value and the range.
pub fn check_length(name: &str, value: f64) -> Result<f64, MeshError> {
    if value.is_finite() && (MIN_LENGTH..=MAX_LENGTH).contains(&value) {
        Ok(value)
    } else {
        Err(out_of_range(name, value))
    }
}

fn out_of_range(name: &str, value: f64) -> MeshError {
    MeshError::OutOfRange {
        name: name.to_string(),
        value: fmt_num(value),
        range: format!("{} and {}", fmt_num(MIN_LENGTH), fmt_num(MAX_LENGTH)),
    }
}

/// `p` when each coordinate's magnitude is at most [`MAX_LENGTH`].
///
/// # Errors
/// [`MeshError::OutOfRange`] naming `name[i]` for the first coordinate out of range.
pub fn check_point(name: &str, p: Vec3) -> Result<Vec3, MeshError> {
    for (i, c) in p.to_array().into_iter().enumerate() {
        if !(c.is_finite() && c.abs() <= MAX_LENGTH) {
            return Err(MeshError::OutOfRange {
                name: format!("{name}[{i}]"),
                value: fmt_num(c),
                range: format!("{} and {}", fmt_num(-MAX_LENGTH), fmt_num(MAX_LENGTH)),
            });
        }
    }
    Ok(p)
}

fn budget(what: impl FnOnce() -> String, vertices: f64, corners: f64, faces: f64) -> Result<(), MeshError> {
    check_mesh_size(what, vertices, corners, faces).map_err(MeshError::from)
}

impl Mesh {
    /// [`Mesh::cube`] with `size` checked by [`check_length`].
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for `size`.
    pub fn try_cube(size: f64) -> Result<Mesh, MeshError> {
        Ok(Mesh::cube(check_length("size", size)?))
    }

    /// [`Mesh::cuboid`] with the corners checked by [`check_point`].
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for a coordinate of `min` or `max`.
    pub fn try_cuboid(min: Vec3, max: Vec3) -> Result<Mesh, MeshError> {
        Ok(Mesh::cuboid(check_point("min", min)?, check_point("max", max)?))
    }

    /// [`Mesh::icosphere`] with `radius` checked by [`check_length`] and the mesh of
    /// 10·4ˢ + 2 vertices and 20·4ˢ triangles by the memory budget.
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for `radius`; [`MeshError::Limit`] over the budget or when
    /// the current cancellation token stops the work ([`Mesh::icosphere_stoppable`]).
    pub fn try_icosphere(radius: f64, subdivisions: u32) -> Result<Mesh, MeshError> {
        check_length("radius", radius)?;
        let f = 20.0 * 4f64.powi(subdivisions.min(1000) as i32);
        budget(
            || format!("an icosphere of {subdivisions} subdivisions ({} triangles)", fmt_num(f)),
            f / 2.0,
            3.0 * f,
            f,
        )?;
        Mesh::icosphere_stoppable(radius, subdivisions)
    }

    /// Checks the arguments of [`Mesh::uv_sphere`]: `radius` by [`check_length`], the
    /// `segments` × `rings` mesh by the memory budget.
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for `radius`; [`MeshError::Limit`] over the budget.
    pub fn check_uv_sphere(radius: f64, segments: u32, rings: u32) -> Result<(), MeshError> {
        check_length("radius", radius)?;
        let f = f64::from(segments.max(3)) * f64::from(rings.max(2));
        budget(|| format!("a {segments} × {rings} UV sphere"), f, 4.0 * f, f)
    }

    /// [`Mesh::uv_sphere`] after [`Mesh::check_uv_sphere`], stopping with the current
    /// cancellation token (polled every row, charged while the mesh is built).
    ///
    /// # Errors
    /// As [`Mesh::check_uv_sphere`]; [`MeshError::Limit`] when the token stops the work.
    pub fn try_uv_sphere(radius: f64, segments: u32, rings: u32) -> Result<Mesh, MeshError> {
        Mesh::check_uv_sphere(radius, segments, rings)?;
        Mesh::uv_sphere_with(radius, segments, rings, true)
    }

    /// [`Mesh::cylinder`] with `radius` and `height` checked by [`check_length`].
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for `radius` or `height`.
    pub fn try_cylinder(radius: f64, height: f64, segments: u32) -> Result<Mesh, MeshError> {
        Ok(Mesh::cylinder(check_length("radius", radius)?, check_length("height", height)?, segments))
    }

    /// [`Mesh::cone`] with `height` checked by [`check_length`], and each radius either 0 (an
    /// apex) or a length [`check_length`] accepts, not both 0.
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for a radius or `height`, or when both radii are 0.
    pub fn try_cone(bottom: f64, top: f64, height: f64, segments: u32) -> Result<Mesh, MeshError> {
        let radius = |name: &str, r: f64| if r == 0.0 { Ok(0.0) } else { check_length(name, r) };
        let (b, t) = (radius("bottom", bottom)?, radius("top", top)?);
        if b == 0.0 && t == 0.0 {
            return Err(MeshError::OutOfRange {
                name: "top".into(),
                value: "0".into(),
                range: format!("{} and {} when `bottom` is 0 too", fmt_num(MIN_LENGTH), fmt_num(MAX_LENGTH)),
            });
        }
        Ok(Mesh::cone(b, t, check_length("height", height)?, segments))
    }

    /// [`Mesh::torus`] with the radii checked by [`check_length`] and the
    /// `major_segments` × `minor_segments` mesh by the memory budget.
    ///
    /// # Errors
    /// [`MeshError::OutOfRange`] for `major` or `minor`; [`MeshError::Limit`] over the budget or
    /// when the current cancellation token stops the work (polled every row).
    pub fn try_torus(major: f64, minor: f64, major_segments: u32, minor_segments: u32) -> Result<Mesh, MeshError> {
        check_length("major", major)?;
        check_length("minor", minor)?;
        let f = f64::from(major_segments.max(3)) * f64::from(minor_segments.max(3));
        budget(|| format!("a {major_segments} × {minor_segments} torus"), f, 4.0 * f, f)?;
        Mesh::torus_with(major, minor, major_segments, minor_segments, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stopped_token_stops_the_checked_primitives_and_the_same_calls_then_succeed() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let stopped = MeshError::Limit(LimitError::Stopped(StopReason::Interrupted));
            assert_eq!(Mesh::try_icosphere(1.0, 3).unwrap_err(), stopped);
            assert_eq!(Mesh::try_uv_sphere(1.0, 16, 8).unwrap_err(), stopped);
            assert_eq!(Mesh::try_torus(2.0, 1.0, 16, 8).unwrap_err(), stopped);
            // The plain constructors never stop, and build the same meshes.
            assert!(Mesh::uv_sphere(1.0, 16, 8).is_closed());
        }
        assert_eq!(Mesh::try_icosphere(1.0, 3).unwrap(), Mesh::icosphere(1.0, 3));
        assert_eq!(Mesh::try_uv_sphere(1.0, 16, 8).unwrap(), Mesh::uv_sphere(1.0, 16, 8));
        assert_eq!(Mesh::try_torus(2.0, 1.0, 16, 8).unwrap(), Mesh::torus(2.0, 1.0, 16, 8));
    }
    use crate::limits::LimitError;

    #[test]
    fn lengths_whose_square_or_cube_leave_f64_are_refused_with_the_range() {
        // 1e155² overflows and 1e-300² underflows: normalising an icosphere's midpoints would
        // divide by infinity or zero. Both are refused before building.
        for r in [1e155, 1e-300, f64::NAN, -1.0, 0.0] {
            let e = Mesh::try_icosphere(r, 2).unwrap_err();
            assert!(matches!(e, MeshError::OutOfRange { .. }), "{r}: {e}");
            assert!(e.to_string().contains("`radius` must be between 1e-100 and 1e100"), "{e}");
        }
        let e = Mesh::try_cube(1e200).unwrap_err().to_string();
        assert!(e.ends_with("got 1e200"), "no 200-digit decimal: {e}");
        let m = Mesh::try_icosphere(1e100, 2).unwrap();
        assert!(m.volume().is_finite() && m.positions().iter().all(|p| crate::math::is_finite(*p)));
        assert!(Mesh::try_cuboid(Vec3::ZERO, Vec3::new(1.0, 1e101, 1.0)).is_err());
    }

    #[test]
    fn a_sphere_whose_product_of_counts_is_huge_is_refused_before_allocating() {
        // Each count alone is allowed (100,000); 1e10 quads are about 2.4 TiB.
        let e = Mesh::try_uv_sphere(1.0, 100_000, 100_000).unwrap_err();
        assert!(matches!(e, MeshError::Limit(LimitError::OverBudget { .. })), "{e}");
        assert!(e.to_string().starts_with("a 100000 × 100000 UV sphere needs an estimated"), "{e}");
        assert!(Mesh::try_torus(2.0, 1.0, 100_000, 100_000).is_err());
        assert!(Mesh::try_icosphere(1.0, 40).is_err());
        assert_eq!(Mesh::try_uv_sphere(1.0, 8, 4).unwrap().face_count(), 32);
    }
}
