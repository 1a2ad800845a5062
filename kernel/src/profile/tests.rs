//! Tests of 2D profiles: construction and repair, booleans, offsets, fillets, chamfers, hulls,
//! transforms and measures.

use std::f64::consts::PI;

use super::measure::contour_area;
use super::*;

/// Asserts `a` and `b` agree within `tol`, printing both and the difference.
#[track_caller]
pub(super) fn assert_near(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b}: difference {} > {tol}", (a - b).abs());
}

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

fn square(lo: f64, hi: f64) -> Profile {
    Profile::rect(v(lo, lo), v(hi, hi)).unwrap()
}

/// The L of three unit squares: [0,2]×[0,1] ∪ [0,1]×[0,2] (five convex corners, one concave).
fn ell() -> Profile {
    Profile::rect(v(0.0, 0.0), v(2.0, 1.0)).unwrap().union(&Profile::rect(v(0.0, 0.0), v(1.0, 2.0)).unwrap())
}

/// The area of the regular n-gon inscribed in the unit circle.
fn ngon_area(n: u32) -> f64 {
    f64::from(n) / 2.0 * (2.0 * PI / f64::from(n)).sin()
}

#[test]
fn a_rectangle_is_its_four_corners_counter_clockwise_in_either_corner_order() {
    let p = Profile::rect(v(3.0, 2.0), v(-1.0, 0.0)).unwrap();
    assert_eq!(p.contours(), &[vec![v(-1.0, 0.0), v(3.0, 0.0), v(3.0, 2.0), v(-1.0, 2.0)]]);
    assert_eq!(p.area(), 8.0);
    assert_eq!(p.bounds(), Some((v(-1.0, 0.0), v(3.0, 2.0))));
}

#[test]
fn a_circle_is_the_inscribed_polygon_exact_on_the_axes() {
    // Area of the inscribed n-gon: (n/2)·r²·sin(2π/n).
    let p = Profile::circle(2.0, 12).unwrap();
    let c = &p.contours()[0];
    assert_eq!(c.len(), 12);
    assert_eq!((c[0], c[3], c[6], c[9]), (v(2.0, 0.0), v(0.0, 2.0), v(-2.0, 0.0), v(0.0, -2.0)));
    assert_near(p.area(), 4.0 * ngon_area(12), 1e-12);
}

#[test]
fn a_clockwise_polygon_comes_out_counter_clockwise() {
    let p = Profile::polygon(&[v(0.0, 0.0), v(0.0, 1.0), v(1.0, 1.0), v(1.0, 0.0)], FillRule::NonZero).unwrap();
    assert_near(p.area(), 1.0, 1e-12);
    assert!(contour_area(&p.contours()[0]) > 0.0);
}

#[test]
fn a_bow_tie_keeps_both_lobes_under_either_rule() {
    // The figure-eight (0,0) (2,2) (2,0) (0,2) crosses itself at (1,1): two triangles of area 1,
    // one wound each way; both rules keep both (winding ±1 is odd and non-zero).
    let bow = [v(0.0, 0.0), v(2.0, 2.0), v(2.0, 0.0), v(0.0, 2.0)];
    for rule in [FillRule::EvenOdd, FillRule::NonZero] {
        let p = Profile::polygon(&bow, rule).unwrap();
        assert_near(p.area(), 2.0, 1e-9);
        assert_eq!(p.contours().len(), 2, "{rule:?}");
        assert!(p.contours().iter().all(|c| contour_area(c) > 0.0));
    }
}

#[test]
fn a_doubly_wound_square_fills_under_non_zero_and_not_under_even_odd() {
    // Winding number 2 inside: non-zero keeps it, even-odd leaves nothing.
    let s = [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
    let twice: Vec<Vec2> = s.iter().chain(s.iter()).copied().collect();
    assert_near(Profile::polygon(&twice, FillRule::NonZero).unwrap().area(), 1.0, 1e-9);
    let e = Profile::polygon(&twice, FillRule::EvenOdd).unwrap_err();
    assert_eq!(e, ProfileError::ZeroArea { what: "the polygon".into() });
}

#[test]
fn a_hole_is_a_hole_whichever_way_it_runs_under_even_odd() {
    let outer = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(0.0, 4.0)];
    let hole_same_way = vec![v(1.0, 1.0), v(3.0, 1.0), v(3.0, 3.0), v(1.0, 3.0)];
    let p = Profile::from_contours(&[outer.clone(), hole_same_way.clone()], FillRule::EvenOdd).unwrap();
    assert_near(p.area(), 12.0, 1e-9);
    assert_eq!(p.contours().len(), 2);
    assert_eq!((0..2).filter(|&i| p.is_hole(i)).count(), 1, "one hole, clockwise");
    // Non-zero: the same-way "hole" winds 2 there, so it is filled.
    let q = Profile::from_contours(&[outer.clone(), hole_same_way.clone()], FillRule::NonZero).unwrap();
    assert_near(q.area(), 16.0, 1e-9);
    // Run the other way it is a hole under both rules.
    let mut hole = hole_same_way;
    hole.reverse();
    let r = Profile::from_contours(&[outer, hole], FillRule::NonZero).unwrap();
    assert_near(r.area(), 12.0, 1e-9);
}

