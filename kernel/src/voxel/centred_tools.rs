//! Tool grids made to be placed by their centre: [`Voxels::centred_sphere`] and
//! [`Voxels::centred_box`].
//!
//! [`Voxels::sculpt`] puts a tool grid's centre at the sculpt position (Heurtebise & Thon §3.3
//! place tools by their own frame); a shape filled off-centre in its tool grid would land off the
//! position by the difference. These builders choose the smallest power-of-two grid holding the
//! shape with one empty voxel on every side, put the shape's centre at the grid's centre, and map
//! the grid so that centre is world position 0 (voxel size 1): the tool lands centred on `at`, and
//! its own `to_mesh` is centred on the origin.

use super::{VoxelError, Voxels, MAX_SIZE};
use crate::math::Vec3;

/// The smallest power-of-two side holding `extent` voxels plus one empty voxel each side.
fn side_for(what: &'static str, extent: f64) -> Result<usize, VoxelError> {
    let need = extent + 2.0;
    if need > MAX_SIZE as f64 {
        return Err(VoxelError::InvalidArgument {
            what,
            reason: format!(
                "{extent} voxels across need a grid above the largest ({MAX_SIZE}³) with a voxel of margin"
            ),
        });
    }
    Ok((need.ceil() as usize).next_power_of_two())
}

impl Voxels {
    /// A tool grid holding the ball of `radius` (voxel units) centred in the grid, with the grid's
    /// centre at world position 0: the smallest power-of-two side above 2 · radius + 2.
    ///
    /// # Errors
    /// [`VoxelError::NonFinite`] for a NaN or infinite radius; [`VoxelError::InvalidArgument`] for
    /// a radius that is not positive or needs a grid over [`MAX_SIZE`].
    pub fn centred_sphere(radius: f64) -> Result<Voxels, VoxelError> {
        if !radius.is_finite() {
            return Err(VoxelError::NonFinite { what: "sphere radius", value: format!("{radius}") });
        }
        if radius <= 0.0 {
            return Err(VoxelError::InvalidArgument {
                what: "sphere radius",
                reason: format!("{radius} is not positive"),
            });
        }
        let n = side_for("sphere radius", 2.0 * radius)?;
        let mut v = Voxels::with_map(n, Vec3::splat(-(n as f64) / 2.0), 1.0)?;
        v.fill_sphere(Vec3::ZERO, radius)?;
        Ok(v)
    }

    /// A tool grid holding the axis-aligned box of `size` (voxel units, each side positive)
    /// centred in the grid, with the grid's centre at world position 0: the smallest power-of-two
    /// side above the largest side + 2. A box side that is not a whole number of voxels (or that
    /// differs in parity from the grid) gets partly covered voxels on its faces.
    ///
    /// # Errors
    /// [`VoxelError::NonFinite`] for a NaN or infinite side; [`VoxelError::InvalidArgument`] for a
    /// side that is not positive or needs a grid over [`MAX_SIZE`].
    pub fn centred_box(size: Vec3) -> Result<Voxels, VoxelError> {
        if !crate::math::is_finite(size) {
            return Err(VoxelError::NonFinite { what: "box size", value: format!("{size}") });
        }
        if size.min_element() <= 0.0 {
            return Err(VoxelError::InvalidArgument {
                what: "box size",
                reason: format!("{size} has a side that is not positive"),
            });
        }
        let n = side_for("box size", size.max_element())?;
        let mut v = Voxels::with_map(n, Vec3::splat(-(n as f64) / 2.0), 1.0)?;
        v.fill_box(-size / 2.0, size / 2.0)?;
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn centred_tools_sit_on_the_grid_centre_with_a_margin() {
        let s = Voxels::centred_sphere(5.0).unwrap();
        assert_eq!((s.size(), s.origin()), (16, Vec3::splat(-8.0)));
        assert!((s.volume() - 4.0 / 3.0 * PI * 125.0).abs() < 1.0, "{}", s.volume());
        // The border voxels are empty on every side.
        for i in 0..16 {
            for j in 0..16 {
                for (x, y, z) in [(0, i, j), (15, i, j), (i, 0, j), (i, 15, j), (i, j, 0), (i, j, 15)] {
                    assert_eq!(s.get(x, y, z).unwrap(), 0);
                }
            }
        }
        // Its mesh is centred on the origin.
        let mut s2 = s.clone();
        assert!(s2.to_mesh(0, super::super::DEFAULT_ISO).unwrap().bounds().center().length() < 1e-9);
        // 2r + 2 = 16 still fits 16; a hair more needs 32.
        assert_eq!(Voxels::centred_sphere(7.0).unwrap().size(), 16);
        assert_eq!(Voxels::centred_sphere(7.01).unwrap().size(), 32);
        let b = Voxels::centred_box(Vec3::new(6.0, 4.0, 2.0)).unwrap();
        assert_eq!(b.size(), 8);
        assert!((b.volume() - 48.0).abs() < 1e-9);
        assert_eq!(b.get(1, 2, 3).unwrap(), 255);
        assert_eq!(b.get(0, 2, 3).unwrap(), 0);
    }

    #[test]
    fn bad_sizes_are_refused() {
        assert!(matches!(Voxels::centred_sphere(f64::NAN), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(Voxels::centred_sphere(0.0), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(Voxels::centred_sphere(300.0), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(Voxels::centred_box(Vec3::new(1.0, -1.0, 1.0)), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(Voxels::centred_box(Vec3::new(1.0, f64::INFINITY, 1.0)), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(Voxels::centred_box(Vec3::splat(1e300)), Err(VoxelError::InvalidArgument { .. })));
    }
}
