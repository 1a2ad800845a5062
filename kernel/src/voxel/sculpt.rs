//! Sculpting a grid with a tool grid (Heurtebise & Thon §3.3): the tool is rotated into the
//! object's lattice only where it touches the object, its rotated voxels are cached for the next
//! stroke, and each touched voxel gains or loses the tool's filling percentage, clamped to 0–255.

use std::sync::atomic::{AtomicUsize, Ordering};

use super::rotate::{clip_row, frame, sample_bounds, step_row, Placement};
use super::tool_cache::{CacheKey, ToolCache, UNSET};
use super::{for_each_chunk, VoxelError, Voxels};
use crate::math::{Quat, Vec3};

/// Whether a sculpt adds or removes material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SculptMode {
    /// Each voxel gains the tool's density there, clamped to 255.
    Add,
    /// Each voxel loses the tool's density there, clamped to 0.
    Subtract,
}

impl SculptMode {
    /// `"add"` or `"subtract"`.
    ///
    /// # Errors
    /// [`VoxelError::InvalidArgument`] for any other name.
    pub fn parse(name: &str) -> Result<SculptMode, VoxelError> {
        match name {
            "add" => Ok(SculptMode::Add),
            "subtract" => Ok(SculptMode::Subtract),
            other => Err(VoxelError::InvalidArgument {
                what: "sculpt mode",
                reason: format!("\"{other}\" is not one of \"add\", \"subtract\""),
            }),
        }
    }
}

/// Where and how to apply a tool; see [`Voxels::sculpt`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SculptOptions {
    /// World position of the tool grid's centre. No default (see [`SculptOptions::at`]).
    pub at: Vec3,
    /// Rotation axis through the tool's centre. Default value: +z.
    pub axis: Vec3,
    /// Rotation angle in degrees (right-handed about `axis`). Default value: 0.
    pub angle: f64,
    /// A rotation as a quaternion (any non-zero length; it is normalised), used instead of
    /// `axis` and `angle` when set. Default value: `None`.
    pub rotation: Option<Quat>,
    /// Add or subtract. Default value: [`SculptMode::Add`].
    pub mode: SculptMode,
    /// Trilinear resampling of the rotated tool (§3.2) rather than nearest voxel. Default value:
    /// `true`.
    pub antialias: bool,
}

impl SculptOptions {
    /// Options placing the tool's centre at `at`, with every other field at its default.
    #[must_use]
    pub fn at(at: Vec3) -> SculptOptions {
        SculptOptions { at, axis: Vec3::Z, angle: 0.0, rotation: None, mode: SculptMode::Add, antialias: true }
    }

    /// These options turned by the quaternion `q` (normalised when placed; see
    /// [`SculptOptions::rotation`]), e.g. composed turns `q₂ · q₁` (q₁ first).
    #[must_use]
    pub fn with_quat(mut self, q: Quat) -> SculptOptions {
        self.rotation = Some(q);
        self
    }

    /// These options turned by `degrees` about `axis` (clearing a quaternion set before).
    #[must_use]
    pub fn with_rotation(mut self, axis: Vec3, degrees: f64) -> SculptOptions {
        self.axis = axis;
        self.angle = degrees;
        self.rotation = None;
        self
    }

    /// These options with `mode`.
    #[must_use]
    pub fn with_mode(mut self, mode: SculptMode) -> SculptOptions {
        self.mode = mode;
        self
    }

    /// These options with antialiasing on or off.
    #[must_use]
    pub fn with_antialias(mut self, antialias: bool) -> SculptOptions {
        self.antialias = antialias;
        self
    }
}

/// What a sculpt did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SculptReport {
    /// Object voxels in contact with the tool's reach (all of them inside the grid when adding;
    /// the non-empty ones when subtracting).
    pub contact: usize,
    /// Tool voxels rotated for this stroke.
    pub rotated: usize,
    /// Tool voxels taken from the cache of the previous strokes.
    pub reused: usize,
    /// Object voxels whose density changed.
    pub changed: usize,
}