#[test]
fn separate_contours_stay_separate_under_either_rule() {
    // Three squares apart: three contours, each its own region (a single path joining them by
    // bridges merged such contours through zero-width corridors; now they go in side by side).
    let sq = |x: f64| vec![v(x, 0.0), v(x + 1.0, 0.0), v(x + 1.0, 1.0), v(x, 1.0)];
    for rule in [FillRule::EvenOdd, FillRule::NonZero] {
        let p = Profile::from_contours(&[sq(0.0), sq(3.0), sq(6.0)], rule).unwrap();
        assert_near(p.area(), 3.0, 1e-9);
        assert_eq!(p.contours().len(), 3);
    }
    // A frame (outline and hole) with an island inside its hole and a square beside it: four
    // contours, 16 − 4 + 1 + 1.
    let frame = [sq4(0.0, 4.0), sq4(1.0, 3.0), sq4(1.5, 2.5), sq4(5.0, 6.0)];
    let p = Profile::from_contours(&frame, FillRule::EvenOdd).unwrap();
    assert_eq!(p.contours().len(), 4);
    assert_near(p.area(), 16.0 - 4.0 + 1.0 + 1.0, 1e-9);
}

/// The square [lo, hi]², counter-clockwise.
fn sq4(lo: f64, hi: f64) -> Vec<Vec2> {
    vec![v(lo, lo), v(hi, lo), v(hi, hi), v(lo, hi)]
}

#[test]
fn bad_input_is_refused_naming_what_is_wrong() {
    let nan = Profile::polygon(&[v(0.0, 0.0), v(1.0, f64::NAN), v(1.0, 1.0)], FillRule::EvenOdd).unwrap_err();
    assert_eq!(nan, ProfileError::NonFinite { what: "the polygon".into(), index: 1 });
    let inf = Profile::from_contours(
        &[vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)], vec![v(0.0, 0.0), v(f64::INFINITY, 0.0), v(1.0, 1.0)]],
        FillRule::EvenOdd,
    )
    .unwrap_err();
    assert_eq!(inf.to_string(), "contour 1 has a non-finite coordinate at point 1");
    let two = Profile::polygon(&[v(0.0, 0.0), v(1.0, 0.0)], FillRule::EvenOdd).unwrap_err();
    assert_eq!(two.to_string(), "the polygon has 2 points; it needs at least 3");
    let line = Profile::polygon(&[v(0.0, 0.0), v(1.0, 1.0), v(2.0, 2.0)], FillRule::NonZero).unwrap_err();
    assert_eq!(line.to_string(), "the polygon encloses no area");
    assert!(matches!(Profile::rect(v(0.0, 0.0), v(0.0, 1.0)), Err(ProfileError::ZeroArea { .. })));
    assert!(matches!(Profile::circle(0.0, 8), Err(ProfileError::BadValue { .. })));
    assert_eq!(
        Profile::circle(1.0, 2).unwrap_err().to_string(),
        "the number of segments must be from 3 to 1000000, not 2"
    );
}

