//! Tests of the solids made from profiles (extrude, revolve, sweep, loft) and of the 3D
//! operations (hull, Minkowski sum, split, trim, slice, project), against exact geometry.

use std::f64::consts::PI;

use super::tests::assert_near;
use super::*;
use crate::math::{Mat4, Vec3};
use crate::mesh::Mesh;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// Asserts the mesh is a closed 2-manifold of genus `genus` and returns its volume.
#[track_caller]
fn solid(m: &Mesh, genus: i64) -> f64 {
    assert!(m.face_count() > 0, "empty mesh");
    assert!(m.is_closed(), "open: {} boundary loops", m.boundary_loops().len());
    assert!(m.is_manifold(), "not manifold");
    assert_eq!(m.genus(), genus, "genus");
    let vol = m.volume();
    assert!(vol > 0.0, "faces turned inwards: volume {vol}");
    vol
}

/// (n/2)·sin(2π/n): the area of the regular n-gon inscribed in the unit circle.
fn ngon_area(n: u32) -> f64 {
    f64::from(n) / 2.0 * (2.0 * PI / f64::from(n)).sin()
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Profile {
    Profile::rect(v(x0, y0), v(x1, y1)).unwrap()
}

#[test]
fn an_extruded_rectangle_is_a_box() {
    let m = extrude(&rect(0.0, 0.0, 2.0, 3.0), 4.0, &ExtrudeOptions::DEFAULT).unwrap();
    assert_near(solid(&m, 0), 24.0, 1e-12);
    let b = m.bounds();
    assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(2.0, 3.0, 4.0)));
    let c = extrude(&rect(0.0, 0.0, 2.0, 3.0), 4.0, &ExtrudeOptions::DEFAULT.with_center(true)).unwrap();
    assert_eq!((c.bounds().min.z, c.bounds().max.z), (-2.0, 2.0));
}

#[test]
fn an_extrusion_scaled_at_the_top_is_a_frustum() {
    // Every layer is the base scaled about the axis, so the side lies on the cone through the
    // apex: V = h/3·(A₁ + A₂ + √(A₁A₂)), A₂ = s²A₁ — for a square and for a 40-gon.
    for (p, s) in [(rect(-1.0, -1.0, 1.0, 1.0), 0.5), (Profile::circle(1.5, 40).unwrap(), 1.7)] {
        let h = 3.0;
        let m = extrude(&p, h, &ExtrudeOptions::DEFAULT.with_scale(v(s, s))).unwrap();
        let (a1, a2) = (p.area(), p.area() * s * s);
        assert_near(solid(&m, 0), h / 3.0 * (a1 + a2 + (a1 * a2).sqrt()), 1e-9);
    }
    // Scaled to a point: a cone (pyramid), A₂ = 0.
    let cone = extrude(&rect(-1.0, -1.0, 1.0, 1.0), 3.0, &ExtrudeOptions::DEFAULT.with_scale(v(0.0, 0.0))).unwrap();
    assert_near(solid(&cone, 0), 4.0, 1e-9);
}

#[test]
fn a_twisted_extrusion_of_a_profile_with_a_hole_is_a_closed_solid_of_genus_one() {
    let p = rect(-2.0, -2.0, 2.0, 2.0).difference(&rect(-1.0, -1.0, 1.0, 1.0));
    let m = extrude(&p, 2.0, &ExtrudeOptions::DEFAULT.with_twist(90.0)).unwrap();
    let vol = solid(&m, 1);
    // Each layer has area 12, but a twisted side quad is split into two triangles and bulges
    // (the outline outwards, the hole inwards): not 24 but manifold3d's 25.131634154702738 on
    // the same input (`Manifold.extrude(ring, 2, n_divisions=17, twist_degrees=90)`).
    assert_near(vol, 25.131634154702738, 1e-9);
    // Untwisted it is exact.
    assert_near(solid(&extrude(&p, 2.0, &ExtrudeOptions::DEFAULT).unwrap(), 1), 24.0, 1e-9);
}

