use super::*;
use crate::finish::sharp_edges;

fn check_solid(m: &Mesh, genus: i64) {
    assert!(m.is_closed() && m.is_manifold(), "not a closed manifold");
    assert_eq!(m.genus(), genus);
}

#[test]
fn a_cube_with_sharp_edges_refines_to_the_same_cube() {
    let cube = Mesh::cube(2.0);
    let sharp = sharp_edges(&cube, 60.0).unwrap();
    let r = refine(&sharp, 4).unwrap();
    check_solid(&r, 0);
    assert_eq!(r.face_count(), 12 * 16);
    assert!((r.volume() - 8.0).abs() < 1e-9, "{}", r.volume());
    // Every vertex stays on the cube's surface, and the 12 edges stay creased (4 pieces each).
    for p in r.positions() {
        assert!((p.abs().max_element() - 1.0).abs() < 1e-9, "{p}");
    }
    assert_eq!(r.crease_count(), 12 * 4);
}

#[test]
fn an_untagged_cube_rounds_and_a_sphere_gets_rounder() {
    let r = refine(&Mesh::cube(2.0), 6).unwrap();
    check_solid(&r, 0);
    // Smoothed everywhere: the refinement interpolates, so the corners stay and the faces bulge
    // out between them.
    let max = r.positions().iter().map(|p| p.length()).fold(0.0, f64::max);
    assert!((max - 3f64.sqrt()).abs() < 1e-12, "{max}");
    let bulge = r.positions().iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
    assert!(bulge > 1.05, "{bulge}");
    assert!(r.volume() > 8.0 && r.volume() < 4.0 / 3.0 * std::f64::consts::PI * 3f64.sqrt().powi(3), "{}", r.volume());
    // An icosphere: the refined points lie closer to the sphere than the flat facets' midpoints.
    let ball = Mesh::icosphere(1.0, 1);
    let r = refine(&ball, 4).unwrap();
    check_solid(&r, 0);
    let worst = r.positions().iter().map(|p| (p.length() - 1.0).abs()).fold(0.0, f64::max);
    // The facets' centres of a 1-level icosphere are 0.06 inside the sphere.
    assert!(worst < 0.02, "{worst}");
}

#[test]
fn parts_and_torus_genus_survive() {
    let mut t = Mesh::torus(2.0, 0.6, 16, 8);
    t.set_color([1.0, 0.0, 0.0, 1.0]).unwrap();
    let r = refine_to_length(&t, 0.2).unwrap();
    check_solid(&r, 1);
    assert!((0..r.face_count() as u32).all(|f| r.face_color(f) == Some([1.0, 0.0, 0.0, 1.0])));
    let longest = r.edges().map(|h| r.position(r.origin(h)).distance(r.position(r.target(h)))).fold(0.0, f64::max);
    // Straight pieces are at most `length`; on the curved patches and across the sub-triangles'
    // diagonals somewhat longer.
    assert!(longest < 1.6 * 0.2, "{longest}");
}

#[test]
fn bad_requests_are_refused_by_name_before_allocating() {
    let c = Mesh::cube(1.0);
    assert!(refine(&c, 0).unwrap_err().to_string().contains("`n`"));
    let e = refine(&Mesh::icosphere(1.0, 4), 1000).unwrap_err().to_string();
    assert!(e.contains("estimated") && e.contains("triangles"), "{e}");
    let e = refine_to_length(&c, 1e-9).unwrap_err().to_string();
    assert!(e.contains("refine_to_length") && e.contains("estimated"), "{e}");
    assert!(refine_to_length(&c, f64::NAN).unwrap_err().to_string().contains("`length`"));
    let open = Mesh::from_polygons(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]).unwrap();
    assert!(refine(&open, 2).unwrap_err().to_string().contains("boundary edges"));
}
