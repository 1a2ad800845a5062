//! 3MF, the 3D Manufacturing Format (3MF Consortium, "3MF Core Specification" 1.3, and the
//! "Materials and Properties Extension" 1.2): read and write.
//!
//! A 3MF file is a zip package (Open Packaging Conventions): `[Content_Types].xml`,
//! `_rels/.rels` naming the model part, and the model part (`3D/3dmodel.model`), XML with
//! `<resources>` (objects with a `<mesh>` of `<vertices>` and `<triangles>`, or `<components>`
//! that place other objects) and a `<build>` of items, each an object with an optional affine
//! `transform` (core §3.4.2 and §4.1–4.2).
//!
//! Writing gives one object and one build item; positions as the shortest decimal that reads
//! back to the same `f64` (so a round trip keeps every bit); every face triangulated as
//! [`super::face_triangles`] does. Vertex colours are written as a `<m:colorgroup>` with one
//! colour per vertex (materials extension §3.3). A mesh with face parts (colours, names) is
//! written with one `<basematerials>` entry per colour and one named object per part name
//! (see `parts_model_xml`); base materials belong to the core namespace (core §5.1), colour
//! groups to the materials one. A boolean result's sources (provenance, a debugging view) are
//! not written: they are not the model's colour. What is written validates against the Consortium's core and
//! materials schemas (checked in CI over every 3MF the tests write). 3MF is Z-up and in millimetres by specification: positions are
//! written as they are.
//!
//! Reading places every build item's object (through nested components, with their
//! transforms) into one mesh, and turns colour groups and base materials into vertex colours
//! (the first triangle that colours a vertex decides). Coordinates are scaled from the model's
//! `unit` to millimetres (core §3.3). Objects in other model parts, named by the production
//! extension's `p:path` on items and components (production extension §2–3), are read from
//! those parts; a model that requires any extension other than materials and production
//! (`requiredextensions`: beam lattices, slices, ...) is refused as unsupported, naming it. Shared vertices are named by the file,
//! so nothing is welded. The package is read with its declared sizes checked against the memory
//! budget before anything is inflated, and no part is inflated past its declared size, so a
//! zip bomb is refused, not unpacked.

use std::collections::HashMap;
use std::io::{Cursor, Read, Write};
use std::path::Path;
use std::sync::Arc;

use quick_xml::events::{BytesStart, Event};

use super::error::IoError;
use super::weld::Weld;
use crate::diagnose::Repairs;
use crate::limits::LimitError;
use crate::math::Vec3;
use crate::mesh::{FacePart, Mesh, MeshError};

const CORE_NS: &str = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";
const MATERIAL_NS: &str = "http://schemas.microsoft.com/3dmanufacturing/material/2015/02";
const PRODUCTION_NS: &str = "http://schemas.microsoft.com/3dmanufacturing/production/2015/06";
const MODEL_REL: &str = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";
/// Nesting of components deeper than this is refused (a cycle, or a file built to explode).
const MAX_DEPTH: usize = 32;

fn tmf_error(path: &Path, reason: impl Into<String>) -> IoError {
    IoError::ThreeMf { path: path.into(), reason: reason.into() }
}

/// Writes `mesh` as a 3MF package to `out` (see the module documentation).
///
/// # Errors
/// [`IoError::Mesh`] when a face cannot be triangulated; [`IoError::Write`] for errors of
/// `out`. `path` is only named in errors.
///
/// See also [`read_3mf`], [`super::save`].
pub fn write_3mf<W: Write>(mesh: &Mesh, out: &mut W, path: &Path) -> Result<(), IoError> {
    let (mesh, tris, arities) = super::face_triangles(mesh).map_err(|e| IoError::from_mesh(path, e))?;
    let mesh = &*mesh;
    let stopped = |e: LimitError| IoError::from_mesh(path, MeshError::Limit(e));
    let model = if super::face_groups::has_parts(mesh) {
        parts_model_xml(mesh, &tris, &arities)
    } else {
        model_xml(mesh, &tris)
    }
    .map_err(stopped)?;
    let write_err = |e: std::io::Error| IoError::Write { path: path.into(), source: e };
    let zip_err = |e: zip::result::ZipError| IoError::Write { path: path.into(), source: std::io::Error::other(e) };
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    // A fixed date (1980-01-01, zip's epoch) so that the same mesh gives the same bytes.
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default())
        .unix_permissions(0o644);
    let parts: [(&str, &[u8]); 3] = [
        ("[Content_Types].xml", CONTENT_TYPES.as_bytes()),
        ("_rels/.rels", RELS.as_bytes()),
        ("3D/3dmodel.model", model.as_bytes()),
    ];
    for (name, data) in parts {
        zip.start_file(name, options).map_err(zip_err)?;
        // Deflate runs at tens of megabytes a second: a stop is seen between chunks.
        for chunk in data.chunks(DEFLATE_CHUNK) {
            crate::limits::poll().map_err(stopped)?;
            zip.write_all(chunk).map_err(write_err)?;
        }
    }
    let bytes = zip.finish().map_err(zip_err)?.into_inner();
    out.write_all(&bytes).map_err(write_err)
}

const CONTENT_TYPES: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">\
<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>\
<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>\
</Types>\n";

const RELS: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">\
<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" \
Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>\
</Relationships>\n";

/// `#RRGGBBAA` of a colour in [0, 1].
fn hex(c: [f32; 4]) -> String {
    let b = c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
    format!("#{:02X}{:02X}{:02X}{:02X}", b[0], b[1], b[2], b[3])
}

/// Bytes of the model part compressed between two polls of the cancellation token.
const DEFLATE_CHUNK: usize = 1 << 20;