#[test]
fn extrude_refuses_bad_arguments_by_name() {
    let p = rect(0.0, 0.0, 1.0, 1.0);
    assert_eq!(
        extrude(&Profile::empty(), 1.0, &ExtrudeOptions::DEFAULT).unwrap_err().to_string(),
        "the profile to extrude is empty: it has no contours"
    );
    assert_eq!(
        extrude(&p, 0.0, &ExtrudeOptions::DEFAULT).unwrap_err().to_string(),
        "the height must be positive, not 0"
    );
    assert!(extrude(&p, 1.0, &ExtrudeOptions::DEFAULT.with_scale(v(0.0, 1.0))).is_err());
    assert!(extrude(&p, 1.0, &ExtrudeOptions::DEFAULT.with_slices(0)).is_err());
    assert!(extrude(&p, f64::NAN, &ExtrudeOptions::DEFAULT).is_err());
}

#[test]
fn a_revolved_rectangle_off_the_axis_is_an_annulus_of_genus_one() {
    // Pappus for the polygonal solid: n·sin(2π/n)·A·x̄ with A = 1, x̄ = 1.5 (rectangle
    // [1,2]×[0,1]); the annulus' exact volume π(2² − 1²)·1 is the limit.
    let n = 48;
    let m = revolve(&rect(1.0, 0.0, 2.0, 1.0), &RevolveOptions::DEFAULT.with_segments(n)).unwrap();
    let vol = solid(&m, 1);
    assert_near(vol, 2.0 * ngon_area(n) * 1.5, 1e-9);
    assert_near(vol, 3.0 * PI, 3.0 * PI * (1.0 - ngon_area(n) / PI) + 1e-12);
}

#[test]
fn a_revolved_disc_obeys_pappus_within_the_polygon_error() {
    // A 32-gon of radius r = 0.5 centred at R = 2 (its centroid exactly), turned in 64 steps:
    // V = 64·sin(2π/64)·A₃₂·R exactly, A₃₂ = r²·ngon_area(32). The torus 2π·R·πr² is the limit;
    // the relative gap is 1 − (ngon_area(64)/π)(ngon_area(32)/π).
    let (r, big_r) = (0.5, 2.0);
    let disc = Profile::circle(r, 32).unwrap().translate(v(big_r, 0.0)).unwrap();
    let m = revolve(&disc, &RevolveOptions::DEFAULT.with_segments(64)).unwrap();
    let vol = solid(&m, 1);
    let polygonal = 2.0 * ngon_area(64) * r * r * ngon_area(32) * big_r;
    assert_near(vol, polygonal, 1e-9);
    let torus = 2.0 * PI * big_r * PI * r * r;
    let gap = 1.0 - ngon_area(64) / PI * ngon_area(32) / PI;
    assert!((torus - vol) / torus <= gap + 1e-12 && vol < torus, "{vol} vs {torus}, gap {gap}");
}

#[test]
fn a_partial_revolution_is_capped_and_a_profile_on_the_axis_closes_there() {
    // 90 degrees in 8 steps: 8·sin(π/16)·A·x̄ — the wedges of the full turn's formula.
    let p = rect(1.0, 0.0, 3.0, 1.0);
    let m = revolve(&p, &RevolveOptions::DEFAULT.with_angle(90.0).with_segments(32)).unwrap();
    assert_near(solid(&m, 0), 8.0 * (PI / 16.0).sin() * 2.0 * 2.0, 1e-9);
    // A rectangle from the axis: a cylinder (no hole), its axis vertices shared.
    let c = revolve(&rect(0.0, 0.0, 1.0, 2.0), &RevolveOptions::DEFAULT.with_segments(24)).unwrap();
    assert_near(solid(&c, 0), 2.0 * ngon_area(24), 1e-9);
}

