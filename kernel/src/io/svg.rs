//! SVG 1.1 for 2D profiles: written as one even-odd path, read from `path`, `polygon`,
//! `polyline`, `rect`, `circle` and `ellipse` elements with their `transform`s and those of
//! their groups.
//!
//! Axes: SVG's y points down, the kernel's up; y is negated on writing and on reading, so a
//! profile written and read back is the same region and a file looks in a browser as the
//! profile looks from above. One SVG user unit is one kernel unit (the writer declares
//! millimetres); units on lengths (`px`, `mm`) are ignored and the root `viewBox` does not
//! scale what is read.
//!
//! Reading (SVG 1.1 §8 paths, §9 basic shapes, §7.6 transforms, §5.6 `use`): every shape is a
//! filled region, whatever its `fill` or `stroke` (a laser-cut outline drawn with `fill="none"`
//! still counts); a path's subpaths fill by its `fill-rule` (attribute, `style`, or inherited
//! from its groups; `nonzero` by default) and unclosed subpaths close, as SVG fills them; the
//! shapes are then unioned, as painting them would. Curves become line segments: 16 per cubic or
//! quadratic Bézier, arcs (elliptical, SVG Appendix F.6.5's endpoint-to-centre conversion),
//! circles and rounded rectangle corners (`rx`, `ry`) 64 per full turn. A `<use>` draws the
//! element it names (`href` or `xlink:href`, `#id` in the same document) moved by its `x`, `y`
//! and `transform`, inheriting the `use`'s fill rule, including `symbol`s and what `defs` holds
//! (a `symbol`'s `viewBox` does not scale it); the expansion of references of references is
//! counted before anything is drawn and refused beyond [`MAX_DRAWN_ELEMENTS`], a reference to
//! itself or outside the document is refused, one to no element draws nothing (as browsers
//! do). Shapes inside `defs`, `clipPath`, `mask`, `symbol`, `pattern` and `marker` are not drawn
//! in place, nor elements with `display="none"` (attribute or style) and their content; `text`
//! and `image` are not read.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use quick_xml::events::{BytesStart, Event};

use super::IoError;
use crate::profile::{FillRule, Profile, ProfileError, Vec2};

/// Segments per cubic or quadratic Bézier segment read.
pub const CURVE_SEGMENTS: usize = 16;
/// Segments per full turn of an arc, circle or ellipse read.
pub const ARC_SEGMENTS: usize = 64;
/// The most points a file may produce (beyond it the file is refused, not truncated).
pub const MAX_POINTS: usize = 50_000_000;

/// The number as SVG wants it: shortest round-trip decimal, `-0` written `0`.
fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x}")
    }
}

/// Writes `profile` as an SVG document: one `path` with `fill-rule="evenodd"`, one subpath per
/// contour, y negated (see the [module documentation](self)); the `viewBox` is the profile's
/// bounds with a margin of 1 % of their size.
///
/// # Errors
/// The writer's errors.
pub fn write_svg(profile: &Profile, w: &mut impl Write) -> std::io::Result<()> {
    let (lo, hi) = profile.bounds().unwrap_or((Vec2::ZERO, Vec2::ONE));
    let size = (hi - lo).max(Vec2::splat(f64::MIN_POSITIVE));
    let margin = 0.01 * size.max_element();
    let (x0, y0) = (lo.x - margin, -hi.y - margin);
    let (wd, ht) = (size.x + 2.0 * margin, size.y + 2.0 * margin);
    writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#)?;
    writeln!(
        w,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{}mm" height="{}mm" viewBox="{} {} {} {}">"#,
        num(wd),
        num(ht),
        num(x0),
        num(y0),
        num(wd),
        num(ht)
    )?;
    write!(w, r##"<path fill="#4a7fb5" stroke="none" fill-rule="evenodd" d=""##)?;
    for (i, c) in profile.contours().iter().enumerate() {
        if i > 0 {
            write!(w, " ")?;
        }
        for (j, p) in c.iter().enumerate() {
            write!(w, "{}{} {}", if j == 0 { "M" } else { " L" }, num(p.x), num(-p.y))?;
        }
        write!(w, " Z")?;
    }
    writeln!(w, r#""/>"#)?;
    writeln!(w, "</svg>")
}

/// [`write_svg`] into a string.
#[must_use]
pub fn to_svg(profile: &Profile) -> String {
    let mut out = Vec::new();
    // Writing to a vector cannot fail.
    let _ = write_svg(profile, &mut out);
    String::from_utf8(out).unwrap_or_default()
}

/// An affine map of the plane: x' = a·x + c·y + e, y' = b·x + d·y + f (SVG's `matrix(a b c d e
/// f)`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine([f64; 6]);

impl Affine {
    const IDENTITY: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// `self` after `then`... i.e. the map `p ↦ self(other(p))`.
    fn then(self, other: Affine) -> Affine {
        let [a, b, c, d, e, f] = self.0;
        let [a2, b2, c2, d2, e2, f2] = other.0;
        Affine([
            a * a2 + c * b2,
            b * a2 + d * b2,
            a * c2 + c * d2,
            b * c2 + d * d2,
            a * e2 + c * f2 + e,
            b * e2 + d * f2 + f,
        ])
    }

    fn apply(self, p: Vec2) -> Vec2 {
        let [a, b, c, d, e, f] = self.0;
        Vec2::new(a * p.x + c * p.y + e, b * p.x + d * p.y + f)
    }
}

/// A reading error.
fn bad(path: &Path, reason: impl Into<String>) -> IoError {
    IoError::Svg { path: path.into(), reason: reason.into() }
}

/// The numbers of an SVG number list (`"1,2 -3.5e1-4"`), `None` at the first malformed one.
fn numbers(s: &str) -> Option<Vec<f64>> {
    let mut lex = Lexer { s: s.as_bytes(), i: 0 };
    let mut out = Vec::new();
    loop {
        lex.skip_separators();
        if lex.i >= lex.s.len() {
            return Some(out);
        }
        out.push(lex.number()?);
    }
}

/// The leading number of a length (`"10"`, `"10px"`, `"2.5mm"`; the unit ignored).
fn length(s: &str) -> Option<f64> {
    let mut lex = Lexer { s: s.trim().as_bytes(), i: 0 };
    lex.number()
}

/// A scanner over path data and number lists (SVG 1.1 §8.3.9 grammar).
struct Lexer<'a> {
    s: &'a [u8],
    i: usize,
}

impl Lexer<'_> {
    fn skip_separators(&mut self) {
        while self.i < self.s.len() && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',') {
            self.i += 1;
        }
    }

    /// A number: sign? digits? ('.' digits)? (e sign? digits)?, at least one digit.
    fn number(&mut self) -> Option<f64> {
        self.skip_separators();
        let start = self.i;
        let s = self.s;
        let mut i = self.i;
        if i < s.len() && (s[i] == b'+' || s[i] == b'-') {
            i += 1;
        }
        let mut digits = 0;
        while i < s.len() && s[i].is_ascii_digit() {
            i += 1;
            digits += 1;
        }
        if i < s.len() && s[i] == b'.' {
            i += 1;
            while i < s.len() && s[i].is_ascii_digit() {
                i += 1;
                digits += 1;
            }
        }
        if digits == 0 {
            return None;
        }
        if i < s.len() && (s[i] == b'e' || s[i] == b'E') {
            let mut j = i + 1;
            if j < s.len() && (s[j] == b'+' || s[j] == b'-') {
                j += 1;
            }
            let exp_start = j;
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
            }
            if j > exp_start {
                i = j;
            }
        }
        self.i = i;
        std::str::from_utf8(&s[start..i]).ok()?.parse().ok()
    }

    /// An arc flag: `0` or `1`, which may run into the next number.
    fn flag(&mut self) -> Option<bool> {
        self.skip_separators();
        let c = *self.s.get(self.i)?;
        self.i += 1;
        match c {
            b'0' => Some(false),
            b'1' => Some(true),
            _ => None,
        }
    }

    /// The next command letter, if one comes next.
    fn command(&mut self) -> Option<u8> {
        self.skip_separators();
        let c = *self.s.get(self.i)?;
        if c.is_ascii_alphabetic() && c != b'e' && c != b'E' {
            self.i += 1;
            Some(c)
        } else {
            None
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip_separators();
        self.i >= self.s.len()
    }
}

