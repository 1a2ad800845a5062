//! Face parts: what groups of faces share — a colour, a name, and the recipe calls that made them.
//!
//! A mesh holds a small table of [`FacePart`]s and, per face, an index into it (4 bytes a face,
//! only when the mesh has parts at all). Every operation that makes a mesh from another carries
//! the index of each new face's parent face: transforms and reversal keep face ids, subdivision,
//! triangulation and refinement map each child face to its parent, combining and booleans join
//! the operands' tables and shift their ids, so a face of `a - b` exposed by `b` keeps `b`'s
//! part. A part is what a slicer calls a material or an object's colour; the origin chain is what
//! an editor follows from a clicked face back to the recipe line.
//!
//! Writers group faces by colour (glTF primitives, 3MF base materials, OBJ `usemtl`), so two
//! parts of one colour become one material.

use std::sync::Arc;

use super::{Mesh, MeshError};

/// An RGBA colour, components in `0..=1` (linear factors as glTF and 3MF take them; sRGB hex
/// strings are read as their byte values over 255, as OpenSCAD and slicers do).
pub type Rgba = [f32; 4];

/// A place in a recipe: 1-based line and column of a call, and the file it is in (`None` for the
/// main script when it was given as text, not read from a file).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Span {
    /// The script file, as the runner named it (the path given on the command line, or
    /// `stdlib/NAME.rhai` for a standard-library module).
    pub file: Option<Arc<str>>,
    /// 1-based line.
    pub line: u32,
    /// 1-based column (in characters).
    pub column: u32,
}

/// One step of the chain of calls that made a part, newest first: the call's name (`"cube"`,
/// `"translate"`, `"color"`, `"subtract"`), where it was written, and the step before it.
/// Steps are shared (`Arc`) between the meshes made from one another, so recording a step costs
/// one allocation per part, whatever the chain's length.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Origin {
    /// The script function called.
    pub call: Arc<str>,
    /// Where the call was written.
    pub span: Span,
    /// The step that made the mesh this call was applied to, if recorded.
    pub previous: Option<Arc<Origin>>,
}

impl Origin {
    /// The chain from this step back to the first, newest first.
    pub fn chain(&self) -> impl Iterator<Item = &Origin> {
        std::iter::successors(Some(self), |o| o.previous.as_deref())
    }

    /// The first step of the chain: the call that made the geometry (`cube`, `load`, …).
    #[must_use]
    pub fn first(&self) -> &Origin {
        self.chain().last().unwrap_or(self)
    }
}

/// What a group of faces shares. All fields optional: a default part is a face with nothing
/// recorded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FacePart {
    /// The colour of the faces (written as a material), if set.
    pub color: Option<Rgba>,
    /// A name (an object or material name read from a file, or a part's key in a map of meshes
    /// written to one file), if any.
    pub name: Option<Arc<str>>,
    /// The latest recipe call that made or changed these faces, with the chain before it.
    pub origin: Option<Arc<Origin>>,
}

impl FacePart {
    /// A part with only a colour.
    #[must_use]
    pub fn with_color(color: Rgba) -> FacePart {
        FacePart { color: Some(color), ..FacePart::default() }
    }
}

/// Checks a colour: four finite components in `0..=1`.
///
/// # Errors
/// [`MeshError::BadColor`] naming the first bad component.
pub fn check_color(c: Rgba) -> Result<(), MeshError> {
    match c.iter().position(|x| !(0.0..=1.0).contains(x)) {
        None => Ok(()),
        Some(i) => Err(MeshError::BadColor { component: i, value: f64::from(c[i]) }),
    }
}