#[test]
fn revolve_refuses_a_profile_across_the_axis_naming_the_point() {
    let p = Profile::polygon(&[v(1.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(-0.5, 1.0)], FillRule::EvenOdd).unwrap();
    let e = revolve(&p, &RevolveOptions::DEFAULT).unwrap_err();
    let ProfileError::CrossesAxis { contour: 0, x, .. } = e else { panic!("{e}") };
    assert_eq!(x, -0.5);
    assert!(
        e.to_string().starts_with("the profile crosses the revolve axis: contour 0 reaches x = -0.5 at point"),
        "{e}"
    );
    assert!(revolve(&rect(1.0, 0.0, 2.0, 1.0), &RevolveOptions::DEFAULT.with_angle(400.0)).is_err());
}

#[test]
fn a_sweep_along_a_straight_line_is_an_extrusion() {
    let p = rect(-1.0, -0.5, 1.0, 0.5);
    let m = sweep(&p, &[Vec3::ZERO, Vec3::new(0.0, 0.0, 5.0)], &SweepOptions::DEFAULT).unwrap();
    assert_near(solid(&m, 0), 10.0, 1e-12);
}

#[test]
fn a_mitred_bend_keeps_the_volume_of_area_times_centre_line() {
    // The profile's centroid on the path: the wedge gained outside a mitre equals the one lost
    // inside, so V = A·(sum of segment lengths) exactly, for any turn the profile allows.
    let p = rect(-0.5, -0.5, 0.5, 0.5);
    let path = [Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0), Vec3::new(5.0, 4.0, 1.0), Vec3::new(2.0, 4.0, 3.0)];
    let len: f64 = path.windows(2).map(|w| w[0].distance(w[1])).sum();
    let m = sweep(&p, &path, &SweepOptions::DEFAULT).unwrap();
    assert_near(solid(&m, 0), len, 1e-9);
}

#[test]
fn a_closed_path_gives_a_ring() {
    // A square path of side 6 with a 1×1 profile: genus 1, V = A·perimeter = 24.
    let path = [Vec3::ZERO, Vec3::new(6.0, 0.0, 0.0), Vec3::new(6.0, 6.0, 0.0), Vec3::new(0.0, 6.0, 0.0)];
    let m = sweep(&rect(-0.5, -0.5, 0.5, 0.5), &path, &SweepOptions::DEFAULT.with_closed(true)).unwrap();
    assert_near(solid(&m, 1), 24.0, 1e-9);
    // A circle of 64 points (a non-planar frame problem would show as a twisted seam): the
    // torus of tube radius 0.3, close to 2π²·R·r² (polygon gaps bound the difference).
    let circle: Vec<Vec3> = (0..64)
        .map(|i| {
            let a = 2.0 * PI * f64::from(i) / 64.0;
            Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), 0.5 * (2.0 * a).sin())
        })
        .collect();
    let ring = sweep(&Profile::circle(0.3, 16).unwrap(), &circle, &SweepOptions::DEFAULT.with_closed(true)).unwrap();
    solid(&ring, 1);
}

#[test]
fn sweep_refuses_repeated_points_and_turns_too_sharp_naming_the_point() {
    let p = rect(-0.5, -0.5, 0.5, 0.5);
    let e = sweep(&p, &[Vec3::ZERO, Vec3::X, Vec3::X, Vec3::new(2.0, 0.0, 0.0)], &SweepOptions::DEFAULT).unwrap_err();
    assert_eq!(e, ProfileError::RepeatedPoint { index: 1 });
    assert_eq!(e.to_string(), "the path repeats point 1 at point 2 (consecutive points must differ)");
    // Straight back: a 180-degree turn at point 1.
    let back = sweep(&p, &[Vec3::ZERO, Vec3::X, Vec3::ZERO - Vec3::Y * 1e-3], &SweepOptions::DEFAULT).unwrap_err();
    assert!(matches!(back, ProfileError::SharpTurn { index: 1, .. }), "{back}");
    // A 150-degree turn after a segment of 0.2: the inner side (half-width 0.5·tan 75°) runs back.
    let back_150 = Vec3::new(-(30f64.to_radians().cos()), 0.5, 0.0) * 3.0;
    let path = [Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0) + back_150];
    let sharp = sweep(&rect(-0.5, -0.5, 0.5, 0.5), &path, &SweepOptions::DEFAULT);
    assert!(sharp.is_ok(), "long legs leave room: {sharp:?}");
    let short = [Vec3::ZERO, Vec3::new(0.2, 0.0, 0.0), Vec3::new(0.2, 0.0, 0.0) + back_150];
    let e = sweep(&p, &short, &SweepOptions::DEFAULT).unwrap_err();
    assert!(matches!(e, ProfileError::SharpTurn { index: 1, .. }), "{e}");
    assert!(e.to_string().starts_with("the path turns by 150 degrees at point 1"), "{e}");
    assert!(sweep(&p, &[Vec3::ZERO], &SweepOptions::DEFAULT).is_err());
}