/// Points of the elliptical arc from `p1` to `p2` (SVG 1.1 Appendix F.6.5), `p1` excluded.
fn arc(p1: Vec2, radii: Vec2, phi_deg: f64, large: bool, sweep: bool, p2: Vec2, out: &mut Vec<Vec2>) {
    let (mut rx, mut ry) = (radii.x.abs(), radii.y.abs());
    if rx == 0.0 || ry == 0.0 || p1 == p2 {
        out.push(p2);
        return;
    }
    let (s, c) = phi_deg.to_radians().sin_cos();
    let h = (p1 - p2) / 2.0;
    let (x1, y1) = (c * h.x + s * h.y, -s * h.x + c * h.y);
    let lambda = x1 * x1 / (rx * rx) + y1 * y1 / (ry * ry);
    if lambda > 1.0 {
        rx *= lambda.sqrt();
        ry *= lambda.sqrt();
    }
    let num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
    let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
    let mut coef = if den > 0.0 { (num / den).max(0.0).sqrt() } else { 0.0 };
    if large == sweep {
        coef = -coef;
    }
    let (cx1, cy1) = (coef * rx * y1 / ry, -coef * ry * x1 / rx);
    let m = (p1 + p2) / 2.0;
    let centre = Vec2::new(c * cx1 - s * cy1 + m.x, s * cx1 + c * cy1 + m.y);
    let u = Vec2::new((x1 - cx1) / rx, (y1 - cy1) / ry);
    let v = Vec2::new((-x1 - cx1) / rx, (-y1 - cy1) / ry);
    let theta1 = u.y.atan2(u.x);
    let mut delta = u.perp_dot(v).atan2(u.dot(v));
    if !sweep && delta > 0.0 {
        delta -= std::f64::consts::TAU;
    } else if sweep && delta < 0.0 {
        delta += std::f64::consts::TAU;
    }
    let n = ((delta.abs() / std::f64::consts::TAU * ARC_SEGMENTS as f64).ceil() as usize).max(2);
    for k in 1..n {
        let t = theta1 + delta * k as f64 / n as f64;
        let (st, ct) = t.sin_cos();
        out.push(Vec2::new(centre.x + rx * ct * c - ry * st * s, centre.y + rx * ct * s + ry * st * c));
    }
    out.push(p2);
}

