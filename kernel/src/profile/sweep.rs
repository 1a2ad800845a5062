//! Sweeps: a profile carried along a 3D polyline on rotation-minimising frames.
//!
//! At each path point the profile's x runs along the frame's `r` and its y along `t × r`, `t`
//! the tangent (the bisector of the two segments at an inner point). At an inner point the ring
//! lies in the bisecting (mitre) plane and is stretched by 1/cos(θ/2) across the bend, so that
//! every section perpendicular to a segment is the profile itself, unstretched: the volume is
//! exactly area × centre-line length when the profile's centroid is on the path. Frames are
//! rotation-minimising (`frames`: Wang et al.'s double reflection, exact for a polyline); a
//! closed path spreads the frames' mismatch at the closure (the path's holonomy) evenly along
//! the path, by arc length.

use super::construct::cos_sin_degrees;
use super::convert::{check_number, check_solid_size, mesh_error};
use super::frames;
use super::self_crossing::{nearest, refuse_self_crossing};
use super::{Profile, ProfileError, Vec2};
use crate::csg::engine::triangulate_contours;
use crate::math::{Quat, Vec3};
use crate::mesh::Mesh;

/// Options of [`sweep`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SweepOptions {
    /// The direction the profile's +y faces at the start of the path (made perpendicular to the
    /// path there); `None` for +z, or +y when the path starts along z. Default value: `None`.
    pub up: Option<Vec3>,
    /// The turn of the profile about the path from start to end, degrees, spread by arc length.
    /// On a closed path a multiple of 360 closes smoothly; any other turn is taken back across
    /// the last segment. Default value: 0.
    pub twist: f64,
    /// The profile's scale (x, y) at the end of an open path, blended linearly by arc length
    /// from (1, 1). Default value: (1, 1).
    pub scale: Vec2,
    /// Whether the path's last point joins its first, making a ring with no caps (a last point
    /// equal to the first is dropped). Default value: false.
    pub closed: bool,
}

impl SweepOptions {
    /// No twist or scale, +z up, an open path.
    pub const DEFAULT: SweepOptions = SweepOptions { up: None, twist: 0.0, scale: Vec2::ONE, closed: false };

    /// With +y of the profile facing `up` at the start.
    #[must_use]
    pub fn with_up(mut self, up: Vec3) -> SweepOptions {
        self.up = Some(up);
        self
    }

    /// With `degrees` of twist.
    #[must_use]
    pub fn with_twist(mut self, degrees: f64) -> SweepOptions {
        self.twist = degrees;
        self
    }

    /// With the end scaled by `scale`.
    #[must_use]
    pub fn with_scale(mut self, scale: Vec2) -> SweepOptions {
        self.scale = scale;
        self
    }

    /// Closed or open.
    #[must_use]
    pub fn with_closed(mut self, closed: bool) -> SweepOptions {
        self.closed = closed;
        self
    }
}

impl Default for SweepOptions {
    fn default() -> SweepOptions {
        SweepOptions::DEFAULT
    }
}