#[test]
fn a_sweep_or_loft_that_passes_through_itself_is_refused_naming_where() {
    // The path runs along x, turns twice and comes back down across its start at x = 3.
    let path = [
        Vec3::ZERO,
        Vec3::new(20.0, 0.0, 0.0),
        Vec3::new(20.0, 6.0, 0.0),
        Vec3::new(3.0, 6.0, 0.0),
        Vec3::new(3.0, -6.0, 0.0),
    ];
    let e = sweep(&Profile::circle(1.0, 16).unwrap(), &path, &SweepOptions::DEFAULT).unwrap_err();
    assert!(matches!(&e, ProfileError::SelfCrossing { what: "the sweep", .. }), "{e}");
    assert!(e.to_string().starts_with("the sweep passes through itself near path point 0, at ("), "{e}");
    if let ProfileError::SelfCrossing { at, .. } = e {
        assert!((at.x - 3.0).abs() <= 1.5 && at.y.abs() <= 1.5, "where the tubes meet: {at}");
    }
    // Stopped short of the first leg, the same path is a solid.
    let short = [path[0], path[1], path[2], path[3], Vec3::new(3.0, 2.5, 0.0)];
    solid(&sweep(&Profile::circle(1.0, 16).unwrap(), &short, &SweepOptions::DEFAULT).unwrap(), 0);
    // Squares placed up and across, then back down across the first leg.
    let sq = rect(-2.0, -2.0, 2.0, 2.0);
    let placed = vec![
        Mat4::IDENTITY,
        Mat4::from_translation(Vec3::new(10.0, 0.0, 4.0)),
        Mat4::from_translation(Vec3::new(5.0, 0.0, 0.0)),
    ];
    let e = loft(&[sq.clone(), sq.clone(), sq.clone()], &LoftOptions::DEFAULT.with_transforms(placed)).unwrap_err();
    assert!(matches!(&e, ProfileError::SelfCrossing { what: "the loft", .. }), "{e}");
    assert!(e.to_string().contains("the loft passes through itself near profile"), "{e}");
}

#[test]
fn a_loft_between_similar_squares_is_a_frustum_and_any_two_outlines_loft() {
    // Squares of side 2 and 1 with corners at the same arc-length parameters: the frustum
    // h/3·(4 + 1 + 2).
    let m = loft(
        &[rect(-1.0, -1.0, 1.0, 1.0), rect(-0.5, -0.5, 0.5, 0.5)],
        &LoftOptions::DEFAULT.with_heights(vec![0.0, 3.0]),
    )
    .unwrap();
    assert_near(solid(&m, 0), 7.0, 1e-9);
    // Square to circle to square, all corners kept.
    let ps = [rect(-1.0, -1.0, 1.0, 1.0), Profile::circle(1.0, 30).unwrap(), rect(-0.5, -0.5, 0.5, 0.5)];
    let m = loft(&ps, &LoftOptions::DEFAULT.with_heights(vec![0.0, 1.0, 2.5])).unwrap();
    solid(&m, 0);
    // With holes: genus 1.
    let washer = |r: f64| Profile::circle(r, 24).unwrap().difference(&Profile::circle(r / 2.0, 12).unwrap());
    let m = loft(&[washer(2.0), washer(1.0)], &LoftOptions::DEFAULT).unwrap();
    solid(&m, 1);
}