/// The subpaths of SVG path data, each closed implicitly.
///
/// # Errors
/// A reason naming the position of the first malformed command or number.
fn path_data(d: &str) -> Result<Vec<Vec<Vec2>>, String> {
    let mut lex = Lexer { s: d.as_bytes(), i: 0 };
    let mut subpaths: Vec<Vec<Vec2>> = Vec::new();
    let mut cur: Vec<Vec2> = Vec::new();
    let (mut pos, mut start) = (Vec2::ZERO, Vec2::ZERO);
    // The last control point, for S/s and T/t reflections.
    let mut last_cubic: Option<Vec2> = None;
    let mut last_quad: Option<Vec2> = None;
    let mut cmd: Option<u8> = None;
    let malformed = |i: usize| format!("malformed path data at character {i}");
    while !lex.at_end() {
        let at = lex.i;
        let c = match lex.command() {
            Some(c) => c,
            // Implicit repetition of the previous command (a moveto repeats as a lineto).
            None => match cmd {
                Some(b'M') => b'L',
                Some(b'm') => b'l',
                Some(b'Z' | b'z') | None => return Err(malformed(at)),
                Some(c) => c,
            },
        };
        cmd = Some(c);
        let rel = c.is_ascii_lowercase();
        let base = if rel { pos } else { Vec2::ZERO };
        let mut n = || lex.number().ok_or_else(|| malformed(at));
        let (mut cubic, mut quad) = (None, None);
        match c.to_ascii_uppercase() {
            b'M' => {
                let p = base + Vec2::new(n()?, n()?);
                if cur.len() >= 3 {
                    subpaths.push(std::mem::take(&mut cur));
                }
                cur.clear();
                cur.push(p);
                (pos, start) = (p, p);
            }
            b'L' => {
                pos = base + Vec2::new(n()?, n()?);
                cur.push(pos);
            }
            b'H' => {
                pos = Vec2::new(if rel { pos.x } else { 0.0 } + n()?, pos.y);
                cur.push(pos);
            }
            b'V' => {
                pos = Vec2::new(pos.x, if rel { pos.y } else { 0.0 } + n()?);
                cur.push(pos);
            }
            b'C' | b'S' => {
                let c1 = if c.eq_ignore_ascii_case(&b'C') {
                    base + Vec2::new(n()?, n()?)
                } else {
                    last_cubic.map_or(pos, |q| 2.0 * pos - q)
                };
                let c2 = base + Vec2::new(n()?, n()?);
                let p = base + Vec2::new(n()?, n()?);
                for k in 1..=CURVE_SEGMENTS {
                    let t = k as f64 / CURVE_SEGMENTS as f64;
                    let u = 1.0 - t;
                    cur.push(u * u * u * pos + 3.0 * u * u * t * c1 + 3.0 * u * t * t * c2 + t * t * t * p);
                }
                cubic = Some(c2);
                pos = p;
            }
            b'Q' | b'T' => {
                let q = if c.eq_ignore_ascii_case(&b'Q') {
                    base + Vec2::new(n()?, n()?)
                } else {
                    last_quad.map_or(pos, |q| 2.0 * pos - q)
                };
                let p = base + Vec2::new(n()?, n()?);
                for k in 1..=CURVE_SEGMENTS {
                    let t = k as f64 / CURVE_SEGMENTS as f64;
                    let u = 1.0 - t;
                    cur.push(u * u * pos + 2.0 * u * t * q + t * t * p);
                }
                quad = Some(q);
                pos = p;
            }
            b'A' => {
                let radii = Vec2::new(n()?, n()?);
                let phi = n()?;
                let large = lex.flag().ok_or_else(|| malformed(at))?;
                let sweep = lex.flag().ok_or_else(|| malformed(at))?;
                let mut n = || lex.number().ok_or_else(|| malformed(at));
                let p = base + Vec2::new(n()?, n()?);
                arc(pos, radii, phi, large, sweep, p, &mut cur);
                pos = p;
            }
            b'Z' => {
                if cur.len() >= 3 {
                    subpaths.push(std::mem::take(&mut cur));
                }
                cur.clear();
                cur.push(start);
                pos = start;
            }
            _ => return Err(format!("unknown path command `{}` at character {at}", c as char)),
        }
        (last_cubic, last_quad) = (cubic, quad);
        if cur.len() + subpaths.len() > MAX_POINTS {
            return Err(format!("the path has more than {MAX_POINTS} points"));
        }
    }
    if cur.len() >= 3 {
        subpaths.push(cur);
    }
    Ok(subpaths)
}

/// A `transform` attribute (SVG 1.1 §7.6): a list of `matrix`, `translate`, `scale`, `rotate`,
/// `skewX`, `skewY`, applied right to left.
fn transform(s: &str) -> Option<Affine> {
    let mut m = Affine::IDENTITY;
    let mut rest = s.trim();
    while !rest.is_empty() {
        let open = rest.find('(')?;
        let close = open + rest[open..].find(')')?;
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let a = numbers(&rest[open + 1..close])?;
        let t = match (name, a.as_slice()) {
            ("matrix", &[a, b, c, d, e, f]) => Affine([a, b, c, d, e, f]),
            ("translate", &[x]) => Affine([1.0, 0.0, 0.0, 1.0, x, 0.0]),
            ("translate", &[x, y]) => Affine([1.0, 0.0, 0.0, 1.0, x, y]),
            ("scale", &[x]) => Affine([x, 0.0, 0.0, x, 0.0, 0.0]),
            ("scale", &[x, y]) => Affine([x, 0.0, 0.0, y, 0.0, 0.0]),
            ("rotate", &[r]) | ("rotate", &[r, _, _]) => {
                let (s, c) = r.to_radians().sin_cos();
                let rot = Affine([c, s, -s, c, 0.0, 0.0]);
                if let &[_, cx, cy] = a.as_slice() {
                    Affine([1.0, 0.0, 0.0, 1.0, cx, cy]).then(rot).then(Affine([1.0, 0.0, 0.0, 1.0, -cx, -cy]))
                } else {
                    rot
                }
            }
            ("skewX", &[r]) => Affine([1.0, 0.0, r.to_radians().tan(), 1.0, 0.0, 0.0]),
            ("skewY", &[r]) => Affine([1.0, r.to_radians().tan(), 0.0, 1.0, 0.0, 0.0]),
            _ => return None,
        };
        m = m.then(t);
        rest = rest[close + 1..].trim_start_matches([',', ' ', '\t', '\n', '\r']);
    }
    Some(m)
}

