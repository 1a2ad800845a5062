//! Text as a profile: the glyph outlines of a TrueType or OpenType font, shaped and laid out in
//! lines.
//!
//! Each line is ordered by the Unicode bidirectional algorithm (UAX #9, `unicode-bidi`) into runs
//! of one direction, and each run is shaped by `rustybuzz` (HarfBuzz's shaper in Rust): the
//! font's kerning (`GPOS` and `kern`), ligatures, the joined forms of Arabic and other scripts, and
//! mark placement come out as HarfBuzz and so OpenSCAD's `text` set them. Outlines come from
//! `ttf-parser` (TrueType quadratic and CFF cubic Béziers, each flattened into
//! [`TextOptions::segments`] line segments) and fill by the non-zero rule, as fonts are drawn;
//! each glyph is cleaned once, and only glyphs whose ink boxes meet are unioned (10,000
//! characters take milliseconds, not the seconds a union of the whole text takes). Sizes follow
//! OpenSCAD's `text`: the em square is `size / 0.72` (a size in points at 100 dpi), so capitals
//! stand about `size` tall. Each shaped advance is multiplied by `spacing`; a `\n` starts a new
//! line one line height (ascender − descender + line gap) lower. Characters the font lacks draw
//! its missing-glyph shape (glyph 0).
//!
//! The bundled font is DejaVu Sans 2.37 (Bitstream Vera licence, `kernel/assets/fonts/`), which
//! covers Latin, Greek, Cyrillic, Hebrew and Arabic among others.

use std::collections::HashMap;
use std::sync::Arc;

use rustybuzz::ttf_parser::{GlyphId, OutlineBuilder, Tag};
use rustybuzz::{Direction, Face, Feature, UnicodeBuffer};
use unicode_bidi::{BidiInfo, Level};

use super::convert::check_number;
use super::{Profile, ProfileError, Vec2};
use crate::profile::FillRule;

/// DejaVu Sans, embedded.
static BUNDLED: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// A font's data, checked to parse.
#[derive(Clone, Debug)]
pub struct Font {
    data: Arc<[u8]>,
}

impl Font {
    /// The bundled font, DejaVu Sans.
    #[must_use]
    pub fn bundled() -> Font {
        Font { data: Arc::from(BUNDLED) }
    }

    /// A font from the bytes of a TrueType (`.ttf`) or OpenType (`.otf`) file (the first face
    /// of a collection).
    ///
    /// # Errors
    /// [`ProfileError::Font`] when the data is not a font ttf-parser reads.
    pub fn from_bytes(data: Vec<u8>) -> Result<Font, ProfileError> {
        rustybuzz::ttf_parser::Face::parse(&data, 0).map_err(|e| ProfileError::Font { reason: e.to_string() })?;
        Ok(Font { data: Arc::from(data) })
    }

    /// The font's first face, for shaping and outlines (it parses: checked in the constructors).
    fn face(&self) -> Result<Face<'_>, ProfileError> {
        Face::from_slice(&self.data, 0)
            .ok_or_else(|| ProfileError::Font { reason: "the font has no face the shaper reads".into() })
    }
}

/// Where the text's lines stand across x = 0.
///
/// Default value: [`HAlign::Left`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HAlign {
    /// Each line starts at x = 0.
    #[default]
    Left,
    /// Each line's advance is centred on x = 0.
    Center,
    /// Each line ends (its last advance) at x = 0.
    Right,
}

/// Where the text stands across y = 0.
///
/// Default value: [`VAlign::Baseline`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VAlign {
    /// The first line's baseline on y = 0.
    #[default]
    Baseline,
    /// The lowest ink on y = 0.
    Bottom,
    /// The ink's vertical middle on y = 0.
    Center,
    /// The highest ink on y = 0.
    Top,
}

impl HAlign {
    /// The alignment by its name: `"left"`, `"center"` or `"right"`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<HAlign> {
        match name {
            "left" => Some(HAlign::Left),
            "center" => Some(HAlign::Center),
            "right" => Some(HAlign::Right),
            _ => None,
        }
    }
}

