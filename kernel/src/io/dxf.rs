//! DXF (ASCII) for 2D profiles: written as closed R12 `POLYLINE`s, read from `LWPOLYLINE`,
//! `POLYLINE`, `LINE`, `ARC` and `CIRCLE` entities.
//!
//! A DXF file is pairs of lines: a group code, then its value (AutoCAD DXF Reference, "DXF
//! Format"). The writer emits the smallest R12 (AC1009) file every reader takes: a header with
//! the version and an `ENTITIES` section, one closed `POLYLINE` per contour on layer `0`.
//!
//! Reading: closed polylines are contours as they are; open polylines, lines and arcs are
//! chained end to end (ends within 1e-9 of the drawing's size join) and every chain that closes
//! is a contour; what does not close is left out. Polyline bulges (code 42) and arcs become
//! line segments, 64 per full turn. The region is the even-odd fill of all contours — a loop
//! inside another is a hole, as a laser cutter reads it. Entities in `BLOCKS` are not read
//! (nor `INSERT`s of them); `SPLINE`, `ELLIPSE`, `HATCH` and `TEXT` are ignored; z is dropped.

use std::io::Write;
use std::path::Path;

use super::IoError;
use crate::profile::{FillRule, Profile, Vec2};

/// Segments per full turn of an arc, circle or bulge read.
pub const ARC_SEGMENTS: usize = 64;
/// The most points a file may produce.
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

/// One group: its code, its value, and the 1-based line of the code.
struct Group<'a> {
    code: i32,
    value: &'a str,
    line: usize,
}

fn bad(path: &Path, line: usize, reason: impl Into<String>) -> IoError {
    IoError::Dxf { path: path.into(), line, reason: reason.into() }
}

/// The file's groups.
fn groups<'a>(text: &'a str, path: &Path) -> Result<Vec<Group<'a>>, IoError> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::with_capacity(lines.len() / 2);
    let mut i = 0;
    while i < lines.len() {
        let code_text = lines[i].trim();
        if code_text.is_empty() && i + 1 == lines.len() {
            break;
        }
        let code: i32 =
            code_text.parse().map_err(|_| bad(path, i + 1, format!("group code `{code_text:.20}` is not a number")))?;
        let Some(value) = lines.get(i + 1) else {
            return Err(bad(path, i + 1, format!("group code {code} has no value line")));
        };
        out.push(Group { code, value: value.trim(), line: i + 1 });
        i += 2;
    }
    Ok(out)
}

/// An entity's groups (those after its `0` group, up to the next `0`).
struct Entity<'a, 'g> {
    kind: &'a str,
    line: usize,
    groups: &'g [Group<'a>],
}

impl Entity<'_, '_> {
    /// The value of the first group `code`, as a number.
    fn number(&self, code: i32, path: &Path) -> Result<Option<f64>, IoError> {
        match self.groups.iter().find(|g| g.code == code) {
            None => Ok(None),
            Some(g) => parse(g, path).map(Some),
        }
    }

    fn required(&self, code: i32, path: &Path) -> Result<f64, IoError> {
        self.number(code, path)?.ok_or_else(|| bad(path, self.line, format!("{} has no group {code}", self.kind)))
    }

    fn flags(&self, path: &Path) -> Result<i64, IoError> {
        Ok(self.number(70, path)?.unwrap_or(0.0) as i64)
    }

    /// Vertices from repeated 10/20 groups with their bulges (42, after their vertex).
    fn vertices(&self, path: &Path) -> Result<Vec<(Vec2, f64)>, IoError> {
        let mut out: Vec<(Vec2, f64)> = Vec::new();
        let mut x = None;
        for g in self.groups {
            match g.code {
                10 => x = Some(parse(g, path)?),
                20 => {
                    let Some(px) = x.take() else { return Err(bad(path, g.line, "a y (20) without its x (10)")) };
                    out.push((Vec2::new(px, parse(g, path)?), 0.0));
                }
                42 => {
                    if let Some(last) = out.last_mut() {
                        last.1 = parse(g, path)?;
                    }
                }
                _ => {}
            }
        }
        Ok(out)
    }
}

