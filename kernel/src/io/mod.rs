//! Mesh files: OBJ (read and write), binary STL (write; binary and ASCII read), glTF 2.0 (`.glb`
//! and `.gltf` with a separate `.bin` buffer, read and write), PLY (ASCII and binary, read and
//! write), 3MF (read and write).
//!
//! 2D profiles have their own: SVG and DXF ([`svg`], [`dxf`]; [`load_profile`] and
//! [`save_profile`] by extension).
//!
//! [`load`] and [`save`] pick the format by the extension (case-insensitive). Each format also
//! has functions that read from bytes and write to any [`std::io::Write`], so that they can be
//! used without files; they take the path only to name it in errors.
//!
//! Axes: blocksmith is Z-up. glTF is Y-up by specification and is converted on write and on
//! read, kernel `(x, y, z)` ↔ glTF `(x, z, −y)`, exactly (see [`UpAxis`]); OBJ and STL have no
//! convention and are written and read as they are, unless [`SaveOptions::up`] /
//! [`LoadOptions::up`] say the file is Y-up.
//!
//! Welding: STL stores each triangle's corners apart and glTF (and PLY from many exporters)
//! splits vertices at normal and UV seams; they are welded by position on reading, within a tolerance relative to the model's
//! size ([`Weld`], default 1e-8 of the bounding box's diagonal), so that they read as the closed
//! surfaces they draw. OBJ and 3MF name their shared vertices: by default only corners at equal
//! coordinates are joined there (a file converted from an STL, or split at UV seams, repeats a
//! corner with the same numbers), so vertices a file keeps apart at nearly one place stay apart
//! and our own files read back as written (an OBJ with subdivision tags is never welded: the
//! tags name its vertex ids). A weld never makes a manifold file non-manifold: sheets that touch
//! stay apart.
//!
//! What each format keeps:
//!
//! | | positions | polygons | vertex ids | creases, corners | vertex colours | face colours, part names |
//! |---|---|---|---|---|---|---|
//! | OBJ | exact (f64) | yes | yes | yes (`t` tags) | RGB | `usemtl` + `.mtl` (RGBA f32), `o` |
//! | glTF | f32 | yes (`extras`) | yes | yes (mesh `extras`) | RGBA | a material per colour (RGBA f32), a node per name |
//! | STL | f32 | triangles | no (welded by position) | no | no | no |
//! | PLY | exact (f64) | yes | yes (unless welded) | no | RGB(A), 8 bits | face `red green blue (alpha)`, 8 bits; no names |
//! | 3MF | exact (shortest decimal) | triangles | yes | no | RGBA, 8 bits (colour group) | base materials (8 bits), an object per name |
//!
//! A boolean result's face sources (which operand each face came from) are a debugging view
//! (the studio's provenance colours, [`gltf::write_glb_provenance`]) and are never written as
//! colours.

mod assemble;
mod atomic;
mod draco;
pub mod dxf;
mod error;
mod face_groups;
pub mod gltf;
pub mod obj;
mod options;
pub mod ply;
mod profile_files;
mod single_precision;
mod source_colors;
pub mod stl;
pub mod svg;
pub mod threemf;
pub mod uri;
mod weld;

use std::borrow::Cow;
use std::path::Path;

pub use atomic::{remove_temporaries, write_atomic, StoppableFile};
pub use error::{IoError, KNOWN_EXTENSIONS};
pub use options::{LoadOptions, SaveOptions, UpAxis};
pub use ply::PlyEncoding;
pub use profile_files::{load_font, load_profile, save_profile, ProfileFormat};
pub use source_colors::source_color;
pub use weld::Weld;

use crate::mesh::{Mesh, MeshError};

/// The file formats, as told by the extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront `.obj` text.
    Obj,
    /// Binary glTF 2.0, `.glb`.
    Glb,
    /// glTF 2.0 JSON, `.gltf`, with its buffer in a `.bin` file beside it.
    Gltf,
    /// Stereolithography `.stl` (written binary).
    Stl,
    /// Polygon File Format `.ply` (written binary little-endian unless asked otherwise).
    Ply,
    /// 3D Manufacturing Format `.3mf` (a zip package of XML; Z-up, millimetres).
    ThreeMf,
}

impl Format {
    /// The format of `path` by its extension, case-insensitive.
    ///
    /// # Errors
    /// [`IoError::UnknownExtension`] listing the known extensions.
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Ok(Format::Obj),
            "glb" => Ok(Format::Glb),
            "gltf" => Ok(Format::Gltf),
            "stl" => Ok(Format::Stl),
            "ply" => Ok(Format::Ply),
            "3mf" => Ok(Format::ThreeMf),
            _ => Err(IoError::UnknownExtension {
                path: path.into(),
                ext: path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default(),
            }),
        }
    }
}