#[test]
fn booleans_of_overlapping_squares_have_the_areas_of_inclusion_exclusion() {
    // [0,2]² and [1,3]² overlap in [1,2]²: union 4 + 4 − 1, difference 3, intersection 1.
    let (a, b) = (square(0.0, 2.0), square(1.0, 3.0));
    assert_near((&a + &b).area(), 7.0, 1e-9);
    assert_near((&a - &b).area(), 3.0, 1e-9);
    assert_near(a.intersection(&b).area(), 1.0, 1e-9);
    assert!(a.intersection(&square(5.0, 6.0)).is_empty());
    let ring = square(0.0, 4.0).difference(&square(1.0, 3.0));
    assert_near(ring.area(), 12.0, 1e-9);
    assert_eq!((0..ring.contours().len()).filter(|&i| ring.is_hole(i)).count(), 1);
    assert_near(Profile::union_all(&[a.clone(), b.clone(), square(2.5, 4.0)]).area(), 7.0 + 2.25 - 0.25, 1e-9);
}

#[test]
fn miter_and_negative_offsets_of_a_square_are_squares() {
    // Offsetting [0,10]² by ±1 with sharp corners gives [−1,11]² and [1,9]².
    let s = square(0.0, 10.0);
    let miter = OffsetOptions::DEFAULT.with_join(JoinType::Miter);
    assert_near(s.offset(1.0, &miter).unwrap().area(), 144.0, 1e-6);
    assert_near(s.offset(-1.0, &OffsetOptions::DEFAULT).unwrap().area(), 64.0, 1e-6);
    assert!(s.offset(-5.0, &OffsetOptions::DEFAULT).unwrap().is_empty(), "shrunk to nothing");
}

#[test]
fn a_square_join_cuts_each_corner_at_the_offset_distance() {
    // A right-angled corner squared off at distance 1 from the vertex keeps 1 − (√2 − 1)² of its
    // unit corner square: 140 + 4·(2√2 − 2).
    let s = square(0.0, 10.0);
    let a = s.offset(1.0, &OffsetOptions::DEFAULT.with_join(JoinType::Square)).unwrap().area();
    assert_near(a, 140.0 + 4.0 * (2.0 * 2f64.sqrt() - 2.0), 1e-6);
}

#[test]
fn a_round_offset_adds_the_inscribed_arcs() {
    // 100 + 4·10 + a full turn of unit-radius arc, which lies between the inscribed 32-gon and
    // the circle.
    let a = square(0.0, 10.0).offset(1.0, &OffsetOptions::DEFAULT.with_segments(32)).unwrap().area();
    assert!(a > 140.0 + ngon_area(32) - 1e-6 && a < 140.0 + PI, "{a}");
    let bad = square(0.0, 1.0).offset(1.0, &OffsetOptions::DEFAULT.with_miter_limit(0.5)).unwrap_err();
    assert_eq!(bad.to_string(), "the miter limit must be greater than 1, not 0.5");
}

#[test]
fn a_fillet_rounds_convex_and_concave_corners_alike() {
    // The L has five convex corners (each loses (1 − π/4)r²) and one concave corner (which gains
    // (1 − π/4)r²): area 3 − 4(1 − π/4)r², up to the arcs' polygonal approximation (each
    // quarter arc lies between its inscribed polygon and the circle).
    let r = 0.25;
    let n = 64;
    let f = ell().fillet(r, n).unwrap();
    let exact = 3.0 - 4.0 * (1.0 - PI / 4.0) * r * r;
    let arc_error = (PI - ngon_area(n)) / 4.0 * r * r;
    assert_near(f.area(), exact, 6.0 * arc_error + 1e-6);
    // A square only has convex corners: 100 − 4(1 − π/4).
    let s = square(0.0, 10.0).fillet(1.0, n).unwrap();
    assert_near(s.area(), 100.0 - (4.0 - PI), 4.0 * (PI - ngon_area(n)) / 4.0 + 1e-6);
    assert_eq!(square(0.0, 1.0).fillet(0.0, n).unwrap(), square(0.0, 1.0));
}

#[test]
fn a_chamfer_cuts_right_angles_by_triangles_with_legs_d() {
    // Square: four corners lose d²/2 each. L: five convex corners lose d²/2, the concave corner
    // gains d²/2.
    assert_near(square(0.0, 10.0).chamfer(1.0).unwrap().area(), 98.0, 1e-6);
    assert_near(ell().chamfer(0.2).unwrap().area(), 3.0 - 4.0 * 0.02, 1e-6);
}

