//! Mesh files on disk: round trips through `save`/`load`, files written by another tool
//! (trimesh), and the broken files of tests/data/io (made by tests/data/make_io_data.py).
//!
//! The `.glb`/`.gltf` files written here are left in target/test-output/io so that CI can run the
//! Khronos validator over them.

use std::path::{Path, PathBuf};

use blocksmith_kernel::io::{load, load_with, save, IoError, LoadOptions};
use blocksmith_kernel::mesh::FaceSource;
use blocksmith_kernel::{Mesh, Vec3};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/io").join(name)
}

fn output_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-output/io");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn assert_rel(a: f64, b: f64, tol: f64, what: &str) {
    let d = (a - b).abs() / b.abs().max(1e-300);
    assert!(d <= tol, "{what}: got {a}, expected {b}, relative difference {d:e}");
}

/// A mesh with every attribute a file can carry: a torus of quads off the origin, two crease
/// edges and a corner.
fn decorated_torus() -> Mesh {
    let mut m = Mesh::torus(2.0, 0.5, 24, 12).translate(Vec3::new(0.25, -1.0 / 3.0, 0.1));
    m.crease_edges(&[[0, 1], [0, 12]]).unwrap();
    m.set_corner(0, true);
    m
}

fn assert_same_topology_and_tags(back: &Mesh, m: &Mesh) {
    assert_eq!(
        (back.vertex_count(), back.edge_count(), back.face_count()),
        (m.vertex_count(), m.edge_count(), m.face_count())
    );
    assert_eq!(back.to_polygons(), m.to_polygons());
    let mut a = back.crease_pairs();
    let mut b = m.crease_pairs();
    a.iter_mut().chain(b.iter_mut()).for_each(|p| p.sort_unstable());
    a.sort_unstable();
    b.sort_unstable();
    assert_eq!(a, b, "crease edges");
    assert!(back.is_corner(0));
    assert!(back.is_closed() && back.is_manifold());
    assert_eq!(back.genus(), 1);
}

#[test]
fn obj_round_trip_is_exact() {
    let m = decorated_torus();
    let path = output_dir().join("torus.obj");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    assert_eq!(back.positions(), m.positions(), "OBJ keeps every f64 bit");
    assert_same_topology_and_tags(&back, &m);
}

#[test]
fn glb_and_gltf_round_trips_keep_polygons_creases_and_f32_positions() {
    let m = decorated_torus();
    let f32_positions: Vec<Vec3> = m
        .positions()
        .iter()
        .map(|p| Vec3::new(f64::from(p.x as f32), f64::from(p.y as f32), f64::from(p.z as f32)))
        .collect();
    // The .gltf name has a space: its buffer's URI must be percent-encoded.
    for name in ["torus.glb", "torus with space.gltf"] {
        let path = output_dir().join(name);
        save(&m, &path).unwrap();
        let back = load(&path).unwrap();
        assert_eq!(back.positions(), f32_positions.as_slice(), "{name}: positions are the f32 roundings");
        assert_same_topology_and_tags(&back, &m);
    }
    // Its buffer beside it, named by stem and content hash: `torus with space.HASH.bin`.
    let bins = std::fs::read_dir(output_dir()).unwrap().filter_map(|e| e.ok()).filter(|e| {
        let n = e.file_name().to_string_lossy().into_owned();
        n.starts_with("torus with space.") && n.ends_with(".bin") && n.len() == "torus with space.".len() + 16 + 4
    });
    assert_eq!(bins.count(), 1);
}

#[test]
fn coloured_triangle_mesh_writes_for_the_validator() {
    let mut m = Mesh::icosphere(1.0, 2);
    let colors = m.positions().iter().map(|p| [(p.x as f32 + 1.0) / 2.0, (p.y as f32 + 1.0) / 2.0, 0.5, 1.0]).collect();
    m.set_vertex_colors(Some(colors)).unwrap();
    let path = output_dir().join("colored_icosphere.glb");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    assert_eq!(back.vertex_colors(), m.vertex_colors());
    assert_eq!(back.to_polygons(), m.to_polygons());
}

