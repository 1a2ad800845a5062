//! Colours on faces (API.md §Appearance; kernel `mesh::FacePart`): `m.color(c)` colours every
//! face; the colour rides on the faces through transforms, subdivision, booleans and `combine`,
//! and is written as materials by `save` and `run -o` (glTF, 3MF, OBJ `.mtl`, PLY).
//! `m.face_color(f)` and `m.colors()` read them back.

use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::mesh::{parse_hex_color, Rgba};
use rhai::plugin::*;
use rhai::{Array, FnPtr, INT};

use super::mesh::SharedMesh;
use crate::convert::{closure_error, error, fail, ids, kernel, number, type_name, Color, ColorOrUnit, ScriptResult};

/// A colour argument: `[r, g, b]` or `[r, g, b, a]` with components 0–1, or a hex string
/// `"#rgb"`, `"#rgba"`, `"#rrggbb"`, `"#rrggbbaa"`. Errors name `func` and `arg`.
pub fn color_value(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Rgba> {
    if let Some(s) = v.read_lock::<rhai::ImmutableString>() {
        return parse_hex_color(s.as_str()).map_err(|why| error(func, format!("argument `{arg}`: {why}")));
    }
    let Some(a) = v.read_lock::<Array>() else {
        return fail(
            func,
            format!("argument `{arg}` must be [r, g, b], [r, g, b, a] (0 to 1) or \"#rrggbb\", got {}", type_name(v)),
        );
    };
    if a.len() != 3 && a.len() != 4 {
        return fail(
            func,
            format!("argument `{arg}` must have 3 components [r, g, b] or 4 [r, g, b, a], got {}", a.len()),
        );
    }
    let mut c = [1.0f32; 4];
    for (i, x) in a.iter().enumerate() {
        let n = number(func, &format!("{arg}[{i}]"), x)?;
        if !(0.0..=1.0).contains(&n) {
            let hint = if n > 1.0 && n <= 255.0 { " (components are 0 to 1: divide bytes by 255)" } else { "" };
            return fail(func, format!("argument `{arg}[{i}]` must be between 0 and 1, got {}{hint}", fmt_num(n)));
        }
        c[i] = n as f32;
    }
    Ok(c)
}

/// A colour as the script sees it: `[r, g, b, a]`, components 0–1.
fn color_array(c: Rgba) -> Array {
    c.iter().map(|&x| Dynamic::from(f64::from(x))).collect()
}

#[export_module]
pub mod color_api {
    use super::*;

    /// This mesh with every face coloured `c`: `[r, g, b]` or `[r, g, b, a]` (components 0 to
    /// 1) or a hex string `"#rrggbb"` (also `"#rgb"`, `"#rrggbbaa"`). The colour stays on the
    /// faces through moves, subdivision, booleans (a face of `a - b` cut by `b` keeps `b`'s
    /// colour) and `combine`, and `save` writes it as a material (glTF, 3MF, OBJ with `.mtl`,
    /// PLY face colours).
    ///
    /// ```rhai
    /// let red = cube(2).color("#ff0000");
    /// let bite = red - uv_sphere(1, 24, 12).translate([0, 0, 1]).color([0, 0, 1]);
    /// assert_eq(red.face_color(0), [1.0, 0.0, 0.0, 1.0]);
    /// assert_eq(bite.colors().len(), 2);   // red outside, blue in the bite
    /// ```
    #[rhai_fn(return_raw, pure)]
    pub fn color(m: &mut SharedMesh, c: Color) -> ScriptResult<SharedMesh> {
        let rgba = color_value("color", "c", &c)?;
        let mut out = (*m.0).clone();
        kernel("color", out.set_color(rgba))?;
        Ok(SharedMesh(std::sync::Arc::new(out), m.1.clone()))
    }

    /// This mesh with the faces `faces` (face ids) coloured `c`, the others as they were (a
    /// face without a colour stays without). A new mesh; this one is left as it was.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// let top = m.faces().len() - 1;                       // pick faces by id
    /// let two = m.color([1, 0, 0], [0, top]);
    /// assert_eq(two.face_color(0), [1.0, 0.0, 0.0, 1.0]);
    /// assert_eq(two.face_color(1), ());
    /// assert_eq(two.colors().len(), 1);
    /// ```
    #[rhai_fn(name = "color", return_raw, pure)]
    pub fn color_faces(m: &mut SharedMesh, c: Color, faces: Array) -> ScriptResult<SharedMesh> {
        let rgba = color_value("color", "c", &c)?;
        let f = ids("color", "faces", &faces)?;
        let mut out = (*m.0).clone();
        kernel("color", out.color_faces(&f, rgba))?;
        Ok(SharedMesh(std::sync::Arc::new(out), m.1.clone()))
    }

    /// The ids of the faces for which the closure `f(centre, normal)` returns `true`: `centre`
    /// is the face's centroid and `normal` its unit normal (both `Vec3`). For colouring or
    /// otherwise treating a region picked by place and facing, as CadQuery's face selectors do.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// let top = m.faces_where(|c, n| n.z > 0.9);
    /// assert_eq(top.len(), 1);
    /// let lit = m.color("#999").color("#ffcc00", m.faces_where(|c, n| c.x > 0.5 || n.z > 0.9));
    /// assert_eq(lit.colors().len(), 2);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn faces_where(ctx: NativeCallContext, m: &mut SharedMesh, f: FnPtr) -> ScriptResult<Array> {
        let mesh = std::sync::Arc::clone(&m.0);
        let mut out = Array::new();
        for face in 0..mesh.face_count() as u32 {
            let (centre, normal) = (mesh.face_centroid(face), mesh.face_normal(face));
            let keep: Dynamic = f
                .call_within_context(&ctx, (centre, normal))
                .map_err(|e| error("faces_where", closure_error("the closure", &e)))?;
            let keep = keep.as_bool().map_err(|t| {
                error("faces_where", format!("the closure must return true or false, got {t} for face {face}"))
            })?;
            if keep {
                out.push(Dynamic::from(INT::from(face)));
            }
        }
        Ok(out)
    }

    /// The colour of face `f` as `[r, g, b, a]`, or `()` when the face has none.
    ///
    /// ```rhai
    /// let m = combine([cube(1).color([0, 1, 0]), cube(1)]);
    /// assert_eq(m.face_color(0), [0.0, 1.0, 0.0, 1.0]);
    /// assert_eq(m.face_color(6), ());
    /// ```
    #[rhai_fn(return_raw, pure)]
    pub fn face_color(m: &mut SharedMesh, f: INT) -> ScriptResult<ColorOrUnit> {
        let f = kernel("face_color", m.0.check_face(f))?;
        Ok(m.0.face_color(f).map_or(Dynamic::UNIT, |c| Dynamic::from_array(color_array(c))))
    }

    /// The distinct colours of the faces, each `[r, g, b, a]`, in the order first met by face
    /// id; empty for a mesh without colours.
    ///
    /// ```rhai
    /// let m = cube(2).color("#f00") + cube(1).translate([1, 1, 1]).color("#00f");
    /// assert_eq(m.colors(), [[1.0, 0.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]]);
    /// ```
    #[rhai_fn(pure)]
    pub fn colors(m: &mut SharedMesh) -> Array {
        let mut seen: Vec<Rgba> = Vec::new();
        for f in 0..m.0.face_count() as u32 {
            if let Some(c) = m.0.face_color(f) {
                if !seen.contains(&c) {
                    seen.push(c);
                }
            }
        }
        seen.into_iter().map(|c| Dynamic::from_array(color_array(c))).collect()
    }
}