#[test]
fn a_loft_placed_by_transforms_turns_its_faces_outwards() {
    // Profiles placed going down −z: still a solid of positive volume.
    let t = vec![Mat4::IDENTITY, Mat4::from_translation(Vec3::new(0.0, 0.0, -2.0))];
    let m =
        loft(&[rect(0.0, 0.0, 1.0, 1.0), rect(0.0, 0.0, 1.0, 1.0)], &LoftOptions::DEFAULT.with_transforms(t)).unwrap();
    assert_near(solid(&m, 0), 2.0, 1e-12);
}

#[test]
fn loft_refuses_profiles_that_do_not_correspond() {
    let ring = rect(-2.0, -2.0, 2.0, 2.0).difference(&rect(-1.0, -1.0, 1.0, 1.0));
    let e = loft(&[ring, rect(-1.0, -1.0, 1.0, 1.0)], &LoftOptions::DEFAULT).unwrap_err();
    assert_eq!(
        e.to_string(),
        "profile 1 cannot be lofted from profile 0: it has 1 outer contours and 0 holes, profile 0 has 1 and 1"
    );
    let p = rect(0.0, 0.0, 1.0, 1.0);
    assert!(loft(&[p.clone(), p.clone()], &LoftOptions::DEFAULT.with_heights(vec![1.0, 1.0])).is_err());
    assert!(loft(std::slice::from_ref(&p), &LoftOptions::DEFAULT).is_err());
    // A ring needs placed profiles: closed with heights would run back down through the solid.
    let e = loft(&[p.clone(), p.clone(), p.clone()], &LoftOptions::DEFAULT.with_closed(true)).unwrap_err();
    assert!(e.to_string().starts_with("`closed` must be false when the profiles are stacked by heights"), "{e}");
}

#[test]
fn the_hull_of_a_cubes_corners_is_the_cube() {
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(f64::from(i & 1) * 2.0 - 1.0, f64::from((i >> 1) & 1) * 2.0 - 1.0, f64::from(i >> 2) * 2.0 - 1.0)
        })
        .collect();
    let mut with_inside = corners.clone();
    with_inside.extend([Vec3::ZERO, Vec3::new(0.5, -0.2, 0.9)]);
    let h = hull_points(&with_inside).unwrap();
    assert_near(solid(&h, 0), 8.0, 1e-12);
    assert_eq!(h.vertex_count(), 8, "interior points dropped");
    let m = hull_meshes(&[&Mesh::cube(1.0), &Mesh::cube(1.0).translate(Vec3::new(3.0, 0.0, 0.0))]).unwrap();
    assert_near(solid(&m, 0), 4.0, 1e-12);
    let flat = hull_points(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)]).unwrap_err();
    assert!(matches!(flat, ProfileError::ZeroArea { .. }), "{flat}");
}

