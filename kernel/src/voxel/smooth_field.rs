//! The smoothed density that [`Surface::Smooth`](super::Surface::Smooth) meshes: the image
//! convolved with a separable 7-tap filter, block by block, in exact integer arithmetic.
//!
//! Why: Heurtebise & Thon §2.3 display their voxels by marching cubes "that provides a smooth
//! surface instead of a set of blocky voxels", but over densities that go from 0 to 255 within one
//! voxel the crossing interpolated along a cell edge is close to the edge's midpoint wherever both
//! ends are saturated, so the surface steps with the grid: contour rings on a sphere, knurled
//! faces on a rotated box. Spreading the transition over a few voxels makes the field nearly
//! linear across each cell, so the interpolated crossings (and the face normals they make) follow
//! the true surface; see the measurements in the issue-35 note (95th-percentile normal error on a
//! voxelized sphere from 7.5° to about 2°).
//!
//! The filter: taps `[-1, 0, 9, 16, 9, 0, -1] / 32` along x, y and z. It is the choice of a
//! careful implementer rather than the paper's (which does not say how it smooths):
//! - its second moment is zero, so where a surface's normal lies along a grid axis it does not
//!   move the surface inward with its curvature (a Gaussian or binomial blur of variance σ² moves
//!   a surface of mean curvature H inward by σ²·H). The 3D filter is the product of three 1D ones,
//!   though, and on a plane through it that is not a grid plane its taps no longer cancel: where
//!   the normal is diagonal the smoothed field's level set on a sphere of radius r lies about
//!   0.8/r voxel inside, and the surface's vertices lie on average 0.45/r voxel inside (measured
//!   at r = 8 … 50), against 0.11/r for the raw surface and 1.24/r for the binomial
//!   `[1, 4, 6, 4, 1] / 16` of similar smoothing. With the facets' own chord error a ball of
//!   radius r voxels so loses about 1.76/r² of its volume (raw: 0.82/r²; 1.8 % at r = 10,
//!   0.3 % at r = 25);
//!   `tests_smooth` pins this. (A kernel with zero second moment on every plane, such as a
//!   difference of two isotropic Gaussians, would cancel it; it is not built.)
//! - its response is zero at the Nyquist frequency, where the voxel staircase lives;
//! - it is symmetric, so a plane's half-coverage level (and with it the iso-127.5 surface of a
//!   flat face) does not move;
//! - its step response stays within −3 % … +3 % per axis (about −4 % … +10 % in 3D), so it
//!   never lifts empty space to the default iso level nor sinks a solid below it.
//!
//! Sharp features are rounded over about the filter's radius (three voxels); that is the price of
//! a smooth surface, and [`Surface::Raw`](super::Surface::Raw) keeps the unfiltered one.

use super::marching_cubes::{Image, BS};

/// The filter's half-width in samples.
pub(super) const RADIUS: usize = 3;
/// The filter taps (sum 32).
const TAPS: [i32; 2 * RADIUS + 1] = [-1, 0, 9, 16, 9, 0, -1];
/// The gain of the 3D filter: a filtered value is the density times this for a uniform region.
pub(super) const GAIN: f64 = 32_768.0;
/// Raw samples per window side: the block's samples and the filter's reach on either side.
const W: usize = BS + 2 * RADIUS;

/// The filtered field at the BS³ padded samples `origin + l` (l in 0…BS per axis, x fastest),
/// each density × [`GAIN`], exactly (integers). Samples outside the image read as 0, as the
/// unfiltered marching cubes read them, so the surface stays capped at the border.
pub(super) fn smooth_block(img: Image<'_>, origin: [usize; 3]) -> Vec<i32> {
    let m = img.m as isize;
    let mut raw = vec![0i32; W * W * W];
    let (mut lo, mut hi) = (i32::MAX, i32::MIN);
    for z in 0..W {
        let pz = (origin[2] + z) as isize - RADIUS as isize;
        for y in 0..W {
            let py = (origin[1] + y) as isize - RADIUS as isize;
            let row = &mut raw[(z * W + y) * W..][..W];
            if pz < 1 || pz > m || py < 1 || py > m {
                lo = lo.min(0);
                hi = hi.max(0);
                continue;
            }
            let r = (((pz - 1) * m + py - 1) * m) as usize;
            for (x, slot) in row.iter_mut().enumerate() {
                let px = (origin[0] + x) as isize - RADIUS as isize;
                let v = if px < 1 || px > m { 0 } else { i32::from(img.values[r + px as usize - 1]) };
                *slot = v;
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if lo == hi {
        // A uniform window (most blocks: all empty or all full) filters to itself.
        return vec![lo * GAIN as i32; BS * BS * BS];
    }
    // Along x: W × W rows of BS.
    let mut fx = vec![0i32; W * W * BS];
    for (row, out) in raw.chunks_exact(W).zip(fx.chunks_exact_mut(BS)) {
        for (x, o) in out.iter_mut().enumerate() {
            *o = TAPS.iter().zip(&row[x..x + TAPS.len()]).map(|(t, v)| t * v).sum();
        }
    }
    // Along y: W slices of BS × BS.
    let mut fy = vec![0i32; W * BS * BS];
    for z in 0..W {
        for y in 0..BS {
            for x in 0..BS {
                fy[(z * BS + y) * BS + x] =
                    TAPS.iter().enumerate().map(|(t, w)| w * fx[(z * W + y + t) * BS + x]).sum();
            }
        }
    }
    // Along z: BS³.
    let mut out = vec![0i32; BS * BS * BS];
    for z in 0..BS {
        for y in 0..BS {
            for x in 0..BS {
                out[(z * BS + y) * BS + x] =
                    TAPS.iter().enumerate().map(|(t, w)| w * fy[((z + t) * BS + y) * BS + x]).sum();
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_taps_have_unit_gain_and_no_second_moment() {
        let r = RADIUS as i32;
        assert_eq!(TAPS.iter().sum::<i32>() * TAPS.iter().sum::<i32>() * TAPS.iter().sum::<i32>(), GAIN as i32);
        assert_eq!(TAPS.iter().enumerate().map(|(i, t)| t * (i as i32 - r)).sum::<i32>(), 0);
        assert_eq!(TAPS.iter().enumerate().map(|(i, t)| t * (i as i32 - r).pow(2)).sum::<i32>(), 0);
    }

    #[test]
    fn a_linear_ramp_is_kept_and_the_border_reads_empty() {
        // Densities rising by 3 per voxel along x (inside the image, away from the border) are
        // reproduced exactly: the filter is symmetric with unit gain.
        let m = 64;
        let values: Vec<u8> = (0..m * m * m).map(|i| (20 + 3 * (i % m)) as u8).collect();
        let img = Image { values: &values, m };
        let f = smooth_block(img, [16, 16, 16]);
        for (l, &v) in f.iter().enumerate().take(BS) {
            let voxel = 16 + l - 1;
            assert_eq!(f64::from(v), (20 + 3 * voxel) as f64 * GAIN, "sample {l}");
        }
        // The first block's corner sample is outside the image (padding): only the filter's
        // reach into the image makes it non-zero, and never above the density's scale.
        let g = smooth_block(img, [0, 0, 0]);
        assert!(g[0] < 20 * GAIN as i32);
        // An empty image filters to zero everywhere.
        let zero = vec![0u8; 8];
        assert!(smooth_block(Image { values: &zero, m: 2 }, [0, 0, 0]).iter().all(|&v| v == 0));
    }
}