/// An element's attributes by local name, with `style` declarations (`fill-rule: evenodd`)
/// folded in after them.
fn attributes(e: &BytesStart, path: &Path) -> Result<Vec<(String, String)>, IoError> {
    let mut out: Vec<(String, String)> = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| bad(path, format!("invalid XML attribute: {err}")))?;
        out.push((a.key.local_name().as_ref().to_owned(), a.value.into_owned()));
    }
    let style: Vec<(String, String)> = out
        .iter()
        .filter(|(k, _)| k == "style")
        .flat_map(|(_, v)| {
            v.split(';').filter_map(|d| d.split_once(':')).map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
        })
        .collect();
    out.extend(style);
    Ok(out)
}

fn get<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs.iter().rev().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// What a group passes to its children.
#[derive(Clone, Copy)]
struct Inherited {
    transform: Affine,
    fill: FillRule,
}

/// One element of the document, as read.
struct Element {
    name: String,
    attrs: Vec<(String, String)>,
    children: Vec<usize>,
}

/// The most `<use>`-expanded elements a document may draw: references of references multiply
/// (ten `<use>`s of a group of ten `<use>`s, twelve deep, draw 10¹² shapes from a kilobyte),
/// so the expansion is counted before anything is drawn.
pub const MAX_DRAWN_ELEMENTS: u64 = 1_000_000;
/// The deepest nesting of elements (and of `<use>` references) read; libxml2 refuses beyond 256.
pub const MAX_DEPTH: usize = 256;

/// Containers whose content is drawn only through a `<use>` (or not at all).
fn is_not_drawn_in_place(name: &str) -> bool {
    matches!(name, "defs" | "clipPath" | "mask" | "symbol" | "pattern" | "marker")
}

/// The document's elements in order, the root's children (index 0 is a virtual root).
fn elements(bytes: &[u8], path: &Path) -> Result<Vec<Element>, IoError> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    let mut buf = Vec::new();
    let mut all = vec![Element { name: String::new(), attrs: Vec::new(), children: Vec::new() }];
    let mut open: Vec<usize> = vec![0];
    loop {
        let event = reader
            .read_event_into(&mut buf)
            .map_err(|e| bad(path, format!("invalid XML at byte {}: {e}", reader.buffer_position())))?;
        let (e, empty) = match event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if open.len() > 1 {
                    open.pop();
                }
                buf.clear();
                continue;
            }
            Event::Eof => break,
            _ => {
                buf.clear();
                continue;
            }
        };
        let name = e.local_name().as_ref().to_owned();
        let attrs = attributes(&e, path)?;
        let id = all.len();
        all.push(Element { name, attrs, children: Vec::new() });
        let parent = *open.last().unwrap_or(&0);
        all[parent].children.push(id);
        if !empty {
            if open.len() > MAX_DEPTH {
                return Err(bad(path, format!("elements are nested more than {MAX_DEPTH} deep")));
            }
            open.push(id);
        }
        buf.clear();
    }
    Ok(all)
}

/// Whether an element is hidden with its content (`display="none"`, as attribute or style).
fn displayed(e: &Element) -> bool {
    get(&e.attrs, "display") != Some("none")
}

/// What a `<use>` draws: the element its `href` (or `xlink:href`) names in this document.
/// `Ok(None)` for a reference to no element (drawn as nothing, as browsers do).
fn use_target(e: &Element, ids: &HashMap<&str, usize>, path: &Path) -> Result<Option<usize>, IoError> {
    let Some(href) = get(&e.attrs, "href") else { return Ok(None) };
    match href.trim().strip_prefix('#') {
        Some(id) => Ok(ids.get(id).copied()),
        None => Err(bad(
            path,
            format!("<use> refers to `{href:.60}` outside the document: only references within it (`#id`) are read"),
        )),
    }
}

/// How many elements drawing `node` draws, `<use>` references expanded (memoised per element,
/// so a document of references of references is counted in time linear in its size).
fn drawn_count(
    all: &[Element],
    ids: &HashMap<&str, usize>,
    node: usize,
    memo: &mut [Option<u64>],
    active: &mut Vec<usize>,
    path: &Path,
) -> Result<u64, IoError> {
    if let Some(n) = memo[node] {
        return Ok(n);
    }
    if active.contains(&node) {
        return Err(bad(path, format!("<{}> refers to itself through `<use>`", all[node].name)));
    }
    if active.len() > MAX_DEPTH {
        return Err(bad(path, format!("`<use>` references are nested more than {MAX_DEPTH} deep")));
    }
    active.push(node);
    let e = &all[node];
    let mut n = 1u64;
    if e.name == "use" {
        if let Some(t) = use_target(e, ids, path)? {
            n = n.saturating_add(drawn_count(all, ids, t, memo, active, path)?);
        }
    }
    for &c in &e.children {
        n = n.saturating_add(drawn_count(all, ids, c, memo, active, path)?);
    }
    active.pop();
    memo[node] = Some(n);
    Ok(n)
}