/// The model part's XML.
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] vertices and triangles).
fn model_xml(mesh: &Mesh, tris: &[u32]) -> Result<String, LimitError> {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(64 * mesh.vertex_count() + 48 * tris.len() / 3 + 1024);
    let _ = write!(
        s,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" \
         xmlns=\"{CORE_NS}\" xmlns:m=\"{MATERIAL_NS}\">\n\
         <metadata name=\"Application\">blocksmith {}</metadata>\n<resources>\n",
        env!("CARGO_PKG_VERSION")
    );
    // Property group id 2 (the object is 1): per-vertex colours.
    let colors = mesh.vertex_colors();
    if let Some(colors) = colors {
        s += "<m:colorgroup id=\"2\">\n";
        for &c in colors {
            let _ = writeln!(s, "<m:color color=\"{}\"/>", hex(c));
        }
        s += "</m:colorgroup>\n";
    }
    let object_pid = if colors.is_some() { " pid=\"2\" pindex=\"0\"" } else { "" };
    let _ = write!(s, "<object id=\"1\" type=\"model\"{object_pid}>\n<mesh>\n<vertices>\n");
    let mut fbuf = zmij::Buffer::new();
    for (i, p) in mesh.positions().iter().enumerate() {
        crate::limits::poll_at(i)?;
        s += "<vertex x=\"";
        s += fbuf.format(p.x);
        s += "\" y=\"";
        s += fbuf.format(p.y);
        s += "\" z=\"";
        s += fbuf.format(p.z);
        s += "\"/>\n";
    }
    s += "</vertices>\n<triangles>\n";
    for (i, t) in tris.chunks_exact(3).enumerate() {
        crate::limits::poll_at(i)?;
        let _ = write!(s, "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"", t[0], t[1], t[2]);
        if colors.is_some() {
            let _ = write!(s, " pid=\"2\" p1=\"{}\" p2=\"{}\" p3=\"{}\"", t[0], t[1], t[2]);
        }
        s += "/>\n";
    }
    s += "</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n<item objectid=\"1\"/>\n</build>\n</model>\n";
    Ok(s)
}

/// The model part's XML of a mesh with face parts (colours, names): one `<basematerials>`
/// entry per colour (core §5.1; faces without a colour white, unless no face of their object
/// has one: then the object has no material), and one object per part name
/// (unnamed faces together), each with the vertices its triangles use (in the mesh's order) and a `name`, placed by
/// one build item each, so a slicer lists named parts with their colours.
///
/// # Errors
/// As [`model_xml`].
fn parts_model_xml(mesh: &Mesh, tris: &[u32], arities: &[u32]) -> Result<String, LimitError> {
    use std::fmt::Write as _;
    let groups = super::face_groups::FaceGroups::of(mesh);
    let mut s = String::with_capacity(64 * mesh.vertex_count() + 60 * tris.len() / 3 + 1024);
    let _ = write!(
        s,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" \
         xmlns=\"{CORE_NS}\">\n\
         <metadata name=\"Application\">blocksmith {}</metadata>\n<resources>\n<basematerials id=\"1\">\n",
        env!("CARGO_PKG_VERSION")
    );
    for (k, c) in groups.colors.iter().enumerate() {
        let c = c.unwrap_or([1.0; 4]);
        let _ = writeln!(s, "<base name=\"{}\" displaycolor=\"{}\"/>", escape(&groups.material_name(k)), hex(c));
    }
    s += "</basematerials>\n";
    // The triangles of each face, and each object's triangles in face order.
    let mut first = Vec::with_capacity(arities.len() + 1);
    first.push(0usize);
    for &a in arities {
        first.push(first[first.len() - 1] + a as usize - 2);
    }
    let mut fbuf = zmij::Buffer::new();
    let mut local = vec![u32::MAX; mesh.vertex_count()];
    for (k, (name, faces)) in groups.objects.iter().zip(&groups.object_faces).enumerate() {
        let name_attr = name.as_deref().map(|n| format!(" name=\"{}\"", escape(n))).unwrap_or_default();
        // An object none of whose faces has a colour takes no material, so it reads back
        // uncoloured (one mixing both gives its uncoloured faces the white "default").
        let plain = faces.iter().all(|&f| groups.colors[groups.material_of_face(f) as usize].is_none());
        let pid =
            if plain { String::new() } else { format!(" pid=\"1\" pindex=\"{}\"", groups.material_of_face(faces[0])) };
        let _ = write!(s, "<object id=\"{}\" type=\"model\"{name_attr}{pid}>\n<mesh>\n<vertices>\n", k + 2);
        let face_tris = |f: u32| &tris[3 * first[f as usize]..3 * first[f as usize + 1]];
        // The object's vertices in the mesh's order, so a mesh whose parts hold runs of
        // vertices (a loaded scene's nodes, a fused assembly) reads back in its own order.
        let mut used = Vec::new();
        for &f in faces {
            for &v in face_tris(f) {
                if local[v as usize] == u32::MAX {
                    local[v as usize] = 0;
                    used.push(v);
                }
            }
        }
        used.sort_unstable();
        for (i, &v) in used.iter().enumerate() {
            local[v as usize] = i as u32;
        }
        for (i, &v) in used.iter().enumerate() {
            crate::limits::poll_at(i)?;
            let p = mesh.position(v);
            s += "<vertex x=\"";
            s += fbuf.format(p.x);
            s += "\" y=\"";
            s += fbuf.format(p.y);
            s += "\" z=\"";
            s += fbuf.format(p.z);
            s += "\"/>\n";
        }
        s += "</vertices>\n<triangles>\n";
        for (i, &f) in faces.iter().enumerate() {
            crate::limits::poll_at(i)?;
            let m = groups.material_of_face(f);
            for t in face_tris(f).chunks_exact(3) {
                let [a, b, c] = [t[0], t[1], t[2]].map(|v| local[v as usize]);
                if plain {
                    let _ = writeln!(s, "<triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>");
                } else {
                    let _ = writeln!(s, "<triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\" pid=\"1\" p1=\"{m}\"/>");
                }
            }
        }
        for &v in &used {
            local[v as usize] = u32::MAX;
        }
        s += "</triangles>\n</mesh>\n</object>\n";
    }
    s += "</resources>\n<build>\n";
    for k in 0..groups.objects.len() {
        let _ = writeln!(s, "<item objectid=\"{}\"/>", k + 2);
    }
    s += "</build>\n</model>\n";
    Ok(s)
}

/// `text` with the five XML special characters escaped, for attribute values.
fn escape(text: &str) -> std::borrow::Cow<'_, str> {
    quick_xml::escape::escape(text)
}

