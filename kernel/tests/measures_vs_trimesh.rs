//! The kernel's measures against trimesh's, for cube, box, icosphere, cylinder and a torus
//! built from indexed polygons: volume and area to 1e-9 relative, Euler characteristic and
//! genus exact.
//!
//! The numbers were printed by tests/data/measures_trimesh.py (trimesh 5.2.0), which builds the
//! cube, the box and the icosphere itself and reads the cylinder and the torus from the OBJ
//! files the kernel wrote to tests/data/measures/.

use std::path::{Path, PathBuf};

use blocksmith_kernel::io::obj::write_obj;
use blocksmith_kernel::{Mesh, Vec3};

/// One line of measures_trimesh.py's output.
struct Expected {
    name: &'static str,
    vertices: usize,
    faces: usize,
    volume: f64,
    area: f64,
    euler: i64,
    genus: i64,
}

const TRIMESH: [Expected; 5] = [
    Expected { name: "cube", vertices: 8, faces: 12, volume: 8.0, area: 24.0, euler: 2, genus: 0 },
    Expected { name: "box", vertices: 8, faces: 12, volume: 6.0, area: 31.0, euler: 2, genus: 0 },
    Expected {
        name: "icosphere",
        vertices: 642,
        faces: 1280,
        volume: 4.152740817093058,
        area: 12.506492733969928,
        euler: 2,
        genus: 0,
    },
    Expected {
        name: "cylinder",
        vertices: 32,
        faces: 60,
        volume: CYLINDER_VOLUME,
        area: CYLINDER_AREA,
        euler: 2,
        genus: 0,
    },
    Expected { name: "torus", vertices: 288, faces: 576, volume: TORUS_VOLUME, area: TORUS_AREA, euler: 0, genus: 1 },
];

const CYLINDER_VOLUME: f64 = 20.664905347714846;
const CYLINDER_AREA: f64 = 41.8696099354657;
const TORUS_VOLUME: f64 = 9.317485623690745;
const TORUS_AREA: f64 = 38.751335357235234;

fn ours(name: &str) -> Mesh {
    match name {
        "cube" => Mesh::cube(2.0),
        "box" => Mesh::cuboid(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(2.0, 0.5, 6.0)),
        "icosphere" => Mesh::icosphere(1.0, 3),
        "cylinder" => Mesh::cylinder(1.5, 3.0, 16),
        "torus" => torus_from_indexed_quads(),
        _ => unreachable!("no mesh named {name}"),
    }
}

/// The torus of `Mesh::torus(2.0, 0.5, 24, 12)`, built here from its indexed quads with
/// `Mesh::from_indexed` (the path every file reader takes).
fn torus_from_indexed_quads() -> Mesh {
    let t = Mesh::torus(2.0, 0.5, 24, 12);
    let (indices, arities) = t.to_indexed();
    assert!(arities.iter().all(|&a| a == 4));
    Mesh::from_indexed(t.positions().to_vec(), &indices, &arities).unwrap()
}

fn assert_rel(a: f64, b: f64, tol: f64, what: &str) {
    let d = (a - b).abs() / b.abs();
    assert!(d <= tol, "{what}: ours {a}, trimesh {b}, difference {}, relative {d:e}", a - b);
}

#[test]
fn measures_agree_with_trimesh() {
    for e in &TRIMESH {
        let m = ours(e.name);
        assert!(m.is_closed() && m.is_manifold(), "{}", e.name);
        assert_eq!(m.vertex_count(), e.vertices, "{}: vertices", e.name);
        // trimesh counts triangles; ours may be polygons.
        assert_eq!(m.triangle_count(), e.faces, "{}: triangles", e.name);
        assert_rel(m.volume(), e.volume, 1e-9, &format!("{}: volume", e.name));
        assert_rel(m.area(), e.area, 1e-9, &format!("{}: area", e.name));
        assert_eq!(m.euler(), e.euler, "{}: Euler characteristic", e.name);
        assert_eq!(m.genus(), e.genus, "{}: genus", e.name);
    }
}

fn measures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/measures")
}

fn obj_text(name: &str) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_obj(&ours(name), &mut bytes).unwrap();
    bytes
}

#[test]
fn committed_objs_are_what_the_kernel_writes() {
    // trimesh measured these files; they must still be the kernel's meshes.
    for name in ["cylinder", "torus"] {
        let committed = std::fs::read(measures_dir().join(format!("{name}.obj"))).unwrap();
        assert!(committed == obj_text(name), "tests/data/measures/{name}.obj is stale: rerun write_measure_objs");
    }
}

/// Writes the OBJ files measures_trimesh.py reads.
#[test]
#[ignore = "writes tests/data/measures/*.obj; run by hand before measures_trimesh.py"]
fn write_measure_objs() {
    std::fs::create_dir_all(measures_dir()).unwrap();
    for name in ["cylinder", "torus"] {
        std::fs::write(measures_dir().join(format!("{name}.obj")), obj_text(name)).unwrap();
    }
}