/// Reads the region an SVG document draws (see the [module documentation](self)).
///
/// # Errors
/// [`IoError::Svg`] for malformed XML, a malformed path, number list or transform (naming the
/// element), non-finite coordinates, more than [`MAX_POINTS`] points, `<use>` references that
/// refer to themselves, leave the document, or expand to more than [`MAX_DRAWN_ELEMENTS`]
/// elements, nesting deeper than [`MAX_DEPTH`], or a document that draws no region with area.
pub fn read_svg(bytes: &[u8], path: &Path) -> Result<Profile, IoError> {
    let all = elements(bytes, path)?;
    if !all.iter().any(|e| e.name == "svg") {
        return Err(bad(path, "no <svg> element: not an SVG document"));
    }
    let ids: HashMap<&str, usize> =
        all.iter().enumerate().rev().filter_map(|(i, e)| get(&e.attrs, "id").map(|id| (id, i))).collect();
    let mut memo = vec![None; all.len()];
    let drawn = drawn_count(&all, &ids, 0, &mut memo, &mut Vec::new(), path)?;
    if drawn > MAX_DRAWN_ELEMENTS {
        return Err(bad(
            path,
            format!(
                "its `<use>` references expand to {drawn} elements, more than the {MAX_DRAWN_ELEMENTS} a document may draw"
            ),
        ));
    }
    let mut drawing = Drawing { all: &all, ids: &ids, path, shapes: Vec::new(), points: 0 };
    let root = Inherited { transform: Affine::IDENTITY, fill: FillRule::NonZero };
    for &c in &all[0].children {
        drawing.draw(c, root, 0)?;
    }
    let region = Profile::union_all(&drawing.shapes);
    if region.is_empty() {
        return Err(bad(path, "the document draws no region with area (no closed path, polygon or shape)"));
    }
    Ok(region)
}

/// The walk that draws a document's elements into regions.
struct Drawing<'a> {
    all: &'a [Element],
    ids: &'a HashMap<&'a str, usize>,
    path: &'a Path,
    shapes: Vec<Profile>,
    points: usize,
}

impl Drawing<'_> {
    /// Draws element `node` and its content under what its parent passes. `depth` counts
    /// elements and references (bounded by the counts checked before drawing).
    fn draw(&mut self, node: usize, parent: Inherited, depth: usize) -> Result<(), IoError> {
        let e = &self.all[node];
        if !displayed(e) || is_not_drawn_in_place(&e.name) {
            return Ok(());
        }
        self.draw_content(node, parent, depth)
    }

    /// Draws `node` whether or not it is drawn in place (a `<use>` target inside `defs`, a
    /// `symbol`).
    fn draw_content(&mut self, node: usize, parent: Inherited, depth: usize) -> Result<(), IoError> {
        let (all, path) = (self.all, self.path);
        let e = &all[node];
        if !displayed(e) {
            return Ok(());
        }
        if depth > 2 * MAX_DEPTH {
            return Err(bad(
                path,
                format!("elements and `<use>` references are nested more than {} deep", 2 * MAX_DEPTH),
            ));
        }
        let name = e.name.as_str();
        let own = match get(&e.attrs, "transform") {
            Some(t) => transform(t).ok_or_else(|| bad(path, format!("<{name}>: malformed transform `{t:.60}`")))?,
            None => Affine::IDENTITY,
        };
        let fill = match get(&e.attrs, "fill-rule") {
            Some("evenodd") => FillRule::EvenOdd,
            Some("nonzero") => FillRule::NonZero,
            _ => parent.fill,
        };
        let here = Inherited { transform: parent.transform.then(own), fill };
        self.add_shape(name, shape(name, &e.attrs, path)?, here)?;
        if name == "use" {
            // SVG 1.1 §5.6: the referenced element drawn as the `use`'s child, moved by (x, y).
            if let Some(target) = use_target(e, self.ids, path)? {
                let len = |key: &str| get(&e.attrs, key).and_then(length).unwrap_or(0.0);
                let moved = Affine([1.0, 0.0, 0.0, 1.0, len("x"), len("y")]);
                let inner = Inherited { transform: here.transform.then(moved), fill };
                self.draw_content(target, inner, depth + 1)?;
            }
        }
        for &c in &e.children {
            self.draw(c, here, depth + 1)?;
        }
        Ok(())
    }

    /// Adds the region of one element's contours, placed and flipped to y up.
    fn add_shape(&mut self, name: &str, contours: Vec<Vec<Vec2>>, here: Inherited) -> Result<(), IoError> {
        if contours.is_empty() {
            return Ok(());
        }
        let path = self.path;
        // SVG's y down to the kernel's y up.
        let placed: Vec<Vec<Vec2>> = contours
            .into_iter()
            .map(|c| {
                c.into_iter()
                    .map(|p| {
                        let q = here.transform.apply(p);
                        Vec2::new(q.x, -q.y)
                    })
                    .collect()
            })
            .collect();
        self.points += placed.iter().map(Vec::len).sum::<usize>();
        if self.points > MAX_POINTS {
            return Err(bad(path, format!("the document has more than {MAX_POINTS} points")));
        }
        crate::limits::charge(placed.len() as u64 + 1).map_err(|e| bad(path, e.to_string()))?;
        if let Some(i) = placed.iter().flatten().position(|p| !p.is_finite()) {
            return Err(bad(path, format!("<{name}>: point {i} has a non-finite coordinate")));
        }
        // A shape enclosing nothing (a degenerate polygon) adds nothing.
        match Profile::from_contours(&placed, here.fill) {
            Ok(p) => self.shapes.push(p),
            Err(ProfileError::ZeroArea { .. } | ProfileError::TooFewPoints { .. }) => {}
            Err(e) => return Err(bad(path, format!("<{name}>: {e}"))),
        }
        Ok(())
    }
}

