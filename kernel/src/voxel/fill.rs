//! Filling shapes into a grid with partial coverage: a voxel's density is 255 × the fraction of
//! its unit cube inside the shape, combined with what is there by taking the maximum (a union
//! that is idempotent: filling the same shape twice changes nothing).

use super::{VoxelError, Voxels};
use crate::math::{is_finite, Vec3};

/// Sub-samples per voxel side across which sphere coverage is integrated (the third axis is
/// integrated exactly); 8 × 8 keeps the density error of a boundary voxel well under one step.
const SPHERE_SAMPLES: usize = 8;

/// The length of `[a, b] ∩ [i, i + 1]`.
pub(super) fn overlap(a: f64, b: f64, i: usize) -> f64 {
    let (lo, hi) = (a.max(i as f64), b.min(i as f64 + 1.0));
    (hi - lo).max(0.0)
}

/// A coverage fraction in 0..=1 as a density (rounded to nearest).
pub(super) fn density(fraction: f64) -> u8 {
    (fraction.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The voxel range `[floor(a), ceil(b))` clipped to `[0, n)`.
pub(super) fn voxel_range(a: f64, b: f64, n: usize) -> (usize, usize) {
    let lo = a.floor().max(0.0);
    let hi = b.ceil().min(n as f64);
    if hi <= lo {
        (0, 0)
    } else {
        (lo as usize, hi as usize)
    }
}

fn check_point(what: &'static str, p: Vec3) -> Result<(), VoxelError> {
    if is_finite(p) {
        Ok(())
    } else {
        Err(VoxelError::NonFinite { what, value: format!("{p}") })
    }
}

impl Voxels {
    /// Fills the axis-aligned box between `min` and `max` (world coordinates, corners in any
    /// order) with partial coverage: a voxel's density becomes the larger of its density and
    /// 255 × the fraction of it inside the box. With integer grid bounds exactly the voxels in
    /// `[min, max)` become 255. Parts outside the grid are ignored.
    ///
    /// # Errors
    /// [`VoxelError::NonFinite`] for a NaN or infinite corner; [`VoxelError::Limit`] when the
    /// current cancellation token stops the fill or the undo copy passes the memory budget (see
    /// [`Voxels::edit_slices`]). The grid is unchanged on any error.
    pub fn fill_box(&mut self, min: Vec3, max: Vec3) -> Result<(), VoxelError> {
        check_point("box corner", min)?;
        check_point("box corner", max)?;
        let (a, b) = (self.to_grid(min), self.to_grid(max));
        let (lo, hi) = (a.min(b), a.max(b));
        let n = self.n;
        let (x0, x1) = voxel_range(lo.x, hi.x, n);
        let (y0, y1) = voxel_range(lo.y, hi.y, n);
        let (z0, z1) = voxel_range(lo.z, hi.z, n);
        if x0 >= x1 || y0 >= y1 || z0 >= z1 {
            return Ok(());
        }
        let wx: Vec<f64> = (x0..x1).map(|i| overlap(lo.x, hi.x, i)).collect();
        let wy: Vec<f64> = (y0..y1).map(|i| overlap(lo.y, hi.y, i)).collect();
        self.edit_slices([x0, y0, z0], [x1, y1, z1], |z, slice| {
            let wz = overlap(lo.z, hi.z, z);
            for (y, &fy) in (y0..y1).zip(&wy) {
                let row = &mut slice[y * n..y * n + n];
                for (x, &fx) in (x0..x1).zip(&wx) {
                    row[x] = row[x].max(density(fx * fy * wz));
                }
            }
        })?;
        Ok(())
    }

    /// Fills the ball of `radius` around `center` (world coordinates) with partial coverage:
    /// each voxel's density becomes the larger of its density and 255 × the fraction of it inside
    /// the ball. Voxels wholly inside get 255; boundary voxels integrate the exact chord length
    /// along x over an 8 × 8 grid of (y, z) sub-samples. Parts outside the grid are ignored.
    ///
    /// # Errors
    /// [`VoxelError::NonFinite`] for a NaN or infinite centre or radius,
    /// [`VoxelError::InvalidArgument`] for a radius that is not positive; [`VoxelError::Limit`]
    /// as for [`Voxels::fill_box`]. The grid is unchanged on any error.
    pub fn fill_sphere(&mut self, center: Vec3, radius: f64) -> Result<(), VoxelError> {
        check_point("sphere centre", center)?;
        if !radius.is_finite() {
            return Err(VoxelError::NonFinite { what: "sphere radius", value: format!("{radius}") });
        }
        if radius <= 0.0 {
            return Err(VoxelError::InvalidArgument {
                what: "sphere radius",
                reason: format!("{radius} is not positive"),
            });
        }
        let c = self.to_grid(center);
        let r = radius / self.scale;
        let n = self.n;
        let (x0, x1) = voxel_range(c.x - r, c.x + r, n);
        let (y0, y1) = voxel_range(c.y - r, c.y + r, n);
        let (z0, z1) = voxel_range(c.z - r, c.z + r, n);
        if x0 >= x1 || y0 >= y1 || z0 >= z1 {
            return Ok(());
        }
        self.edit_slices([x0, y0, z0], [x1, y1, z1], |z, slice| {
            for y in y0..y1 {
                let row = &mut slice[y * n..y * n + n];
                for (x, v) in row.iter_mut().enumerate().take(x1).skip(x0) {
                    let d = sphere_coverage(c, r, [x, y, z]);
                    *v = (*v).max(d);
                }
            }
        })?;
        Ok(())
    }
}

/// The density of voxel `v` covered by the ball (grid coordinates).
fn sphere_coverage(c: Vec3, r: f64, v: [usize; 3]) -> u8 {
    let lo = Vec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
    let hi = lo + Vec3::ONE;
    let nearest = c.clamp(lo, hi);
    let r2 = r * r;
    if (nearest - c).length_squared() >= r2 {
        return 0;
    }
    let far = Vec3::new(
        (c.x - lo.x).abs().max((c.x - hi.x).abs()),
        (c.y - lo.y).abs().max((c.y - hi.y).abs()),
        (c.z - lo.z).abs().max((c.z - hi.z).abs()),
    );
    if far.length_squared() <= r2 {
        return 255;
    }
    let k = SPHERE_SAMPLES;
    let mut sum = 0.0;
    for b in 0..k {
        let dz = lo.z + (b as f64 + 0.5) / k as f64 - c.z;
        for a in 0..k {
            let dy = lo.y + (a as f64 + 0.5) / k as f64 - c.y;
            let rest = r2 - dy * dy - dz * dz;
            if rest > 0.0 {
                let h = rest.sqrt();
                sum += overlap(c.x - h, c.x + h, v[0]);
            }
        }
    }
    density(sum / (k * k) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn integer_box_fills_exactly_the_half_open_range() {
        // Voxel i spans [i, i+1), so [2, 5) covers voxels 2, 3, 4 fully and nothing else.
        let mut v = Voxels::new(8).unwrap();
        v.fill_box(Vec3::new(2.0, 1.0, 0.0), Vec3::new(5.0, 3.0, 8.0)).unwrap();
        for z in 0..8 {
            for y in 0..8 {
                for x in 0..8 {
                    let inside = (2..5).contains(&x) && (1..3).contains(&y);
                    assert_eq!(v.get(x, y, z).unwrap(), if inside { 255 } else { 0 }, "({x},{y},{z})");
                }
            }
        }
        assert_eq!(v.filled(), 3 * 2 * 8);
        assert_eq!(v.volume(), 48.0);
    }

    #[test]
    fn fractional_box_gives_partial_densities() {
        // [0.5, 1.75) along x: voxel 0 is half covered (127.5 → 128), voxel 1 three quarters.
        let mut v = Voxels::new(4).unwrap();
        v.fill_box(Vec3::new(0.5, 0.0, 0.0), Vec3::new(1.75, 1.0, 1.0)).unwrap();
        assert_eq!(v.get(0, 0, 0).unwrap(), 128);
        assert_eq!(v.get(1, 0, 0).unwrap(), 191);
        assert_eq!(v.get(2, 0, 0).unwrap(), 0);
    }

    #[test]
    fn sphere_volume_matches_four_thirds_pi_r_cubed() {
        // Partial coverage makes the density sum approximate the ball's volume closely.
        for r in [3.3, 7.0, 12.5] {
            let mut v = Voxels::new(32).unwrap();
            v.fill_sphere(Vec3::splat(16.2), r).unwrap();
            let exact = 4.0 / 3.0 * PI * r * r * r;
            let rel = (v.volume() - exact).abs() / exact;
            assert!(rel < 2e-3, "r {r}: volume {} vs {exact}, relative {rel:e}", v.volume());
        }
    }

    #[test]
    fn sphere_fill_is_a_union_and_idempotent() {
        let mut v = Voxels::new(16).unwrap();
        v.fill_sphere(Vec3::splat(8.0), 5.0).unwrap();
        let once = v.clone();
        v.fill_sphere(Vec3::splat(8.0), 5.0).unwrap();
        assert_eq!(v, once);
        v.fill_sphere(Vec3::splat(8.0), 2.0).unwrap();
        assert_eq!(v, once, "a smaller concentric ball adds nothing");
    }

    #[test]
    fn bad_shapes_are_refused_and_leave_the_grid_unchanged() {
        let mut v = Voxels::new(8).unwrap();
        v.fill_sphere(Vec3::splat(4.0), 2.0).unwrap();
        let before = v.clone();
        assert!(matches!(v.fill_sphere(Vec3::new(f64::NAN, 0.0, 0.0), 1.0), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(v.fill_sphere(Vec3::ZERO, f64::INFINITY), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(v.fill_sphere(Vec3::ZERO, -1.0), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(v.fill_box(Vec3::ZERO, Vec3::splat(f64::NAN)), Err(VoxelError::NonFinite { .. })));
        assert_eq!(v, before);
        // Shapes wholly outside the grid are not errors; they fill nothing.
        v.fill_sphere(Vec3::splat(100.0), 3.0).unwrap();
        v.fill_box(Vec3::splat(-10.0), Vec3::splat(-5.0)).unwrap();
        assert_eq!(v, before);
    }
}
