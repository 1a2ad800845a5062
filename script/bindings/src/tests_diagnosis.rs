use blocksmith_kernel::{Mesh, Vec3};

use super::*;

#[test]
fn a_cube_is_clean_and_one_closed_component() {
    let d = Diagnosis::of(&Mesh::cuboid(Vec3::ZERO, Vec3::ONE)).unwrap();
    assert!(d.is_clean(), "{d:?}");
    assert_eq!(d.components, vec![Component { faces: 6, genus: 0, boundary_loops: 0, at: Vec3::splat(0.5) }]);
    let j = d.json();
    assert_eq!((j["component_count"].as_u64(), j["self_intersections"]["count"].as_u64()), (Some(1), Some(0)));
    assert_eq!(
        d.text()[..2],
        ["components: 1".to_string(), "  0: 6 faces, genus 0, closed, around (0.5, 0.5, 0.5)".to_string()]
    );
    assert_eq!(d.overlay()["clean"], true);
}

#[test]
fn an_empty_mesh_has_no_component() {
    let d = Diagnosis::of(&Mesh::from_polygons(vec![], &Vec::<Vec<u32>>::new()).unwrap()).unwrap();
    assert!(d.components.is_empty() && d.is_clean());
}

#[test]
fn a_torus_and_an_open_overlapping_pair_say_where() {
    let torus = Mesh::try_torus(3.0, 1.0, 24, 12).unwrap();
    // A 3 × 1 rectangle across the tube at z = -0.5: its face crosses the tube's faces.
    let square = Mesh::from_polygons(
        vec![
            Vec3::new(1.5, -0.5, -0.5),
            Vec3::new(4.5, -0.5, -0.5),
            Vec3::new(4.5, 0.5, -0.5),
            Vec3::new(1.5, 0.5, -0.5),
        ],
        &[vec![0, 1, 2, 3]],
    )
    .unwrap();
    let m = Mesh::combine(&[&torus, &square]).unwrap();
    let d = Diagnosis::of(&m).unwrap();
    assert_eq!(
        d.components.iter().map(|c| (c.faces, c.genus, c.boundary_loops)).collect::<Vec<_>>(),
        [(288, 1, 0), (1, 0, 1)]
    );
    assert_eq!(d.boundaries.len(), 1);
    assert_eq!(d.boundaries[0].points.len(), 4);
    assert!((d.boundaries[0].length - 8.0).abs() < 1e-12);
    assert_eq!(d.handles.len(), 1);
    // The tube's circumference as 12 chords: 12 · 2 sin(π/12) ≈ 6.21.
    assert!((d.handles[0].length - 24.0 * (std::f64::consts::PI / 12.0).sin()).abs() < 1e-9, "{}", d.handles[0].length);
    assert!(!d.crossings.is_empty() && d.crossings.iter().all(|(f, _)| f[0] < 288 && f[1] == 288));
    assert_eq!(d.crossing_faces.len(), d.crossings.len() + 1);
    let o = d.overlay();
    assert_eq!(o["boundaries"][0].as_array().unwrap().len(), 12);
    assert_eq!(o["handles"][0].as_array().unwrap().len(), 36);
    assert_eq!(o["clean"], false);
    let text = d.text().join("\n");
    assert!(text.contains("components: 2\n  0: 288 faces, genus 1, closed"), "{text}");
    assert!(text.contains("  1: 1 faces, genus 0, 1 boundary loop"), "{text}");
    assert!(text.contains(&format!("self-intersecting face pairs: {}", d.crossings.len())), "{text}");
    let j = d.json();
    assert_eq!(j["handles"][0]["vertices"], 12);
    assert_eq!(j["boundaries"][0]["component"], 1);
}