/// The contours of one element in its own coordinates (none for elements that are not
/// shapes).
fn shape(name: &str, attrs: &[(String, String)], path: &Path) -> Result<Vec<Vec<Vec2>>, IoError> {
    let len = |key: &str| -> Result<f64, IoError> {
        match get(attrs, key) {
            None => Ok(0.0),
            Some(v) => length(v).ok_or_else(|| bad(path, format!("<{name}>: `{key}` = `{v:.40}` is not a length"))),
        }
    };
    let ellipse = |c: Vec2, r: Vec2| -> Vec<Vec<Vec2>> {
        if r.x <= 0.0 || r.y <= 0.0 {
            return Vec::new();
        }
        vec![(0..ARC_SEGMENTS)
            .map(|k| {
                let (s, co) = (std::f64::consts::TAU * k as f64 / ARC_SEGMENTS as f64).sin_cos();
                c + Vec2::new(r.x * co, r.y * s)
            })
            .collect()]
    };
    Ok(match name {
        "path" => match get(attrs, "d") {
            None => Vec::new(),
            Some(d) => path_data(d).map_err(|reason| bad(path, format!("<path>: {reason}")))?,
        },
        "polygon" | "polyline" => {
            let pts = get(attrs, "points").unwrap_or("");
            let n = numbers(pts).ok_or_else(|| bad(path, format!("<{name}>: malformed points `{pts:.40}`")))?;
            // An odd count drops the last number, as SVG renderers do.
            vec![n.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])).collect()]
        }
        "rect" => {
            let (x, y, w, h) = (len("x")?, len("y")?, len("width")?, len("height")?);
            // Corner radii (SVG 1.1 §9.2): one given stands for both, negative ones are ignored,
            // and each is at most half its side.
            let given = |key: &str| -> Result<Option<f64>, IoError> {
                Ok(if get(attrs, key).is_some_and(|v| v.trim() != "auto") { Some(len(key)?) } else { None })
            };
            let (rx, ry) = match (given("rx")?.filter(|r| *r >= 0.0), given("ry")?.filter(|r| *r >= 0.0)) {
                (Some(rx), Some(ry)) => (rx, ry),
                (Some(r), None) | (None, Some(r)) => (r, r),
                (None, None) => (0.0, 0.0),
            };
            let (rx, ry) = (rx.min(w / 2.0), ry.min(h / 2.0));
            if w <= 0.0 || h <= 0.0 {
                Vec::new()
            } else if rx > 0.0 && ry > 0.0 {
                rounded_rect(Vec2::new(x, y), Vec2::new(w, h), Vec2::new(rx, ry))
            } else {
                vec![vec![Vec2::new(x, y), Vec2::new(x + w, y), Vec2::new(x + w, y + h), Vec2::new(x, y + h)]]
            }
        }
        "circle" => {
            let r = len("r")?;
            ellipse(Vec2::new(len("cx")?, len("cy")?), Vec2::splat(r))
        }
        "ellipse" => ellipse(Vec2::new(len("cx")?, len("cy")?), Vec2::new(len("rx")?, len("ry")?)),
        _ => Vec::new(),
    })
}