/// An affine map as 3MF writes it: `p' = p · M + t` with row vectors (core §3.4.2).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine {
    m: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    const IDENTITY: Affine = Affine { m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], t: [0.0; 3] };

    fn parse(text: &str) -> Option<Affine> {
        let v: Vec<f64> = text.split_ascii_whitespace().map(str::parse).collect::<Result<_, _>>().ok()?;
        if v.len() != 12 || v.iter().any(|x| !x.is_finite()) {
            return None;
        }
        Some(Affine { m: [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]], t: [v[9], v[10], v[11]] })
    }

    fn apply(&self, p: Vec3) -> Vec3 {
        if *self == Affine::IDENTITY {
            // Exactly as written (−0 stays −0).
            return p;
        }
        let m = &self.m;
        Vec3::new(
            p.x * m[0][0] + p.y * m[1][0] + p.z * m[2][0] + self.t[0],
            p.x * m[0][1] + p.y * m[1][1] + p.z * m[2][1] + self.t[1],
            p.x * m[0][2] + p.y * m[1][2] + p.z * m[2][2] + self.t[2],
        )
    }

    /// `self` then `outer`.
    fn then(&self, outer: &Affine) -> Affine {
        let mut r = Affine { m: [[0.0; 3]; 3], t: [0.0; 3] };
        for i in 0..3 {
            for j in 0..3 {
                r.m[i][j] = (0..3).map(|k| self.m[i][k] * outer.m[k][j]).sum();
            }
        }
        let t = outer.apply(Vec3::from_array(self.t));
        r.t = if *outer == Affine::IDENTITY { self.t } else { t.to_array() };
        r
    }

    fn mirrors(&self) -> bool {
        let m = &self.m;
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        det < 0.0
    }
}

/// A triangle's properties: the group and the index of each corner (or one for all).
#[derive(Clone, Copy, Debug, Default)]
struct TriProps {
    pid: Option<u32>,
    p: [Option<u32>; 3],
}

#[derive(Debug, Default)]
struct Object {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    props: Vec<TriProps>,
    /// Each component: its object, transform, and the model part holding the object when the
    /// production extension's `p:path` names another part.
    components: Vec<(u32, Affine, Option<String>)>,
    default: TriProps,
    /// The object's `name`, if any (a part name, read onto its faces).
    name: Option<Arc<str>>,
}

#[derive(Debug, Default)]
struct Model {
    objects: HashMap<u32, Object>,
    /// Colour groups and base materials alike: the colours of a property group by id.
    groups: HashMap<u32, Vec<[f32; 4]>>,
    /// The ids of `groups` that are base materials (read as face colours, not vertex colours).
    bases: std::collections::HashSet<u32>,
    /// Build items: object, transform, and the part holding the object (`p:path`).
    items: Vec<(u32, Affine, Option<String>)>,
    /// Millimetres per unit of the model's coordinates (its `unit`, core §3.3).
    scale: f64,
}

/// The model parts of a package by name (without a leading `/`).
type Parts = HashMap<String, Model>;

/// Millimetres per unit of each `unit` the core specification allows (§3.3, `ST_Unit`).
const UNITS: [(&str, f64); 6] =
    [("micron", 0.001), ("millimeter", 1.0), ("centimeter", 10.0), ("inch", 25.4), ("foot", 304.8), ("meter", 1000.0)];

/// The namespaces of the extensions whose content is read (materials: colours; production:
/// objects in other model parts). A model requiring any other is refused.
const KNOWN_NS: [&str; 3] = [MATERIAL_NS, PRODUCTION_NS, CORE_NS];

/// Reads a 3MF package into one mesh (see the module documentation). `path` is only named in
/// errors.
///
/// # Errors
/// - [`IoError::Unsupported`] for a required extension that is not read (see the module
///   documentation);
/// - [`IoError::ThreeMf`]: not a zip package, no model part (or no part a `p:path` names), a
///   unit not in the specification, a part larger than the memory
///   budget (checked before inflating), invalid XML, a missing or unparsable attribute, a
///   build item or component naming no object, components nested deeper than 32 or in a
///   cycle;
/// - [`IoError::IndexOutOfRange`] for a triangle naming a vertex its object does not have;
/// - [`IoError::NonFinite`] for a NaN or infinite coordinate;
/// - [`IoError::Mesh`] when the triangles do not make a manifold mesh.
///
/// See also [`write_3mf`], [`super::load`].
pub fn read_3mf(bytes: &[u8], path: &Path) -> Result<Mesh, IoError> {
    read_3mf_report(bytes, path, Weld::DEFAULT, true).map(|r| r.0)
}

/// [`read_3mf`], welding corners by `weld` ([`Weld::for_named_vertices`]: by default only
/// corners at equal coordinates; the specification asks for shared vertices, but an exporter
/// may write each triangle's corners apart), repairing a file that is not
/// manifold as written (or refusing it when `repair` is false), with what was repaired (see
/// [`super::assemble`]).
///
/// # Errors
/// As [`read_3mf`]; [`IoError::NotManifold`] when `repair` is false and the file is not a
/// manifold surface as written.
pub(crate) fn read_3mf_report(bytes: &[u8], path: &Path, weld: Weld, repair: bool) -> Result<(Mesh, Repairs), IoError> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| tmf_error(path, format!("not a 3MF package (a zip archive): {e}")))?;
    let model_name = match read_part(&mut zip, "_rels/.rels", path)? {
        Some(rels) => model_part_name(&rels, path)?,
        None => "3D/3dmodel.model".to_string(),
    };
    let model_name = model_name.trim_start_matches('/').to_string();
    let xml = read_part(&mut zip, &model_name, path)?
        .ok_or_else(|| tmf_error(path, format!("the package has no model part {model_name}")))?;
    let root = parse_model(&xml, path)?;
    // The production extension's other model parts, each read once.
    let mut parts = Parts::new();
    let named =
        root.items.iter().map(|i| &i.2).chain(root.objects.values().flat_map(|o| o.components.iter().map(|c| &c.2)));
    let mut wanted: Vec<String> = named.flatten().map(|p| p.trim_start_matches('/').to_string()).collect();
    wanted.sort();
    wanted.dedup();
    for name in wanted.into_iter().filter(|n| *n != model_name) {
        let xml = read_part(&mut zip, &name, path)?
            .ok_or_else(|| tmf_error(path, format!("the package has no part {name}, which a p:path names")))?;
        let part = parse_model(&xml, path)?;
        if part
            .objects
            .values()
            .any(|o| o.components.iter().any(|c| c.2.as_deref().is_some_and(|p| p.trim_start_matches('/') != name)))
        {
            return Err(tmf_error(
                path,
                format!("part {name}: a component names another part (p:path is allowed only in the root model)"),
            ));
        }
        parts.insert(name, part);
    }
    let scale = root.scale;
    parts.insert(model_name.clone(), root);
    build_mesh(&parts, &model_name, scale, weld, repair, path)
}

