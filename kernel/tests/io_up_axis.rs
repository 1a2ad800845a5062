//! The up axis of files: blocksmith is Z-up, glTF Y-up by specification (glTF 2.0 §3.4), so
//! glTF is converted on write and read; OBJ and STL take an `up` option.

use std::path::{Path, PathBuf};

use blocksmith_kernel::io::{load, load_with, save, save_with, IoError, LoadOptions, SaveOptions, UpAxis};
use blocksmith_kernel::{Mesh, Vec3};

fn output_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-output/io");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A box 1 wide, 2 deep and 5 tall (in z), off the origin, with f32-exact coordinates.
fn tall_box() -> Mesh {
    Mesh::cuboid(Vec3::new(0.5, 1.0, 0.25), Vec3::new(1.5, 3.0, 5.25))
}

#[test]
fn a_tall_box_written_to_glb_is_tallest_in_gltf_y_and_reads_back_exactly() {
    let m = tall_box();
    let path = output_dir().join("tall_box.glb");
    save(&m, &path).unwrap();
    // The file's POSITION accessor, read by the gltf crate (not our reader).
    let (doc, buffers, _) = gltf::import(&path).unwrap();
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let pos: Vec<[f32; 3]> = prim.reader(|b| Some(&buffers[b.index()])).read_positions().unwrap().collect();
    let extent = |k: usize| {
        let (lo, hi) = pos.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| (lo.min(p[k]), hi.max(p[k])));
        (lo, hi)
    };
    // Kernel z ∈ [0.25, 5.25] is glTF y; kernel y ∈ [1, 3] is glTF −z ∈ [−3, −1].
    assert_eq!(extent(0), (0.5, 1.5));
    assert_eq!(extent(1), (0.25, 5.25), "the height is along glTF's up axis");
    assert_eq!(extent(2), (-3.0, -1.0));
    // The normals turn with the positions: each corner's normal points away from the centre
    // (1, 2.75, −2) along every glTF axis.
    let normals: Vec<[f32; 3]> = prim.reader(|b| Some(&buffers[b.index()])).read_normals().unwrap().collect();
    for (p, n) in pos.iter().zip(&normals) {
        let c = [1.0, 2.75, -2.0];
        assert!((0..3).all(|k| (p[k] - c[k]) * n[k] > 0.0), "normal {n:?} at {p:?}");
    }
    let back = load(&path).unwrap();
    assert_eq!(back.positions(), m.positions(), "exact round trip");
    assert_eq!(back.to_polygons(), m.to_polygons());
}

#[test]
fn obj_and_stl_take_an_up_axis_both_ways() {
    let m = tall_box();
    for name in ["tall_box_y_up.obj", "tall_box_y_up.stl"] {
        let path = output_dir().join(name);
        save_with(&m, &path, &SaveOptions::DEFAULT.with_up(UpAxis::Y)).unwrap();
        // Read as it is (Z-up), the file's height is along y.
        let raw = load(&path).unwrap();
        let b = raw.bounds();
        assert_eq!((b.min.y, b.max.y), (0.25, 5.25), "{name}");
        // Read as Y-up, it is the box again, exactly.
        let back = load_with(&path, &LoadOptions::DEFAULT.with_up(UpAxis::Y)).unwrap();
        assert_eq!(back.bounds(), m.bounds(), "{name}");
        assert!((back.volume() - 10.0).abs() < 1e-12, "{name}: {}", back.volume());
    }
}

#[test]
fn gltf_refuses_another_up_axis() {
    let path = output_dir().join("never_written.glb");
    let e = save_with(&tall_box(), &path, &SaveOptions::DEFAULT.with_up(UpAxis::Z)).unwrap_err();
    assert!(matches!(e, IoError::Unsupported { .. }) && e.to_string().contains("Y-up by specification"), "{e}");
    let e = load_with(&path, &LoadOptions::DEFAULT.with_up(UpAxis::Z)).unwrap_err();
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
}