/// A rectangle at `corner` of `size` with elliptical corners of radii `r`: a quarter of
/// [`ARC_SEGMENTS`] per corner, the straight sides between them.
fn rounded_rect(corner: Vec2, size: Vec2, r: Vec2) -> Vec<Vec<Vec2>> {
    let quarter = ARC_SEGMENTS / 4;
    let centres = [
        Vec2::new(corner.x + size.x - r.x, corner.y + r.y),
        Vec2::new(corner.x + size.x - r.x, corner.y + size.y - r.y),
        Vec2::new(corner.x + r.x, corner.y + size.y - r.y),
        Vec2::new(corner.x + r.x, corner.y + r.y),
    ];
    let mut out = Vec::with_capacity(4 * (quarter + 1));
    for (k, c) in centres.iter().enumerate() {
        for j in 0..=quarter {
            let angle = std::f64::consts::FRAC_PI_2 * (k as f64 - 1.0 + j as f64 / quarter as f64);
            let (s, co) = angle.sin_cos();
            out.push(*c + Vec2::new(r.x * co, r.y * s));
        }
    }
    // Where a radius is half the side, neighbouring arcs meet: drop the repeated points.
    out.dedup_by(|a, b| (*a - *b).length() <= 1e-12 * (1.0 + b.length()));
    if out.len() > 1 && (out[0] - out[out.len() - 1]).length() <= 1e-12 * (1.0 + out[0].length()) {
        out.pop();
    }
    vec![out]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::FillRule;

    fn read(s: &str) -> Result<Profile, IoError> {
        read_svg(s.as_bytes(), Path::new("t.svg"))
    }

    /// Regions pass through the engine's 1e-8 grid: areas agree to about 1e-8 of their size.
    #[track_caller]
    fn near(a: f64, b: f64, tol: f64) {
        assert!((a - b).abs() <= tol, "{a} vs {b}: difference {}", (a - b).abs());
    }

    #[test]
    fn a_written_profile_reads_back_as_the_same_region() {
        // A square with a hole and an island: every contour exact (shortest decimals round-trip).
        let outer = Profile::rect(Vec2::new(0.0, 0.0), Vec2::new(10.0, 8.0)).unwrap();
        let hole = Profile::rect(Vec2::new(2.0, 2.0), Vec2::new(8.0, 6.0)).unwrap();
        let island = Profile::circle(1.0, 16).unwrap().translate(Vec2::new(5.0, 4.0)).unwrap();
        let p = outer.difference(&hole).union(&island);
        let back = read(&to_svg(&p)).unwrap();
        near(back.area(), p.area(), 1e-7);
        assert_eq!(back.contours().len(), 3);
        assert_eq!(back.bounds(), p.bounds());
    }

    #[test]
    fn path_commands_relative_and_absolute_draw_the_same_square() {
        // Each draws the 10×10 square with corners (0,0) and (10,10) in SVG space.
        for d in ["M0 0 L10 0 L10 10 L0 10 Z", "m0,0 h10 v10 h-10 z", "M0,0H10V10H0", "M0-0 10 0 10 10 0 10z"] {
            let p = read(&format!(r#"<svg><path d="{d}"/></svg>"#)).unwrap();
            near(p.area(), 100.0, 1e-7);
            assert_eq!(p.bounds(), Some((Vec2::new(0.0, -10.0), Vec2::new(10.0, 0.0))), "{d}: y negated");
        }
    }

    #[test]
    fn arcs_and_curves_are_flattened_close_to_their_areas() {
        // Two half-circle arcs of radius 5: the 64-gon's area (n/2)·r²·sin(2π/n).
        let p = read(r#"<svg><path d="M0 0 A5 5 0 0 1 10 0 A5 5 0 0 1 0 0 Z"/></svg>"#).unwrap();
        let n = ARC_SEGMENTS as f64;
        near(p.area(), n / 2.0 * 25.0 * (std::f64::consts::TAU / n).sin(), 1e-7);
        // A quadratic from (0,0) via (5,10) to (10,0), closed: the parabola's area 2/3·10·5.
        let q = read(r#"<svg><path d="M0 0 Q5 10 10 0 Z"/></svg>"#).unwrap();
        near(q.area(), 200.0 / 6.0, 0.2);
        // Arc radii too small are scaled up (F.6.6): a half circle on the chord.
        let h = read(r#"<svg><path d="M0 0 A1 1 0 0 0 4 0 Z"/></svg>"#).unwrap();
        near(h.area(), std::f64::consts::PI * 2.0, 0.02);
    }

    #[test]
    fn basic_shapes_transforms_and_fill_rules() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg">
            <g transform="translate(100 0) scale(2)">
              <rect x="0" y="0" width="3" height="2" fill="none" stroke="black"/>
            </g>
            <g transform="rotate(90)"><polygon points="0,0 1,0 1,1 0,1"/></g>
            <defs><rect width="50" height="50"/></defs>
            <path fill-rule="evenodd" d="M20 0 h6 v6 h-6 z M22 2 h2 v2 h-2 z"/>
            <path style="fill-rule:nonzero" d="M40 0 h6 v6 h-6 z M42 2 h2 v2 h-2 z"/>
            <circle cx="0" cy="50" r="2"/>
            <line x1="0" y1="0" x2="5" y2="5"/>
          </svg>"#;
        let p = read(svg).unwrap();
        let disc = ARC_SEGMENTS as f64 / 2.0 * 4.0 * (std::f64::consts::TAU / ARC_SEGMENTS as f64).sin();
        // 6×4 rect (scaled), unit square, 36 − 4 even-odd, 36 non-zero (same-way inner square), disc.
        near(p.area(), 24.0 + 1.0 + 32.0 + 36.0 + disc, 1e-7);
        let (lo, hi) = p.bounds().unwrap();
        assert_eq!((lo.x, hi.x), (-2.0, 106.0));
        // SVG y from 0 (the top of everything) to 52 (the circle's bottom), negated.
        assert_eq!((lo.y, hi.y), (-52.0, 0.0));
    }

    #[test]
    fn use_draws_what_it_names_moved_and_symbols_and_defs_through_it() {
        // A 2×1 rect in defs drawn twice by `use` (moved by x, and by a transform), a symbol's
        // even-odd square with a hole drawn once (the fill rule is the symbol's own), a hidden
        // group, and a dangling reference: 2 + 2 + (16 − 4).
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink">
            <defs><rect id="bar" width="2" height="1"/></defs>
            <symbol id="frame"><path fill-rule="evenodd" d="M0 0 h4 v4 h-4 z M1 1 h2 v2 h-2 z"/></symbol>
            <use href="#bar" x="10"/>
            <use xlink:href="#bar" transform="translate(0 20)"/>
            <use href="#frame" x="30" y="30"/>
            <g style="display:none"><rect width="100" height="100"/></g>
            <use href="#nothing"/>
          </svg>"##;
        let p = read(svg).unwrap();
        near(p.area(), 2.0 + 2.0 + 12.0, 1e-7);
        let (lo, hi) = p.bounds().unwrap();
        assert_eq!((lo.x, hi.x), (0.0, 34.0));
        assert_eq!((lo.y, hi.y), (-34.0, 0.0));
        // A `use` of a `use`: the moves compose.
        let nested = read(
            r##"<svg><rect id="a" width="1" height="1"/><use id="b" href="#a" x="5"/><use href="#b" y="5"/></svg>"##,
        )
        .unwrap();
        near(nested.area(), 3.0, 1e-9);
        assert_eq!(nested.bounds().unwrap(), (Vec2::new(0.0, -6.0), Vec2::new(6.0, 0.0)));
    }

    #[test]
    fn rounded_rectangles_take_their_corner_radii() {
        // Four quarter-ellipse corners of 16 segments each in a 10×6 rect.
        let polygon_quarters = |rx: f64, ry: f64| 32.0 * rx * ry * (std::f64::consts::PI / 32.0).sin();
        for (attrs, rx, ry) in [
            (r#"rx="2" ry="1""#, 2.0, 1.0),
            (r#"rx="2""#, 2.0, 2.0),
            (r#"ry="1.5""#, 1.5, 1.5),
            (r#"rx="9" ry="9""#, 5.0, 3.0),
            (r#"rx="-1" ry="2""#, 2.0, 2.0),
        ] {
            let p = read(&format!(r#"<svg><rect width="10" height="6" {attrs}/></svg>"#)).unwrap();
            near(p.area(), 60.0 - 4.0 * rx * ry + polygon_quarters(rx, ry), 1e-7);
            assert_eq!(p.bounds().unwrap(), (Vec2::new(0.0, -6.0), Vec2::new(10.0, 0.0)), "{attrs}");
        }
        // A pill: radii half the sides meet without repeating a point.
        let pill = read(r#"<svg><rect width="4" height="4" rx="2"/></svg>"#).unwrap();
        assert_eq!(pill.contours()[0].len(), ARC_SEGMENTS);
    }

    #[test]
    fn use_references_that_loop_multiply_or_leave_the_file_are_refused() {
        // Ten uses of a group of ten uses of …, twelve deep, from under 2 KB: 10¹² shapes.
        let mut svg = String::from(r#"<svg><defs><rect id="l0" width="1" height="1"/>"#);
        for level in 1..=12 {
            svg += &format!(r#"<g id="l{level}">"#);
            for k in 0..10 {
                svg += &format!(r##"<use href="#l{}" x="{k}"/>"##, level - 1);
            }
            svg += "</g>";
        }
        svg += r##"</defs><use href="#l12"/></svg>"##;
        assert!(svg.len() < 4000);
        let e = read(&svg).unwrap_err().to_string();
        assert!(e.contains("expand to") && e.contains("more than the 1000000"), "{e}");
        for (svg, reason) in [
            (r##"<svg><g id="a"><use href="#a"/></g></svg>"##, "refers to itself"),
            (r##"<svg><use id="a" href="#b"/><use id="b" href="#a"/></svg>"##, "refers to itself"),
            (r#"<svg><use href="other.svg#a"/></svg>"#, "outside the document"),
        ] {
            let e = read(svg).unwrap_err().to_string();
            assert!(e.contains(reason), "{svg}: {e}");
        }
        let deep = format!("<svg>{}<rect width=\"1\" height=\"1\"/>{}</svg>", "<g>".repeat(300), "</g>".repeat(300));
        assert!(read(&deep).unwrap_err().to_string().contains("nested more than 256 deep"));
    }

    #[test]
    fn malformed_documents_are_refused_with_a_reason() {
        for (svg, reason) in [
            ("<svg><path d=\"M0 0 L10\"/></svg>", "<path>: malformed path data"),
            ("<svg><path d=\"M0 0 X1 1\"/></svg>", "<path>: unknown path command `X`"),
            ("<svg><g transform=\"spin(3)\"><rect width=\"1\" height=\"1\"/></g></svg>", "<g>: malformed transform"),
            ("<svg><rect width=\"1\" height=\"1\"/><line x2=\"1\"/></svg>", ""),
            ("<svg></svg>", "draws no region"),
            ("<html/>", "not an SVG document"),
            ("<svg><path d=\"M0 0 L1e400 0 L1 1 Z\"/></svg>", "non-finite"),
            (
                "<svg><path d=\"M0 0 L1e12 0 L1 1 Z\"/></svg>",
                "<path>: the polygon has a coordinate 1000000000000 at point 1, beyond",
            ),
            ("<svg><rect width=\"1\" height=\"1\"", "invalid XML"),
        ] {
            match read(svg) {
                Ok(p) => assert!(reason.is_empty() && p.area() == 1.0, "{svg} read"),
                Err(e) => assert!(!reason.is_empty() && e.to_string().contains(reason), "{svg}: {e}"),
            }
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic_or_hang() {
        // A fixed pseudo-random sequence of mutations of a valid document, and random bytes:
        // every read returns (a profile or an error).
        let base = to_svg(&Profile::polygon(&[Vec2::ZERO, Vec2::X, Vec2::ONE], FillRule::NonZero).unwrap())
            + r#"<svg><path d="M0 0 C1 2 3 4 5 0 S 1 1 2 2 Q 0 1 2 2 T 4 4 A 1 2 30 1 0 5 5 z"/></svg>"#;
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for round in 0..3000 {
            let mut bytes = base.clone().into_bytes();
            if round % 10 == 0 {
                bytes = (0..(next() % 200)).map(|_| (next() % 256) as u8).collect();
            } else {
                for _ in 0..(1 + next() % 6) {
                    let i = (next() as usize) % bytes.len().max(1);
                    match next() % 3 {
                        0 => {
                            let alphabet = b"0123456789.-+eMmLlHhVvCcSsQqTtAaZz <>/\"=,";
                            bytes[i] = alphabet[(next() % alphabet.len() as u64) as usize];
                        }
                        1 => {
                            bytes.truncate(i);
                        }
                        _ => bytes.insert(i, (next() % 128) as u8),
                    }
                    if bytes.is_empty() {
                        break;
                    }
                }
            }
            let _ = read_svg(&bytes, Path::new("fuzz.svg"));
        }
    }
}
