//! Every measure that scripts reach and that gives a centre, a normal or a radius is the same for
//! a model moved far from the origin (up to 1e8) as for the model at the origin, moved: each sums
//! about a point of the model (the centre of its bounds, or its first point), never about the
//! origin, so no digits are lost to cancellation.
//!
//! At 1e8 the coordinates themselves are spaced 1.49e-8 apart, so the moved model is the model
//! to within that; the tolerances are a few of those spacings, while a sum about the origin
//! misses by orders of magnitude more (the volume of a unit icosphere at 1e6 came out at −1135).

use blocksmith_kernel::polar::{Frame, PolarMesh};
use blocksmith_kernel::solve::{fit_cylinder, RadiusRule, ShapeUp};
use blocksmith_kernel::{Mesh, Vec3};

const OFFSETS: [f64; 4] = [1e4, 1e6, 1e7, 1e8];

/// The offset of each test: off every axis, with mixed signs.
fn offset(d: f64) -> Vec3 {
    Vec3::new(d, -0.75 * d, 0.5 * d)
}

/// Allowed error of a point near `d`: four coordinate spacings there, plus a model-sized floor.
fn point_tol(d: f64) -> f64 {
    4.0 * d * f64::EPSILON + 1e-12
}

fn assert_point(what: &str, d: f64, got: Vec3, want: Vec3) {
    let e = (got - want).abs().max_element();
    assert!(e <= point_tol(d), "{what} at offset {d:e}: {got} against {want}, {e:e} off");
}

/// A unit direction: the tolerance is relative to the model's size (1), a few spacings at `d`.
fn assert_direction(what: &str, d: f64, got: Vec3, want: Vec3) {
    let e = (got - want).length();
    assert!(e <= 8.0 * point_tol(d), "{what} at offset {d:e}: {got} against {want}, {e:e} off");
}

fn assert_value(what: &str, d: f64, got: f64, want: f64) {
    let e = (got - want).abs();
    assert!(e <= 8.0 * point_tol(d) * want.abs().max(1.0), "{what} at offset {d:e}: {got} against {want}, {e:e} off");
}

#[test]
fn mesh_measures_and_normals() {
    // A lumpy closed mesh of quads and triangles (a torus) and a sphere of triangles.
    for m in [Mesh::torus(1.0, 0.4, 48, 24), Mesh::icosphere(1.0, 3)] {
        let (volume, area, centroid) = (m.volume(), m.area(), m.centroid());
        let normals = m.vertex_normals();
        for d in OFFSETS {
            let o = offset(d);
            let far = m.translate(o);
            assert_value("volume", d, far.volume(), volume);
            assert_value("area", d, far.area(), area);
            assert_point("centroid", d, far.centroid() - o, centroid);
            for f in (0..m.face_count() as u32).step_by(37) {
                assert_point("face centroid", d, far.face_centroid(f) - o, m.face_centroid(f));
                assert_direction("face normal", d, far.face_normal(f), m.face_normal(f));
                assert_value("face area", d, far.face_area(f), m.face_area(f));
            }
            for (v, n) in far.vertex_normals().iter().enumerate().step_by(41) {
                assert_direction("vertex normal", d, *n, normals[v]);
            }
        }
    }
}

#[test]
fn triangulation_centres_of_skew_polygons() {
    // A non-planar hexagon whose projection crosses itself is cut about its centroid: the
    // added vertex is the corners' mean wherever the polygon lies.
    let corners = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(-0.5, 0.9, 0.4),
        Vec3::new(-0.5, -0.9, -0.4),
        Vec3::new(1.0, 0.1, 0.3),
        Vec3::new(-0.5, 0.8, -0.2),
        Vec3::new(-0.4, -0.9, 0.2),
    ];
    let near = Mesh::from_polygons(corners.to_vec(), &[(0..6).collect::<Vec<u32>>()]).unwrap();
    let t0 = near.triangulate().unwrap();
    for d in OFFSETS {
        let o = offset(d);
        let t = near.translate(o).triangulate().unwrap();
        assert_eq!(t.vertex_count(), t0.vertex_count());
        for v in 0..t0.vertex_count() as u32 {
            assert_point("triangulation vertex", d, t.position(v) - o, t0.position(v));
        }
    }
}

#[test]
fn cylinder_fit() {
    let m = Mesh::cylinder(0.5, 2.0, 24);
    let ring: Vec<Vec3> = (0..24).map(|v| m.position(v)).collect();
    let c0 = fit_cylinder(&ring, RadiusRule::Mean).unwrap();
    for d in OFFSETS {
        let o = offset(d);
        let moved: Vec<Vec3> = ring.iter().map(|p| *p + o).collect();
        let c = fit_cylinder(&moved, RadiusRule::Mean).unwrap();
        assert_point("cylinder centre", d, c.center - o, c0.center);
        assert_direction("cylinder axis", d, c.axis * c.axis.dot(c0.axis).signum(), c0.axis);
        assert_value("cylinder radius", d, c.radius, c0.radius);
    }
}

