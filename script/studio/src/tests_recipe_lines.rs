use std::path::Path;

use blocksmith_kernel::{Mesh, Vec3};
use blocksmith_script::api::mesh::SharedMesh;

use super::*;

/// The die's case in small: a cube with a sphere's bite out of its top.
const RECIPE: &str = "let body = cube(2);\nlet pip = uv_sphere(0.3, 16, 8).translate([0, 0, 1]);\nbody - pip\n";

fn run(dir: &Path) -> (Mesh, String) {
    let path = dir.join("die.rhai");
    std::fs::write(&path, RECIPE).unwrap();
    let run = blocksmith_script::run::run_recipe(&path, blocksmith_script::EngineOptions::default())
        .unwrap_or_else(|f| panic!("{}", f.error));
    let m = run.value.try_cast::<SharedMesh>().unwrap();
    ((*m.0).clone(), path.display().to_string())
}

fn calls(steps: &[Step]) -> Vec<String> {
    steps.iter().map(|s| format!("{}@{}:{}", s.call, s.site.line, s.site.column)).collect()
}

#[test]
fn a_point_in_the_bite_leads_to_the_sphere_and_one_on_the_side_to_the_cube() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, path) = run(dir.path());
    // The bite's bottom is the sphere's lowest point, 0.3 under the top.
    let f = face_at(&mesh, Vec3::new(0.0, 0.0, 0.7)).unwrap();
    let steps = chain(&mesh, f);
    assert_eq!(calls(&steps), ["uv_sphere@2:11", "translate@2:33", "-@3:6"]);
    assert_eq!(steps[0].site.file.as_deref(), Some(path.as_str()));
    assert_eq!(steps[0].site.path(), Some(Path::new(&path).canonicalize().unwrap()));
    let side = face_at(&mesh, Vec3::new(1.0, 0.2, -0.3)).unwrap();
    assert_eq!(calls(&chain(&mesh, side)), ["cube@1:12", "-@3:6"]);
}

#[test]
fn the_faces_of_a_line_are_those_its_call_made_and_only_those() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, path) = run(dir.path());
    let sphere = |file: Option<String>, column| faces_made_at(&mesh, &Site { file, line: 2, column });
    let by_line = sphere(None, 0);
    assert!(!by_line.is_empty());
    assert!(by_line.iter().all(|&f| chain(&mesh, f)[0].call == "uv_sphere"));
    let others = (0..mesh.face_count() as u32).filter(|f| !by_line.contains(f));
    assert!(others.into_iter().all(|f| chain(&mesh, f)[0].call == "cube"));
    // The same faces by the call's column, by the file's path however it is written, and none
    // for another file or a column where no call starts.
    assert_eq!(sphere(None, 11), by_line);
    assert_eq!(sphere(Some(path.clone()), 11), by_line);
    let roundabout = dir.path().join(".").join("die.rhai").display().to_string();
    assert_eq!(sphere(Some(roundabout), 0), by_line);
    assert!(sphere(Some(dir.path().join("other.rhai").display().to_string()), 0).is_empty());
    assert!(sphere(None, 5).is_empty());
    // The subtraction on line 3 made every face.
    assert_eq!(faces_made_at(&mesh, &Site { file: None, line: 3, column: 0 }).len(), mesh.face_count());
    // Their triangles: nine numbers each, all on the sphere of radius 0.3 about (0, 0, 1).
    let t = triangles(&mesh, &by_line);
    assert_eq!(t.len() % 9, 0);
    for p in t.chunks(3) {
        let r = Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]) - 1.0).length();
        assert!(r <= 0.3 + 1e-6, "corner {p:?} off the sphere");
    }
}

#[test]
fn the_nearest_point_of_a_triangle_is_found_in_every_region() {
    let (a, b, c) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
    let near = |x: f64, y: f64, z: f64| closest_on_triangle(Vec3::new(x, y, z), a, b, c);
    assert_eq!(near(0.5, 0.5, 3.0), Vec3::new(0.5, 0.5, 0.0), "inside: straight down");
    assert_eq!(near(-1.0, -1.0, 0.0), a);
    assert_eq!(near(3.0, -1.0, 0.0), b);
    assert_eq!(near(-1.0, 3.0, 0.0), c);
    assert_eq!(near(1.0, -1.0, 0.0), Vec3::new(1.0, 0.0, 0.0), "edge ab");
    assert_eq!(near(-1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0), "edge ac");
    assert_eq!(near(2.0, 2.0, 0.0), Vec3::new(1.0, 1.0, 0.0), "edge bc");
}

#[test]
fn a_mesh_without_origins_has_no_chain_and_no_faces_of_a_line() {
    let cube = Mesh::try_cube(2.0).unwrap();
    assert!(chain(&cube, 0).is_empty());
    assert!(faces_made_at(&cube, &Site { file: None, line: 1, column: 0 }).is_empty());
    assert_eq!(face_at(&cube, Vec3::new(0.0, 0.0, 5.0)).map(|f| cube.face_normal(f).z > 0.9), Some(true));
}

#[test]
fn a_faces_corners_are_its_polygons_triangles_at_full_precision() {
    // A cylinder's top cap is one 32-gon: 30 triangles of its fan, every corner on the rim at
    // z = 1 and radius 1.5 (f64, not the f32 the drawn triangles hold).
    let mesh = Mesh::cylinder(1.5, 2.0, 32);
    let top = face_at(&mesh, Vec3::new(0.1, 0.2, 1.0)).unwrap();
    let corners = corners(&mesh, top);
    assert_eq!(corners.len(), 30 * 9);
    for p in corners.chunks(3) {
        assert_eq!(p[2], 1.0);
        let r = p[0].hypot(p[1]);
        assert!((r - 1.5).abs() < 1e-15, "a corner at radius {r}, off by {}", (r - 1.5).abs());
    }
}