/// The bytes of the part `name` (without a leading `/`), `None` when there is none. Its
/// declared size is checked against the memory budget before inflating, and no more than it
/// is inflated.
fn read_part<R: Read + std::io::Seek>(
    zip: &mut zip::ZipArchive<R>,
    name: &str,
    path: &Path,
) -> Result<Option<Vec<u8>>, IoError> {
    let name = name.trim_start_matches('/');
    let mut file = match zip.by_name(name) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(tmf_error(path, format!("part {name}: {e}"))),
    };
    let size = file.size();
    crate::limits::check_memory(|| format!("the 3MF part {name}, which declares {size} bytes"), size as f64)
        .map_err(|e| tmf_error(path, e.to_string()))?;
    let mut data = Vec::with_capacity(size as usize);
    (&mut file).take(size).read_to_end(&mut data).map_err(|e| tmf_error(path, format!("part {name}: {e}")))?;
    if (data.len() as u64) < size {
        return Err(tmf_error(path, format!("part {name} holds {} bytes, it declares {size}", data.len())));
    }
    Ok(Some(data))
}

/// The model part named by the package relationships.
fn model_part_name(rels: &[u8], path: &Path) -> Result<String, IoError> {
    let mut reader = quick_xml::Reader::from_reader(rels);
    let mut buf = Vec::new();
    loop {
        match reader.read_event_into(&mut buf) {
            Ok(Event::Start(e) | Event::Empty(e)) if e.local_name().as_ref() == "Relationship" => {
                let a = attrs(&e, path)?;
                if a.get("Type").map(String::as_str) == Some(MODEL_REL) {
                    if let Some(t) = a.get("Target") {
                        return Ok(t.clone());
                    }
                }
            }
            Ok(Event::Eof) => return Err(tmf_error(path, "_rels/.rels names no 3D model part")),
            Err(e) => return Err(tmf_error(path, format!("_rels/.rels: {e}"))),
            _ => {}
        }
        buf.clear();
    }
}

/// The attributes of an element by local name (namespace prefixes dropped).
fn attrs(e: &BytesStart, path: &Path) -> Result<HashMap<String, String>, IoError> {
    let mut out = HashMap::new();
    for a in e.attributes() {
        let a = a.map_err(|err| tmf_error(path, format!("invalid XML attribute: {err}")))?;
        let key = a.key.local_name().as_ref().to_owned();
        let value = a.value.into_owned();
        out.insert(key, value);
    }
    Ok(out)
}

fn number<T: std::str::FromStr>(a: &HashMap<String, String>, key: &str, what: &str, path: &Path) -> Result<T, IoError> {
    let v = a.get(key).ok_or_else(|| tmf_error(path, format!("{what} has no `{key}`")))?;
    v.trim().parse().map_err(|_| tmf_error(path, format!("{what}: `{key}` = `{v:.40}` is not a valid number")))
}

fn optional<T: std::str::FromStr>(
    a: &HashMap<String, String>,
    key: &str,
    what: &str,
    path: &Path,
) -> Result<Option<T>, IoError> {
    if a.contains_key(key) {
        number(a, key, what, path).map(Some)
    } else {
        Ok(None)
    }
}

/// `#RRGGBB` or `#RRGGBBAA`.
fn parse_color(text: &str) -> Option<[f32; 4]> {
    let h = text.trim().strip_prefix('#')?;
    if !(h.len() == 6 || h.len() == 8) || !h.is_ascii() {
        return None;
    }
    let byte = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok().map(|b| f32::from(b) / 255.0);
    Some([byte(0)?, byte(2)?, byte(4)?, if h.len() == 8 { byte(6)? } else { 1.0 }])
}

fn parse_model(xml: &[u8], path: &Path) -> Result<Model, IoError> {
    let mut reader = quick_xml::Reader::from_reader(xml);
    let mut buf = Vec::new();
    let mut model = Model { scale: 1.0, ..Model::default() };
    let mut object: Option<(u32, Object)> = None;
    let mut group: Option<(u32, Vec<[f32; 4]>)> = None;
    loop {
        let event = reader.read_event_into(&mut buf).map_err(|e| {
            tmf_error(path, format!("invalid XML in the model at byte {}: {e}", reader.error_position()))
        })?;
        let empty = matches!(event, Event::Empty(_));
        match event {
            Event::Start(e) | Event::Empty(e) => {
                let a = attrs(&e, path)?;
                match e.local_name().as_ref() {
                    "model" => model_header(&e, &a, &mut model, path)?,
                    "object" => {
                        let id = number(&a, "id", "an object", path)?;
                        let default = TriProps {
                            pid: optional(&a, "pid", "an object", path)?,
                            p: [optional(&a, "pindex", "an object", path)?, None, None],
                        };
                        let name = a
                            .get("name")
                            .filter(|n| !n.is_empty())
                            .map(|n| Arc::from(quick_xml::escape::unescape(n).unwrap_or(n.into()).as_ref()));
                        object = Some((id, Object { default, name, ..Object::default() }));
                    }
                    "vertex" => {
                        let (_, o) = object.as_mut().ok_or_else(|| tmf_error(path, "a vertex outside an object"))?;
                        let p = Vec3::new(
                            number(&a, "x", "a vertex", path)?,
                            number(&a, "y", "a vertex", path)?,
                            number(&a, "z", "a vertex", path)?,
                        );
                        o.vertices.push(p);
                    }
                    "triangle" => {
                        let (_, o) = object.as_mut().ok_or_else(|| tmf_error(path, "a triangle outside an object"))?;
                        let v = [
                            number(&a, "v1", "a triangle", path)?,
                            number(&a, "v2", "a triangle", path)?,
                            number(&a, "v3", "a triangle", path)?,
                        ];
                        o.triangles.push(v);
                        o.props.push(TriProps {
                            pid: optional(&a, "pid", "a triangle", path)?,
                            p: [
                                optional(&a, "p1", "a triangle", path)?,
                                optional(&a, "p2", "a triangle", path)?,
                                optional(&a, "p3", "a triangle", path)?,
                            ],
                        });
                    }
                    "component" => {
                        let (_, o) = object.as_mut().ok_or_else(|| tmf_error(path, "a component outside an object"))?;
                        let t = transform(&a, "a component", path)?;
                        o.components.push((number(&a, "objectid", "a component", path)?, t, a.get("path").cloned()));
                    }
                    "colorgroup" | "basematerials" => {
                        group = Some((number(&a, "id", "a property group", path)?, Vec::new()));
                    }
                    "color" | "base" => {
                        let key = if e.local_name().as_ref() == "color" { "color" } else { "displaycolor" };
                        if let Some((_, g)) = group.as_mut() {
                            let text = a.get(key).map_or("", String::as_str);
                            let c = parse_color(text).ok_or_else(|| {
                                tmf_error(path, format!("`{key}` = `{text:.40}` is not a colour #RRGGBB[AA]"))
                            })?;
                            g.push(c);
                        }
                    }
                    "item" => {
                        let t = transform(&a, "a build item", path)?;
                        model.items.push((number(&a, "objectid", "a build item", path)?, t, a.get("path").cloned()));
                    }
                    _ => {}
                }
                if empty {
                    close(e.local_name().as_ref(), &mut model, &mut object, &mut group);
                }
            }
            Event::End(e) => close(e.local_name().as_ref(), &mut model, &mut object, &mut group),
            Event::Eof => break,
            _ => {}
        }
        buf.clear();
    }
    Ok(model)
}