/// A latitude–longitude polar sphere of radius 1 moved by `o`, with 64 vertices per loop.
fn polar_sphere(o: Vec3) -> PolarMesh {
    let mut pm = PolarMesh::uv_sphere(1.0, 64, 8);
    for v in 0..pm.vertex_count() as u32 {
        let p = pm.position(v);
        pm.set_position(v, p + o).unwrap();
    }
    pm
}

/// The equator's vertices (the fourth of the seven loops).
fn equator() -> Vec<u32> {
    (1 + 3 * 64..1 + 4 * 64).collect()
}

#[test]
fn polar_frames_skeleton_and_selection_edits() {
    let near = polar_sphere(Vec3::ZERO);
    let h = near.mesh().find_halfedge(1 + 3 * 64, 2 + 3 * 64).unwrap();
    let lf0 = near.loop_frame(i64::from(h)).unwrap();
    // A selection that is not a loop: the principal-axes frame.
    let patch: Vec<u32> = (1 + 2 * 64..1 + 2 * 64 + 9).chain(1 + 3 * 64..1 + 3 * 64 + 9).collect();
    let sf0 = near.selection_frame(&patch).unwrap();
    let sk0 = near.skeleton(None).unwrap();
    for d in OFFSETS {
        let o = offset(d);
        let far = polar_sphere(o);
        let lf = far.loop_frame(i64::from(h)).unwrap();
        assert_point("loop centre", d, lf.center - o, lf0.center);
        assert_direction("loop normal", d, lf.normal, lf0.normal);
        assert_direction("loop tangent", d, lf.tangent, lf0.tangent);
        let sf = far.selection_frame(&patch).unwrap();
        assert_point("selection centre", d, sf.center - o, sf0.center);
        assert_direction("selection normal", d, sf.normal, sf0.normal);
        let sk = far.skeleton(None).unwrap();
        for (i, p) in sk.positions().iter().enumerate() {
            assert_point("skeleton node", d, *p - o, sk0.positions()[i]);
            assert_direction("skeleton normal", d, sk.normal(i as u32), sk0.normal(i as u32));
        }
    }
}

#[test]
fn polar_edits_about_their_own_centres() {
    // Scaling and turning a loop about its centre, adding a feature on a run of it (its pole
    // stands out from the run's centre along the run's normal): the results move with the model.
    let run: Vec<u32> = (1 + 3 * 64..1 + 3 * 64 + 12).collect();
    let edit = |o: Vec3| {
        let mut pm = polar_sphere(o);
        pm.scale_vertices(&equator(), Vec3::splat(1.25), None, Frame::Global).unwrap();
        pm.rotate_vertices(&equator(), Vec3::Z, 10.0, None, Frame::Global).unwrap();
        pm.add_feature(&run).unwrap();
        (0..pm.vertex_count() as u32).map(|v| pm.position(v) - o).collect::<Vec<Vec3>>()
    };
    let at0 = edit(Vec3::ZERO);
    for d in OFFSETS {
        let got = edit(offset(d));
        assert_eq!(got.len(), at0.len());
        for (g, w) in got.iter().zip(&at0) {
            // Positions derived from several others: a few more spacings.
            assert!((*g - *w).abs().max_element() <= 4.0 * point_tol(d), "offset {d:e}: {g} against {w}");
        }
    }
}

#[test]
fn shape_up_circle_projection() {
    // The equator pulled out of round, then made a circle again by Shape-Up: the solved ring is
    // the same about the moved centre.
    let solve = |o: Vec3| {
        let mut pm = polar_sphere(o);
        for (i, v) in equator().into_iter().enumerate() {
            let p = pm.position(v);
            pm.set_position(v, p + Vec3::new(0.1 * (3.0 * i as f64).sin(), 0.0, 0.05 * (i as f64).cos())).unwrap();
        }
        let mut up = ShapeUp::new(pm.mesh()).unwrap();
        up.circle(&equator(), 10.0).unwrap();
        up.closeness(1.0).unwrap();
        let s = up.factor().unwrap().solve(pm.mesh().positions(), 20).unwrap();
        equator().into_iter().map(|v| s.positions[v as usize] - o).collect::<Vec<Vec3>>()
    };
    let at0 = solve(Vec3::ZERO);
    for d in OFFSETS {
        for (g, w) in solve(offset(d)).iter().zip(&at0) {
            assert!((*g - *w).abs().max_element() <= 16.0 * point_tol(d), "offset {d:e}: {g} against {w}");
        }
    }
}