#[test]
fn meshes_with_colours_or_sources_write_3mf_for_the_schema_check() {
    // CI validates every .3mf written here against the 3MF core and materials schemas: one with
    // a colour group (materials namespace), one with base materials (core namespace).
    let mut coloured = Mesh::icosphere(1.0, 2);
    let colors = coloured.positions().iter().map(|p| [(p.x as f32 + 1.0) / 2.0, 0.25, 0.5, 1.0]).collect();
    coloured.set_vertex_colors(Some(colors)).unwrap();
    let path = output_dir().join("colored_icosphere.3mf");
    save(&coloured, &path).unwrap();
    assert_eq!(load(&path).unwrap().vertex_colors().map(<[_]>::len), Some(coloured.vertex_count()));

    // Two cubes apart, coloured red and blue: two base materials, one per triangle, read back as
    // the faces' colours (the provenance of a boolean's inputs is a debugging view, not written).
    let mut red = Mesh::cube(2.0);
    red.set_color([1.0, 0.0, 0.0, 1.0]).unwrap();
    let mut blue = Mesh::cube(1.0).translate(Vec3::new(4.0, 0.0, -1.0));
    blue.set_color([0.0, 0.0, 1.0, 1.0]).unwrap();
    let mut parted = Mesh::combine(&[&red, &blue]).unwrap();
    let sources = (0..12).map(|face| FaceSource::Mesh { leaf: face / 6, face }).collect();
    parted.set_face_sources(Some(sources)).unwrap();
    let path = output_dir().join("coloured_cubes.3mf");
    save(&parted, &path).unwrap();
    let back = load(&path).unwrap();
    assert!(back.is_closed() && back.is_manifold());
    let mut seen: Vec<[u32; 4]> =
        (0..back.face_count() as u32).map(|f| back.face_color(f).expect("a base material").map(f32::to_bits)).collect();
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), 2, "{seen:?}");
}

#[test]
fn closed_mesh_written_as_stl_reloads_watertight() {
    // The cylinder's 16-gon caps are triangulated; welding by position closes the mesh again.
    let m = Mesh::cylinder(1.5, 3.0, 16);
    let path = output_dir().join("cylinder.stl");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    assert!(back.is_closed() && back.is_manifold());
    assert_eq!(back.genus(), 0);
    assert_eq!(back.vertex_count(), m.vertex_count());
    assert_eq!(back.face_count(), m.triangle_count());
    assert_rel(back.volume(), m.volume(), 1e-6, "volume");
    assert_rel(back.area(), m.area(), 1e-6, "area");
}

#[test]
fn obj_with_quads_loads_with_its_quads() {
    // tests/data/io/quads.obj: a cube of side 2 with normals, uvs, an object and a material.
    let m = load(data("quads.obj")).unwrap();
    assert!(m.is_quad_mesh());
    assert_eq!((m.vertex_count(), m.face_count()), (8, 6));
    assert!(m.is_closed());
    assert_rel(m.volume(), 8.0, 1e-15, "volume");
    assert_eq!(m.position(7), Vec3::new(1.0, 1.0, 1.0), "vertex 7 is the 8th v line");
}

#[test]
fn glb_written_by_trimesh_loads() {
    // trimesh's box of extents 2: 8 vertices, 12 triangles, volume 8.
    let m = load(data("trimesh_box.glb")).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (8, 12));
    assert!(m.is_closed());
    assert_rel(m.volume(), 8.0, 1e-7, "volume");

    // The scene: the box and an icosphere of radius 0.8 (3 subdivisions) at x = 2.5, red.
    // trimesh gives the icosphere's volume as 2.1262032983516455 (in f64; the file is f32).
    let s = load(data("trimesh_scene.glb")).unwrap();
    assert_eq!((s.vertex_count(), s.face_count()), (8 + 642, 12 + 1280));
    assert_eq!(s.component_count(), 2);
    assert!(s.is_closed());
    assert_rel(s.volume(), 8.0 + 2.1262032983516455, 1e-6, "volume");
    let colors = s.vertex_colors().expect("the icosphere has COLOR_0");
    assert_eq!(colors[0], [1.0; 4], "the box has no colours: white");
    // u8 components normalised by gltf: within an f32 rounding of k/255.
    let red = [200.0 / 255.0, 60.0 / 255.0, 60.0 / 255.0, 1.0f32];
    assert!(colors[8].iter().zip(red).all(|(a, b)| (a - b).abs() < 1e-6), "{:?} vs {red:?}", colors[8]);
}