/// Reads a CSS-style hex colour: `#rgb`, `#rgba`, `#rrggbb` or `#rrggbbaa` (the `#` required,
/// digits in either case); each byte over 255.
///
/// # Errors
/// A message saying what is wrong with `text` (the caller names the function and argument).
pub fn parse_hex_color(text: &str) -> Result<Rgba, String> {
    let Some(digits) = text.strip_prefix('#') else {
        return Err(format!("\"{text}\" is not a colour: hex colours start with `#` (\"#rrggbb\")"));
    };
    if let Some(bad) = digits.chars().find(|c| !c.is_ascii_hexdigit()) {
        return Err(format!("\"{text}\" is not a colour: `{bad}` is not a hex digit"));
    }
    let nibble = |i: usize| f32::from(u8::from_str_radix(&digits[i..=i], 16).unwrap_or(0));
    let byte = |i: usize| f32::from(u8::from_str_radix(&digits[2 * i..2 * i + 2], 16).unwrap_or(0));
    let mut c = [1.0f32; 4];
    match digits.len() {
        3 | 4 => {
            for (i, x) in c.iter_mut().enumerate().take(digits.len()) {
                *x = nibble(i) * 17.0 / 255.0;
            }
        }
        6 | 8 => {
            for (i, x) in c.iter_mut().enumerate().take(digits.len() / 2) {
                *x = byte(i) / 255.0;
            }
        }
        n => {
            return Err(format!(
                "\"{text}\" is not a colour: it has {n} hex digits, not 3, 4, 6 or 8 (\"#rgb\", \"#rrggbb\", \"#rrggbbaa\")"
            ))
        }
    }
    Ok(c)
}

/// `c` as `#rrggbb`, or `#rrggbbaa` when it is not opaque (each component rounded to a byte).
#[must_use]
pub fn to_hex_color(c: Rgba) -> String {
    let b = c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
    if b[3] == 255 {
        format!("#{:02x}{:02x}{:02x}", b[0], b[1], b[2])
    } else {
        format!("#{:02x}{:02x}{:02x}{:02x}", b[0], b[1], b[2], b[3])
    }
}

impl Mesh {
    /// The part table (empty when the mesh has no parts).
    #[must_use]
    pub fn parts(&self) -> &[FacePart] {
        &self.parts
    }

    /// The part id of every face (#F, each below `parts().len()`), when the mesh has parts.
    #[must_use]
    pub fn face_part_ids(&self) -> Option<&[u32]> {
        self.face_parts.as_deref()
    }

    /// The part of face `f`, when the mesh has parts.
    #[must_use]
    pub fn face_part(&self, f: u32) -> Option<&FacePart> {
        self.face_parts.as_ref().map(|ids| &self.parts[ids[f as usize] as usize])
    }

    /// The colour of face `f`, when it has one.
    #[must_use]
    pub fn face_color(&self, f: u32) -> Option<Rgba> {
        self.face_part(f).and_then(|p| p.color)
    }

    /// Whether any face has a colour.
    #[must_use]
    pub fn has_face_colors(&self) -> bool {
        self.face_parts.is_some() && self.parts.iter().any(|p| p.color.is_some())
    }

    /// Sets the part table and one part id per face.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] when `ids` does not have one entry per face or names a part
    /// past the table; [`MeshError::BadColor`] for a colour out of `0..=1`. Unchanged on error.
    pub fn set_face_parts(&mut self, ids: Vec<u32>, parts: Vec<FacePart>) -> Result<(), MeshError> {
        if ids.len() != self.face_count() {
            return Err(MeshError::NoSuchElement {
                what: "face part id",
                id: ids.len() as u64,
                count: self.face_count(),
            });
        }
        if let Some(&bad) = ids.iter().find(|&&i| i as usize >= parts.len()) {
            return Err(MeshError::NoSuchElement { what: "face part", id: u64::from(bad), count: parts.len() });
        }
        for c in parts.iter().filter_map(|p| p.color) {
            check_color(c)?;
        }
        self.face_parts = Some(ids);
        self.parts = parts;
        Ok(())
    }

    /// Removes every part (colours, names, origins) from the faces.
    pub fn clear_face_parts(&mut self) {
        self.face_parts = None;
        self.parts.clear();
    }

    /// The mesh with every face coloured `color`: a mesh without parts gets one part of that
    /// colour; a mesh with parts keeps them (their names and origins) with the colour replaced.
    ///
    /// # Errors
    /// [`MeshError::BadColor`] for a component outside `0..=1` (NaN included).
    pub fn set_color(&mut self, color: Rgba) -> Result<(), MeshError> {
        check_color(color)?;
        self.ensure_parts();
        for p in &mut self.parts {
            p.color = Some(color);
        }
        Ok(())
    }