/// The `<model>` element: its unit (core §3.3) and the extensions it requires
/// (`requiredextensions`, prefixes declared on it).
fn model_header(e: &BytesStart, a: &HashMap<String, String>, model: &mut Model, path: &Path) -> Result<(), IoError> {
    let unit = a.get("unit").map_or("millimeter", String::as_str);
    model.scale = UNITS.iter().find(|(u, _)| *u == unit).map(|&(_, s)| s).ok_or_else(|| {
        tmf_error(
            path,
            format!("the model's unit `{unit:.40}` is not one of micron, millimeter, centimeter, inch, foot, meter"),
        )
    })?;
    let Some(required) = a.get("requiredextensions") else { return Ok(()) };
    // Prefix declarations (`xmlns:p`) are attributes of this element.
    let mut prefixes: HashMap<String, String> = HashMap::new();
    for attr in e.attributes().flatten() {
        if let Some(prefix) = attr.key.as_ref().strip_prefix("xmlns:") {
            prefixes.insert(prefix.to_string(), attr.value.to_string());
        }
    }
    for prefix in required.split_whitespace() {
        let ns = prefixes.get(prefix).map_or("an undeclared namespace", String::as_str);
        if !KNOWN_NS.contains(&ns) {
            return Err(IoError::Unsupported {
                path: path.into(),
                reason: format!(
                    "the 3MF model requires the extension `{prefix}` ({ns}), which blocksmith does not read"
                ),
            });
        }
    }
    Ok(())
}

fn close(name: &str, model: &mut Model, object: &mut Option<(u32, Object)>, group: &mut Option<(u32, Vec<[f32; 4]>)>) {
    match name {
        "object" => {
            if let Some((id, o)) = object.take() {
                model.objects.insert(id, o);
            }
        }
        "colorgroup" | "basematerials" => {
            if let Some((id, g)) = group.take() {
                model.groups.insert(id, g);
                if name == "basematerials" {
                    model.bases.insert(id);
                }
            }
        }
        _ => {}
    }
}

fn transform(a: &HashMap<String, String>, what: &str, path: &Path) -> Result<Affine, IoError> {
    match a.get("transform") {
        None => Ok(Affine::IDENTITY),
        Some(t) => Affine::parse(t)
            .ok_or_else(|| tmf_error(path, format!("{what}: transform `{t:.80}` is not 12 finite numbers"))),
    }
}

/// The part a component or item of part `part` names: its `p:path`, else its own part.
fn part_of<'a>(p: &'a Option<String>, part: &'a str) -> &'a str {
    p.as_deref().map_or(part, |p| p.trim_start_matches('/'))
}

/// The placements, vertices and triangles object `id` of `part` makes (itself and its components,
/// saturating at `u128::MAX`), counted before anything is placed so that a file nesting
/// components to explode is refused first. Each object is counted once (`memo`), so that a
/// DAG of components 10 wide and 12 deep costs its 120 edges, not its 10¹² placements.
fn triangle_count<'a>(
    parts: &'a Parts,
    part: &'a str,
    id: u32,
    depth: usize,
    memo: &mut HashMap<(&'a str, u32), u128>,
    path: &Path,
) -> Result<u128, IoError> {
    if let Some(&n) = memo.get(&(part, id)) {
        return Ok(n);
    }
    if depth > MAX_DEPTH {
        return Err(tmf_error(
            path,
            format!("components nested deeper than {MAX_DEPTH} (or in a cycle) at object {id}"),
        ));
    }
    crate::limits::check().map_err(|e| IoError::from_mesh(path, MeshError::Limit(e)))?;
    let o = parts
        .get(part)
        .and_then(|m| m.objects.get(&id))
        .ok_or_else(|| tmf_error(path, format!("no object with id {id} in part {part}")))?;
    // The placement itself counts too: a DAG of empty objects still costs its walk.
    let mut n = 1 + o.triangles.len() as u128 + o.vertices.len() as u128;
    for (c, _, p) in &o.components {
        n = n.saturating_add(triangle_count(parts, part_of(p, part), *c, depth + 1, memo, path)?);
    }
    memo.insert((part, id), n);
    Ok(n)
}

/// A part as the reader tells parts apart: its object's name and its colour's bits.
type PartKey = (Option<Arc<str>>, Option<[u32; 4]>);

struct Placed {
    positions: Vec<Vec3>,
    indices: Vec<u32>,
    colors: Vec<Option<[f32; 4]>>,
    /// Each triangle's part (its object's name, its base material's colour) in `parts`.
    face_parts: Vec<u32>,
    parts: Vec<FacePart>,
    part_ids: HashMap<PartKey, u32>,
}

impl Placed {
    /// The id of the part named `name` of colour `color`, added when new.
    fn part(&mut self, name: Option<&Arc<str>>, color: Option<[f32; 4]>) -> u32 {
        let key = (name.cloned(), color.map(|c| c.map(f32::to_bits)));
        let next = self.parts.len() as u32;
        let id = *self.part_ids.entry(key).or_insert(next);
        if id == next {
            self.parts.push(FacePart { color, name: name.cloned(), origin: None });
        }
        id
    }
}

