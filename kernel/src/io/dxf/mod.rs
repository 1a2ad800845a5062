//! DXF (ASCII) for 2D profiles: written as closed R12 `POLYLINE`s; read from `LWPOLYLINE`,
//! `POLYLINE`, `LINE`, `ARC`, `CIRCLE`, `ELLIPSE` and `SPLINE` entities and the blocks `INSERT`
//! places.
//!
//! A DXF file is pairs of lines: a group code, then its value (AutoCAD DXF Reference, "DXF
//! Format"). The writer emits the smallest R12 (AC1009) file every reader takes: a header with
//! the version and an `ENTITIES` section, one closed `POLYLINE` per contour on layer `0`.
//!
//! Reading: closed polylines, circles, whole ellipses and closed splines are contours as they
//! are; open polylines, lines, arcs, partial ellipses and open splines are chained end to end
//! (ends within 1e-9 of the drawing's size join) and every chain that closes is a contour; what
//! does not close is left out. Arcs, bulges and ellipses become line segments, [`ARC_SEGMENTS`]
//! per full turn; a spline [`curves::SPLINE_SEGMENTS`] per knot span of its NURBS (exact on the
//! curve, rational ones included), or, given only fit points, a centripetal Catmull–Rom curve
//! through them. Entities in an entity coordinate system (an extrusion direction other than +z,
//! as mirrored arcs are written) are mapped to the drawing's. An `INSERT` (and a `MINSERT`
//! array) places its block's entities moved, rotated and scaled, blocks within blocks, with the
//! expansion counted before it is drawn ([`drawing`]). The region is the even-odd fill of all
//! contours — a loop inside another is a hole, as a laser cutter reads it. Paper-space entities,
//! `HATCH`, `TEXT`, `DIMENSION` and meshes are not read; z is dropped.

use std::io::Write;
use std::path::Path;

use super::IoError;
use crate::profile::{FillRule, Profile, Vec2};

mod chain;
pub mod curves;
pub mod drawing;
mod groups;
#[cfg(test)]
mod tests;

/// Segments per full turn of an arc, circle or bulge read.
pub const ARC_SEGMENTS: usize = 64;
/// The most points a file may produce (its inserts' placements counted as points).
pub const MAX_POINTS: usize = 50_000_000;

/// Writes `profile` as an R12 ASCII DXF: one closed `POLYLINE` per contour (outer contours
/// counter-clockwise, holes clockwise), coordinates as shortest round-trip decimals.
///
/// # Errors
/// The writer's errors.
pub fn write_dxf(profile: &Profile, w: &mut impl Write) -> std::io::Result<()> {
    let pair = |w: &mut dyn Write, code: u32, value: &str| writeln!(w, "{code:>3}\n{value}");
    pair(w, 0, "SECTION")?;
    pair(w, 2, "HEADER")?;
    pair(w, 9, "$ACADVER")?;
    pair(w, 1, "AC1009")?;
    pair(w, 0, "ENDSEC")?;
    pair(w, 0, "SECTION")?;
    pair(w, 2, "ENTITIES")?;
    for c in profile.contours() {
        pair(w, 0, "POLYLINE")?;
        pair(w, 8, "0")?;
        pair(w, 66, "1")?;
        pair(w, 10, "0.0")?;
        pair(w, 20, "0.0")?;
        pair(w, 30, "0.0")?;
        pair(w, 70, "1")?;
        for p in c {
            pair(w, 0, "VERTEX")?;
            pair(w, 8, "0")?;
            pair(w, 10, &format!("{:?}", p.x))?;
            pair(w, 20, &format!("{:?}", p.y))?;
            pair(w, 30, "0.0")?;
        }
        pair(w, 0, "SEQEND")?;
        pair(w, 8, "0")?;
    }
    pair(w, 0, "ENDSEC")?;
    pair(w, 0, "EOF")
}

/// [`write_dxf`] into a string.
#[must_use]
pub fn to_dxf(profile: &Profile) -> String {
    let mut out = Vec::new();
    // Writing to a vector cannot fail.
    let _ = write_dxf(profile, &mut out);
    String::from_utf8(out).unwrap_or_default()
}

/// A malformed-DXF error at `line` (0: the file as a whole).
pub(super) fn bad(path: &Path, line: usize, reason: impl Into<String>) -> IoError {
    IoError::Dxf { path: path.into(), line, reason: reason.into() }
}

/// Reads the region a DXF file draws (see the [module documentation](self)).
///
/// # Errors
/// [`IoError::Dxf`] naming the line: text that is not UTF-8, a group code that is not a number
/// or has no value, a coordinate that does not parse or is not finite, an entity missing a
/// coordinate, a spline that cannot be evaluated (saying why), blocks that place themselves,
/// nest deeper than [`drawing::MAX_DEPTH`] or refer to another file, more than [`MAX_POINTS`]
/// points (inserts expanded) or more than the memory budget, or no closed contour with area.
pub fn read_dxf(bytes: &[u8], path: &Path) -> Result<Profile, IoError> {
    let text = std::str::from_utf8(bytes).map_err(|e| bad(path, 0, format!("not UTF-8 text: {e}")))?;
    let groups = groups::groups(text, path)?;
    crate::limits::charge(groups.len() as u64).map_err(|e| bad(path, 0, e.to_string()))?;
    let entities = groups::entities(&groups);
    let mut closed: Vec<Vec<Vec2>> = Vec::new();
    let mut open: Vec<Vec<Vec2>> = Vec::new();
    for piece in drawing::pieces(&entities, path)? {
        if piece.closed {
            closed.push(piece.points);
        } else {
            open.push(piece.points);
        }
    }
    let size = closed
        .iter()
        .chain(&open)
        .flatten()
        .fold(None, |b: Option<(Vec2, Vec2)>, &p| Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p)))))
        .map_or(1.0, |(lo, hi)| (hi - lo).max_element().max(1e-300));
    closed.extend(chain::chain(open, 1e-9 * size));
    closed.retain(|c| c.len() >= 3);
    if closed.is_empty() {
        return Err(bad(path, 0, "no closed contour (closed polyline, circle, or lines and arcs joined end to end)"));
    }
    Profile::from_contours(&closed, FillRule::EvenOdd).map_err(|e| bad(path, 0, format!("the closed contours: {e}")))
}