#[test]
fn the_hull_of_an_l_is_the_l_with_its_notch_filled() {
    // Hull corners (0,0) (2,0) (2,1) (1,2) (0,2): the 2×2 square less a half unit triangle.
    let h = ell().hull().unwrap();
    assert_near(h.area(), 3.5, 1e-12);
    assert_eq!(h.contours()[0].len(), 5);
    // Two unit squares on a diagonal: the hexagon (0,0) (1,0) (4,3) (4,4) (3,4) (0,1), the 4×4
    // square less two right triangles of legs 3: 16 − 9.
    let both = Profile::hull_all(&[square(0.0, 1.0), square(3.0, 4.0)]).unwrap();
    assert_near(both.area(), 7.0, 1e-12);
    let line = Profile::hull_of_points(&[v(0.0, 0.0), v(1.0, 1.0), v(2.0, 2.0)]).unwrap_err();
    assert!(matches!(line, ProfileError::ZeroArea { .. }), "{line}");
}

#[test]
fn transforms_move_exactly_and_keep_outer_contours_counter_clockwise() {
    let p = Profile::rect(v(1.0, 0.0), v(3.0, 1.0)).unwrap();
    let r = p.rotate(90.0).unwrap();
    assert_eq!(r.bounds(), Some((v(-1.0, 1.0), v(0.0, 3.0))), "exact at 90 degrees");
    let t = p.translate(v(-1.0, 2.0)).unwrap();
    assert_eq!(t.bounds(), Some((v(0.0, 2.0), v(2.0, 3.0))));
    for q in [p.mirror(v(1.0, 0.0)).unwrap(), p.scale(v(-1.0, 2.0)).unwrap()] {
        assert!(q.area() > 0.0 && contour_area(&q.contours()[0]) > 0.0, "{q:?}");
    }
    assert_eq!(p.mirror(v(1.0, 0.0)).unwrap().bounds(), Some((v(-3.0, 0.0), v(-1.0, 1.0))));
    assert_near(p.scale(v(-1.0, 2.0)).unwrap().area(), 4.0, 1e-12);
    assert!(p.mirror(v(0.0, 0.0)).is_err() && p.scale(v(0.0, 1.0)).is_err() && p.rotate(f64::NAN).is_err());
}

#[test]
fn simplify_drops_points_on_straight_edges() {
    // A square with a point in the middle of each side: the four extra points lie on lines.
    let pts = [v(0.0, 0.0), v(1.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(2.0, 2.0), v(1.0, 2.0), v(0.0, 2.0), v(0.0, 1.0)];
    let p = Profile::polygon(&pts, FillRule::EvenOdd).unwrap();
    let s = p.simplify(1e-6).unwrap();
    assert_eq!(s.point_count(), 4);
    assert_near(s.area(), 4.0, 1e-12);
    assert!(p.simplify(-1.0).is_err());
}

#[test]
fn fill_rules_and_joins_are_named() {
    assert_eq!(FillRule::from_name("even-odd"), Some(FillRule::EvenOdd));
    assert_eq!(FillRule::from_name("nonzero"), Some(FillRule::NonZero));
    assert_eq!(JoinType::from_name("miter"), Some(JoinType::Miter));
    assert_eq!(JoinType::from_name("bevel"), None);
}

#[test]
fn coordinates_beyond_the_engine_s_range_are_refused_by_name() {
    // The 2D engine holds coordinates as integers on a 1e-8 grid: beyond ±1e9 (MAX_REACH) they
    // would overflow or lose the region silently, so every way in refuses them.
    let big = 1e300;
    let e = Profile::polygon(&[v(0.0, 0.0), v(big, 0.0), v(big, big)], FillRule::NonZero).unwrap_err();
    assert_eq!(e, ProfileError::OutOfRange { what: "the polygon".into(), index: 1, value: big });
    assert!(e.to_string().contains("beyond the 2D range of ±1e9"), "{e}");
    assert!(Profile::rect(v(0.0, 0.0), v(2e9, 1.0)).is_err());
    assert!(Profile::circle(2e9, 8).is_err());
    let s = square(0.0, 1.0);
    assert!(matches!(s.translate(v(1e20, 0.0)), Err(ProfileError::OutOfRange { .. })));
    assert!(matches!(s.scale(v(1e15, 1e15)), Err(ProfileError::OutOfRange { .. })));
    assert!(Profile::hull_of_points(&[v(0.0, 0.0), v(1e200, 0.0), v(0.0, 1e200)]).is_err());
    // At the limit everything still works.
    let edge = s.translate(v(MAX_REACH - 2.0, 0.0)).unwrap();
    assert_near(edge.union(&s).area(), 2.0, 1e-6);
}