/// Places object `id` of `part` moved by `t` into `out`, with its components; one unit of work
/// per placement, and a poll every [`crate::limits::POLL_EVERY`] triangles.
fn place(
    parts: &Parts,
    part: &str,
    id: u32,
    t: &Affine,
    name: Option<&Arc<str>>,
    out: &mut Placed,
    path: &Path,
) -> Result<(), IoError> {
    let stopped = |e: LimitError| IoError::from_mesh(path, MeshError::Limit(e));
    crate::limits::check().map_err(stopped)?;
    let model = &parts[part];
    let o = &model.objects[&id];
    // A component's triangles are named by their own object, else by the object placing them.
    let name = o.name.as_ref().or(name);
    let base = out.positions.len();
    out.positions.extend(o.vertices.iter().map(|&p| t.apply(p)));
    out.colors.resize(out.positions.len(), None);
    let flip = t.mirrors();
    for (k, (tri, props)) in o.triangles.iter().zip(&o.props).enumerate() {
        crate::limits::poll_at(k).map_err(stopped)?;
        for &v in tri {
            if v as usize >= o.vertices.len() {
                return Err(IoError::IndexOutOfRange {
                    path: path.into(),
                    at: format!("object {id} triangle {k}"),
                    index: i64::from(v),
                    vertex_count: o.vertices.len(),
                });
            }
        }
        let corners = if flip { [tri[0], tri[2], tri[1]] } else { *tri };
        out.indices.extend(corners.iter().map(|&v| (base + v as usize) as u32));
        // Triangle properties, or the object's default for all three corners.
        let (pid, p) = match props.pid {
            Some(pid) => (Some(pid), props.p),
            None => (o.default.pid, [o.default.p[0]; 3]),
        };
        let materials = pid.filter(|pid| model.bases.contains(pid)).and_then(|pid| model.groups.get(&pid));
        let face_color = materials.and_then(|colors| p[0].and_then(|i| colors.get(i as usize)).copied());
        let face_part = out.part(name, face_color);
        out.face_parts.push(face_part);
        if let Some(colors) = pid.filter(|pid| !model.bases.contains(pid)).and_then(|pid| model.groups.get(&pid)) {
            for (c, &v) in tri.iter().enumerate() {
                let index = p[c].or(p[0]);
                let slot = &mut out.colors[base + v as usize];
                if let (None, Some(&color)) = (*slot, index.and_then(|i| colors.get(i as usize))) {
                    *slot = Some(color);
                }
            }
        }
    }
    for (c, ct, p) in &o.components {
        place(parts, part_of(p, part), *c, &ct.then(t), name, out, path)?;
    }
    Ok(())
}