/// Reads the mesh in the file at `path` with the default [`LoadOptions`]; see [`load_with`].
///
/// # Errors
/// As [`load_with`].
pub fn load(path: impl AsRef<Path>) -> Result<Mesh, IoError> {
    load_with(path, &LoadOptions::DEFAULT)
}

/// Reads the mesh in the file at `path`, by extension: `.obj`, `.glb`, `.gltf`, `.stl`, `.ply`,
/// `.3mf`, in kernel (Z-up) axes. `options.up` is the file's up axis (OBJ, STL and PLY only; glTF is
/// Y-up by specification), `options.weld` how corners at one place are welded.
///
/// # Errors
/// [`IoError::UnknownExtension`] first, then [`IoError::Unsupported`] for an up axis given to
/// glTF, then [`IoError::NotFound`] / [`IoError::Read`], then the format's own errors
/// ([`obj::read_obj`], [`gltf::read_gltf_with`], [`stl::read_stl_with`], [`ply::read_ply_with`]).
///
/// See also [`save_with`].
pub fn load_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Mesh, IoError> {
    load_report(path, options).map(|r| r.0)
}

/// [`load_with`], also returning what was repaired: a file whose faces do not make a manifold
/// surface as written is loaded as the nearest one without moving a vertex (see
/// [`crate::diagnose::repair_polygons`]) unless `options.repair` is false, and the
/// [`Repairs`](crate::diagnose::Repairs) say what was split, separated, flipped or dropped,
/// and where (empty for a valid file). Welding never makes a manifold file non-manifold: what
/// it would break is kept apart, silently.
///
/// # Errors
/// As [`load_with`]; [`IoError::NotManifold`] when `options.repair` is false and the file is
/// not a manifold surface as written.
pub fn load_report(path: impl AsRef<Path>, options: &LoadOptions) -> Result<(Mesh, crate::diagnose::Repairs), IoError> {
    let path = path.as_ref();
    let format = Format::from_path(path)?;
    let up = file_up(format, options.up, path)?;
    let bytes = uri::read_regular(path).map_err(|e| e.into_io(path))?;
    let repair = options.repair;
    let (mesh, repairs) = match format {
        Format::Obj => {
            obj::read_obj_report(&bytes, Some(path.parent().unwrap_or(Path::new(""))), path, options.weld, repair)?
        }
        Format::Glb | Format::Gltf => gltf::read_gltf_report(&bytes, path.parent(), path, options.weld, repair)?,
        Format::Stl => stl::read_stl_report(&bytes, path, options.weld, repair)?,
        Format::Ply => ply::read_ply_report(&bytes, path, options.weld, repair)?,
        Format::ThreeMf => threemf::read_3mf_report(&bytes, path, options.weld, repair)?,
    };
    let mesh = match up {
        UpAxis::Z => mesh,
        up => mesh.map_positions(|p| up.from_file(p)),
    };
    Ok((mesh, repairs))
}

/// The up axis asked of a format that has no convention (OBJ, STL), Z when none is asked;
/// glTF converts by itself and refuses another axis.
fn file_up(format: Format, up: Option<UpAxis>, path: &Path) -> Result<UpAxis, IoError> {
    match (format, up) {
        (Format::Glb | Format::Gltf, Some(UpAxis::Z)) => Err(IoError::Unsupported {
            path: path.into(),
            reason: "glTF is Y-up by specification and always converted to and from Z-up: it takes no up axis".into(),
        }),
        (Format::Glb | Format::Gltf, _) => Ok(UpAxis::Z),
        (Format::ThreeMf, Some(UpAxis::Y)) => Err(IoError::Unsupported {
            path: path.into(),
            reason: "3MF is Z-up by specification: it takes no other up axis".into(),
        }),
        (_, up) => Ok(up.unwrap_or_default()),
    }
}

/// Writes `mesh` to the file at `path` with the default [`SaveOptions`]; see [`save_with`].
///
/// # Errors
/// As [`save_with`].
pub fn save(mesh: &Mesh, path: impl AsRef<Path>) -> Result<(), IoError> {
    save_with(mesh, path, &SaveOptions::DEFAULT)
}

