//! `Profile`: 2D regions and the solids made from them (API.md §2D profiles and sweeps; kernel
//! `profile`): `rect`, `circle`, `polygon`, booleans, offsets, fillets, chamfers, hulls,
//! transforms and measures; `extrude`, `revolve`, `sweep` and `loft` to a closed manifold
//! `Mesh`; and the 3D operations that go with them — `hull` of meshes or points, `minkowski`,
//! `split`, `trim`, `slice` and `project`.
//!
//! A point of a profile is written `[x, y]`; angles are in degrees, counter-clockwise.

use std::rc::Rc;

use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::profile::{
    self as kernel_profile, ExtrudeOptions, FillRule, Font, HAlign, JoinType, LoftOptions, OffsetOptions,
    Profile as KernelProfile, RevolveOptions, SweepOptions, TextDirection, TextOptions, VAlign, Vec2,
};
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{error, fail, kernel, number, type_name, vec3, Number, Options, ScriptResult, Vector};

/// A 2D region as scripts hold it (script type `Profile`): shared, and never changed — every
/// operation returns a new profile.
#[derive(Clone, Debug)]
pub struct Profile(pub Rc<KernelProfile>);

impl Profile {
    fn new(p: KernelProfile) -> Profile {
        Profile(Rc::new(p))
    }
}

/// A point `[x, y]` (an array of two numbers) as a script passes it.
pub type Point2 = Dynamic;

/// Registers the `Profile` type and every profile function on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Profile>("Profile");
    engine.register_global_module(exported_module!(profile_api).into());
}

/// Segments per full turn where a script gives none (a circle, a fillet's arcs).
const DEFAULT_SEGMENTS: INT = 32;
/// The most segments a circle or arc may be asked for.
const MAX_SEGMENTS: INT = kernel_profile::MAX_SEGMENTS as INT;