fn parse(g: &Group, path: &Path) -> Result<f64, IoError> {
    let v: f64 = g.value.parse().map_err(|_| bad(path, g.line + 1, format!("`{:.30}` is not a number", g.value)))?;
    if !v.is_finite() {
        return Err(bad(path, g.line + 1, format!("`{:.30}` is not a finite number", g.value)));
    }
    Ok(v)
}

/// Points along the arc about `centre` of `radius` from angle `a0` turning `sweep` (radians,
/// counter-clockwise positive), the start excluded.
fn arc_points(centre: Vec2, radius: f64, a0: f64, sweep: f64, out: &mut Vec<Vec2>) {
    let n = ((sweep.abs() / std::f64::consts::TAU * ARC_SEGMENTS as f64).ceil() as usize).clamp(1, ARC_SEGMENTS);
    for k in 1..=n {
        let (s, c) = (a0 + sweep * k as f64 / n as f64).sin_cos();
        out.push(centre + radius * Vec2::new(c, s));
    }
}

/// A polyline's points with its bulges made arcs: the bulge of vertex i (tan of a quarter of
/// the arc's angle, counter-clockwise positive) bends the segment to vertex i + 1.
fn polyline(vertices: &[(Vec2, f64)], closed: bool) -> Vec<Vec2> {
    let n = vertices.len();
    let mut out = Vec::with_capacity(n);
    let Some(&(first, _)) = vertices.first() else { return out };
    out.push(first);
    let segments = if closed { n } else { n - 1 };
    for i in 0..segments {
        let ((p, bulge), (q, _)) = (vertices[i], vertices[(i + 1) % n]);
        let chord = q - p;
        let len = chord.length();
        if bulge != 0.0 && len > 0.0 {
            let theta = 4.0 * bulge.atan();
            let radius = len / (2.0 * (theta / 2.0).sin()).abs();
            let d = len / (2.0 * (theta / 2.0).tan());
            let centre = (p + q) / 2.0 + chord.perp() / len * d;
            let a0 = (p - centre).y.atan2((p - centre).x);
            arc_points(centre, radius, a0, theta, &mut out);
        } else {
            out.push(q);
        }
    }
    if closed {
        out.pop();
    }
    out
}

/// Open pieces chained end to end into closed contours (ends within `tol` join); pieces that do
/// not close are dropped. Ends are found through a grid of cells of side `tol` (the 3×3 cells
/// about an end hold every end within `tol`), so chaining is linear in the pieces.
fn chain(pieces: Vec<Vec<Vec2>>, tol: f64) -> Vec<Vec<Vec2>> {
    use std::collections::HashMap;
    let cell = |p: Vec2| ((p.x / tol).floor() as i64, (p.y / tol).floor() as i64);
    // Cell → (piece, whether it is the piece's last point).
    let mut ends: HashMap<(i64, i64), Vec<(usize, bool)>> = HashMap::new();
    for (k, p) in pieces.iter().enumerate() {
        ends.entry(cell(p[0])).or_default().push((k, false));
        ends.entry(cell(p[p.len() - 1])).or_default().push((k, true));
    }
    let mut used = vec![false; pieces.len()];
    let find = |at: Vec2, used: &[bool], ends: &HashMap<(i64, i64), Vec<(usize, bool)>>| {
        let (cx, cy) = cell(at);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &(k, last) in ends.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let p = &pieces[k];
                    let q = if last { p[p.len() - 1] } else { p[0] };
                    if !used[k] && q.distance(at) <= tol {
                        return Some((k, last));
                    }
                }
            }
        }
        None
    };
    let mut out = Vec::new();
    for first in 0..pieces.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let mut cur = pieces[first].clone();
        loop {
            let (start, end) = (cur[0], cur[cur.len() - 1]);
            if cur.len() > 2 && start.distance(end) <= tol {
                cur.pop();
                out.push(cur);
                break;
            }
            let Some((k, last)) = find(end, &used, &ends) else { break };
            used[k] = true;
            if last {
                cur.extend(pieces[k].iter().rev().skip(1));
            } else {
                cur.extend_from_slice(&pieces[k][1..]);
            }
        }
    }
    out
}