/// Writes `mesh` to the file at `path`, by extension: `.obj`, `.glb`, `.gltf` (which also
/// writes its buffer beside it as `STEM.HASH.bin`, the pair changing together or not at all:
/// see [`gltf`]'s `save_gltf_pair`), `.stl`, `.ply` (in
/// `options.ply`'s encoding), `.3mf`. glTF is written Y-up (converted exactly); OBJ, STL and PLY Z-up
/// unless `options.up` says otherwise. Each file is
/// written atomically ([`write_atomic`]): a failing save leaves the old file as it was. An OBJ of
/// a mesh with face colours also writes its material library beside it, `STEM.mtl` (see
/// [`obj::material_library_path`]), before the OBJ that names it.
///
/// # Errors
/// [`IoError::UnknownExtension`]; [`IoError::Unsupported`] for an up axis given to glTF;
/// [`IoError::Write`] when the file cannot be created or written; [`IoError::Mesh`] when a
/// face cannot be triangulated (glTF, STL) or the mesh is too large for the format.
///
/// glTF and STL hold 32-bit coordinates: an edge whose two ends round to one 32-bit point is
/// collapsed first, so that a closed mesh stays closed for readers that join corners by
/// position (`single_precision`); other meshes are written as they are.
///
/// See also [`load_with`].
pub fn save_with(mesh: &Mesh, path: impl AsRef<Path>, options: &SaveOptions) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = Format::from_path(path)?;
    let turned;
    let mesh = match file_up(format, options.up, path)? {
        UpAxis::Z => mesh,
        up => {
            turned = mesh.map_positions(|p| up.to_file(p));
            &turned
        }
    };
    match format {
        Format::Obj => {
            // The material library first, so the OBJ never names a library that is not there.
            let library = obj::material_library_path(mesh, path);
            if let Some(lib) = &library {
                write_atomic(lib, |w| {
                    obj::write_mtl(mesh, w).map_err(|e| IoError::Write { path: lib.into(), source: e })
                })?;
            }
            let name = library.as_ref().and_then(|l| l.file_name()).map(|n| n.to_string_lossy().into_owned());
            write_atomic(path, |w| {
                obj::write_obj_with_library(mesh, w, name.as_deref())
                    .map_err(|e| IoError::Write { path: path.into(), source: e })
            })
        }
        Format::Glb => write_atomic(path, |w| gltf::write_glb(&*single(mesh, path)?, w, path)),
        Format::Stl => write_atomic(path, |w| stl::write_stl(&*single(mesh, path)?, w, path)),
        Format::Ply => write_atomic(path, |w| ply::write_ply(mesh, w, options.ply, path)),
        Format::ThreeMf => write_atomic(path, |w| threemf::write_3mf(mesh, w, path)),
        Format::Gltf => gltf::save_gltf_pair(&*single(mesh, path)?, path),
    }
}

/// `mesh` as a format with 32-bit coordinates holds it closed
/// ([`single_precision::for_single_precision`]).
fn single<'a>(mesh: &'a Mesh, path: &Path) -> Result<Cow<'a, Mesh>, IoError> {
    single_precision::for_single_precision(mesh).map_err(|e| IoError::from_mesh(path, MeshError::Limit(e)))
}

/// What a triangle format writes: the mesh (the one given, or its triangulation with added
/// centres), the triangles of every face, each face's arity.
pub(crate) type WrittenTriangles<'a> = (Cow<'a, Mesh>, Vec<u32>, Vec<u32>);