/// `[x, y]` from an array of two finite numbers (or a `Vec3` whose z is 0).
fn point2(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec2> {
    if let Some(p) = v.clone().try_cast::<Vec3>() {
        if p.z == 0.0 && p.x.is_finite() && p.y.is_finite() {
            return Ok(Vec2::new(p.x, p.y));
        }
        return fail(func, format!("argument `{arg}` must be a point [x, y], got a Vec3 off the plane z = 0"));
    }
    match v.read_lock::<Array>() {
        Some(a) if a.len() == 2 => {
            Ok(Vec2::new(number(func, &format!("{arg}[0]"), &a[0])?, number(func, &format!("{arg}[1]"), &a[1])?))
        }
        Some(a) => fail(func, format!("argument `{arg}` must be a point [x, y], got an array of {}", a.len())),
        None => fail(func, format!("argument `{arg}` must be a point [x, y], got {}", type_name(v))),
    }
}

/// A scale `[sx, sy]` from a number (uniform) or a point.
fn factor2(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec2> {
    if v.is_float() || v.is_int() {
        Ok(Vec2::splat(number(func, arg, v)?))
    } else {
        point2(func, arg, v)
    }
}

/// A list of points `[[x, y], …]`.
fn points2(func: &str, arg: &str, v: &Array) -> ScriptResult<Vec<Vec2>> {
    v.iter().enumerate().map(|(i, p)| point2(func, &format!("{arg}[{i}]"), p)).collect()
}

/// A segment count between 3 and [`MAX_SEGMENTS`].
fn segments(func: &str, arg: &str, n: INT) -> ScriptResult<u32> {
    if !(3..=MAX_SEGMENTS).contains(&n) {
        return fail(func, format!("{arg} must be between 3 and {MAX_SEGMENTS}, got {n}"));
    }
    Ok(n as u32)
}

/// The profiles of an array, each checked.
fn profiles(func: &str, arg: &str, v: &Array) -> ScriptResult<Vec<KernelProfile>> {
    v.iter()
        .enumerate()
        .map(|(i, p)| match p.read_lock::<Profile>() {
            Some(p) => Ok((*p.0).clone()),
            None => fail(func, format!("argument `{arg}[{i}]` must be a Profile, got {}", type_name(p))),
        })
        .collect()
}

/// Whether `v` is an array of points (its first element a number pair) rather than an array
/// of contours (its first element an array of points).
fn is_point_list(v: &Array) -> bool {
    v.first()
        .and_then(|first| first.read_lock::<Array>().map(|a| a.first().is_none_or(|x| !x.is_array())))
        .unwrap_or(true)
}

fn make_polygon(points: &Array, fill: FillRule) -> ScriptResult<Profile> {
    let p = if is_point_list(points) {
        KernelProfile::polygon(&points2("polygon", "points", points)?, fill)
    } else {
        let contours = points
            .iter()
            .enumerate()
            .map(|(i, c)| match c.read_lock::<Array>() {
                Some(c) => points2("polygon", &format!("contours[{i}]"), &c),
                None => fail(
                    "polygon",
                    format!("argument `contours[{i}]` must be an array of points, got {}", type_name(c)),
                ),
            })
            .collect::<ScriptResult<Vec<_>>>()?;
        KernelProfile::from_contours(&contours, fill)
    };
    kernel("polygon", p).map(Profile::new)
}

/// The font of `text`'s option `font`: a TTF/OTF file (read as `load` reads: from the working
/// directory, else next to the script, within what the run may read), else the bundled one.
fn text_font(ctx: &NativeCallContext, opts: &Options) -> ScriptResult<Font> {
    let Some(v) = opts.raw("font") else { return Ok(Font::bundled()) };
    let Some(path) = v.clone().into_immutable_string().ok() else {
        return fail("text", format!("option `font` must be the path of a .ttf or .otf file, got {}", type_name(v)));
    };
    let p = super::paths::input_file(ctx, "text", &path)?;
    blocksmith_kernel::io::load_font(&p).map_err(|e| error("text", format!("option `font`: {e}")))
}

fn text_options(opts: &Options) -> ScriptResult<TextOptions> {
    let halign = opts.choice("halign", "left", &["left", "center", "right"])?;
    let valign = opts.choice("valign", "baseline", &["baseline", "bottom", "center", "top"])?;
    let direction = opts.choice("direction", "auto", &["auto", "ltr", "rtl"])?;
    let segments = opts.int("segments", 8)?;
    if !(1..=64).contains(&segments) {
        return fail("text", format!("option `segments` must be between 1 and 64, got {segments}"));
    }
    Ok(TextOptions::DEFAULT
        .with_size(opts.number("size", 10.0)?)
        .with_halign(HAlign::from_name(&halign).unwrap_or_default())
        .with_valign(VAlign::from_name(&valign).unwrap_or_default())
        .with_spacing(opts.number("spacing", 1.0)?)
        .with_segments(segments as u32)
        .with_direction(TextDirection::from_name(&direction).unwrap_or_default())
        .with_kerning(opts.bool("kerning", true)?))
}

fn offset_options(func: &'static str, options: Map) -> ScriptResult<OffsetOptions> {
    let opts = Options::new(func, options, &["join", "miter_limit", "segments"])?;
    let join = opts.choice("join", "round", &["round", "miter", "square"])?;
    let mut o = OffsetOptions::DEFAULT.with_join(JoinType::from_name(&join).unwrap_or_default());
    if opts.has("miter_limit") {
        o = o.with_miter_limit(opts.number("miter_limit", 2.0)?);
    }
    let n = opts.int("segments", DEFAULT_SEGMENTS)?;
    Ok(o.with_segments(segments(func, "option `segments`", n)?))
}

fn extrude_options(options: Map) -> ScriptResult<ExtrudeOptions> {
    let opts = Options::new("extrude", options, &["twist", "scale", "slices", "center"])?;
    let mut o = ExtrudeOptions::DEFAULT.with_twist(opts.number("twist", 0.0)?).with_center(opts.bool("center", false)?);
    if let Some(s) = opts.raw("scale") {
        o = o.with_scale(factor2("extrude", "option `scale`", s)?);
    }
    if opts.has("slices") {
        let n = opts.int("slices", 1)?;
        if !(1..=MAX_SEGMENTS).contains(&n) {
            return fail("extrude", format!("option `slices` must be between 1 and {MAX_SEGMENTS}, got {n}"));
        }
        o = o.with_slices(n as u32);
    }
    Ok(o)
}

fn revolve_options(options: Map) -> ScriptResult<RevolveOptions> {
    let opts = Options::new("revolve", options, &["angle", "segments"])?;
    let n = opts.int("segments", DEFAULT_SEGMENTS)?;
    Ok(RevolveOptions::DEFAULT.with_angle(opts.number("angle", 360.0)?).with_segments(segments(
        "revolve",
        "option `segments`",
        n,
    )?))
}

fn sweep_options(options: Map) -> ScriptResult<SweepOptions> {
    let opts = Options::new("sweep", options, &["up", "twist", "scale", "closed"])?;
    let mut o = SweepOptions::DEFAULT.with_twist(opts.number("twist", 0.0)?).with_closed(opts.bool("closed", false)?);
    if let Some(up) = opts.raw("up") {
        o = o.with_up(vec3("sweep", "option `up`", up)?);
    }
    if let Some(s) = opts.raw("scale") {
        o = o.with_scale(factor2("sweep", "option `scale`", s)?);
    }
    Ok(o)
}

fn loft_options(options: Map) -> ScriptResult<LoftOptions> {
    let opts = Options::new("loft", options, &["heights", "transforms", "closed"])?;
    let mut o = LoftOptions::DEFAULT.with_closed(opts.bool("closed", false)?);
    match (opts.raw("heights"), opts.raw("transforms")) {
        (Some(_), Some(_)) => return fail("loft", "give option `heights` or option `transforms`, not both"),
        (Some(h), None) => {
            let Some(h) = h.read_lock::<Array>() else {
                return fail("loft", format!("option `heights` must be an array of numbers, got {}", type_name(h)));
            };
            let heights: ScriptResult<Vec<f64>> =
                h.iter().enumerate().map(|(i, x)| number("loft", &format!("option `heights[{i}]`"), x)).collect();
            o = o.with_heights(heights?);
        }
        (None, Some(t)) => {
            let Some(t) = t.read_lock::<Array>() else {
                return fail(
                    "loft",
                    format!("option `transforms` must be an array of 4×4 matrices, got {}", type_name(t)),
                );
            };
            let matrices: ScriptResult<Vec<_>> =
                t.iter().enumerate().map(|(i, m)| matrix("loft", &format!("transforms[{i}]"), m)).collect();
            o = o.with_transforms(matrices?);
        }
        (None, None) => {}
    }
    Ok(o)
}

/// A 4×4 matrix from four rows of four numbers (row-major, as written on paper: the last
/// column is the translation).
fn matrix(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<blocksmith_kernel::math::Mat4> {
    let bad = || error(func, format!("option `{arg}` must be 4 rows of 4 numbers, got {}", type_name(v)));
    let rows = v.read_lock::<Array>().filter(|r| r.len() == 4).ok_or_else(bad)?;
    let mut m = [0.0; 16];
    for (i, row) in rows.iter().enumerate() {
        let row = row.read_lock::<Array>().filter(|r| r.len() == 4).ok_or_else(bad)?;
        for (j, x) in row.iter().enumerate() {
            // glam is column-major: element (row i, column j) goes to j * 4 + i.
            m[j * 4 + i] = number(func, &format!("option `{arg}[{i}][{j}]`"), x)?;
        }
    }
    Ok(blocksmith_kernel::math::Mat4::from_cols_array(&m))
}

fn point_map(p: Vec2) -> Dynamic {
    Dynamic::from_array(vec![Dynamic::from(p.x), Dynamic::from(p.y)])
}

#[export_module]
pub mod profile_api {
    use super::*;

    /// The rectangle from corner `min` to corner `max` (`[x, y]` each), like `box` in 3D.
    ///
    /// ```rhai
    /// let r = rect([0, 0], [4, 2]);
    /// assert_near(r.area(), 8.0, 1e-12);
    /// assert_eq(r.contours().len(), 1);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn rect(min: Point2, max: Point2) -> ScriptResult<Profile> {
        let (a, b) = (point2("rect", "min", &min)?, point2("rect", "max", &max)?);
        kernel("rect", KernelProfile::rect(a, b)).map(Profile::new)
    }

    /// The circle of radius `r` about the origin as a regular polygon of 32 sides (its corners
    /// on the circle).
    ///
    /// ```rhai
    /// let c = circle(1);
    /// // A regular 32-gon inscribed in the unit circle: (32 / 2) sin(360° / 32).
    /// assert_near(c.area(), 16.0 * sin(2.0 * PI() / 32.0), 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn circle(r: Number) -> ScriptResult<Profile> {
        let r = number("circle", "r", &r)?;
        kernel("circle", KernelProfile::circle(r, DEFAULT_SEGMENTS as u32)).map(Profile::new)
    }

    /// The circle of radius `r` about the origin as a regular polygon of `segments` sides (3 or
    /// more), its corners on the circle.
    ///
    /// ```rhai
    /// let square = circle(1, 4);
    /// assert_near(square.area(), 2.0, 1e-12);
    /// ```
    #[rhai_fn(name = "circle", return_raw)]
    pub fn circle_segments(r: Number, segments_: INT) -> ScriptResult<Profile> {
        let r = number("circle", "r", &r)?;
        let n = segments("circle", "argument `segments`", segments_)?;
        kernel("circle", KernelProfile::circle(r, n)).map(Profile::new)
    }

    /// The region inside `points` (`[[x, y], …]`, in either direction), or inside
    /// `[outer, hole, …]` when given several contours. A self-intersecting outline is repaired
    /// by the even-odd rule (`polygon(points, #{ fill: "nonzero" })` for the other): the result
    /// is always a clean region.
    ///
    /// ```rhai
    /// let square = [[0, 0], [4, 0], [4, 4], [0, 4]];
    /// let hole = [[1, 1], [3, 1], [3, 3], [1, 3]];
    /// assert_near(polygon(square).area(), 16.0, 1e-12);
    /// assert_near(polygon([square, hole]).area(), 12.0, 1e-12);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn polygon(points: Array) -> ScriptResult<Profile> {
        make_polygon(&points, FillRule::EvenOdd)
    }

    /// As `polygon(points)`, with option `fill`: `"evenodd"` (the default: a hole is a hole
    /// whichever way it runs) or `"nonzero"` (a region wound twice stays filled).
    ///
    /// ```rhai
    /// // Two overlapping squares in one outline list: even-odd leaves their overlap out.
    /// let a = [[0, 0], [2, 0], [2, 2], [0, 2]];
    /// let b = [[1, 1], [3, 1], [3, 3], [1, 3]];
    /// assert_near(polygon([a, b], #{ fill: "evenodd" }).area(), 6.0, 1e-12);
    /// assert_near(polygon([a, b], #{ fill: "nonzero" }).area(), 7.0, 1e-12);
    /// ```
    #[rhai_fn(name = "polygon", return_raw)]
    pub fn polygon_with(points: Array, options: Map) -> ScriptResult<Profile> {
        let opts = Options::new("polygon", options, &["fill"])?;
        let fill = opts.choice("fill", "evenodd", &["evenodd", "nonzero"])?;
        make_polygon(&points, FillRule::from_name(&fill).unwrap_or_default())
    }

    /// The outlines of `s` set in the bundled font (DejaVu Sans) at size 10 — capitals about 10
    /// tall, as OpenSCAD's `text` — starting at x = 0 on the baseline y = 0. Lines break at
    /// `\n`.
    ///
    /// ```rhai
    /// let t = text("Hi");
    /// assert(t.area() > 0.0 && t.contours().len() == 3, "H, the i's stem and its dot");
    /// assert_near(t.bounds().min[1], 0.0, 0.05);          // on the baseline
    /// ```
    #[rhai_fn(name = "text", return_raw)]
    pub fn text_plain(ctx: NativeCallContext, s: &str) -> ScriptResult<Profile> {
        text_with(ctx, s, Map::new())
    }

    /// As `text(s)`, with options `size` (capitals about this tall; default 10), `font` (the
    /// path of a .ttf or .otf file; default the bundled DejaVu Sans), `halign` (`"left"`,
    /// `"center"`, `"right"` about x = 0), `valign` (`"baseline"`, `"bottom"`, `"center"`,
    /// `"top"` about y = 0), `spacing` (a factor on every advance; default 1), `segments`
    /// (per curve of an outline, 1 to 64; default 8), `kerning` (the font's kerning; default
    /// true) and `direction` (each line's base direction: `"auto"` from its first strong
    /// character, `"ltr"` or `"rtl"`; default `"auto"`). Text is shaped as HarfBuzz shapes it:
    /// kerning, ligatures, joined Arabic forms, and right-to-left runs in their order.
    ///
    /// ```rhai
    /// // Kerning pulls "AV" together; Hebrew reads right to left.
    /// let kerned = text("AV").bounds().max[0];
    /// let plain = text("AV", #{ kerning: false }).bounds().max[0];
    /// assert(kerned < plain, "kerned narrower");
    /// assert(text("שלום").area() > 0.0, "right to left");
    /// ```
    ///
    /// ```rhai
    /// // An engraved nameplate: the text centred, cut 0.5 into a 60 × 16 plate.
    /// let label = text("blocksmith", #{ size: 6, halign: "center", valign: "center" });
    /// assert_near(label.bounds().min[0], -label.bounds().max[0], 0.5);
    /// let plate = extrude(rect([-30, -8], [30, 8]), 2) - extrude(label, 1).translate([0, 0, 1.5]);
    /// assert(plate.is_closed() && plate.volume() < 60.0 * 16.0 * 2.0, "engraved");
    /// ```
    #[rhai_fn(name = "text", return_raw)]
    pub fn text_with(ctx: NativeCallContext, s: &str, options: Map) -> ScriptResult<Profile> {
        let opts = Options::new(
            "text",
            options,
            &["size", "font", "halign", "valign", "spacing", "segments", "kerning", "direction"],
        )?;
        let font = text_font(&ctx, &opts)?;
        let o = text_options(&opts)?;
        kernel("text", kernel_profile::text(s, &font, &o)).map(Profile::new)
    }

    /// `a + b`: the union of two profiles.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let p = rect([0, 0], [2, 2]) + rect([1, 1], [3, 3]);
    /// assert_near(p.area(), 7.0, 1e-12);
    /// ```
    #[rhai_fn(name = "+", name = "union", pure)]
    pub fn union(a: &mut Profile, b: Profile) -> Profile {
        Profile::new(a.0.union(&b.0))
    }

    /// `a - b`: `a` with `b` cut away.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let frame = rect([0, 0], [4, 4]) - rect([1, 1], [3, 3]);
    /// assert_near(frame.area(), 12.0, 1e-12);
    /// assert_eq(frame.contours().len(), 2);
    /// ```
    #[rhai_fn(name = "-", name = "subtract", pure)]
    pub fn subtract(a: &mut Profile, b: Profile) -> Profile {
        Profile::new(a.0.difference(&b.0))
    }

    /// The region inside both profiles.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let p = intersect(rect([0, 0], [2, 2]), rect([1, 1], [3, 3]));
    /// assert_near(p.area(), 1.0, 1e-12);
    /// ```
    #[rhai_fn(pure)]
    pub fn intersect(a: &mut Profile, b: Profile) -> Profile {
        Profile::new(a.0.intersection(&b.0))
    }

    /// The profile grown by `delta` (shrunk when negative), corners rounded with 32 segments
    /// per turn.
    ///
    /// ```rhai
    /// let p = rect([0, 0], [2, 2]).offset(-0.5);
    /// assert_near(p.area(), 1.0, 1e-9);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn offset(p: &mut Profile, delta: Number) -> ScriptResult<Profile> {
        let d = number("offset", "delta", &delta)?;
        kernel("offset", p.0.offset(d, &OffsetOptions::DEFAULT)).map(Profile::new)
    }

    /// The profile grown by `delta` (shrunk when negative) with options `join` (`"round"`,
    /// `"miter"` or `"square"`), `miter_limit` (for miter joins, in multiples of `delta`;
    /// default 2) and `segments` (per full turn of a round join; default 32).
    ///
    /// ```rhai
    /// // Mitred corners stay square: a 2×2 square grown by 1 is 4×4.
    /// let p = rect([0, 0], [2, 2]).offset(1, #{ join: "miter" });
    /// assert_near(p.area(), 16.0, 1e-9);
    /// ```
    #[rhai_fn(name = "offset", pure, return_raw)]
    pub fn offset_with(p: &mut Profile, delta: Number, options: Map) -> ScriptResult<Profile> {
        let d = number("offset", "delta", &delta)?;
        let o = offset_options("offset", options)?;
        kernel("offset", p.0.offset(d, &o)).map(Profile::new)
    }

    /// Every corner, convex and concave, rounded with radius `r` (32 segments per turn). Parts
    /// thinner than `2 r` vanish and gaps narrower than `2 r` close.
    ///
    /// ```rhai
    /// // A 4×4 square with corners of radius 1: the four quarter arcs make one 32-gon circle.
    /// let p = rect([0, 0], [4, 4]).fillet(1);
    /// assert_near(p.area(), 16.0 - 4.0 + 16.0 * sin(2.0 * PI() / 32.0), 1e-6);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn fillet(p: &mut Profile, r: Number) -> ScriptResult<Profile> {
        let r = number("fillet", "r", &r)?;
        kernel("fillet", p.0.fillet(r, DEFAULT_SEGMENTS as u32)).map(Profile::new)
    }

    /// Every corner, convex and concave, cut by a straight chamfer; a right-angled corner loses
    /// a right triangle with legs `d`.
    ///
    /// ```rhai
    /// let p = rect([0, 0], [4, 4]).chamfer(1);
    /// assert_near(p.area(), 16.0 - 4.0 * 0.5, 1e-9);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn chamfer(p: &mut Profile, d: Number) -> ScriptResult<Profile> {
        let d = number("chamfer", "d", &d)?;
        kernel("chamfer", p.0.chamfer(d)).map(Profile::new)
    }

    /// The convex hull of the profile.
    ///
    /// ```rhai
    /// let l = polygon([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]);
    /// assert_near(l.hull().area(), 3.5, 1e-12);
    /// ```
    #[rhai_fn(name = "hull", pure, return_raw)]
    pub fn hull_profile(p: &mut Profile) -> ScriptResult<Profile> {
        kernel("hull", p.0.hull()).map(Profile::new)
    }

    /// The profile moved by `offset` (`[x, y]`).
    ///
    /// ```rhai
    /// let p = rect([0, 0], [1, 1]).translate([2, 3]);
    /// assert_eq(p.bounds().min, [2.0, 3.0]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn translate(p: &mut Profile, offset: Point2) -> ScriptResult<Profile> {
        let v = point2("translate", "offset", &offset)?;
        kernel("translate", p.0.translate(v)).map(Profile::new)
    }

    /// The profile turned `degrees` counter-clockwise about the origin.
    ///
    /// ```rhai
    /// let p = rect([0, 0], [2, 1]).rotate(90);
    /// assert_eq(p.bounds().min, [-1.0, 0.0]);
    /// assert_eq(p.bounds().max, [0.0, 2.0]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn rotate(p: &mut Profile, degrees: Number) -> ScriptResult<Profile> {
        let d = number("rotate", "degrees", &degrees)?;
        kernel("rotate", p.0.rotate(d)).map(Profile::new)
    }

    /// The profile scaled about the origin by `factor`: a number, or `[sx, sy]`.
    ///
    /// ```rhai
    /// assert_near(rect([0, 0], [1, 1]).scale([3, 2]).area(), 6.0, 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn scale(p: &mut Profile, factor: NumberOrPoint2) -> ScriptResult<Profile> {
        let f = factor2("scale", "factor", &factor)?;
        kernel("scale", p.0.scale(f)).map(Profile::new)
    }

    /// The profile reflected in the line through the origin perpendicular to `normal`
    /// (`[nx, ny]`).
    ///
    /// ```rhai
    /// let p = rect([1, 0], [2, 1]).mirror([1, 0]);
    /// assert_eq(p.bounds().min, [-2.0, 0.0]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn mirror(p: &mut Profile, normal: Point2) -> ScriptResult<Profile> {
        let n = point2("mirror", "normal", &normal)?;
        kernel("mirror", p.0.mirror(n)).map(Profile::new)
    }

    /// The profile with points that lie within `epsilon` of the line through their neighbours
    /// removed.
    ///
    /// ```rhai
    /// let p = polygon([[0, 0], [1, 0.0001], [2, 0], [2, 2], [0, 2]]).simplify(0.01);
    /// assert_eq(p.contours()[0].len(), 4);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn simplify(p: &mut Profile, epsilon: Number) -> ScriptResult<Profile> {
        let e = number("simplify", "epsilon", &epsilon)?;
        kernel("simplify", p.0.simplify(e)).map(Profile::new)
    }

    /// The area enclosed: outer contours less holes.
    ///
    /// ```rhai
    /// assert_near((rect([0, 0], [3, 3]) - rect([1, 1], [2, 2])).area(), 8.0, 1e-12);
    /// ```
    #[rhai_fn(pure)]
    pub fn area(p: &mut Profile) -> f64 {
        p.0.area()
    }

    /// The bounding rectangle as `#{ min: [x, y], max: [x, y] }`.
    ///
    /// ```rhai
    /// let b = circle(2, 4).bounds();
    /// assert_eq(b.min, [-2.0, -2.0]);
    /// assert_eq(b.max, [2.0, 2.0]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn bounds(p: &mut Profile) -> ScriptResult<Map> {
        let Some((min, max)) = p.0.bounds() else {
            return fail("bounds", "the profile is empty, so it has no bounds");
        };
        let mut map = Map::new();
        map.insert("min".into(), point_map(min));
        map.insert("max".into(), point_map(max));
        Ok(map)
    }

    /// The contours as arrays of `[x, y]` points: outer contours counter-clockwise, holes
    /// clockwise.
    ///
    /// ```rhai
    /// let c = (rect([0, 0], [3, 3]) - rect([1, 1], [2, 2])).contours();
    /// assert_eq(c.len(), 2);
    /// assert_eq(c[0].len(), 4);
    /// ```
    #[rhai_fn(pure)]
    pub fn contours(p: &mut Profile) -> Array {
        p.0.contours().iter().map(|c| Dynamic::from_array(c.iter().map(|&q| point_map(q)).collect())).collect()
    }

    /// A one-line summary: `Profile(C contours, P points, area A)`.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(p: &mut Profile) -> String {
        format!(
            "Profile({} contours, {} points, area {})",
            p.0.contours().len(),
            p.0.point_count(),
            fmt_num(p.0.area())
        )
    }

    /// The profile extruded up z to `height`: a closed manifold `Mesh` (OpenSCAD's
    /// `linear_extrude`).
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// let m = extrude(rect([0, 0], [2, 3]), 4);
    /// assert(m.is_closed(), "closed");
    /// assert_near(m.volume(), 24.0, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn extrude(p: Profile, height: Number) -> ScriptResult<SharedMesh> {
        let h = number("extrude", "height", &height)?;
        kernel("extrude", kernel_profile::extrude(&p.0, h, &ExtrudeOptions::DEFAULT)).map(SharedMesh::new)
    }

    /// As `extrude(p, height)`, with options `twist` (degrees the top turns), `scale` (the
    /// top's scale: a number or `[sx, sy]`), `slices` (layers; default one per 5° of twist) and
    /// `center` (span z from −height/2 to height/2).
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// // A frustum: V = h/3 (A1 + A2 + √(A1 A2)).
    /// let m = extrude(rect([-1, -1], [1, 1]), 3, #{ scale: 0.5 });
    /// assert_near(m.volume(), 1.0 * (4.0 + 1.0 + 2.0), 1e-9);
    /// ```
    #[rhai_fn(name = "extrude", return_raw)]
    pub fn extrude_with(p: Profile, height: Number, options: Map) -> ScriptResult<SharedMesh> {
        let h = number("extrude", "height", &height)?;
        let o = extrude_options(options)?;
        kernel("extrude", kernel_profile::extrude(&p.0, h, &o)).map(SharedMesh::new)
    }

    /// The profile turned a full turn about the z axis in 32 segments: its x is the radius and
    /// its y becomes z (OpenSCAD's `rotate_extrude`). A profile reaching to x < 0 is refused.
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// // An annulus of radii 1 and 2, height 1, as a 32-gon ring.
    /// let m = revolve(rect([1, 0], [2, 1]));
    /// assert(m.is_closed() && m.genus() == 1, "a ring");
    /// assert_near(m.volume(), 16.0 * sin(2.0 * PI() / 32.0) * 3.0, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn revolve(p: Profile) -> ScriptResult<SharedMesh> {
        kernel("revolve", kernel_profile::revolve(&p.0, &RevolveOptions::DEFAULT)).map(SharedMesh::new)
    }

    /// As `revolve(p)`, with options `angle` (degrees, up to 360; a partial turn is capped) and
    /// `segments` (per full turn; default 32).
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// let half = revolve(rect([1, 0], [2, 1]), #{ angle: 180, segments: 64 });
    /// assert(half.is_closed() && half.genus() == 0, "capped");
    /// ```
    #[rhai_fn(name = "revolve", return_raw)]
    pub fn revolve_with(p: Profile, options: Map) -> ScriptResult<SharedMesh> {
        let o = revolve_options(options)?;
        kernel("revolve", kernel_profile::revolve(&p.0, &o)).map(SharedMesh::new)
    }

    /// The profile swept along `path` (an array of 3D points) on rotation-minimising frames:
    /// the profile's plane stays perpendicular to the path and does not spin about it. A path
    /// with repeated points, turning so sharply that the profile would cross itself, or coming
    /// back through its own tube (checked exactly on the result), is refused naming the point.
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// let m = sweep(circle(0.5, 16), [[0, 0, 0], [0, 0, 2], [2, 0, 4]]);
    /// assert(m.is_closed() && m.genus() == 0, "a bent tube");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn sweep(p: Profile, path: Array) -> ScriptResult<SharedMesh> {
        sweep_with(p, path, Map::new())
    }

    /// As `sweep(p, path)`, with options `up` (the direction the profile's +y faces at the
    /// start), `twist` (degrees over the path), `scale` (at the end: a number or `[sx, sy]`)
    /// and `closed` (the path is a loop: a ring with no caps).
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// let ring = [];
    /// for i in 0..24 { let a = i * 2.0 * PI() / 24.0; ring.push([3.0 * cos(a), 3.0 * sin(a), 0]); }
    /// let m = sweep(circle(0.5, 12), ring, #{ closed: true });
    /// assert(m.is_closed() && m.genus() == 1, "a torus");
    /// ```
    #[rhai_fn(name = "sweep", return_raw)]
    pub fn sweep_with(p: Profile, path: Array, options: Map) -> ScriptResult<SharedMesh> {
        let points: Vec<Vec3> = path
            .iter()
            .enumerate()
            .map(|(i, q)| vec3("sweep", &format!("path[{i}]"), q))
            .collect::<ScriptResult<_>>()?;
        let o = sweep_options(options)?;
        kernel("sweep", kernel_profile::sweep(&p.0, &points, &o)).map(SharedMesh::new)
    }

    /// A solid through `profiles` one unit apart up z (contours matched and resampled, so any
    /// profiles with the same contour structure loft). A loft whose placed profiles make it pass
    /// through itself is refused naming the profile nearest the crossing.
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// let m = loft([rect([-1, -1], [1, 1]), circle(0.5, 32)]);
    /// assert(m.is_closed() && m.genus() == 0, "closed");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn loft(profiles: Array) -> ScriptResult<SharedMesh> {
        loft_with(profiles, Map::new())
    }

    /// As `loft(profiles)`, with option `heights` (the z of each profile, increasing) or
    /// `transforms` (for each profile a 4×4 matrix, four rows of four numbers, placing its
    /// plane), and `closed` (the last joins back to the first: a ring with no caps).
    ///
    /// Topic: 2d
    ///
    /// ```rhai
    /// // Equal squares at heights 0 and 2: a box.
    /// let m = loft([rect([0, 0], [1, 1]), rect([0, 0], [1, 1])], #{ heights: [0, 2] });
    /// assert_near(m.volume(), 2.0, 1e-9);
    /// ```
    #[rhai_fn(name = "loft", return_raw)]
    pub fn loft_with(profiles: Array, options: Map) -> ScriptResult<SharedMesh> {
        let ps = super::profiles("loft", "profiles", &profiles)?;
        let o = loft_options(options)?;
        kernel("loft", kernel_profile::loft(&ps, &o)).map(SharedMesh::new)
    }

    /// The convex hull of `items`: of profiles (a `Profile`), or of meshes and 3D points
    /// (`[x, y, z]` or `Vec3`) together (a closed `Mesh`).
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let corners = [];
    /// for x in [0, 1] { for y in [0, 1] { for z in [0, 1] { corners.push([x, y, z]); } } }
    /// assert_near(hull(corners).volume(), 1.0, 1e-12);
    /// assert_near(hull([cube(1), cube(1).translate([2, 0, 0])]).volume(), 3.0, 1e-9);
    /// assert_near(hull([circle(1, 4), circle(1, 4).translate([2, 0])]).area(), 6.0, 1e-9);
    /// ```
    #[rhai_fn(name = "hull", return_raw)]
    pub fn hull_of(items: Array) -> ScriptResult<Dynamic> {
        if items.is_empty() {
            return fail("hull", "argument `items` is empty: give profiles, or meshes and points");
        }
        if items.iter().all(|v| v.is::<Profile>()) {
            let ps = super::profiles("hull", "items", &items)?;
            return kernel("hull", KernelProfile::hull_all(&ps)).map(|p| Dynamic::from(Profile::new(p)));
        }
        let mut meshes = Vec::new();
        let mut points = Vec::new();
        for (i, v) in items.iter().enumerate() {
            if let Some(m) = v.read_lock::<SharedMesh>() {
                meshes.push(std::sync::Arc::clone(&m.0));
            } else if v.is::<Profile>() {
                return fail(
                    "hull",
                    format!("argument `items[{i}]` is a Profile among meshes and points: hull profiles on their own"),
                );
            } else {
                points.push(vec3("hull", &format!("items[{i}]"), v)?);
            }
        }
        for m in &meshes {
            points.extend_from_slice(m.positions());
        }
        kernel("hull", kernel_profile::hull_points(&points)).map(|m| Dynamic::from(SharedMesh::new(m)))
    }

    /// The Minkowski sum of two meshes: `a` grown by the shape of `b` (a cube with a sphere
    /// gives a rounded cube). Convex operands are summed exactly; others by convex parts.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let m = minkowski(cube(2), cube(1));
    /// assert_near(m.volume(), 27.0, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn minkowski(a: SharedMesh, b: SharedMesh) -> ScriptResult<SharedMesh> {
        let _task = crate::progress::start("minkowski", None);
        kernel("minkowski", kernel_profile::minkowski(&a.0, &b.0)).map(SharedMesh::new)
    }

    /// The mesh cut by the plane `normal · p = offset` into `[below, above]` (the side
    /// `normal` points away from first), each closed.
    ///
    /// ```rhai
    /// let parts = cube(2).split([0, 0, 1], 0.5);
    /// assert_near(parts[0].volume(), 6.0, 1e-9);
    /// assert_near(parts[1].volume(), 2.0, 1e-9);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn split(m: &mut SharedMesh, normal: Vector, offset: Number) -> ScriptResult<Array> {
        let n = vec3("split", "normal", &normal)?;
        let d = number("split", "offset", &offset)?;
        let (below, above) = kernel("split", kernel_profile::split(&m.0, n, d))?;
        Ok(vec![Dynamic::from(SharedMesh::new(below)), Dynamic::from(SharedMesh::new(above))])
    }

    /// The part of the mesh below the plane `normal · p = offset` (the side `normal` points away
    /// from), closed.
    ///
    /// ```rhai
    /// assert_near(cube(2).trim([0, 0, 1], 0).volume(), 4.0, 1e-9);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn trim(m: &mut SharedMesh, normal: Vector, offset: Number) -> ScriptResult<SharedMesh> {
        let n = vec3("trim", "normal", &normal)?;
        let d = number("trim", "offset", &offset)?;
        kernel("trim", kernel_profile::trim(&m.0, n, d)).map(SharedMesh::new)
    }

    /// The section of the mesh at height `z`: a `Profile`.
    ///
    /// ```rhai
    /// let s = cube(2).slice(0.25);
    /// assert_near(s.area(), 4.0, 1e-9);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn slice(m: &mut SharedMesh, z: Number) -> ScriptResult<Profile> {
        let z = number("slice", "z", &z)?;
        kernel("slice", kernel_profile::slice(&m.0, z)).map(Profile::new)
    }

    /// The shadow of the mesh on the xy plane: a `Profile`.
    ///
    /// ```rhai
    /// // The engine works on a grid of 1e-8: areas agree to about that.
    /// let s = cube(2).rotate([0, 0, 1], 45).project();
    /// assert_near(s.area(), 4.0, 1e-6);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn project(m: &mut SharedMesh) -> ScriptResult<Profile> {
        kernel("project", kernel_profile::project(&m.0)).map(Profile::new)
    }
}