/// Reads the region a DXF file draws (see the [module documentation](self)).
///
/// # Errors
/// [`IoError::Dxf`] naming the line: text that is not UTF-8, a group code that is not a number
/// or has no value, a coordinate that does not parse or is not finite, an entity missing a
/// coordinate, more than [`MAX_POINTS`] points, or no closed contour with area.
pub fn read_dxf(bytes: &[u8], path: &Path) -> Result<Profile, IoError> {
    let text = std::str::from_utf8(bytes).map_err(|e| bad(path, 0, format!("not UTF-8 text: {e}")))?;
    let groups = groups(text, path)?;
    crate::limits::charge(groups.len() as u64).map_err(|e| bad(path, 0, e.to_string()))?;
    let mut closed: Vec<Vec<Vec2>> = Vec::new();
    let mut open: Vec<Vec<Vec2>> = Vec::new();
    let mut points = 0usize;
    let mut section = "";
    // The POLYLINE being read: its flags, line and vertices.
    let mut poly: Option<(bool, Vec<(Vec2, f64)>)> = None;
    let mut i = 0;
    while i < groups.len() {
        let g = &groups[i];
        if g.code != 0 {
            i += 1;
            continue;
        }
        let end = groups[i + 1..].iter().position(|h| h.code == 0).map_or(groups.len(), |k| i + 1 + k);
        let e = Entity { kind: g.value, line: g.line, groups: &groups[i + 1..end] };
        i = end;
        match e.kind {
            "SECTION" => {
                section = e.groups.iter().find(|h| h.code == 2).map_or("", |h| h.value);
                continue;
            }
            "ENDSEC" => {
                section = "";
                continue;
            }
            _ if section != "ENTITIES" => continue,
            _ => {}
        }
        let mut piece: Option<(bool, Vec<Vec2>)> = None;
        match e.kind {
            "LWPOLYLINE" => {
                let is_closed = e.flags(path)? & 1 == 1;
                piece = Some((is_closed, polyline(&e.vertices(path)?, is_closed)));
            }
            "POLYLINE" => poly = Some((e.flags(path)? & 1 == 1, Vec::new())),
            "VERTEX" => {
                if let Some((_, vs)) = poly.as_mut() {
                    let p = Vec2::new(e.required(10, path)?, e.required(20, path)?);
                    vs.push((p, e.number(42, path)?.unwrap_or(0.0)));
                }
            }
            "SEQEND" => {
                if let Some((is_closed, vs)) = poly.take() {
                    piece = Some((is_closed, polyline(&vs, is_closed)));
                }
            }
            "LINE" => {
                let a = Vec2::new(e.required(10, path)?, e.required(20, path)?);
                let b = Vec2::new(e.required(11, path)?, e.required(21, path)?);
                piece = Some((false, vec![a, b]));
            }
            "ARC" | "CIRCLE" => {
                let centre = Vec2::new(e.required(10, path)?, e.required(20, path)?);
                let r = e.required(40, path)?;
                if r > 0.0 {
                    let (a0, sweep) = if e.kind == "CIRCLE" {
                        (0.0, std::f64::consts::TAU)
                    } else {
                        let (a, b) = (e.required(50, path)?.to_radians(), e.required(51, path)?.to_radians());
                        let sweep = (b - a).rem_euclid(std::f64::consts::TAU);
                        (a, if sweep == 0.0 { std::f64::consts::TAU } else { sweep })
                    };
                    let mut pts = vec![centre + r * Vec2::new(a0.cos(), a0.sin())];
                    arc_points(centre, r, a0, sweep, &mut pts);
                    let full = e.kind == "CIRCLE";
                    if full {
                        pts.pop();
                    }
                    piece = Some((full, pts));
                }
            }
            _ => {}
        }
        if let Some((is_closed, pts)) = piece {
            points += pts.len();
            if points > MAX_POINTS {
                return Err(bad(path, e.line, format!("the drawing has more than {MAX_POINTS} points")));
            }
            if pts.len() >= 2 {
                if is_closed {
                    closed.push(pts)
                } else {
                    open.push(pts)
                }
            }
        }
    }
    let size = closed
        .iter()
        .chain(&open)
        .flatten()
        .fold(None, |b: Option<(Vec2, Vec2)>, &p| Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p)))))
        .map_or(1.0, |(lo, hi)| (hi - lo).max_element().max(1e-300));
    closed.extend(chain(open, 1e-9 * size));
    closed.retain(|c| c.len() >= 3);
    if closed.is_empty() {
        return Err(bad(path, 0, "no closed contour (closed polyline, circle, or lines and arcs joined end to end)"));
    }
    Profile::from_contours(&closed, FillRule::EvenOdd).map_err(|e| bad(path, 0, format!("the closed contours: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(s: &str) -> Result<Profile, IoError> {
        read_dxf(s.as_bytes(), Path::new("t.dxf"))
    }

    /// Regions pass through the engine's 1e-8 grid: areas agree to about 1e-8 of their size.
    #[track_caller]
    fn near(a: f64, b: f64, tol: f64) {
        assert!((a - b).abs() <= tol, "{a} vs {b}: difference {}", (a - b).abs());
    }

    /// A DXF from (code, value) pairs inside an ENTITIES section.
    fn entities(pairs: &[(i32, &str)]) -> String {
        let mut s = String::from("0\nSECTION\n2\nENTITIES\n");
        for (c, v) in pairs {
            s += &format!("{c}\n{v}\n");
        }
        s + "0\nENDSEC\n0\nEOF\n"
    }

    #[test]
    fn a_written_profile_reads_back_as_the_same_region() {
        let p = Profile::rect(Vec2::new(0.0, 0.0), Vec2::new(10.0, 8.0))
            .unwrap()
            .difference(&Profile::circle(2.0, 24).unwrap().translate(Vec2::new(5.0, 4.0)).unwrap());
        let back = read(&to_dxf(&p)).unwrap();
        assert_eq!(back.contours().len(), 2);
        near(back.area(), p.area(), 1e-7);
        assert_eq!(back.bounds(), p.bounds());
    }

    #[test]
    fn lines_and_arcs_joined_end_to_end_make_a_slot() {
        // A slot: two lines 10 long and two half circles of radius 1 at their ends, in any order
        // and direction: area 20 + the 64-gon's (each half has 32 segments).
        let dxf = entities(&[
            (0, "LINE"),
            (10, "0"),
            (20, "0"),
            (11, "10"),
            (21, "0"),
            (0, "ARC"),
            (10, "0"),
            (20, "1"),
            (40, "1"),
            (50, "90"),
            (51, "270"),
            (0, "LINE"),
            (10, "0"),
            (20, "2"),
            (11, "10"),
            (21, "2"),
            (0, "ARC"),
            (10, "10"),
            (20, "1"),
            (40, "1"),
            (50, "270"),
            (51, "90"),
        ]);
        let p = read(&dxf).unwrap();
        let n = ARC_SEGMENTS as f64;
        near(p.area(), 20.0 + n / 2.0 * (std::f64::consts::TAU / n).sin(), 1e-7);
    }

    #[test]
    fn an_lwpolyline_with_bulges_and_a_circle_inside_make_a_hole() {
        // A 4×2 rectangle whose right side bulges out in a half circle (bulge 1 = 180°), and a
        // circle of radius 0.5 inside it: even-odd makes the circle a hole.
        let dxf = entities(&[
            (0, "LWPOLYLINE"),
            (90, "4"),
            (70, "1"),
            (10, "0"),
            (20, "0"),
            (10, "4"),
            (20, "0"),
            (42, "1"),
            (10, "4"),
            (20, "2"),
            (10, "0"),
            (20, "2"),
            (0, "CIRCLE"),
            (10, "1"),
            (20, "1"),
            (40, "0.5"),
        ]);
        let p = read(&dxf).unwrap();
        let n = ARC_SEGMENTS as f64;
        let disc = |r: f64| n / 2.0 * r * r * (std::f64::consts::TAU / n).sin();
        near(p.area(), 8.0 + disc(1.0) / 2.0 - disc(0.5), 1e-7);
        assert_eq!(p.contours().len(), 2);
        assert_eq!(p.bounds().unwrap().1.x, 5.0, "the bulge reaches x = 4 + 1");
    }

    #[test]
    fn malformed_files_are_refused_naming_the_line() {
        for (dxf, reason) in [
            ("0\nSECTION\n2\nENTITIES\nxx\nLINE\n", ":5: malformed DXF: group code `xx` is not a number"),
            ("0\nSECTION\n2\nENTITIES\n0\n", "has no value line"),
            (
                &entities(&[(0, "LINE"), (10, "a"), (20, "0"), (11, "1"), (21, "1")]) as &str,
                ":8: malformed DXF: `a` is not a number",
            ),
            (&entities(&[(0, "LINE"), (10, "0"), (20, "0"), (11, "1")]), "LINE has no group 21"),
            (&entities(&[(0, "LINE"), (10, "0"), (20, "0"), (11, "1"), (21, "1")]), "no closed contour"),
            (&entities(&[(0, "CIRCLE"), (10, "1e999"), (20, "0"), (40, "1")]), "not a finite number"),
        ] {
            let e = read(dxf).unwrap_err().to_string();
            assert!(e.contains(reason), "{e}");
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic_or_hang() {
        let p = Profile::circle(1.0, 8).unwrap();
        let base = to_dxf(&p)
            + &entities(&[
                (0, "LWPOLYLINE"),
                (70, "1"),
                (10, "0"),
                (20, "0"),
                (42, "-2"),
                (10, "3"),
                (20, "0"),
                (10, "3"),
                (20, "3"),
            ]);
        let mut state = 0x243f_6a88_85a3_08d3_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for round in 0..3000 {
            let mut bytes = base.clone().into_bytes();
            if round % 10 == 0 {
                bytes = (0..(next() % 300))
                    .map(|_| b"0123456789.-e\n ABCDEFGHIJKLMNOPQRSTUVWXYZ"[(next() % 40) as usize])
                    .collect();
            } else {
                for _ in 0..(1 + next() % 6) {
                    let i = (next() as usize) % bytes.len().max(1);
                    match next() % 3 {
                        0 => bytes[i] = b"0123456789.-e\n"[(next() % 14) as usize],
                        1 => bytes.truncate(i),
                        _ => bytes.insert(i, (next() % 128) as u8),
                    }
                    if bytes.is_empty() {
                        break;
                    }
                }
            }
            let _ = read_dxf(&bytes, Path::new("fuzz.dxf"));
        }
    }

    /// Writes `target/peers/profile/plate.{dxf,svg}` (a plate with a bore, a slot and cut-out text) for the peer
    /// checks: `ezdxf` reads the DXF back (`kernel/benches/profile_peer.py dxf`), a browser
    /// renders the SVG. Run with `--ignored`.
    #[test]
    #[ignore = "writes sample files for the peers"]
    fn write_peer_samples() {
        let plate = Profile::rect(Vec2::new(0.0, 0.0), Vec2::new(40.0, 25.0)).unwrap().fillet(3.0, 32).unwrap();
        let bore = Profile::circle(5.0, 48).unwrap().translate(Vec2::new(12.0, 12.5)).unwrap();
        let slot = Profile::rect(Vec2::new(24.0, 10.0), Vec2::new(34.0, 15.0)).unwrap().fillet(2.4, 32).unwrap();
        let label = crate::profile::text(
            "blocksmith",
            &crate::profile::Font::bundled(),
            &crate::profile::TextOptions::DEFAULT.with_size(3.5),
        )
        .unwrap()
        .translate(Vec2::new(4.0, 3.0))
        .unwrap();
        let p = plate.difference(&bore).difference(&slot).difference(&label);
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/peers/profile");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("plate.dxf"), to_dxf(&p)).unwrap();
        std::fs::write(dir.join("plate.svg"), super::super::svg::to_svg(&p)).unwrap();
        let summary: Vec<String> =
            p.contours().iter().map(|c| format!("{} {:.12}", c.len(), crate::profile::contour_area(c))).collect();
        std::fs::write(dir.join("plate.txt"), summary.join("\n") + "\n").unwrap();
        println!("PROFILE_SAMPLE area={} contours={}", p.area(), p.contours().len());
    }
}
