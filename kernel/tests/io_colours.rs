//! Face colours and part names through every format that keeps them (issue 31): glTF
//! materials and named nodes, 3MF base materials and named objects, OBJ `usemtl` with a `.mtl`
//! and `o` groups, PLY face colours. Each file is written to target/test-output/colours (CI runs
//! the Khronos validator, trimesh and the 3MF schemas over them), read back, and checked:
//! closed, manifold, the same volume, and the faces of each colour and name counted.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::io::{load, load_with, save, LoadOptions, Weld};
use blocksmith_kernel::mesh::to_hex_color;
use blocksmith_kernel::{Mesh, Vec3};

fn output_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-output/colours");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A red cube of quads named "body" minus a blue sphere (the bite is blue), beside a green,
/// half-transparent torus of quads named "lid", beside an uncoloured, unnamed cube.
fn parts_model() -> Mesh {
    let mut cube = Mesh::cube(2.0);
    cube.set_color([1.0, 0.0, 0.0, 1.0]).unwrap();
    let mut ball = Mesh::icosphere(0.8, 2).translate(Vec3::new(1.0, 1.0, 1.0));
    ball.set_color([0.0, 0.0, 1.0, 1.0]).unwrap();
    let mut body = Csg::mesh(cube).difference(Csg::mesh(ball)).evaluate().unwrap();
    body.map_parts(|p| p.name = Some("body".into()));
    let mut lid = Mesh::torus(1.0, 0.3, 16, 8).translate(Vec3::new(4.0, 0.0, 0.0));
    lid.set_color([0.0, 0.8, 0.2, 0.5]).unwrap();
    lid.map_parts(|p| p.name = Some("lid".into()));
    let plain = Mesh::cube(1.0).translate(Vec3::new(0.0, 4.0, 0.0));
    Mesh::combine(&[&body, &lid, &plain]).unwrap()
}

/// Faces per (colour as 8-bit hex, part name).
fn census(m: &Mesh) -> BTreeMap<(Option<String>, Option<String>), usize> {
    let mut out = BTreeMap::new();
    for f in 0..m.face_count() as u32 {
        let p = m.face_part(f);
        let key = (p.and_then(|p| p.color).map(to_hex_color), p.and_then(|p| p.name.as_deref().map(str::to_string)));
        *out.entry(key).or_insert(0) += 1;
    }
    out
}

/// The checks every read-back file passes: closed, manifold, the same volume, area and the same
/// faces per colour and name as `m` (whose faces the format keeps).
fn assert_same_parts(back: &Mesh, m: &Mesh, what: &str) {
    assert!(back.is_closed() && back.is_manifold(), "{what}: closed and manifold");
    assert_eq!(back.component_count(), 3, "{what}");
    assert!(
        (back.volume() - m.volume()).abs() < 1e-5 * m.volume(),
        "{what}: volume {} vs {}",
        back.volume(),
        m.volume()
    );
    assert_eq!(census(back), census(m), "{what}: faces per colour and name");
}

#[test]
fn the_model_has_four_colours_in_three_parts() {
    let m = parts_model();
    let c = census(&m);
    // The cube's 6 quads are cut by the sphere: red faces stay, the bite is blue.
    let colours: Vec<_> = c.keys().map(|k| k.0.clone()).collect();
    assert!(colours.contains(&Some("#ff0000".into())) && colours.contains(&Some("#0000ff".into())), "{c:?}");
    assert_eq!(c[&(Some("#00cc3380".into()), Some("lid".into()))], 16 * 8);
    assert_eq!(c[&(None, None)], 6);
    assert!(m.is_closed() && m.is_manifold());
}

#[test]
fn glb_keeps_colours_as_materials_and_names_as_nodes() {
    let m = parts_model();
    let path = output_dir().join("parts.glb");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    assert_same_parts(&back, &m, "glb");
    // Colours are f32 in the file: exact.
    let mut want: Vec<_> = (0..m.face_count() as u32).map(|f| m.face_color(f).map(|c| c.map(f32::to_bits))).collect();
    let mut got: Vec<_> =
        (0..back.face_count() as u32).map(|f| back.face_color(f).map(|c| c.map(f32::to_bits))).collect();
    want.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, want);
    // The torus's quads come back as quads (each primitive's arity runs).
    assert_eq!(back.face_count(), m.face_count());
    // Every primitive shares the vertices: unwelded, the file has the mesh's vertices.
    let raw = load_with(&path, &LoadOptions::DEFAULT.with_weld(Weld::Off)).unwrap();
    assert_eq!((raw.vertex_count(), raw.face_count()), (m.vertex_count(), m.face_count()));
    assert!(raw.is_closed());
    // The JSON: one node per part name (the unnamed cube's node has none), one material per
    // colour, the transparent one blended.
    let bytes = std::fs::read(&path).unwrap();
    let glb = gltf::Gltf::from_slice(&bytes).unwrap();
    let names: Vec<Option<&str>> = glb.nodes().map(|n| n.name()).collect();
    assert_eq!(names, [Some("body"), Some("lid"), None]);
    let materials: Vec<(Option<&str>, [f32; 4], gltf::material::AlphaMode)> =
        glb.materials().map(|x| (x.name(), x.pbr_metallic_roughness().base_color_factor(), x.alpha_mode())).collect();
    assert_eq!(materials.len(), 3, "{materials:?}");
    assert!(materials.contains(&(Some("#00cc3380"), [0.0, 0.8, 0.2, 0.5], gltf::material::AlphaMode::Blend)));
    assert!(materials.contains(&(Some("#ff0000"), [1.0, 0.0, 0.0, 1.0], gltf::material::AlphaMode::Opaque)));
    let primitives: usize = glb.meshes().map(|x| x.primitives().len()).sum();
    assert_eq!(primitives, 4, "red and blue in the body, green in the lid, the plain cube's default material");
}