impl VAlign {
    /// The alignment by its name: `"baseline"`, `"bottom"`, `"center"` or `"top"`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<VAlign> {
        match name {
            "baseline" => Some(VAlign::Baseline),
            "bottom" => Some(VAlign::Bottom),
            "center" => Some(VAlign::Center),
            "top" => Some(VAlign::Top),
            _ => None,
        }
    }
}

/// The base direction of each line, which orders its runs of left-to-right and right-to-left
/// script (the paragraph level of the Unicode bidirectional algorithm, as CSS `direction`).
///
/// Default value: [`TextDirection::Auto`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TextDirection {
    /// From the line's first strong character (rule P2 of UAX #9); left to right if it has none.
    #[default]
    Auto,
    /// Left to right: runs of right-to-left script inside still read right to left.
    Ltr,
    /// Right to left: runs of left-to-right script inside still read left to right.
    Rtl,
}

impl TextDirection {
    /// The direction by its name: `"auto"`, `"ltr"` or `"rtl"`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<TextDirection> {
        match name {
            "auto" => Some(TextDirection::Auto),
            "ltr" => Some(TextDirection::Ltr),
            "rtl" => Some(TextDirection::Rtl),
            _ => None,
        }
    }

    fn paragraph_level(self) -> Option<Level> {
        match self {
            TextDirection::Auto => None,
            TextDirection::Ltr => Some(Level::ltr()),
            TextDirection::Rtl => Some(Level::rtl()),
        }
    }
}

/// Options of [`text`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct TextOptions {
    /// The size: the em square is `size / 0.72` (capitals about `size` tall). Default value: 10.
    pub size: f64,
    /// Horizontal alignment. Default value: [`HAlign::Left`].
    pub halign: HAlign,
    /// Vertical alignment. Default value: [`VAlign::Baseline`].
    pub valign: VAlign,
    /// The factor on every advance width (1 as the font sets it, at least 0). Default value: 1.
    pub spacing: f64,
    /// Line segments per Bézier curve of an outline (1 to 64). Default value: 8.
    pub segments: u32,
    /// The base direction of each line. Default value: [`TextDirection::Auto`].
    pub direction: TextDirection,
    /// Whether the font's kerning applies (the OpenType `kern` feature). Default value: true.
    pub kerning: bool,
}

impl TextOptions {
    /// Size 10, left on the baseline, the font's spacing and kerning, 8 segments per curve, each
    /// line's direction from its first strong character.
    pub const DEFAULT: TextOptions = TextOptions {
        size: 10.0,
        halign: HAlign::Left,
        valign: VAlign::Baseline,
        spacing: 1.0,
        segments: 8,
        direction: TextDirection::Auto,
        kerning: true,
    };

    /// With `size`.
    #[must_use]
    pub fn with_size(mut self, size: f64) -> TextOptions {
        self.size = size;
        self
    }

    /// With the horizontal alignment `halign`.
    #[must_use]
    pub fn with_halign(mut self, halign: HAlign) -> TextOptions {
        self.halign = halign;
        self
    }

    /// With the vertical alignment `valign`.
    #[must_use]
    pub fn with_valign(mut self, valign: VAlign) -> TextOptions {
        self.valign = valign;
        self
    }

    /// With `spacing`.
    #[must_use]
    pub fn with_spacing(mut self, spacing: f64) -> TextOptions {
        self.spacing = spacing;
        self
    }

    /// With `segments` per curve.
    #[must_use]
    pub fn with_segments(mut self, segments: u32) -> TextOptions {
        self.segments = segments;
        self
    }

    /// With the base `direction` of each line.
    #[must_use]
    pub fn with_direction(mut self, direction: TextDirection) -> TextOptions {
        self.direction = direction;
        self
    }

    /// With the font's kerning on or off.
    #[must_use]
    pub fn with_kerning(mut self, kerning: bool) -> TextOptions {
        self.kerning = kerning;
        self
    }
}