#[test]
fn the_minkowski_sum_of_two_boxes_adds_their_sides() {
    // [−1,1]³ ⊕ [−0.5,0.5]×[0,1]×[0,2]: a box of sides 3, 3, 4.
    let a = Mesh::cube(2.0);
    let b = Mesh::cuboid(Vec3::new(-0.5, 0.0, 0.0), Vec3::new(0.5, 1.0, 2.0));
    let m = minkowski(&a, &b).unwrap();
    assert_near(solid(&m, 0), 36.0, 1e-9);
    let bb = m.bounds();
    assert_eq!((bb.min, bb.max), (Vec3::new(-1.5, -1.0, -1.0), Vec3::new(1.5, 2.0, 3.0)));
    // A non-convex operand (an L prism) summed with a cube: the L grown by 0.5 (mitred: a box
    // is its own mitre) and thickened: area of the L offset with sharp corners × (1 + 1).
    let l = rect(0.0, 0.0, 2.0, 1.0).union(&rect(0.0, 0.0, 1.0, 2.0));
    let lp = extrude(&l, 1.0, &ExtrudeOptions::DEFAULT).unwrap();
    let m = minkowski(&lp, &Mesh::cube(1.0)).unwrap();
    let grown = l.offset(0.5, &OffsetOptions::DEFAULT.with_join(JoinType::Miter)).unwrap().area();
    assert_near(solid(&m, 0), grown * 2.0, 1e-9);
    let mut open = Mesh::cube(1.0);
    open = Mesh::from_polygons(open.positions().to_vec(), &open.to_polygons()[1..]).unwrap();
    let e = minkowski(&open, &a).unwrap_err();
    assert!(e.to_string().starts_with("the first operand is not a closed solid"), "{e}");
}

#[test]
fn split_and_trim_cut_a_cube_into_exact_parts() {
    let cube = Mesh::cube(2.0);
    let (below, above) = split(&cube, Vec3::Z, 0.5).unwrap();
    assert_near(solid(&below, 0), 6.0, 1e-12);
    assert_near(solid(&above, 0), 2.0, 1e-12);
    assert_eq!(above.bounds().min.z, 0.5);
    // A slanted plane through the centre halves it.
    let t = trim(&cube, Vec3::new(1.0, 1.0, 1.0), 0.0).unwrap();
    assert_near(solid(&t, 0), 4.0, 1e-12);
    let (none, all) = split(&cube, Vec3::Z, -5.0).unwrap();
    assert_eq!(none.face_count(), 0);
    assert_near(solid(&all, 0), 8.0, 1e-12);
    assert!(split(&cube, Vec3::ZERO, 0.0).is_err());
}

#[test]
fn a_slice_and_a_shadow_are_the_sections_expected() {
    let cube = Mesh::cube(2.0);
    assert_near(slice(&cube, 0.3).unwrap().area(), 4.0, 1e-12);
    assert!(slice(&cube, 3.0).unwrap().is_empty());
    // A revolved annulus sliced through its middle: the ring between radii 1 and 2 (as n-gons).
    let ring = revolve(&rect(1.0, 0.0, 2.0, 1.0), &RevolveOptions::DEFAULT.with_segments(48)).unwrap();
    let s = slice(&ring, 0.5).unwrap();
    // (Sections come back through the engine's 1e-8 grid.)
    assert_near(s.area(), (4.0 - 1.0) * ngon_area(48), 1e-7);
    assert_eq!(s.contours().len(), 2);
    // The shadow of a tilted box is its outline.
    let shadow = project(&Mesh::cuboid(Vec3::ZERO, Vec3::new(3.0, 2.0, 1.0))).unwrap();
    assert_near(shadow.area(), 6.0, 1e-12);
}

#[test]
fn results_match_manifold3d_on_the_same_inputs() {
    // Figures printed by manifold3d 3.5.4 (the C++ library this engine ports) on the same
    // inputs, see the module report: a 64-gon twisted 90° over 32 layers; a square offset by 1
    // with round joins of 32 segments per turn; the L prism ⊕ a unit cube; a partial revolve.
    let c = extrude(&Profile::circle(1.0, 64).unwrap(), 2.0, &ExtrudeOptions::DEFAULT.with_twist(90.0).with_slices(32))
        .unwrap();
    assert_near(c.volume(), 6.275618758697754, 1e-9);
    let o = rect(0.0, 0.0, 10.0, 10.0).offset(1.0, &OffsetOptions::DEFAULT.with_segments(32)).unwrap();
    assert_near(o.area(), 143.1214451390775, 1e-7);
    let p = revolve(&rect(1.0, 0.0, 3.0, 1.0), &RevolveOptions::DEFAULT.with_angle(90.0).with_segments(32)).unwrap();
    assert_near(p.volume(), 6.242890304516104, 1e-9);
    let l = extrude(&rect(0.0, 0.0, 2.0, 1.0).union(&rect(0.0, 0.0, 1.0, 2.0)), 1.0, &ExtrudeOptions::DEFAULT).unwrap();
    assert_near(minkowski(&l, &Mesh::cube(1.0)).unwrap().volume(), 16.0, 1e-9);
}