/// Loads a broken file and checks that the message names it.
fn broken(name: &str) -> IoError {
    let path = data(name);
    let e = load(&path).expect_err(name);
    let msg = e.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "{name}: the message must name the path: {msg}");
    e
}

#[test]
fn each_broken_file_gives_its_error() {
    let e = broken("bad_index.obj");
    assert!(matches!(&e, IoError::IndexOutOfRange { at, index: 9, vertex_count: 8, .. } if at == "line 11"), "{e}");
    let e = broken("junk_line.obj");
    assert!(matches!(e, IoError::Obj { line: 4, .. }) && e.to_string().contains("unknown keyword \"this\""), "{e}");
    let e = broken("nan.obj");
    assert!(matches!(e, IoError::NonFinite { vertex: 2, .. }), "{e}");
    // Three triangles on one edge: loaded by default as the nearest manifold mesh (the third
    // face separated), refused when repair is off.
    let repaired = load(data("nonmanifold.obj")).unwrap();
    assert!(repaired.is_manifold() && repaired.face_count() == 3, "{repaired:?}");
    let path = data("nonmanifold.obj");
    let e = load_with(&path, &LoadOptions::DEFAULT.with_repair(false)).expect_err("repair: false");
    assert!(matches!(e, IoError::NotManifold { .. }) && e.to_string().contains("non-manifold"), "{e}");
    assert!(e.to_string().starts_with(&path.display().to_string()), "{e}");
    let e = broken("broken.glb");
    assert!(matches!(e, IoError::IndexOutOfRange { index: 9999, vertex_count: 8, .. }), "{e}");
    assert!(e.to_string().contains("mesh 0 primitive 0"), "{e}");
    let e = broken("truncated.glb");
    assert!(matches!(e, IoError::Gltf { .. }), "{e}");
    let e = broken("truncated.stl");
    assert!(matches!(e, IoError::Stl { .. }), "{e}");
    let e = broken("missing.obj");
    assert!(matches!(e, IoError::NotFound { .. }), "{e}");
}

#[test]
fn gltf_without_its_buffer_file_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.gltf");
    save(&Mesh::cube(1.0), &path).unwrap();
    let bin = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "bin"))
        .unwrap();
    std::fs::remove_file(&bin).unwrap();
    let e = load(&path).unwrap_err();
    assert!(matches!(e, IoError::Gltf { .. }), "{e}");
    // The message starts with the file being loaded and names the missing one.
    let bin = bin.display().to_string();
    assert!(e.to_string().starts_with(&path.display().to_string()) && e.to_string().contains("buffer"), "{e}");
    assert!(e.to_string().contains(&format!("{bin} is not found")), "{e}");
}

#[test]
fn a_directory_is_a_read_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("folder.obj");
    std::fs::create_dir(&path).unwrap();
    let e = load(&path).unwrap_err();
    assert!(matches!(e, IoError::Read { .. }), "{e}");
}

#[test]
fn vertex_used_by_no_face_keeps_its_id_in_gltf() {
    // A square with a stray fifth vertex: glTF vertex i stays mesh vertex i, the stray one too.
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y, Vec3::new(3.0, 3.0, 3.0)];
    let m = Mesh::from_polygons(p, &[[0u32, 1, 2, 3]]).unwrap();
    // An open square: under `open/`, which CI's independent closedness check skips.
    let dir = output_dir().join("open");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("unused_vertex.glb");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    assert_eq!(back.positions(), m.positions());
    assert_eq!(back.to_polygons(), vec![vec![0, 1, 2, 3]]);
}

#[test]
fn a_stop_lands_inside_loading_a_large_file_in_every_format() {
    // 81,920 triangles: the weld and the mesh build each poll or charge the token more than once.
    use blocksmith_kernel::limits::{install, CancelToken};
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;
    let m = Mesh::icosphere(1.0, 6);
    let d = tempfile::tempdir().unwrap();
    for ext in ["stl", "glb", "ply", "obj", "3mf"] {
        let p = d.path().join(format!("big.{ext}"));
        save(&m, &p).unwrap();
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = load(&p).unwrap_err().to_string();
            assert!(e.ends_with("interrupted"), "{ext}: {e}");
        }
        assert_eq!(load(&p).unwrap().face_count(), m.face_count(), "{ext}");
    }
}