impl Default for TextOptions {
    fn default() -> TextOptions {
        TextOptions::DEFAULT
    }
}

/// Collects a glyph's contours in font units, curves flattened.
struct Outline {
    segments: u32,
    contours: Vec<Vec<Vec2>>,
    at: Vec2,
}

impl Outline {
    fn push(&mut self, p: Vec2) {
        if let Some(c) = self.contours.last_mut() {
            c.push(p);
        }
        self.at = p;
    }
}

impl OutlineBuilder for Outline {
    fn move_to(&mut self, x: f32, y: f32) {
        let p = Vec2::new(f64::from(x), f64::from(y));
        self.contours.push(vec![p]);
        self.at = p;
    }

    fn line_to(&mut self, x: f32, y: f32) {
        self.push(Vec2::new(f64::from(x), f64::from(y)));
    }

    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let (p0, c, p) = (self.at, Vec2::new(f64::from(x1), f64::from(y1)), Vec2::new(f64::from(x), f64::from(y)));
        for k in 1..=self.segments {
            let t = f64::from(k) / f64::from(self.segments);
            let u = 1.0 - t;
            self.push(u * u * p0 + 2.0 * u * t * c + t * t * p);
        }
    }

    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let p0 = self.at;
        let (c1, c2) = (Vec2::new(f64::from(x1), f64::from(y1)), Vec2::new(f64::from(x2), f64::from(y2)));
        let p = Vec2::new(f64::from(x), f64::from(y));
        for k in 1..=self.segments {
            let t = f64::from(k) / f64::from(self.segments);
            let u = 1.0 - t;
            self.push(u * u * u * p0 + 3.0 * u * u * t * c1 + 3.0 * u * t * t * c2 + t * t * t * p);
        }
    }

    fn close(&mut self) {
        // The contour closes back to its first point implicitly; drop a repeated last point.
        if let Some(c) = self.contours.last_mut() {
            if c.len() > 1 && c.first() == c.last() {
                c.pop();
            }
        }
    }
}