/// `profile` swept along the polyline `path`, a closed manifold triangle mesh (a ring for a
/// closed path). See the [module documentation](self) for the frames.
///
/// A path that comes back through its own tube is refused (checked exactly on the result,
/// O(n log n) in its faces).
///
/// # Errors
/// [`ProfileError::Empty`] for an empty profile; [`ProfileError::TooFewPoints`] for a path of
/// fewer than 2 points (3 closed); [`ProfileError::NonFinite`] naming a path point;
/// [`ProfileError::RepeatedPoint`] for two consecutive equal points;
/// [`ProfileError::SharpTurn`] naming the point where the path turns so sharply that the
/// profile would fold over itself (a side of the tube running backwards);
/// [`ProfileError::BadValue`] for a non-finite twist, a scale not positive, a scale on a closed
/// path, a zero or non-finite `up` or one along the path's start;
/// [`ProfileError::SelfCrossing`] naming the path point nearest where the tube passes through
/// itself.
pub fn sweep(profile: &Profile, path: &[Vec3], options: &SweepOptions) -> Result<Mesh, ProfileError> {
    profile.require_region("the profile to sweep")?;
    check_number("the twist", options.twist, false)?;
    let s = options.scale;
    if !(s.x.is_finite() && s.y.is_finite() && s.x > 0.0 && s.y > 0.0) {
        let value = if s.x.is_finite() && s.x > 0.0 { s.y } else { s.x };
        return Err(ProfileError::BadValue { name: "the end scale", value, expected: "positive in x and y" });
    }
    if options.closed && s != Vec2::ONE {
        return Err(ProfileError::BadValue {
            name: "the end scale of a closed path",
            value: if s.x != 1.0 { s.x } else { s.y },
            expected: "1 (a ring has no end)",
        });
    }
    if let Some(index) = path.iter().position(|p| !p.is_finite()) {
        return Err(ProfileError::NonFinite { what: "the path".into(), index });
    }
    let mut path = path.to_vec();
    if options.closed && path.len() > 1 && path[0] == path[path.len() - 1] {
        path.pop();
    }
    let needed = if options.closed { 3 } else { 2 };
    if path.len() < needed {
        return Err(ProfileError::TooFewPoints { what: "the path".into(), count: path.len(), needed });
    }
    let n = path.len();
    let segments = if options.closed { n } else { n - 1 };
    let mut dirs = Vec::with_capacity(segments);
    let mut lengths = Vec::with_capacity(segments);
    for i in 0..segments {
        let d = path[(i + 1) % n] - path[i];
        let len = d.length();
        if len == 0.0 || !len.is_finite() {
            return Err(ProfileError::RepeatedPoint { index: i });
        }
        dirs.push(d / len);
        lengths.push(len);
    }
    // Tangents: the bisector at inner points (and at every point of a ring), the segment at ends.
    let mut tangents = Vec::with_capacity(n);
    let mut stretch = Vec::with_capacity(n);
    for i in 0..n {
        let (before, after) = match (options.closed, i) {
            (false, 0) => (dirs[0], dirs[0]),
            (false, i) if i == n - 1 => (dirs[n - 2], dirs[n - 2]),
            (_, i) => (dirs[(i + segments - 1) % segments], dirs[i % segments]),
        };
        let sum = before + after;
        let turn = before.dot(after).clamp(-1.0, 1.0).acos().to_degrees();
        let Some(t) = sum.try_normalize().filter(|t| t.dot(after) > 1e-6) else {
            return Err(ProfileError::SharpTurn { index: i, degrees: turn });
        };
        // Across the bend (unit, perpendicular to t) and the stretch that puts the ring in the
        // mitre plane.
        let across = (after - before).try_normalize().unwrap_or(Vec3::ZERO);
        tangents.push(t);
        stretch.push((across, 1.0 / t.dot(after), turn));
    }
    // The first frame from `up`.
    let t0 = tangents[0];
    let up = match options.up {
        Some(up) => {
            if !up.is_finite() {
                return Err(ProfileError::NonFinite { what: "the up direction".into(), index: 0 });
            }
            up
        }
        None if t0.z.abs() < 0.999 => Vec3::Z,
        None => Vec3::Y,
    };
    let Some(b0) = (up - up.dot(t0) * t0).try_normalize() else {
        return Err(ProfileError::BadValue {
            name: "the up direction's part across the path",
            value: 0.0,
            expected: "non-zero (up must not be zero nor along the path's start)",
        });
    };
    let r0 = b0.cross(t0);
    // Segment frames (constant along each segment), then each point's frame on its tangent:
    // the segment before it carried halfway round the turn.
    let seg_r = frames::polyline(&dirs, r0);
    let mut r: Vec<Vec3> = (0..n)
        .map(|i| match (options.closed, i) {
            (false, 0) => seg_r[0],
            // A ring's first point takes the frame the chain starts with (the last segment's
            // comes back turned by the gap undone below).
            (true, 0) => frames::transport(seg_r[0], dirs[0], tangents[0]),
            (_, i) => {
                let before = (i + segments - 1) % segments;
                frames::transport(seg_r[before], dirs[before], tangents[i])
            }
        })
        .collect();
    // Arc length at each point, and the total.
    let mut arc = vec![0.0; n + 1];
    for i in 0..segments {
        arc[i + 1] = arc[i] + lengths[i];
    }
    let total = arc[segments];
    if options.closed {
        // The first segment's frame carried once round comes back turned by `gap` about its
        // direction: undo that gradually, by arc length.
        let back = frames::transport(seg_r[segments - 1], dirs[segments - 1], dirs[0]);
        let gap = dirs[0].dot(back.cross(seg_r[0])).atan2(back.dot(seg_r[0]));
        for i in 0..n {
            r[i] = Quat::from_axis_angle(tangents[i], gap * arc[i] / total) * r[i];
        }
    }
    // The rings.
    let contours = profile.contours();
    let per_ring = profile.point_count();
    check_solid_size(
        || format!("a sweep of {per_ring} points along {n} path points"),
        (per_ring * n) as f64,
        2.0 * (per_ring * n) as f64,
    )?;
    crate::limits::charge((per_ring * n) as u64)?;
    let mut positions = Vec::with_capacity(per_ring * n);
    for i in 0..n {
        let f = arc[i] / total;
        let (c, sn) = cos_sin_degrees(options.twist * f);
        let sc = Vec2::ONE + (s - Vec2::ONE) * f;
        let (t, ri) = (tangents[i], r[i]);
        let bi = t.cross(ri);
        let (across, k, _) = stretch[i];
        for q in contours.iter().flatten() {
            let q = *q * sc;
            let q = Vec2::new(c * q.x - sn * q.y, sn * q.x + c * q.y);
            let d = q.x * ri + q.y * bi;
            positions.push(path[i] + d + d.dot(across) * (k - 1.0) * across);
        }
    }
    // No side may run backwards along its segment.
    for seg in 0..segments {
        let (i, j) = (seg, (seg + 1) % n);
        for p in 0..per_ring {
            let a = (positions[i * per_ring + p] - path[i]).dot(dirs[seg]);
            let b = (positions[j * per_ring + p] - path[j]).dot(dirs[seg]);
            if lengths[seg] + b - a <= 1e-9 * lengths[seg] {
                let index = if a > -b { i } else { j };
                return Err(ProfileError::SharpTurn { index, degrees: stretch[index].2 });
            }
        }
    }
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let ring = |i: usize, p: usize| (i * per_ring + p) as u32;
    let mut start = 0;
    for c in contours {
        let len = c.len();
        for seg in 0..segments {
            let (i, j) = (seg, (seg + 1) % n);
            for p in 0..len {
                let (a, b) = (start + p, start + (p + 1) % len);
                faces.push([ring(i, a), ring(i, b), ring(j, b)]);
                faces.push([ring(i, a), ring(j, b), ring(j, a)]);
            }
        }
        start += len;
    }
    if !options.closed {
        for [a, b, c] in triangulate_contours(contours) {
            faces.push([c, b, a]);
            let last = ((n - 1) * per_ring) as u32;
            faces.push([a + last, b + last, c + last]);
        }
    }
    let mesh = Mesh::from_polygons(positions, &faces).map_err(mesh_error)?;
    refuse_self_crossing(&mesh, "the sweep", |at| format!("path point {}", nearest(path.iter().copied(), at)))?;
    Ok(mesh)
}