    /// The mesh with the faces `faces` coloured `color` and the others as they were: each part
    /// those faces are in is copied with the colour replaced (names and origins kept).
    ///
    /// # Errors
    /// [`MeshError::BadColor`] for a component outside `0..=1` (NaN included);
    /// [`MeshError::NoSuchElement`] for a face id out of range. Unchanged on error.
    pub fn color_faces(&mut self, faces: &[u32], color: Rgba) -> Result<(), MeshError> {
        check_color(color)?;
        for &f in faces {
            self.check_face(i64::from(f))?;
        }
        self.ensure_parts();
        let mut recoloured: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        for &f in faces {
            let old = self.face_parts.as_ref().map_or(0, |ids| ids[f as usize]);
            let new = *recoloured.entry(old).or_insert_with(|| {
                let part = FacePart { color: Some(color), ..self.parts[old as usize].clone() };
                self.parts.push(part);
                self.parts.len() as u32 - 1
            });
            if let Some(ids) = &mut self.face_parts {
                ids[f as usize] = new;
            }
        }
        self.drop_unused_parts();
        Ok(())
    }

    /// Removes the parts no face is in, renumbering the others in order.
    fn drop_unused_parts(&mut self) {
        let Some(ids) = &mut self.face_parts else { return };
        let mut used = vec![false; self.parts.len()];
        for &i in ids.iter() {
            used[i as usize] = true;
        }
        if used.iter().all(|&u| u) {
            return;
        }
        let mut renumber = vec![u32::MAX; self.parts.len()];
        let mut kept = Vec::new();
        for (i, part) in std::mem::take(&mut self.parts).into_iter().enumerate() {
            if used[i] {
                renumber[i] = kept.len() as u32;
                kept.push(part);
            }
        }
        for i in ids.iter_mut() {
            *i = renumber[*i as usize];
        }
        self.parts = kept;
    }

    /// Applies `f` to every part (a mesh without parts gets one default part first, so `f` sees
    /// every face).
    pub fn map_parts(&mut self, mut f: impl FnMut(&mut FacePart)) {
        self.ensure_parts();
        self.parts.iter_mut().for_each(&mut f);
    }

    /// Records the recipe call `call` at `span` as the newest step of every part's origin chain.
    pub fn record_origin(&mut self, call: &str, span: Span) {
        let call: Arc<str> = Arc::from(call);
        self.map_parts(|p| {
            p.origin = Some(Arc::new(Origin { call: call.clone(), span: span.clone(), previous: p.origin.take() }));
        });
    }

    /// Gives this mesh the parts of `from`: face `f` takes the part of `from`'s face
    /// `parent_faces[f]` (one entry per face of this mesh). The way an operation that builds a new
    /// mesh (subdivision, triangulation, remeshing, decimation) carries colours and origins.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] when `parent_faces` does not have one entry per face or names
    /// a face `from` does not have. Unchanged on error.
    pub fn inherit_parts(&mut self, from: &Mesh, parent_faces: &[u32]) -> Result<(), MeshError> {
        let Some(src) = &from.face_parts else {
            self.clear_face_parts();
            return Ok(());
        };
        if parent_faces.len() != self.face_count() {
            return Err(MeshError::NoSuchElement {
                what: "parent face",
                id: parent_faces.len() as u64,
                count: self.face_count(),
            });
        }
        let ids = parent_faces
            .iter()
            .map(|&f| {
                src.get(f as usize).copied().ok_or(MeshError::NoSuchElement {
                    what: "parent face",
                    id: u64::from(f),
                    count: from.face_count(),
                })
            })
            .collect::<Result<Vec<u32>, _>>()?;
        self.face_parts = Some(ids);
        self.parts.clone_from(&from.parts);
        Ok(())
    }

    /// Gives a mesh without parts one default part covering every face.
    fn ensure_parts(&mut self) {
        if self.face_parts.is_none() {
            self.parts = vec![FacePart::default()];
            self.face_parts = Some(vec![0; self.face_count()]);
        }
    }
}

/// The part tables of `meshes` joined in order, and each mesh's first id in the joined table;
/// `None` when no mesh has parts. A mesh without parts gets one default part in the table.
pub(crate) fn joined_parts(meshes: &[&Mesh]) -> Option<(Vec<FacePart>, Vec<u32>)> {
    if meshes.iter().all(|m| m.face_parts.is_none()) {
        return None;
    }
    let mut table = Vec::new();
    let mut offsets = Vec::with_capacity(meshes.len());
    for m in meshes {
        offsets.push(table.len() as u32);
        if m.face_parts.is_some() {
            table.extend_from_slice(&m.parts);
        } else {
            table.push(FacePart::default());
        }
    }
    Some((table, offsets))
}