/// `s` set in `font` as a profile (see the [module documentation](self)).
///
/// # Errors
/// [`ProfileError::Empty`] for an empty string; [`ProfileError::ZeroArea`] when no character
/// draws anything (only spaces); [`ProfileError::BadValue`] for a size not positive and
/// finite, a spacing negative or not finite, segments outside 1 to 64;
/// [`ProfileError::OutOfRange`] for text reaching beyond [`MAX_REACH`](super::MAX_REACH);
/// [`ProfileError::Limit`] when stopped.
pub fn text(s: &str, font: &Font, options: &TextOptions) -> Result<Profile, ProfileError> {
    if s.is_empty() {
        return Err(ProfileError::Empty { what: "the text".into() });
    }
    check_number("the text size", options.size, true)?;
    check_number("the spacing", options.spacing, false)?;
    if options.spacing < 0.0 {
        return Err(ProfileError::BadValue { name: "the spacing", value: options.spacing, expected: "at least 0" });
    }
    if !(1..=64).contains(&options.segments) {
        return Err(ProfileError::BadValue {
            name: "the segments per curve",
            value: f64::from(options.segments),
            expected: "from 1 to 64",
        });
    }
    let face = font.face()?;
    let scale = options.size / 0.72 / f64::from(face.units_per_em().max(1));
    // Each glyph's region, cleaned once in font units (non-zero fill), with its ink bounds.
    let mut cache: HashMap<GlyphId, Option<(Profile, Vec2, Vec2)>> = HashMap::new();
    // The placed glyphs: their id, offset (font units), and ink bounds (model units).
    let mut placed: Vec<(GlyphId, Vec2, Vec2, Vec2)> = Vec::new();
    for (gid, origin) in layout(s, &face, options)? {
        let glyph = cache.entry(gid).or_insert_with(|| {
            let mut o = Outline { segments: options.segments, contours: Vec::new(), at: Vec2::ZERO };
            face.outline_glyph(gid, &mut o);
            o.contours.retain(|c| c.len() >= 3);
            let p = Profile::from_contours(&o.contours, FillRule::NonZero).ok()?;
            let (lo, hi) = p.bounds()?;
            Some((p, lo, hi))
        });
        if let Some((_, lo, hi)) = glyph {
            placed.push((gid, origin, (*lo + origin) * scale, (*hi + origin) * scale));
        }
    }
    if placed.is_empty() {
        return Err(ProfileError::ZeroArea { what: "the text (it has no visible characters)".into() });
    }
    let (lo, hi) = placed.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), g| (lo.min(g.2), hi.max(g.3)));
    let dy = match options.valign {
        VAlign::Baseline => 0.0,
        VAlign::Bottom => -lo.y,
        VAlign::Center => -(lo.y + hi.y) / 2.0,
        VAlign::Top => -hi.y,
    };
    let reach = lo.abs().max(hi.abs()).max_element() + dy.abs();
    if !reach.is_finite() || reach > super::MAX_REACH {
        return Err(ProfileError::OutOfRange { what: "the text".into(), index: 0, value: reach });
    }
    // Glyphs whose ink boxes meet are unioned; the others are apart, so their clean contours
    // go in as they are (no union of the whole text, which for long texts dominates).
    let groups = overlapping_groups(&placed);
    let to_model = |gid: GlyphId, origin: Vec2| -> Profile {
        let Some(Some((p, _, _))) = cache.get(&gid) else { return Profile::empty() };
        let contours = p
            .contours()
            .iter()
            .map(|c| c.iter().map(|&q| Vec2::new((q.x + origin.x) * scale, (q.y + origin.y) * scale + dy)).collect())
            .collect();
        Profile { contours }
    };
    let mut contours: Vec<Vec<Vec2>> = Vec::new();
    for group in groups {
        crate::limits::charge(group.len() as u64)?;
        if let [one] = group.as_slice() {
            contours.extend(to_model(placed[*one].0, placed[*one].1).contours);
        } else {
            let parts: Vec<Profile> = group.iter().map(|&k| to_model(placed[k].0, placed[k].1)).collect();
            contours.extend(Profile::union_all(&parts).contours);
        }
    }
    Ok(Profile { contours })
}

/// Where each glyph of `s` stands, in font units: the pen position of its origin after shaping,
/// bidirectional ordering, spacing and horizontal alignment (glyphs in visual order, line by
/// line). Control characters other than the line break are dropped.
fn layout(s: &str, face: &Face<'_>, options: &TextOptions) -> Result<Vec<(GlyphId, Vec2)>, ProfileError> {
    let line_height = f64::from(i32::from(face.ascender()) - i32::from(face.descender()) + i32::from(face.line_gap()));
    let features: Vec<Feature> =
        if options.kerning { Vec::new() } else { vec![Feature::new(Tag::from_bytes(b"kern"), 0, ..)] };
    let mut placed = Vec::new();
    let mut buffer = UnicodeBuffer::new();
    for (line_no, raw) in s.split('\n').enumerate() {
        crate::limits::charge(raw.len() as u64 + 1)?;
        let line: String = raw.chars().filter(|c| !c.is_control()).collect();
        let first = placed.len();
        let y = -(line_no as f64) * line_height;
        let mut pen = 0.0;
        let bidi = BidiInfo::new(&line, options.direction.paragraph_level());
        for paragraph in &bidi.paragraphs {
            let (levels, runs) = bidi.visual_runs(paragraph, paragraph.range.clone());
            for run in runs {
                let rtl = levels[run.start].is_rtl();
                buffer.push_str(&line[run]);
                buffer.set_direction(if rtl { Direction::RightToLeft } else { Direction::LeftToRight });
                buffer.guess_segment_properties();
                let shaped = rustybuzz::shape(face, &features, buffer);
                for (info, at) in shaped.glyph_infos().iter().zip(shaped.glyph_positions()) {
                    let gid = GlyphId(u16::try_from(info.glyph_id).unwrap_or(0));
                    placed.push((gid, Vec2::new(pen + f64::from(at.x_offset), y + f64::from(at.y_offset))));
                    pen += f64::from(at.x_advance) * options.spacing;
                }
                buffer = shaped.clear();
            }
        }
        let shift = match options.halign {
            HAlign::Left => 0.0,
            HAlign::Center => -pen / 2.0,
            HAlign::Right => -pen,
        };
        for g in &mut placed[first..] {
            g.1.x += shift;
        }
    }
    Ok(placed)
}