/// A scale given as a number or as `[sx, sy]`.
pub type NumberOrPoint2 = Dynamic;

#[cfg(test)]
mod tests {
    use crate::{new_engine, EngineOptions};

    fn error_of(script: &str) -> String {
        let engine = new_engine(EngineOptions::default());
        engine.eval::<rhai::Dynamic>(script).map(|_| String::new()).unwrap_or_else(|e| e.to_string())
    }

    #[test]
    fn bad_input_is_refused_naming_the_function_and_the_argument() {
        // Each message names the function and what is wrong, never a panic or a broken mesh.
        for (script, expected) in [
            ("rect([0, 0], [0, 5])", "rect:"),
            ("circle(1, 2)", "circle: argument `segments` must be between 3"),
            ("polygon([[0, 0], [1, 1]])", "polygon:"),
            ("polygon([[0, 0], [1, 1], [2, 2]])", "polygon:"),
            ("polygon([[0, 0], [1, 0], [0, 1 / 0.0]])", "polygon:"),
            ("rect([0, 0], [1, 1]).offset(1, #{ join: \"bevel\" })", "offset: option `join`"),
            ("revolve(rect([-1, 0], [1, 1]))", "revolve:"),
            ("sweep(circle(1), [[0, 0, 0], [0, 0, 0], [0, 0, 1]])", "sweep:"),
            ("extrude(rect([0, 0], [1, 1]) - rect([0, 0], [1, 1]), 1)", "extrude:"),
            ("extrude(rect([0, 0], [1, 1]), 1, #{ twist: 10, slice: 3 })", "extrude: unknown option `slice`"),
            ("hull([])", "hull: argument `items` is empty"),
            ("hull([circle(1), cube(1)])", "hull: argument `items[0]`"),
            ("rect([0, 0], [1, 2, 3])", "rect: argument `max` must be a point [x, y]"),
            ("text(\"\")", "text:"),
            ("text(\"   \")", "text:"),
            ("text(\"a\", #{ size: 0 })", "text:"),
            ("text(\"a\", #{ halign: \"middle\" })", "text: option `halign`"),
            ("text(\"a\", #{ direction: \"up\" })", "text: option `direction`"),
            ("text(\"a\", #{ kerning: 1 })", "text: option `kerning`"),
            ("text(\"a\", #{ font: \"no-such-font.ttf\" })", "text: option `font`: no-such-font.ttf: file not found"),
            ("text(\"a\", #{ font: 3 })", "text: option `font` must be the path"),
        ] {
            let e = error_of(script);
            assert!(e.contains(expected), "{script}: {e}");
        }
    }