#[test]
fn requests_too_large_for_memory_are_refused_before_building() {
    // Four billion layers of a square: far over any memory budget, refused by estimate.
    let e = extrude(&rect(0.0, 0.0, 1.0, 1.0), 1.0, &ExtrudeOptions::DEFAULT.with_slices(4_000_000_000)).unwrap_err();
    assert!(matches!(e, ProfileError::Limit(_)), "{e}");
    assert!(e.to_string().starts_with("an extrusion of 4 points in 4000000000 layers"), "{e}");
    assert!(Profile::circle(1.0, 2_000_000).is_err(), "more than MAX_SEGMENTS");
}

#[test]
fn sweep_refuses_an_up_along_the_path() {
    let e =
        sweep(&rect(0.0, 0.0, 1.0, 1.0), &[Vec3::ZERO, Vec3::Z], &SweepOptions::DEFAULT.with_up(Vec3::Z)).unwrap_err();
    assert!(matches!(e, ProfileError::BadValue { .. }), "{e}");
    // The default up turns to +y for a path along z: the profile's y faces +y.
    let m = sweep(&rect(0.0, 0.0, 1.0, 2.0), &[Vec3::ZERO, Vec3::Z], &SweepOptions::DEFAULT).unwrap();
    let b = m.bounds();
    assert!((b.max.y - 2.0).abs() < 1e-12 && b.min.y.abs() < 1e-12, "{b:?}");
}

#[test]
fn a_closed_loft_through_placed_profiles_is_a_ring() {
    // Eight unit squares stood up around the z axis at radius 3 (each in the plane through the
    // axis), joined round: a closed ring of genus 1.
    let transforms: Vec<Mat4> = (0..8)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 8.0;
            Mat4::from_rotation_z(a)
                * Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0))
                * Mat4::from_rotation_x(PI / 2.0)
        })
        .collect();
    let squares = vec![rect(-0.5, -0.5, 0.5, 0.5); 8];
    let m = loft(&squares, &LoftOptions::DEFAULT.with_transforms(transforms).with_closed(true)).unwrap();
    // The octagonal ring's volume by Pappus for the polygonal solid: 8·sin(2π/8)·A·x̄ = 8·sin(π/4)·1·3.
    assert_near(solid(&m, 1), 8.0 * (PI / 4.0).sin() * 3.0, 1e-9);
}

#[test]
fn profiles_touching_at_a_corner_extrude_to_a_closed_solid() {
    // Two squares meeting at one corner: the engine keeps two vertices there, so the mesh stays
    // a 2-manifold (two components touching at an edge in space, not in topology).
    let p = rect(0.0, 0.0, 1.0, 1.0).union(&rect(1.0, 1.0, 2.0, 2.0));
    let m = extrude(&p, 1.0, &ExtrudeOptions::DEFAULT).unwrap();
    assert!(m.is_closed() && m.is_manifold());
    assert_near(m.volume(), 2.0, 1e-12);
}