impl Voxels {
    /// Sculpts this grid with `tool` (§3.3): the tool grid's centre is placed at `options.at`
    /// (world coordinates), turned by `options.angle` degrees about `options.axis` (or by the
    /// quaternion `options.rotation` when set), and every
    /// object voxel in contact gains (add) or loses (subtract) the tool's density at its centre,
    /// clamped to 0–255. The tool's voxels are resampled at the object's voxel centres (their
    /// voxel sizes may differ; a tool much finer than the object is point-sampled).
    ///
    /// Only tool voxels in contact with the object are rotated (every reachable voxel inside the
    /// grid when adding, the non-empty ones when subtracting), and rotated voxels are kept: a later
    /// stroke with the same tool, rotation and sub-voxel offset — a drag by whole voxels — rotates
    /// only the voxels newly in contact. The hierarchy and surface caches are updated for the
    /// changed box. A tool wholly outside the grid changes nothing.
    ///
    /// # Errors
    /// [`VoxelError::NonFinite`] for a non-finite position, axis, angle or quaternion;
    /// [`VoxelError::InvalidArgument`] for a zero axis or quaternion, a position absurdly far from the grid, or a
    /// tool whose rotated reach exceeds 2²⁷ object voxels. The grid is unchanged on error.
    ///
    /// See also [`rotate_tool`](super::rotate_tool); Heurtebise & Thon §3.1–3.3, Algorithm 1.
    pub fn sculpt(&mut self, tool: &Voxels, options: &SculptOptions) -> Result<SculptReport, VoxelError> {
        let p = match options.rotation {
            Some(q) => Placement::with_quat(self, tool, options.at, q)?,
            None => Placement::new(self, tool, options.at, options.axis, options.angle)?,
        };
        let (rel, dims) = p.reach(tool.n)?;
        let n = self.n as i64;
        let glo = [p.anchor[0] + rel[0], p.anchor[1] + rel[1], p.anchor[2] + rel[2]];
        let clo = glo.map(|v| v.max(0));
        let chi = [0, 1, 2].map(|a| (glo[a] + dims[a] as i64).min(n));
        if (0..3).any(|a| clo[a] >= chi[a]) {
            return Ok(SculptReport::default());
        }
        let key = CacheKey {
            tool: tool.revision,
            tool_n: tool.n,
            rotation: p.rotation.to_cols_array().map(f64::to_bits),
            ratio: p.ratio.to_bits(),
            frac: p.frac.to_array().map(f64::to_bits),
            antialias: options.antialias,
        };
        let mut cache = match self.tool_cache.take() {
            Some(c) if c.key == key => c,
            _ => ToolCache {
                key,
                bounds: sample_bounds(tool),
                rel,
                dims,
                values: vec![UNSET; dims[0] * dims[1] * dims[2]],
            },
        };
        debug_assert!(cache.rel == rel && cache.dims == dims, "the reach depends only on the cache key");
        let unset_before = cache.values.iter().filter(|&&v| v == UNSET).count();

        // Pass 1: rotate the tool voxels in contact that are not cached yet (Algorithm 1 runs).
        let (b, k, j, i) = frame(&p, tool.n);
        let subtract = options.mode == SculptMode::Subtract;
        let (nu, data, tdata, tn, aa) = (self.n, &self.data[..], &tool.data[..], tool.n, options.antialias);
        let contact = |g: usize| !subtract || data[g] > 0;
        let bounds = cache.bounds;
        let cx = ((clo[0] - glo[0]) as usize, (chi[0] - glo[0]) as usize);
        // Each plane charges its voxels to the caller's token (on the workers too); once it
        // stops, the remaining planes are skipped and the grid is left as it was.
        let token = crate::limits::current();
        for_each_chunk(self.parallel, &mut cache.values, dims[0] * dims[1], |z, plane| {
            let gz = glo[2] + z as i64;
            if gz < clo[2] || gz >= chi[2] || token.charge((dims[0] * dims[1]) as u64).is_err() {
                return;
            }
            let mut buf = Vec::new();
            for (y, row) in plane.chunks_mut(dims[0]).enumerate() {
                let gy = glo[1] + y as i64;
                if gy < clo[1] || gy >= chi[1] {
                    continue;
                }
                let q0 = b + k * (rel[0] as f64) + j * ((rel[1] + y as i64) as f64) + i * ((rel[2] + z as i64) as f64);
                let (xa, xb) = bounds.map_or((0, 0), |b| clip_row(q0, k, dims[0], b));
                let gbase = (gz as usize * nu + gy as usize) * nu;
                let mut x = cx.0;
                while x < cx.1 {
                    let need = |x: usize| row[x] == UNSET && contact(gbase + (glo[0] + x as i64) as usize);
                    if !need(x) {
                        x += 1;
                        continue;
                    }
                    let start = x;
                    while x < cx.1 && need(x) {
                        x += 1;
                    }
                    // Voxels outside the clipped row cannot reach the tool: they are empty.
                    let (a, e) = (start.max(xa), x.min(xb));
                    for v in &mut row[start..x] {
                        *v = 0;
                    }
                    if a < e {
                        buf.resize(e - a, 0);
                        step_row(tdata, tn, q0 + k * a as f64, k, &mut buf, aa);
                        for (v, &t) in row[a..e].iter_mut().zip(&buf) {
                            *v = u16::from(t);
                        }
                    }
                }
            }
        });
        if let Some(reason) = token.stopped() {
            return Err(crate::limits::LimitError::Stopped(reason).into());
        }
        let rotated = unset_before - cache.values.iter().filter(|&&v| v == UNSET).count();

        // Pass 2: add or subtract the filling percentage, clamped (§3.3).
        let counts = (AtomicUsize::new(0), AtomicUsize::new(0));
        let (lo, hi) = (clo.map(|v| v as usize), chi.map(|v| v as usize));
        let edited = {
            let values = &cache.values;
            let n = self.n;
            self.edit_slices(lo, hi, |z, slice| {
                let (mut touched, mut changed) = (0, 0);
                let cz = z as i64 - glo[2];
                for y in lo[1]..hi[1] {
                    let cy = y as i64 - glo[1];
                    let crow = (cz as usize * dims[1] + cy as usize) * dims[0];
                    let row = &mut slice[y * n..y * n + n];
                    for x in lo[0]..hi[0] {
                        let v = row[x];
                        if subtract && v == 0 {
                            continue;
                        }
                        touched += 1;
                        let t = values[crow + (x as i64 - glo[0]) as usize];
                        debug_assert!(t != UNSET, "pass 1 rotated every voxel in contact");
                        let t = t.min(255) as u8;
                        let new = if subtract { v.saturating_sub(t) } else { v.saturating_add(t) };
                        if new != v {
                            row[x] = new;
                            changed += 1;
                        }
                    }
                }
                counts.0.fetch_add(touched, Ordering::Relaxed);
                counts.1.fetch_add(changed, Ordering::Relaxed);
            })
        };
        // The rotated tool is kept even when the stroke stopped: it is right for the next one.
        self.tool_cache = Some(cache);
        edited?;
        let contact = counts.0.into_inner();
        Ok(SculptReport { contact, rotated, reused: contact - rotated.min(contact), changed: counts.1.into_inner() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::voxel::DEFAULT_ISO;

    #[test]
    fn a_stopped_token_stops_a_stroke_and_leaves_the_grid_as_it_was() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let mut block = Voxels::new(32).unwrap();
        block.fill_box(Vec3::splat(4.0), Vec3::splat(28.0)).unwrap();
        let before = block.data().to_vec();
        let tool = ball_tool(16, 6.0);
        let stroke = SculptOptions::at(Vec3::new(16.0, 16.0, 28.0)).with_mode(SculptMode::Subtract);
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = block.sculpt(&tool, &stroke).unwrap_err();
            assert_eq!(e, VoxelError::Limit(LimitError::Stopped(StopReason::Interrupted)));
        }
        assert_eq!(block.data(), &before[..]);
        assert!(block.sculpt(&tool, &stroke).unwrap().changed > 0);
    }

    fn ball_tool(n: usize, r: f64) -> Voxels {
        let mut t = Voxels::new(n).unwrap();
        t.fill_sphere(Vec3::splat(n as f64 / 2.0), r).unwrap();
        t
    }

    #[test]
    fn adding_a_ball_into_empty_space_copies_its_volume() {
        // Unrotated, centred on a voxel corner: the tool lands voxel for voxel.
        let tool = ball_tool(16, 6.0);
        let mut v = Voxels::new(32).unwrap();
        let r = v.sculpt(&tool, &SculptOptions::at(Vec3::splat(16.0))).unwrap();
        assert!((v.volume() - tool.volume()).abs() < 1e-9);
        assert_eq!(r.changed, tool.filled());
        assert_eq!(r.reused, 0);
        let m = v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert!(m.is_closed() && m.is_manifold() && m.genus() == 0);
    }

    #[test]
    fn subtract_clamps_at_zero_and_add_at_255() {
        // Subtracting a ball from a full block removes its volume exactly (no voxel goes below 0
        // because the block is full); adding it back restores the block (clamped at 255).
        let tool = ball_tool(16, 5.0);
        let mut v = Voxels::new(32).unwrap();
        v.fill_box(Vec3::splat(4.0), Vec3::splat(28.0)).unwrap();
        let full = v.clone();
        let at = SculptOptions::at(Vec3::splat(16.0));
        v.sculpt(&tool, &at.with_mode(SculptMode::Subtract)).unwrap();
        assert!((full.volume() - v.volume() - tool.volume()).abs() < 1e-9);
        let m = v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(m.component_count(), 2, "a block with a spherical cavity has two shells");
        v.sculpt(&tool, &at).unwrap();
        assert_eq!(v, full);
        // Voxel by voxel, with densities below the tool's: subtract clamps to 0 and add to 255,
        // never wrapping. The tool lands voxel for voxel here (see the first test), so the
        // expected values come straight from the tool grid.
        let mut v = Voxels::new(32).unwrap();
        v.data.fill(100);
        let mut w = v.clone();
        v.sculpt(&tool, &at.with_mode(SculptMode::Subtract)).unwrap();
        w.data.fill(200);
        w.sculpt(&tool, &at).unwrap();
        for z in 0..16i64 {
            for y in 0..16i64 {
                for x in 0..16i64 {
                    let t = tool.get(x, y, z).unwrap();
                    assert_eq!(v.get(x + 8, y + 8, z + 8).unwrap(), 100u8.saturating_sub(t));
                    assert_eq!(w.get(x + 8, y + 8, z + 8).unwrap(), 200u8.saturating_add(t));
                }
            }
        }
        assert!(v.data.contains(&0) && w.data.contains(&255));
    }

    #[test]
    fn dragging_by_whole_voxels_reuses_rotated_voxels() {
        // Same rotation and sub-voxel offset: only voxels newly in contact are rotated.
        let tool = ball_tool(16, 6.0);
        let mut v = Voxels::new(64).unwrap();
        let o = SculptOptions::at(Vec3::new(20.3, 30.6, 31.1)).with_rotation(Vec3::new(1.0, 1.0, 0.0), 30.0);
        let first = v.sculpt(&tool, &o).unwrap();
        assert_eq!(first.reused, 0);
        assert_eq!(first.rotated, first.contact);
        let second = v.sculpt(&tool, &SculptOptions { at: o.at + Vec3::new(2.0, 0.0, 0.0), ..o }).unwrap();
        assert!(second.reused > 0 && second.rotated < second.contact / 4, "{second:?}");
        assert_eq!(second.reused + second.rotated, second.contact);
        // A different sub-voxel offset invalidates the cache.
        let third = v.sculpt(&tool, &SculptOptions { at: o.at + Vec3::new(0.5, 0.0, 0.0), ..o }).unwrap();
        assert_eq!(third.reused, 0);
    }

    #[test]
    fn cached_strokes_equal_fresh_strokes_and_parallel_equals_serial() {
        let tool = {
            let mut t = ball_tool(16, 5.0);
            t.fill_box(Vec3::new(2.0, 7.0, 7.0), Vec3::new(14.0, 9.0, 9.0)).unwrap();
            t
        };
        let strokes: Vec<SculptOptions> = (0..4)
            .map(|s| {
                SculptOptions::at(Vec3::new(14.25 + 3.0 * f64::from(s), 16.5, 15.75))
                    .with_rotation(Vec3::new(0.2, 1.0, 0.4), 41.0)
                    .with_mode(if s == 2 { SculptMode::Subtract } else { SculptMode::Add })
            })
            .collect();
        let mut base = Voxels::new(32).unwrap();
        base.fill_sphere(Vec3::splat(16.0), 6.0).unwrap();
        let (mut cached, mut fresh, mut serial) = (base.clone(), base.clone(), base.clone());
        serial.set_parallel(false);
        for s in &strokes {
            cached.sculpt(&tool, s).unwrap();
            fresh.tool_cache = None;
            fresh.sculpt(&tool, s).unwrap();
            serial.sculpt(&tool, s).unwrap();
        }
        assert_eq!(cached, fresh);
        assert_eq!(cached, serial);
        assert!(cached.volume() > base.volume());
    }

    #[test]
    fn sculpt_keeps_hierarchy_and_surfaces_in_step() {
        let tool = ball_tool(8, 3.0);
        let mut v = Voxels::new(32).unwrap();
        v.fill_sphere(Vec3::splat(16.0), 9.0).unwrap();
        v.to_mesh(1, DEFAULT_ISO).unwrap();
        assert!(v.has_hierarchy());
        v.sculpt(&tool, &SculptOptions::at(Vec3::new(25.0, 16.0, 16.0)).with_mode(SculptMode::Subtract)).unwrap();
        let mut fresh = v.clone();
        fresh.clear_caches();
        assert_eq!(v.hierarchy(), fresh.hierarchy());
        assert_eq!(v.to_mesh(1, DEFAULT_ISO).unwrap(), fresh.to_mesh(1, DEFAULT_ISO).unwrap());
    }

    #[test]
    fn bad_placements_are_refused_and_far_tools_change_nothing() {
        let tool = ball_tool(8, 3.0);
        let mut v = Voxels::new(16).unwrap();
        v.fill_sphere(Vec3::splat(8.0), 4.0).unwrap();
        let before = v.clone();
        let o = SculptOptions::at(Vec3::splat(8.0));
        assert!(matches!(
            v.sculpt(&tool, &SculptOptions::at(Vec3::new(f64::NAN, 0.0, 0.0))),
            Err(VoxelError::NonFinite { .. })
        ));
        assert!(matches!(v.sculpt(&tool, &o.with_rotation(Vec3::ZERO, 10.0)), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(v.sculpt(&tool, &o.with_rotation(Vec3::Z, f64::INFINITY)), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(
            v.sculpt(&tool, &SculptOptions::at(Vec3::splat(1e300))),
            Err(VoxelError::InvalidArgument { .. })
        ));
        assert_eq!(v, before);
        assert_eq!(v.sculpt(&tool, &SculptOptions::at(Vec3::splat(100.0))).unwrap(), SculptReport::default());
        assert_eq!(v, before);
        assert!(SculptMode::parse("carve").is_err());
        assert_eq!(SculptMode::parse("subtract"), Ok(SculptMode::Subtract));
    }
}