/// The placed glyphs grouped by meeting ink boxes (transitively): a sweep along x keeping the
/// boxes still open, joined by union–find.
fn overlapping_groups(placed: &[(GlyphId, Vec2, Vec2, Vec2)]) -> Vec<Vec<usize>> {
    let n = placed.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| placed[a].2.x.total_cmp(&placed[b].2.x));
    let mut open: Vec<usize> = Vec::new();
    for &i in &order {
        let (lo, hi) = (placed[i].2, placed[i].3);
        open.retain(|&j| placed[j].3.x >= lo.x);
        for &j in &open {
            let (lo2, hi2) = (placed[j].2, placed[j].3);
            if lo.y <= hi2.y && lo2.y <= hi.y {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                parent[a.max(b)] = a.min(b);
            }
        }
        open.push(i);
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for i in 0..n {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i);
    }
    let mut out: Vec<Vec<usize>> = groups.into_values().collect();
    out.sort_by_key(|g| g[0]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::tests::assert_near;
    use crate::profile::{extrude, ExtrudeOptions};

    /// DejaVu Sans' units per em and cap height, from its `head` and `OS/2` tables.
    const UPEM: f64 = 2048.0;

    #[test]
    fn an_i_is_one_rectangle_a_cap_height_tall() {
        // DejaVu Sans draws `I` as a single stem rectangle from the baseline to the cap height
        // (1493 units): at size 10 it stands 1493/2048 · 10/0.72 tall.
        let p = text("I", &Font::bundled(), &TextOptions::DEFAULT).unwrap();
        assert_eq!(p.contours().len(), 1);
        assert_eq!(p.contours()[0].len(), 4);
        let (lo, hi) = p.bounds().unwrap();
        assert_near(lo.y, 0.0, 1e-9);
        assert_near(hi.y, 1493.0 / UPEM * 10.0 / 0.72, 1e-7);
    }

    #[test]
    fn an_o_has_a_hole_and_glyphs_follow_their_advances() {
        let font = Font::bundled();
        let o = text("o", &font, &TextOptions::DEFAULT).unwrap();
        assert_eq!(o.contours().len(), 2);
        assert_eq!((0..2).filter(|&i| o.is_hole(i)).count(), 1);
        // "II" is two stems one advance apart: twice the area, and spacing 2 moves the second
        // one a further advance.
        let one = text("I", &font, &TextOptions::DEFAULT).unwrap();
        let two = text("II", &font, &TextOptions::DEFAULT).unwrap();
        assert_near(two.area(), 2.0 * one.area(), 1e-6);
        let wide = text("II", &font, &TextOptions::DEFAULT.with_spacing(2.0)).unwrap();
        let advance = two.bounds().unwrap().1.x - one.bounds().unwrap().1.x;
        assert_near(wide.bounds().unwrap().1.x - two.bounds().unwrap().1.x, advance, 1e-7);
    }

    #[test]
    fn alignment_places_the_ink_and_the_advance_about_the_origin() {
        let font = Font::bundled();
        let top = text("Hello", &font, &TextOptions::DEFAULT.with_valign(VAlign::Top)).unwrap();
        assert_near(top.bounds().unwrap().1.y, 0.0, 1e-7);
        let mid = text("Hello", &font, &TextOptions::DEFAULT.with_valign(VAlign::Center)).unwrap();
        let (lo, hi) = mid.bounds().unwrap();
        assert_near(lo.y + hi.y, 0.0, 1e-7);
        let right = text("Hello", &font, &TextOptions::DEFAULT.with_halign(HAlign::Right)).unwrap();
        assert!(right.bounds().unwrap().1.x <= 0.0);
        // Two lines: the second one line height lower.
        let lines = text("H\nH", &font, &TextOptions::DEFAULT).unwrap();
        assert_eq!(lines.contours().len(), 2);
        assert_near(lines.area(), 2.0 * text("H", &font, &TextOptions::DEFAULT).unwrap().area(), 1e-6);
    }

    #[test]
    fn bad_text_and_fonts_are_refused_by_name() {
        let font = Font::bundled();
        assert_eq!(
            text("", &font, &TextOptions::DEFAULT).unwrap_err().to_string(),
            "the text is empty: it has no contours"
        );
        assert!(matches!(text("   ", &font, &TextOptions::DEFAULT), Err(ProfileError::ZeroArea { .. })));
        assert!(text("a", &font, &TextOptions::DEFAULT.with_size(0.0)).is_err());
        assert!(text("a", &font, &TextOptions::DEFAULT.with_segments(0)).is_err());
        assert!(matches!(
            text("a", &font, &TextOptions::DEFAULT.with_size(1e12)),
            Err(ProfileError::OutOfRange { .. })
        ));
        let e = Font::from_bytes(b"not a font".to_vec()).unwrap_err();
        assert!(e.to_string().starts_with("the font cannot be read"), "{e}");
        // A character the font lacks draws the missing-glyph box instead of failing.
        assert!(!text("\u{10FFFD}", &font, &TextOptions::DEFAULT).unwrap().is_empty());
    }

    #[test]
    fn heights_and_area_match_openscad_in_the_same_font() {
        // OpenSCAD 2021.01: `linear_extrude(1) text("Hello", size=10, font="DejaVu Sans")`, its
        // STL measured by trimesh: ink y from −0.1984 to 10.5536, x from 1.3630, volume 110.431.
        // The size convention gives the same heights (to the STL's float precision and
        // FreeType's hinting); the area is within 0.5 % (OpenSCAD flattens curves more
        // coarsely). Widths differ by OpenSCAD's shaping (hinted advances, kerning): not compared.
        let p = text("Hello", &Font::bundled(), &TextOptions::DEFAULT).unwrap();
        let (lo, hi) = p.bounds().unwrap();
        assert_near(lo.y, -0.1984, 0.002);
        assert_near(hi.y, 10.5536, 0.002);
        assert_near(lo.x, 1.3630, 0.001);
        assert_near(p.area(), 110.431, 0.005 * 110.431);
    }

    #[test]
    fn glyphs_apart_skip_the_union_and_give_what_it_would() {
        // Only glyphs whose ink boxes meet are unioned; the rest go in as they are. The result
        // is the union of the whole text all the same: same points, same area.
        let lines: String = (0..10).map(|_| "The quick brown fox jumps over the lazy dog 0123456789\n").collect();
        let p = text(&lines, &Font::bundled(), &TextOptions::DEFAULT).unwrap();
        let all = Profile::from_contours(p.contours(), FillRule::NonZero).unwrap();
        assert_eq!(p.point_count(), all.point_count());
        assert_near(p.area(), all.area(), 1e-9 * all.area());
        // Spacing 0 stacks every glyph at one place: they meet and are unioned into one stem.
        let stacked = text("IIII", &Font::bundled(), &TextOptions::DEFAULT.with_spacing(0.0)).unwrap();
        let one = text("I", &Font::bundled(), &TextOptions::DEFAULT).unwrap();
        assert_eq!(stacked.contours().len(), 1);
        assert_near(stacked.area(), one.area(), 1e-6);
    }

    /// The glyph ids and pen x positions of `s`'s layout.
    fn glyphs(s: &str, options: &TextOptions) -> Vec<(u16, f64)> {
        let font = Font::bundled();
        let face = font.face().unwrap();
        layout(s, &face, options).unwrap().into_iter().map(|(g, at)| (g.0, at.x)).collect()
    }

    #[test]
    fn the_fonts_kerning_pulls_pairs_together_and_can_be_turned_off() {
        // DejaVu Sans kerns "AV" and "To" in its GPOS table: the second glyph starts before the
        // first one's advance. Without kerning it starts exactly there.
        let font = Font::bundled();
        let face = font.face().unwrap();
        for pair in ["AV", "To", "Ty"] {
            let first = face.glyph_index(pair.chars().next().unwrap()).unwrap();
            let advance = f64::from(face.glyph_hor_advance(first).unwrap());
            let kerned = glyphs(pair, &TextOptions::DEFAULT);
            assert!(kerned[1].1 < advance - 20.0, "{pair}: {kerned:?} against advance {advance}");
            let plain = glyphs(pair, &TextOptions::DEFAULT.with_kerning(false));
            assert_near(plain[1].1, advance, 1e-12);
        }
        // The kerned word is narrower, by the same ink.
        let kerned = text("AVATAR", &font, &TextOptions::DEFAULT).unwrap();
        let plain = text("AVATAR", &font, &TextOptions::DEFAULT.with_kerning(false)).unwrap();
        assert!(kerned.bounds().unwrap().1.x < plain.bounds().unwrap().1.x - 1.0);
        assert_near(kerned.area(), plain.area(), 1e-6 * plain.area());
    }

    #[test]
    fn right_to_left_runs_read_right_to_left_inside_either_base_direction() {
        // Hebrew alef then bet: bet (first in visual order) stands left of alef.
        let font = Font::bundled();
        let face = font.face().unwrap();
        let (alef, bet) = (face.glyph_index('א').unwrap().0, face.glyph_index('ב').unwrap().0);
        let g = glyphs("אב", &TextOptions::DEFAULT);
        assert_eq!(g.iter().map(|g| g.0).collect::<Vec<_>>(), vec![bet, alef]);
        // A Latin word then a Hebrew one: left to right by the first strong character, so the
        // Latin word comes first; with base direction right to left, the Hebrew one does.
        let mixed = "ab אב";
        let a = face.glyph_index('a').unwrap().0;
        let ltr = glyphs(mixed, &TextOptions::DEFAULT);
        assert_eq!(ltr[0].0, a);
        assert_eq!(ltr.last().unwrap().0, alef);
        let rtl = glyphs(mixed, &TextOptions::DEFAULT.with_direction(TextDirection::Rtl));
        assert_eq!(rtl[0].0, bet);
        assert_eq!(rtl.last().unwrap().0, face.glyph_index('b').unwrap().0);
        // Pen positions increase along the visual order either way.
        for w in rtl.windows(2).chain(ltr.windows(2)) {
            assert!(w[1].1 > w[0].1, "{rtl:?} {ltr:?}");
        }
    }

    #[test]
    fn joined_scripts_take_their_contextual_forms() {
        // Arabic beh alone is its isolated form; three in a row take initial, medial and final
        // forms, which are other glyphs than the isolated one (DejaVu Sans has all four).
        let font = Font::bundled();
        let isolated = glyphs("ب", &TextOptions::DEFAULT);
        let joined = glyphs("ببب", &TextOptions::DEFAULT);
        assert_eq!(isolated.len(), 1);
        assert_eq!(joined.len(), 3);
        assert!(joined.iter().all(|g| g.0 != isolated[0].0), "{joined:?} {isolated:?}");
        let word = text("سلام", &font, &TextOptions::DEFAULT).unwrap();
        assert!(word.area() > 0.0);
        let m = extrude(&word, 1.0, &ExtrudeOptions::DEFAULT).unwrap();
        assert!(m.is_closed() && m.is_manifold());
    }

    #[test]
    fn engraved_text_extrudes_to_a_closed_solid() {
        let p = text("Blocksmith 3D!", &Font::bundled(), &TextOptions::DEFAULT.with_size(5.0)).unwrap();
        let m = extrude(&p, 1.0, &ExtrudeOptions::DEFAULT).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_near(m.volume(), p.area(), 1e-9 * p.area());
    }
}