/// The mesh of the build of the root part `root`, its positions scaled by `scale` to
/// millimetres.
fn build_mesh<'a>(
    parts: &'a Parts,
    root: &'a str,
    scale: f64,
    weld: Weld,
    repair: bool,
    path: &Path,
) -> Result<(Mesh, Repairs), IoError> {
    let model = &parts[root];
    let mut total: u128 = 0;
    let mut memo = HashMap::new();
    for (id, _, p) in &model.items {
        total = total.saturating_add(triangle_count(parts, part_of(p, root), *id, 0, &mut memo, path)?);
    }
    // Each placed vertex or triangle takes at most ~40 bytes here and in the mesh.
    crate::limits::check_memory(
        || format!("the 3MF build's {total} placements, placed vertices and triangles"),
        total as f64 * 160.0,
    )
    .map_err(|e| tmf_error(path, e.to_string()))?;
    let mut out = Placed {
        positions: Vec::new(),
        indices: Vec::new(),
        colors: Vec::new(),
        face_parts: Vec::new(),
        parts: Vec::new(),
        part_ids: HashMap::new(),
    };
    for (id, t, p) in &model.items {
        place(parts, part_of(p, root), *id, t, None, &mut out, path)?;
    }
    if scale != 1.0 {
        for p in &mut out.positions {
            *p *= scale;
        }
    }
    if out.positions.len() > u32::MAX as usize {
        return Err(tmf_error(path, "more than 2³² − 1 vertices"));
    }
    let any_color = out.colors.iter().any(Option::is_some);
    let arities = vec![3u32; out.indices.len() / 3];
    let a = super::assemble::assemble(
        &out.positions,
        &out.indices,
        &arities,
        super::assemble::Topology::Indexed,
        weld.for_named_vertices(),
        repair,
        path,
    )?;
    let mut a = a;
    if out.parts.iter().any(|p| p.color.is_some() || p.name.is_some()) {
        a.set_input_parts(&out.face_parts, std::mem::take(&mut out.parts), path)?;
    }
    let mut mesh = a.mesh;
    if any_color {
        let colors = a.vertex_from.iter().map(|&v| out.colors[v as usize].unwrap_or([1.0; 4])).collect();
        mesh.set_vertex_colors(Some(colors)).map_err(|e| IoError::from_mesh(path, e))?;
    }
    Ok((mesh, a.repairs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::FaceSource;

    fn written(mesh: &Mesh) -> Vec<u8> {
        let mut bytes = Vec::new();
        write_3mf(mesh, &mut bytes, Path::new("mem.3mf")).unwrap();
        bytes
    }

    #[test]
    fn a_stop_lands_inside_the_model_text_before_a_byte_is_written() {
        use crate::limits::{install, CancelToken, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let m = crate::io::gltf::tests::few_faces_many_vertices();
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let mut bytes = Vec::new();
            let e = write_3mf(&m, &mut bytes, Path::new("mem.3mf")).unwrap_err();
            assert!(
                matches!(
                    e,
                    IoError::Mesh { source: MeshError::Limit(LimitError::Stopped(StopReason::Interrupted)), .. }
                ),
                "{e}"
            );
            assert!(bytes.is_empty());
        }
        assert!(!written(&m).is_empty());
    }

    /// A package of `model` XML with the standard parts.
    fn package(model: &str) -> Vec<u8> {
        package_with(model, &[])
    }

    /// A package of the root model `model` and further parts `(name, xml)`.
    fn package_with(model: &str, more: &[(&str, &str)]) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let o = zip::write::SimpleFileOptions::default();
        let base = [("[Content_Types].xml", CONTENT_TYPES), ("_rels/.rels", RELS), ("3D/3dmodel.model", model)];
        for (name, data) in base.iter().chain(more) {
            zip.start_file(*name, o).unwrap();
            zip.write_all(data.as_bytes()).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    /// A unit tetrahedron as object `id`, in a model of `unit` with `head` on its element.
    fn tetra_model(unit: &str, head: &str, id: u32, build: &str) -> String {
        format!(
            "<?xml version=\"1.0\"?><model unit=\"{unit}\" xmlns=\"{CORE_NS}\" {head}><resources>\
             <object id=\"{id}\" type=\"model\"><mesh><vertices>\
             <vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/>\
             <vertex x=\"0\" y=\"0\" z=\"1\"/></vertices><triangles>\
             <triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" v2=\"1\" v3=\"3\"/>\
             <triangle v1=\"0\" v2=\"3\" v3=\"2\"/><triangle v1=\"1\" v2=\"2\" v3=\"3\"/></triangles></mesh></object>\
             </resources><build>{build}</build></model>"
        )
    }

    #[test]
    fn units_are_read_as_millimetres() {
        for (unit, mm) in [
            ("micron", 0.001),
            ("millimeter", 1.0),
            ("centimeter", 10.0),
            ("inch", 25.4),
            ("foot", 304.8),
            ("meter", 1000.0),
        ] {
            let m =
                read_3mf(&package(&tetra_model(unit, "", 1, "<item objectid=\"1\"/>")), Path::new("u.3mf")).unwrap();
            assert_eq!(m.position(1), Vec3::new(mm, 0.0, 0.0), "{unit}");
            assert!((m.volume() - mm * mm * mm / 6.0).abs() < 1e-12 * mm * mm * mm, "{unit}");
        }
        let e = read_3mf(&package(&tetra_model("parsec", "", 1, "<item objectid=\"1\"/>")), Path::new("u.3mf"))
            .unwrap_err();
        assert!(e.to_string().contains("unit `parsec` is not one of"), "{e}");
    }

    #[test]
    fn required_extensions_are_read_or_refused_by_name() {
        // Beam lattices are not read: refused, naming the extension.
        let beams =
            "xmlns:b=\"http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02\" requiredextensions=\"b\"";
        let e = read_3mf(&package(&tetra_model("millimeter", beams, 1, "<item objectid=\"1\"/>")), Path::new("b.3mf"))
            .unwrap_err();
        assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
        assert!(
            e.to_string().contains(
                "requires the extension `b` (http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02)"
            ),
            "{e}"
        );
        // Materials and production are read.
        let ok = format!("xmlns:m=\"{MATERIAL_NS}\" xmlns:p=\"{PRODUCTION_NS}\" requiredextensions=\"m p\"");
        assert!(read_3mf(&package(&tetra_model("millimeter", &ok, 1, "<item objectid=\"1\"/>")), Path::new("p.3mf"))
            .is_ok());
    }

    #[test]
    fn production_parts_named_by_p_path_are_placed() {
        // The root model holds no mesh: an item places object 9 of another part (as slicers
        // write one part per object), and a component of object 2 places it again, moved.
        let head = format!("xmlns:p=\"{PRODUCTION_NS}\" requiredextensions=\"p\"");
        let root = format!(
            "<?xml version=\"1.0\"?><model unit=\"millimeter\" xmlns=\"{CORE_NS}\" {head}><resources>\
             <object id=\"2\" type=\"model\"><components>\
             <component p:path=\"/3D/Objects/tetra.model\" objectid=\"9\" transform=\"1 0 0 0 1 0 0 0 1 0 0 4\"/>\
             </components></object></resources><build>\
             <item p:path=\"/3D/Objects/tetra.model\" objectid=\"9\"/><item objectid=\"2\"/></build></model>"
        );
        let part = tetra_model("millimeter", "", 9, "");
        let m = read_3mf(&package_with(&root, &[("3D/Objects/tetra.model", &part)]), Path::new("p.3mf")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count(), m.component_count()), (8, 8, 2));
        assert_eq!(m.position(7), Vec3::new(0.0, 0.0, 5.0));
        // A p:path to a part the package lacks.
        let e = read_3mf(&package(&root), Path::new("p.3mf")).unwrap_err();
        assert!(e.to_string().contains("no part 3D/Objects/tetra.model, which a p:path names"), "{e}");
    }

    #[test]
    fn round_trip_keeps_every_bit_and_the_same_bytes() {
        let m = Mesh::torus(2.0, 0.5, 12, 8).map_positions(|p| p * 0.1 + Vec3::new(1e5, -3.0, 1.0 / 3.0));
        let t = m.triangulate().unwrap();
        let bytes = written(&m);
        let back = read_3mf(&bytes, Path::new("mem.3mf")).unwrap();
        assert_eq!(back.positions(), t.positions());
        assert_eq!(back.to_polygons(), t.to_polygons());
        assert!(back.is_closed() && back.is_manifold());
        assert_eq!(written(&back), bytes, "the same mesh gives the same bytes");
    }

    #[test]
    fn vertex_colours_round_trip_in_8_bits() {
        let mut m = Mesh::cube(1.0).triangulate().unwrap();
        let colors: Vec<[f32; 4]> =
            (0..8).map(|i| [i as f32 / 255.0, 1.0, 0.0, if i == 3 { 0.0 } else { 1.0 }]).collect();
        m.set_vertex_colors(Some(colors.clone())).unwrap();
        let back = read_3mf(&written(&m), Path::new("c.3mf")).unwrap();
        assert_eq!(back.vertex_colors(), Some(colors.as_slice()));
    }

    #[test]
    fn face_sources_are_not_written_as_colours() {
        // Provenance is a debugging view: an uncoloured boolean result is saved uncoloured,
        // and reads back without colours. Base materials are core elements (core §5.1): a
        // prefixed `m:basematerials` would be outside both schemas.
        let mut m = Mesh::cube(1.0);
        m.set_face_sources(Some((0..6).map(|face| FaceSource::Mesh { leaf: face / 3, face }).collect())).unwrap();
        let bytes = written(&m);
        let mut zip = zip::ZipArchive::new(Cursor::new(bytes.clone())).unwrap();
        let mut xml = String::new();
        zip.by_name("3D/3dmodel.model").unwrap().read_to_string(&mut xml).unwrap();
        assert!(!xml.contains("basematerials") && !xml.contains("pid="), "{xml}");
        let back = read_3mf(&bytes, Path::new("plain.3mf")).unwrap();
        assert!(!back.has_face_colors() && back.vertex_colors().is_none());
        // A coloured result writes its own colours, not its sources'.
        m.set_color([0.0, 1.0, 0.0, 1.0]).unwrap();
        let mut zip = zip::ZipArchive::new(Cursor::new(written(&m))).unwrap();
        let mut xml = String::new();
        zip.by_name("3D/3dmodel.model").unwrap().read_to_string(&mut xml).unwrap();
        assert!(
            xml.contains("<base name=\"#00ff00\" displaycolor=\"#00FF00FF\"/>") && !xml.contains("source 0"),
            "{xml}"
        );
    }

    #[test]
    fn face_colours_and_part_names_round_trip_as_base_materials_and_objects() {
        let mut a = Mesh::cube(2.0);
        a.set_color([1.0, 0.0, 0.0, 1.0]).unwrap();
        a.map_parts(|p| p.name = Some("body".into()));
        let mut b = Mesh::cube(1.0).translate(Vec3::new(3.0, 0.0, 0.0));
        b.set_color([0.0, 0.0, 1.0, 0.5]).unwrap();
        b.map_parts(|p| p.name = Some("lid & cap".into()));
        let m = Mesh::combine(&[&a, &b]).unwrap();
        let bytes = written(&m);
        let mut zip = zip::ZipArchive::new(Cursor::new(bytes.clone())).unwrap();
        let mut xml = String::new();
        zip.by_name("3D/3dmodel.model").unwrap().read_to_string(&mut xml).unwrap();
        assert!(xml.contains("name=\"lid &amp; cap\""), "{xml}");
        assert_eq!(xml.matches("<item objectid=").count(), 2, "{xml}");
        let back = read_3mf(&bytes, Path::new("parts.3mf")).unwrap();
        assert_eq!(back.face_count(), 24);
        // Each object writes its vertices in the mesh's order: they read back in place.
        assert_eq!(back.positions(), m.positions());
        // Why: each cube's 12 triangles keep its colour (8 bits) and its object's name.
        let blue = [0.0, 0.0, 1.0, 128.0 / 255.0];
        for f in 0..24 {
            let p = back.face_part(f).unwrap();
            let (c, n) = if f < 12 { ([1.0, 0.0, 0.0, 1.0], "body") } else { (blue, "lid & cap") };
            assert_eq!((p.color, p.name.as_deref()), (Some(c), Some(n)), "face {f}");
        }
        assert!(back.vertex_colors().is_none());
    }

    #[test]
    fn build_items_and_components_are_placed_with_their_transforms() {
        // One tetrahedron placed twice: by an item moved 5 in x, and by a mirrored component
        // (x → −x), whose triangles are turned so it stays outward.
        let model = format!(
            "<?xml version=\"1.0\"?><model unit=\"millimeter\" xmlns=\"{CORE_NS}\" xmlns:m=\"{MATERIAL_NS}\"><resources>\
             <m:basematerials id=\"7\"><m:base name=\"red\" displaycolor=\"#FF0000\"/></m:basematerials>\
             <object id=\"1\" type=\"model\" pid=\"7\" pindex=\"0\"><mesh><vertices>\
             <vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/>\
             <vertex x=\"0\" y=\"0\" z=\"1\"/></vertices><triangles>\
             <triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" v2=\"1\" v3=\"3\"/>\
             <triangle v1=\"0\" v2=\"3\" v3=\"2\"/><triangle v1=\"1\" v2=\"2\" v3=\"3\"/></triangles></mesh></object>\
             <object id=\"2\" type=\"model\"><components><component objectid=\"1\" transform=\"-1 0 0 0 1 0 0 0 1 -2 0 0\"/>\
             </components></object></resources>\
             <build><item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 5 0 0\"/><item objectid=\"2\"/></build></model>"
        );
        let m = read_3mf(&package(&model), Path::new("placed.3mf")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count(), m.component_count()), (8, 8, 2));
        assert!(m.is_closed());
        assert!((m.volume() - 2.0 / 6.0).abs() < 1e-15, "{}", m.volume());
        assert_eq!(m.position(0), Vec3::new(5.0, 0.0, 0.0));
        assert_eq!(m.position(5), Vec3::new(-3.0, 0.0, 0.0));
        // Base materials are face colours: every face of both placements is red.
        assert!((0..8).all(|f| m.face_color(f) == Some([1.0, 0.0, 0.0, 1.0])));
        assert!(m.vertex_colors().is_none());
    }

    #[test]
    fn malformed_packages_are_3mf_errors_naming_the_path() {
        let cube = "<model xmlns=\"x\"><resources><object id=\"1\"><mesh><vertices><vertex x=\"0\" y=\"0\"/>\
                    </vertices></mesh></object></resources><build><item objectid=\"1\"/></build></model>";
        let cycle = "<model><resources><object id=\"1\"><components><component objectid=\"1\"/></components>\
                     </object></resources><build><item objectid=\"1\"/></build></model>";
        let cases: [(Vec<u8>, &str); 5] = [
            (b"PK not really".to_vec(), "not a 3MF package"),
            (package("<model><resources></object></model>"), "invalid XML"),
            (package(cube), "a vertex has no `z`"),
            (package(cycle), "nested deeper than 32"),
            (package("<model><build><item objectid=\"9\"/></build></model>"), "no object with id 9"),
        ];
        for (bytes, want) in cases {
            let e = read_3mf(&bytes, Path::new("bad.3mf")).map(|_| ()).expect_err(want);
            assert!(e.to_string().starts_with("bad.3mf: malformed 3MF: "), "{e}");
            assert!(e.to_string().contains(want), "{e} (wanted {want})");
        }
    }

    /// A model whose object `k` (1 ≤ k ≤ `depth`) holds `width` components placing object
    /// `k − 1`, object 0 a tetrahedron: `width^depth` placements of the tetrahedron from a file
    /// of a few hundred bytes.
    fn component_dag(width: usize, depth: usize) -> String {
        let mut objects = String::new();
        for k in 1..=depth {
            let comps = format!("<component objectid=\"{}\"/>", k - 1).repeat(width);
            objects.push_str(&format!("<object id=\"{k}\" type=\"model\"><components>{comps}</components></object>"));
        }
        let tetra = tetra_model("millimeter", "", 0, &format!("<item objectid=\"{depth}\"/>"));
        tetra.replace("</resources>", &format!("{objects}</resources>"))
    }

    #[test]
    fn a_component_dag_is_counted_per_object_and_refused_before_its_walk() {
        // 10 wide and 12 deep: 10¹² placements, 8·10¹² vertices and triangles. Counting each
        // object once costs 120 component visits, so the refusal comes at once (the walk it
        // replaces took hours); a small DAG (2 wide, 3 deep: 8 tetrahedra) is still placed.
        let bytes = package(&component_dag(10, 12));
        let t = std::time::Instant::now();
        let e = read_3mf(&bytes, Path::new("dag.3mf")).map(|_| ()).unwrap_err();
        assert!(t.elapsed().as_secs_f64() < 1.0, "{:?}", t.elapsed());
        assert!(e.to_string().contains("over the memory budget"), "{e}");
        assert!(e.to_string().contains("9111111111111 placements"), "{e}");
        let m = read_3mf(&package(&component_dag(2, 3)), Path::new("dag.3mf")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (32, 32));
    }

    #[test]
    fn placing_components_stops_on_the_token() {
        // Under a set interrupt the walk stops at its first placement.
        use crate::limits::{install, CancelToken, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
        let e = read_3mf(&package(&component_dag(2, 3)), Path::new("dag.3mf")).unwrap_err();
        assert!(
            matches!(e, IoError::Mesh { source: MeshError::Limit(LimitError::Stopped(StopReason::Interrupted)), .. }),
            "{e}"
        );
    }
}