#[test]
fn a_profile_touching_the_axis_at_a_point_revolves_to_a_pinched_solid() {
    // A 32-gon of radius 1 at x = 1 touches the axis at its vertex (0, 0): the solid pinches to
    // a point there. The engine shares one vertex between the two fans; the mesh gets one per
    // fan, so it stays a 2-manifold (a sphere-like surface, genus 0) with Pappus's volume.
    let disc = Profile::circle(1.0, 32).unwrap().translate(v(1.0, 0.0)).unwrap();
    let m = revolve(&disc, &RevolveOptions::DEFAULT.with_segments(48)).unwrap();
    assert_near(solid(&m, 0), 48.0 * (2.0 * PI / 48.0).sin() * ngon_area(32) * 1.0, 1e-9);
    // A triangle with its apex on the axis: a double cone meeting at a point.
    let tri = Profile::polygon(&[v(0.0, 0.0), v(1.0, -1.0), v(1.0, 1.0)], FillRule::EvenOdd).unwrap();
    let c = revolve(&tri, &RevolveOptions::DEFAULT.with_segments(24)).unwrap();
    // ∫x dA over the triangle: area 1, centroid x = 2/3.
    assert_near(solid(&c, 0), 24.0 * (2.0 * PI / 24.0).sin() * (2.0 / 3.0), 1e-9);
}

#[test]
fn extrusions_and_revolutions_are_the_engines_solids_without_building_them() {
    // `extrude` and `revolve` build the mesh from the engine's construction directly (no
    // sort, normals or collider); the result must be the mesh of the engine's own solid up to
    // the order of vertices and faces: the same counts, positions and volume.
    use crate::csg::engine::Solid;
    let holed = Profile::circle(1.0, 40).unwrap().difference(&rect(-0.3, -0.3, 0.3, 0.3));
    let corner = rect(0.0, 0.0, 1.0, 1.0).union(&rect(1.0, 1.0, 2.0, 2.0));
    let on_axis = Profile::circle(1.0, 32).unwrap().translate(v(1.0, 0.0)).unwrap();
    let tri = Profile::polygon(&[v(0.0, 0.0), v(1.0, -1.0), v(1.0, 1.0)], FillRule::EvenOdd).unwrap();
    let ring = rect(1.0, 0.0, 2.0, 1.0).difference(&rect(1.2, 0.2, 1.4, 0.4));
    let sorted = |m: &Mesh| {
        let mut p: Vec<[u64; 3]> =
            m.positions().iter().map(|q| [q.x.to_bits(), q.y.to_bits(), q.z.to_bits()]).collect();
        p.sort_unstable();
        p
    };
    let same = |ours: &Mesh, engine: &Solid, what: &str| {
        let theirs = super::convert::mesh_from_solid(engine).unwrap();
        assert!(ours.is_closed() && ours.is_manifold(), "{what}: not a closed 2-manifold");
        assert_eq!(ours.face_count(), theirs.face_count(), "{what}: faces");
        assert_eq!(ours.vertex_count(), theirs.vertex_count(), "{what}: vertices");
        assert_eq!(ours.genus(), theirs.genus(), "{what}: genus");
        assert_eq!(sorted(ours), sorted(&theirs), "{what}: positions");
        assert_near(ours.volume(), theirs.volume(), 1e-12 * theirs.volume().abs().max(1.0));
    };
    for (what, p, twist, scale) in [
        ("a holed disc, twisted", &holed, 90.0, Vec2::ONE),
        ("a holed disc to a point", &holed, 0.0, Vec2::ZERO),
        ("squares touching at a corner, scaled", &corner, 30.0, Vec2::new(0.5, 2.0)),
    ] {
        let options = ExtrudeOptions::DEFAULT.with_twist(twist).with_scale(scale).with_slices(7);
        let ours = extrude(p, 2.0, &options).unwrap();
        let engine = Solid::extrude(p.contours(), 2.0, 6, twist, scale).unwrap();
        same(&ours, &engine, what);
    }
    for (what, p, angle) in [
        ("a disc touching the axis", &on_axis, 360.0),
        ("a triangle with its apex on the axis, partly", &tri, 135.0),
        ("a holed rectangle, partly", &ring, 90.0),
        ("a holed rectangle", &ring, 360.0),
    ] {
        let options = RevolveOptions::DEFAULT.with_angle(angle).with_segments(24);
        let ours = revolve(p, &options).unwrap();
        let engine = Solid::revolve(p.contours(), options.steps(), angle).unwrap();
        same(&ours, &engine, what);
    }
}
