//! The regression corpus of real-world file classes (tests/data/files, made by make_files.py):
//! each file loads with trimesh's counts, Euler characteristic, area (1e-9 relative) and volume,
//! and shows the behaviour named in expected.json (`closed`: a closed manifold mesh;
//! `triangulates`: a valid triangulation, written to STL and GLB and read back closed).
//! Every closed one is also written to PLY (binary and ASCII) and 3MF and read back bit for bit, and
//! the written files are left for CI's independent trimesh check.

use std::path::{Path, PathBuf};

use blocksmith_kernel::io::{load, save, save_with, PlyEncoding, SaveOptions};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/files")
}

fn assert_rel(name: &str, what: &str, got: f64, want: f64) {
    let d = (got - want).abs() / want.abs().max(1e-300);
    assert!(d <= 1e-9, "{name}: {what} {got}, trimesh {want}, relative difference {d:e}");
}

#[test]
fn every_corpus_file_matches_trimesh_and_its_behaviour() {
    let text = std::fs::read_to_string(corpus().join("expected.json")).unwrap();
    let expected: serde_json::Value = serde_json::from_str(&text).unwrap();
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-output/files");
    std::fs::create_dir_all(&out).unwrap();
    let entries = expected.as_object().unwrap();
    assert!(entries.len() >= 6);
    for (name, e) in entries {
        let m = load(corpus().join(name)).unwrap_or_else(|err| panic!("{name}: {err}"));
        let int = |k: &str| e[k].as_u64().unwrap() as usize;
        if let Some(p) = e.get("polygons") {
            assert_eq!(m.face_count(), p.as_u64().unwrap() as usize, "{name}: polygons");
        }
        if e.get("colors").is_some() {
            assert!(m.vertex_colors().is_some(), "{name}: colours");
        }
        if let Some(c) = e.get("components") {
            assert_eq!(m.component_count(), c.as_u64().unwrap() as usize, "{name}: components");
        }
        let t = m.triangulate().unwrap_or_else(|err| panic!("{name}: {err}"));
        assert_eq!((t.vertex_count(), t.face_count()), (int("vertices"), int("faces")), "{name}: counts");
        assert_eq!(t.euler(), e["euler"].as_i64().unwrap(), "{name}: Euler characteristic");
        assert_rel(name, "area", m.area(), e["area"].as_f64().unwrap());
        // The pillow's two skew quads enclose no side of their own: which way its tetrahedron
        // faces depends on the diagonals taken, so only its volume's size is held (and the K₅
        // torus crosses itself).
        let volume = if e["must"] == "triangulates" { m.volume().abs() } else { m.volume() };
        let want = e["volume"].as_f64().unwrap();
        if want.abs() < 1e-12 * m.area() {
            // No volume (the torus's sheets cancel): both sums are rounding noise.
            assert!(volume.abs() < 1e-12 * m.area(), "{name}: volume {volume}, trimesh {want}");
        } else {
            assert_rel(name, "volume", volume, want);
        }
        assert!(t.is_closed() && t.is_manifold(), "{name}: not closed");
        match e["must"].as_str().unwrap() {
            "closed" => {
                assert!(m.is_closed() && m.is_manifold(), "{name}");
                for (enc, suffix) in [(PlyEncoding::BinaryLittleEndian, "bin"), (PlyEncoding::Ascii, "ascii")] {
                    let path = out.join(format!("{name}.{suffix}.ply"));
                    save_with(&m, &path, &SaveOptions::DEFAULT.with_ply(enc)).unwrap();
                    let back = load(&path).unwrap_or_else(|err| panic!("{name}: {err}"));
                    assert_eq!(back.positions(), m.positions(), "{name}.{suffix}.ply");
                    assert_eq!(back.to_polygons(), m.to_polygons(), "{name}.{suffix}.ply");
                }
                // 3MF keeps triangles: the triangulated mesh comes back bit for bit.
                let path = out.join(format!("{name}.3mf"));
                save(&m, &path).unwrap_or_else(|err| panic!("{name}: {err}"));
                let back = load(&path).unwrap_or_else(|err| panic!("{name}: {err}"));
                assert_eq!(back.positions(), t.positions(), "{name}.3mf");
                assert_eq!(back.to_polygons(), t.to_polygons(), "{name}.3mf");
            }
            "triangulates" => {
                for ext in ["stl", "glb"] {
                    let path = out.join(format!("{name}.{ext}"));
                    save(&m, &path).unwrap_or_else(|err| panic!("{name}: {err}"));
                    let back = load(&path).unwrap();
                    assert!(back.is_closed() && back.is_manifold(), "{name}.{ext}");
                    assert_eq!(back.vertex_count(), int("vertices"), "{name}.{ext}");
                }
            }
            other => panic!("{name}: unknown behaviour {other}"),
        }
    }
}