/// The mesh to write, the triangles of every face, each face's consecutively, and each face's
/// arity: see [`Mesh::triangulate_faces`]. When some face can only be cut about an added centre,
/// the mesh to write is [`Mesh::triangulate`]'s (with the added vertices), every face a
/// triangle.
///
/// # Errors
/// As [`Mesh::triangulate_with_sources`].
pub(crate) fn face_triangles(mesh: &Mesh) -> Result<WrittenTriangles<'_>, MeshError> {
    let plan = mesh.plan_triangles()?;
    if plan.centres.is_empty() {
        return Ok((Cow::Borrowed(mesh), plan.tris, plan.arities));
    }
    let t = mesh.triangulate()?;
    let tris: Vec<u32> = (0..t.face_count() as u32).flat_map(|f| t.face_vertices(f)).collect();
    let arities = vec![3; t.face_count()];
    Ok((Cow::Owned(t), tris, arities))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn unknown_extension_lists_the_known_ones() {
        for name in ["mesh.3ds", "mesh", "dir.obj/mesh.fbx"] {
            let e = load(name).unwrap_err();
            assert!(matches!(e, IoError::UnknownExtension { .. }), "{e}");
            assert!(
                e.to_string().starts_with(name) && e.to_string().contains(".obj, .glb, .gltf, .stl, .ply, .3mf"),
                "{e}"
            );
            assert!(matches!(save(&Mesh::cube(1.0), name), Err(IoError::UnknownExtension { .. })));
        }
    }

    #[test]
    fn missing_file_is_not_found_naming_the_path() {
        for name in [
            "/nonexistent/dir/mesh.obj",
            "/nonexistent/mesh.GLB",
            "/nonexistent/m.gltf",
            "/nonexistent/m.stl",
            "/n/m.ply",
        ] {
            let e = load(name).unwrap_err();
            assert!(matches!(e, IoError::NotFound { .. }), "{e}");
            assert_eq!(e.to_string(), format!("{name}: file not found"));
        }
    }

    #[test]
    fn unwritable_path_is_a_write_error() {
        let e = save(&Mesh::cube(1.0), "/nonexistent/dir/cube.obj").unwrap_err();
        assert!(matches!(e, IoError::Write { .. }) && e.to_string().starts_with("/nonexistent/dir/cube.obj"), "{e}");
    }

    #[test]
    fn a_save_failing_to_triangulate_leaves_the_old_file_in_every_format() {
        // A self-crossing pentagon cannot be triangulated for glTF and STL, and the .gltf
        // writer fails before writing either of its files.
        let p: Vec<Vec3> =
            [(0., 0.), (2., 2.), (2., 0.), (0., 2.), (1., 3.)].iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let bad = Mesh::from_polygons(p, &[[0, 2, 1, 3, 4]]).unwrap();
        let dir = tempfile::tempdir().unwrap();
        for name in ["old.glb", "old.stl", "old.gltf"] {
            let path = dir.path().join(name);
            save(&Mesh::cube(1.0), &path).unwrap();
            let before = std::fs::read(&path).unwrap();
            assert!(matches!(save(&bad, &path), Err(IoError::Mesh { .. })), "{name}");
            assert_eq!(std::fs::read(&path).unwrap(), before, "{name} was changed");
        }
        let mut names: Vec<String> =
            std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        names.sort();
        // The .gltf's buffer is `old.HASH.bin`.
        assert_eq!(names.len(), 4, "no temporary file remains: {names:?}");
        assert!(names[0].starts_with("old.") && names[0].ends_with(".bin"), "{names:?}");
        assert_eq!(names[1..], ["old.glb", "old.gltf", "old.stl"], "no temporary file remains");
    }

    #[test]
    fn a_mesh_needing_added_centres_saves_closed_in_every_triangle_format() {
        // K₅ on a torus as five quads: both diagonals of each quad are edges, so the written
        // triangles take a vertex at each quad's centre, and read back as the torus they draw.
        let p: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.3 * f64::from(i % 2) + 0.1 * f64::from(i))
            })
            .collect();
        let m =
            Mesh::from_polygons(p, &[[0u32, 1, 2, 3], [0, 2, 4, 1], [0, 4, 3, 2], [0, 3, 1, 4], [1, 3, 4, 2]]).unwrap();
        let dir = tempfile::tempdir().unwrap();
        for name in ["k5.stl", "k5.glb", "k5.3mf", "k5.gltf"] {
            let path = dir.path().join(name);
            save(&m, &path).unwrap();
            let back = load(&path).unwrap();
            assert!(back.is_closed() && back.is_manifold(), "{name}");
            assert_eq!((back.vertex_count(), back.face_count(), back.euler()), (10, 20, 0), "{name}");
            assert!((back.area() - m.area()).abs() < 1e-6 * m.area(), "{name}");
        }
    }

    #[test]
    fn face_triangles_start_with_each_faces_first_edge() {
        // An L-shaped hexagon (not convex: triangulated by spade) and a quad.
        let p = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.), (3., 0.), (3., 1.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        let m = Mesh::from_polygons(p, &[vec![3, 4, 5, 0, 1, 2], vec![1, 6, 7, 2]]).unwrap();
        let (_, tris, arities) = face_triangles(&m).unwrap();
        assert_eq!(arities, vec![6, 4]);
        assert_eq!(tris.len(), 3 * (4 + 2));
        assert_eq!(&tris[..2], &[3, 4]);
        assert_eq!(&tris[12..], &[1, 6, 7, 1, 7, 2]);
        // The triangles cover the hexagon: their areas add up to 3.
        let area: f64 = tris[..12]
            .chunks(3)
            .map(|t| {
                let (a, b, c) = (m.position(t[0]), m.position(t[1]), m.position(t[2]));
                (b - a).cross(c - a).z / 2.0
            })
            .sum();
        assert!((area - 3.0).abs() < 1e-12, "area {area}");
    }
}