/// The part id of face `f` of `m` in a joined table where `m`'s first id is `offset`.
pub(crate) fn joined_id(m: &Mesh, offset: u32, f: u32) -> u32 {
    offset + m.face_parts.as_ref().map_or(0, |ids| ids[f as usize])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    const RED: Rgba = [1.0, 0.0, 0.0, 1.0];
    const BLUE: Rgba = [0.0, 0.0, 1.0, 1.0];

    /// The ±1 cube with its −x, +x, −y faces red and the others blue (cube faces are −x +x −y
    /// +y −z +z).
    fn two_colour_cube() -> Mesh {
        let mut m = Mesh::cube(2.0);
        m.set_face_parts(vec![0, 0, 0, 1, 1, 1], vec![FacePart::with_color(RED), FacePart::with_color(BLUE)]).unwrap();
        m
    }

    /// The colour a face of a refined or moved two-colour cube must have: its parent is the cube
    /// face its normal points most along.
    fn expected(n: Vec3) -> Rgba {
        let a = n.abs();
        if a.x >= a.y.max(a.z) || (a.y >= a.z && n.y < 0.0) {
            RED
        } else {
            BLUE
        }
    }

    #[test]
    fn some_faces_recoloured_keep_the_others_and_leave_no_unused_part() {
        let mut m = two_colour_cube();
        // All red faces turned green: the red part goes, the blue stays.
        let green: Rgba = [0.0, 1.0, 0.0, 1.0];
        m.color_faces(&[0, 1, 2], green).unwrap();
        assert_eq!(m.parts().len(), 2);
        assert_eq!(
            (0..6).map(|f| m.face_color(f).unwrap()).collect::<Vec<_>>(),
            [green, green, green, BLUE, BLUE, BLUE]
        );
        // One blue face turned red: a third part, the others as they were.
        m.color_faces(&[5], RED).unwrap();
        assert_eq!(m.face_color(5), Some(RED));
        assert_eq!(m.face_color(4), Some(BLUE));
        assert_eq!(m.parts().len(), 3);
        // A mesh without parts gets them; bad input leaves the mesh as it was.
        let mut plain = Mesh::cube(1.0);
        plain.color_faces(&[2], RED).unwrap();
        assert_eq!((plain.face_color(1), plain.face_color(2)), (None, Some(RED)));
        let before = m.clone();
        assert!(matches!(m.color_faces(&[1, 6], RED), Err(MeshError::NoSuchElement { .. })));
        assert!(matches!(m.color_faces(&[1], [2.0, 0.0, 0.0, 1.0]), Err(MeshError::BadColor { component: 0, .. })));
        assert_eq!(m.face_part_ids(), before.face_part_ids());
        assert_eq!(m.parts(), before.parts());
    }

    #[test]
    fn hex_colours_read_every_css_length_and_refuse_the_rest() {
        assert_eq!(parse_hex_color("#ff0000").unwrap(), RED);
        assert_eq!(parse_hex_color("#F00").unwrap(), RED);
        assert_eq!(parse_hex_color("#0000ff80").unwrap(), [0.0, 0.0, 1.0, 128.0 / 255.0]);
        assert_eq!(parse_hex_color("#00f8").unwrap(), [0.0, 0.0, 1.0, 136.0 / 255.0]);
        assert_eq!(parse_hex_color("#ff00").unwrap(), [1.0, 1.0, 0.0, 0.0], "four digits are #rgba");
        for (bad, says) in [("ff0000", "start with `#`"), ("#12345", "5 hex digits"), ("#gg0000", "`g`")] {
            let e = parse_hex_color(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
        assert_eq!(to_hex_color(parse_hex_color("#12abef").unwrap()), "#12abef");
        assert_eq!(to_hex_color([0.0, 0.0, 1.0, 0.5]), "#0000ff80");
    }

    #[test]
    fn colours_outside_zero_to_one_are_refused_and_leave_the_mesh() {
        let mut m = Mesh::cube(1.0);
        let e = m.set_color([0.5, f32::NAN, 0.0, 1.0]).unwrap_err();
        assert!(matches!(e, MeshError::BadColor { component: 1, .. }), "{e}");
        assert_eq!(m.set_color([1.5, 0.0, 0.0, 1.0]).unwrap_err(), MeshError::BadColor { component: 0, value: 1.5 });
        assert!(m.face_part_ids().is_none() && m.parts().is_empty());
        assert!(m.set_face_parts(vec![0; 5], vec![FacePart::default()]).is_err(), "one id per face");
        assert!(m.set_face_parts(vec![1; 6], vec![FacePart::default()]).is_err(), "ids within the table");
    }

    #[test]
    fn set_color_keeps_origins_and_colours_every_face() {
        let mut m = two_colour_cube();
        m.record_origin("cube", Span { file: None, line: 3, column: 9 });
        m.set_color([0.0, 1.0, 0.0, 1.0]).unwrap();
        assert_eq!(m.parts().len(), 2, "parts kept");
        assert!((0..6).all(|f| m.face_color(f) == Some([0.0, 1.0, 0.0, 1.0])));
        assert!(m.parts().iter().all(|p| p.origin.as_ref().unwrap().call.as_ref() == "cube"));
    }

    #[test]
    fn origins_chain_newest_first() {
        let mut m = Mesh::cube(1.0);
        m.record_origin("cube", Span { file: Some("a.rhai".into()), line: 1, column: 9 });
        m.record_origin("translate", Span { file: Some("a.rhai".into()), line: 1, column: 17 });
        let o = m.face_part(4).unwrap().origin.as_ref().unwrap();
        let calls: Vec<&str> = o.chain().map(|o| o.call.as_ref()).collect();
        assert_eq!(calls, ["translate", "cube"]);
        assert_eq!(o.first().span.column, 9);
    }

    #[test]
    fn transforms_and_reversal_keep_face_colours() {
        let m = two_colour_cube();
        for moved in [m.translate(Vec3::new(1.0, 2.0, 3.0)), m.scale(Vec3::splat(2.0)), m.mirror(Vec3::X)] {
            assert_eq!(moved.face_part_ids(), m.face_part_ids(), "face ids are kept");
            assert_eq!(moved.parts(), m.parts());
        }
    }

    #[test]
    fn subdivision_and_triangulation_give_each_child_its_parents_colour() {
        // Every edge sharp: the faces stay flat, so each child's normal is its parent's.
        let mut m = two_colour_cube();
        m.crease_all();
        let cc = m.catmull_clark(2).unwrap();
        let mut tri = m.triangulate().unwrap();
        tri.crease_all();
        let lp = tri.loop_subdivide(2).unwrap();
        for (name, r, faces) in [("catmull-clark", &cc, 96), ("triangulate", &tri, 12), ("loop", &lp, 192)] {
            assert_eq!(r.face_count(), faces, "{name}");
            for f in 0..r.face_count() as u32 {
                // Why: a child face's normal still points along its parent's cube face.
                assert_eq!(r.face_color(f), Some(expected(r.face_normal(f))), "{name} face {f}");
            }
        }
    }

    #[test]
    fn combine_joins_the_tables_and_gives_plain_meshes_a_default_part() {
        let a = two_colour_cube();
        let b = Mesh::cube(1.0);
        let c = Mesh::combine(&[&a, &b, &a]).unwrap();
        assert_eq!(c.parts().len(), 5);
        let ids = c.face_part_ids().unwrap();
        assert_eq!(ids, [0, 0, 0, 1, 1, 1, 2, 2, 2, 2, 2, 2, 3, 3, 3, 4, 4, 4]);
        assert_eq!(c.face_color(7), None);
        assert_eq!(c.face_color(17), Some(BLUE));
        let plain = Mesh::combine(&[&b, &b]).unwrap();
        assert!(plain.face_part_ids().is_none(), "no parts made up");
    }

    #[test]
    fn edits_give_new_faces_the_removed_faces_part() {
        let mut m = two_colour_cube();
        // Split the red −x face along a diagonal.
        let hs: Vec<u32> = m.face_halfedges(0).collect();
        let (h, _) = m.split_face(hs[0], hs[2]).unwrap();
        let f = m.face(h);
        assert_eq!(m.face_count(), 7);
        assert_eq!(m.face_part_ids().unwrap().len(), 7);
        assert_eq!(m.face_color(f), Some(RED));
        for g in 0..7 {
            assert_eq!(m.face_color(g), Some(expected(m.face_normal(g))), "face {g}");
        }
    }

    #[test]
    fn inherit_parts_checks_its_map() {
        let m = two_colour_cube();
        let mut t = m.triangulate().unwrap();
        assert!(t.inherit_parts(&m, &[0; 3]).is_err());
        assert!(t.inherit_parts(&m, &[9; 12]).is_err());
        t.inherit_parts(&m, &[5; 12]).unwrap();
        assert!((0..12).all(|f| t.face_color(f) == Some(BLUE)));
    }
}