    #[test]
    fn a_font_file_that_is_not_a_font_is_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.ttf");
        std::fs::write(&bad, b"not a font at all").unwrap();
        let e = error_of(&format!("text(\"a\", #{{ font: {:?} }})", bad.display().to_string()));
        assert!(e.contains("text:") && e.to_lowercase().contains("font"), "{e}");
    }

    #[test]
    fn profiles_are_values_that_operations_leave_as_they_were() {
        let engine = new_engine(EngineOptions::default());
        let areas: rhai::Array = engine
            .eval(
                "let p = rect([0, 0], [2, 2]);\nlet q = p.offset(1).translate([5, 0]);\n[p.area(), p.bounds().min[0]]",
            )
            .unwrap();
        assert_eq!((areas[0].as_float(), areas[1].as_float()), (Ok(4.0), Ok(0.0)));
    }

    #[test]
    fn a_profile_round_trips_through_a_mesh_section() {
        // Extrude then slice gives the profile back: the area of a holed square, exactly.
        let engine = new_engine(EngineOptions::default());
        let area: f64 =
            engine.eval("let p = rect([0, 0], [3, 3]) - rect([1, 1], [2, 2]);\nextrude(p, 2).slice(1).area()").unwrap();
        assert!((area - 8.0).abs() < 1e-9, "{area}");
    }
}