#[test]
fn gltf_pair_keeps_colours_and_names() {
    let m = parts_model();
    let path = output_dir().join("parts.gltf");
    save(&m, &path).unwrap();
    assert_same_parts(&load(&path).unwrap(), &m, "gltf");
}

#[test]
fn three_mf_keeps_colours_as_base_materials_and_names_as_objects() {
    let m = parts_model();
    let path = output_dir().join("parts.3mf");
    save(&m, &path).unwrap();
    let back = load(&path).unwrap();
    // 3MF writes triangles.
    assert!(back.is_closed() && back.is_manifold());
    assert_eq!(census(&back), census(&m.triangulate().unwrap()));
}

#[test]
fn an_uncoloured_boolean_result_is_saved_without_colours_in_every_format() {
    // Provenance (which input each face came from) is the studio's debugging view, not the
    // model's colour.
    let m = Csg::mesh(Mesh::cube(2.0))
        .difference(Csg::mesh(Mesh::icosphere(0.8, 2).translate(Vec3::splat(1.0))))
        .evaluate()
        .unwrap();
    assert!(m.face_sources().is_some());
    for name in ["plain_bite.glb", "plain_bite.gltf", "plain_bite.3mf", "plain_bite.obj", "plain_bite.ply"] {
        let path = output_dir().join(name);
        save(&m, &path).unwrap();
        let back = load(&path).unwrap();
        assert!(back.is_closed() && back.is_manifold(), "{name}");
        assert!(!back.has_face_colors() && back.vertex_colors().is_none(), "{name}: no colours");
        assert_eq!(back.face_count(), m.face_count(), "{name}");
    }
}

#[test]
fn obj_keeps_colours_in_its_material_library_and_names_as_objects() {
    let m = parts_model();
    let path = output_dir().join("parts.obj");
    save(&m, &path).unwrap();
    let mtl = std::fs::read_to_string(output_dir().join("parts.mtl")).unwrap();
    assert_eq!(mtl.matches("newmtl ").count(), 3, "{mtl}");
    assert!(mtl.contains("newmtl #00cc3380\nKd 0 0.8 0.2\nd 0.5\n"), "{mtl}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("mtllib parts.mtl\n") && text.contains("o body\n") && text.contains("o lid\n"));
    let back = load(&path).unwrap();
    assert_same_parts(&back, &m, "obj");
    // Exact positions and the same vertices; colours exact in f32.
    assert_eq!(back.positions(), m.positions());
    let mut want: Vec<_> = (0..m.face_count() as u32).map(|f| m.face_color(f).map(|c| c.map(f32::to_bits))).collect();
    let mut got: Vec<_> =
        (0..back.face_count() as u32).map(|f| back.face_color(f).map(|c| c.map(f32::to_bits))).collect();
    want.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, want);
    // Without its library the OBJ still loads, names kept, colours gone.
    let lone = output_dir().join("lone");
    std::fs::create_dir_all(&lone).unwrap();
    std::fs::copy(&path, lone.join("parts.obj")).unwrap();
    let _ = std::fs::remove_file(lone.join("parts.mtl"));
    let bare = load(lone.join("parts.obj")).unwrap();
    assert!(!bare.has_face_colors() && bare.face_part(0).is_some());
    // A mesh without colours writes no library.
    let plain = output_dir().join("plain_cube.obj");
    save(&Mesh::cube(1.0), &plain).unwrap();
    assert!(!output_dir().join("plain_cube.mtl").exists());
    assert!(!std::fs::read_to_string(&plain).unwrap().contains("mtllib"));
}

#[test]
fn ply_keeps_face_colours_in_8_bits() {
    // Triangles in the files left for CI (trimesh reads no binary PLY mixing triangles and
    // quads); the polygons in a temporary folder.
    let tmp = tempfile::tempdir().unwrap();
    for (m, dir) in [(parts_model().triangulate().unwrap(), output_dir()), (parts_model(), tmp.path().to_path_buf())] {
        ply_round_trip(&m, &dir);
    }
}

fn ply_round_trip(m: &Mesh, dir: &Path) {
    for (name, enc) in [
        ("parts.ply", blocksmith_kernel::io::PlyEncoding::BinaryLittleEndian),
        ("parts_ascii.ply", blocksmith_kernel::io::PlyEncoding::Ascii),
        ("parts_be.ply", blocksmith_kernel::io::PlyEncoding::BinaryBigEndian),
    ] {
        let path = dir.join(name);
        blocksmith_kernel::io::save_with(m, &path, &blocksmith_kernel::io::SaveOptions::DEFAULT.with_ply(enc)).unwrap();
        let back = load(&path).unwrap();
        assert!(back.is_closed() && back.is_manifold(), "{name}");
        assert_eq!(back.face_count(), m.face_count(), "{name}");
        // PLY keeps faces in order, colours in 8 bits, no names; an uncoloured face is white.
        for f in 0..m.face_count() as u32 {
            let want = to_hex_color(m.face_color(f).unwrap_or([1.0; 4]));
            assert_eq!(back.face_color(f).map(to_hex_color), Some(want), "{name} face {f}");
        }
        assert!(back.parts().iter().all(|p| p.name.is_none()));
    }
}
