//! Semi-sharp creases and corners, boundary modes and the triangle option: the classic checks of
//! DeRose, Kass & Truong (1998) §3 and OpenSubdiv's `Sdc` rules on small shapes. Agreement with
//! OpenSubdiv itself on a corpus is in `kernel/tests/subdiv_opensubdiv.rs`.

use super::test_meshes::{assert_close, grid, mixed_torus};
use super::TriangleSubdivision;
use super::{BoundaryInterpolation, CreaseMethod, LimitEvaluator, Refiner, Scheme, SubdivError, SubdivOptions};
use crate::math::Vec3;
use crate::mesh::Mesh;

fn all_edges(m: &Mesh) -> Vec<[u32; 2]> {
    m.edges().map(|h| [m.origin(h), m.target(h)]).collect()
}

fn assert_same_positions(a: &Mesh, b: &Mesh, tol: f64) {
    assert_eq!(a.vertex_count(), b.vertex_count());
    for (p, q) in a.positions().iter().zip(b.positions()) {
        assert_close(*p, *q, tol);
    }
}

/// The same points in any order (a refined mesh's edge points follow its edge order, which
/// differs between a mesh refined in one call and one rebuilt between levels).
fn assert_same_point_sets(a: &Mesh, b: &Mesh, tol: f64) {
    let sorted = |m: &Mesh| {
        let mut p = m.positions().to_vec();
        let key = |v: &Vec3| ((v.x * 1e9).round() as i64, (v.y * 1e9).round() as i64, (v.z * 1e9).round() as i64);
        p.sort_by_key(key);
        p
    };
    assert_eq!(a.vertex_count(), b.vertex_count());
    for (p, q) in sorted(a).iter().zip(&sorted(b)) {
        assert_close(*p, *q, tol);
    }
}

#[test]
fn cube_at_sharpness_one_is_one_sharp_level_then_one_smooth() {
    // The definition of sharpness 1: the sharp rules for one level, the smooth ones after.
    let mut semi = Mesh::cube(2.0);
    semi.crease_edges_sharpness(&all_edges(&semi), 1.0).unwrap();
    let two = semi.catmull_clark(2).unwrap();
    let mut sharp = Mesh::cube(2.0);
    sharp.crease_all();
    let mut one = sharp.catmull_clark(1).unwrap();
    one.clear_creases();
    let smooth_after = one.catmull_clark(1).unwrap();
    assert_same_point_sets(&two, &smooth_after, 1e-15);
    // ... and differs from both the smooth and the infinitely sharp cube.
    let smooth = Mesh::cube(2.0).catmull_clark(2).unwrap();
    let inf = sharp.catmull_clark(2).unwrap();
    assert!((two.position(0) - smooth.position(0)).length() > 0.05);
    assert!((two.position(0) - inf.position(0)).length() > 0.05);
    // The sharpness is used up: the level-1 mesh carries no crease.
    assert_eq!(semi.catmull_clark(1).unwrap().crease_count(), 0);
}

#[test]
fn sharpness_zero_is_smooth_and_large_sharpness_is_infinite() {
    let t = mixed_torus();
    let ring: Vec<[u32; 2]> = vec![[0, 6], [6, 12], [12, 18]];
    let smooth = t.catmull_clark(3).unwrap();
    let mut zero = t.clone();
    zero.crease_edges_sharpness(&ring, 0.0).unwrap();
    assert_eq!(zero.crease_count(), 0);
    assert_eq!(zero.catmull_clark(3).unwrap(), smooth);
    // A tiny sharpness moves the surface by about that much.
    let mut tiny = t.clone();
    tiny.crease_edges_sharpness(&ring, 1e-9).unwrap();
    let d = tiny
        .catmull_clark(3)
        .unwrap()
        .positions()
        .iter()
        .zip(smooth.positions())
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    assert!(d > 0.0 && d < 1e-8, "sharpness 1e-9 moved the surface by {d:e}");
    // 10 and more is OpenSubdiv's infinity; s ≥ levels gives the infinitely sharp result too.
    let mut inf = t.clone();
    inf.crease_edges(&ring).unwrap();
    let inf3 = inf.catmull_clark(3).unwrap();
    for s in [3.0, 5.5, 10.0, 1e6] {
        let mut m = t.clone();
        m.crease_edges_sharpness(&ring, s).unwrap();
        assert_same_positions(&m.catmull_clark(3).unwrap(), &inf3, 0.0);
    }
    // 2.5 is sharp for two levels, blended in the third: not the infinitely sharp result.
    let mut m = t.clone();
    m.crease_edges_sharpness(&ring, 2.5).unwrap();
    assert_same_positions(&m.catmull_clark(2).unwrap(), &inf.catmull_clark(2).unwrap(), 0.0);
    assert!(m.catmull_clark(3).unwrap() != inf3);
    // Bad sharpness is refused, naming it, and nothing changes.
    let e = m.crease_edges_sharpness(&ring, f64::NAN).unwrap_err();
    assert!(e.to_string().contains("sharpness NaN"), "{e}");
    assert!(m.crease_edges_sharpness(&ring, -1.0).is_err());
}

#[test]
fn fractional_sharpness_blends_the_edge_rules_by_its_value() {
    // One level with sharpness 0.4 on an edge: its edge point is 0.4 · midpoint + 0.6 · smooth.
    let cube = Mesh::cube(2.0);
    let h = cube.edges().next().unwrap();
    let (a, b) = (cube.origin(h), cube.target(h));
    let mut semi = cube.clone();
    semi.crease_edges_sharpness(&[[a, b]], 0.4).unwrap();
    let mut sharp = cube.clone();
    sharp.crease_edges(&[[a, b]]).unwrap();
    let e = 8; // the first edge's point
    let (s, m, i) = (cube.catmull_clark(1).unwrap(), semi.catmull_clark(1).unwrap(), sharp.catmull_clark(1).unwrap());
    // 0.4 in f32 is what OpenSubdiv weighs with.
    let w = f64::from(0.4f32);
    assert_close(m.position(e), i.position(e) * w + s.position(e) * (1.0 - w), 1e-15);
}

#[test]
fn semi_sharp_tags_decay_per_level_and_refining_twice_is_refining_once_by_two() {
    for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
        let mut t = mixed_torus();
        t.crease_edges_sharpness(&[[0, 6], [6, 12]], 2.7).unwrap();
        t.crease_edges_sharpness(&[[12, 18]], 1.25).unwrap();
        t.set_corner_sharpness(30, 1.5);
        t.set_subdiv_options(SubdivOptions { crease: method, ..SubdivOptions::default() });
        let one = t.catmull_clark(1).unwrap();
        assert_eq!(one.subdiv_options().crease, method);
        let direct = t.catmull_clark(3).unwrap();
        let stepped = one.catmull_clark(1).unwrap().catmull_clark(1).unwrap();
        assert_same_point_sets(&direct, &stepped, 1e-15);
        if method == CreaseMethod::Uniform {
            // 2.7 (as f32, OpenSubdiv's precision) less one on both halves of both edges, 1.25 less
            // one on both halves of the third; the corner keeps its id and loses one.
            let mut got: Vec<f64> = one.crease_sharpnesses().into_iter().map(|(_, s)| s).collect();
            got.sort_by(f64::total_cmp);
            let s27 = f64::from(2.7f32 - 1.0);
            assert_eq!(got, vec![0.25, 0.25, s27, s27, s27, s27]);
            assert_eq!(one.corner_sharpness(30), 0.5);
            assert_eq!(one.crease_count(), 6);
        }
    }
}

#[test]
fn boundary_modes_move_or_pin_the_grid_corner() {
    let g = grid(2);
    let with = |boundary| {
        let mut m = g.clone();
        m.set_subdiv_options(SubdivOptions { boundary, ..SubdivOptions::default() });
        m.catmull_clark(2).unwrap()
    };
    let edge_only = with(BoundaryInterpolation::EdgeOnly);
    let none = with(BoundaryInterpolation::None);
    let corner = with(BoundaryInterpolation::EdgeAndCorner);
    assert_same_positions(&edge_only, &none, 0.0);
    // The valence-2 corner (0,0) moves along the boundary curve in edge only, stays in edge and corner.
    assert!(edge_only.position(0).length() > 0.05);
    assert_eq!(corner.position(0), Vec3::ZERO);
    assert!(corner.is_corner(0) && !corner.is_corner(1));
    // Only the four topological corners are pinned; the limit keeps them too.
    let mut m = g.clone();
    m.set_subdiv_options(SubdivOptions { boundary: BoundaryInterpolation::EdgeAndCorner, ..SubdivOptions::default() });
    let l = m.catmull_clark_limit().unwrap();
    assert_eq!(l.position(0), Vec3::ZERO);
    assert!(l.position(1).y > 0.0 - 1e-15 && (l.position(1) - g.position(1)).length() < 1e-12);
}

#[test]
fn smooth_triangle_weights_change_only_edges_next_to_triangles() {
    let t = mixed_torus();
    let mut smooth_tri = t.clone();
    smooth_tri.set_subdiv_options(SubdivOptions { triangles: TriangleSubdivision::Smooth, ..SubdivOptions::default() });
    let (a, b) = (t.catmull_clark(1).unwrap(), smooth_tri.catmull_clark(1).unwrap());
    let nv = t.vertex_count() as u32;
    let mut changed = 0;
    for (e, h) in t.edges().enumerate() {
        let tri = |f: u32| f != crate::mesh::NONE && t.face_arity(f) == 3;
        let next_to_triangle = tri(t.face(h)) || tri(t.face(t.twin(h)));
        let (p, q) = (a.position(nv + e as u32), b.position(nv + e as u32));
        if next_to_triangle {
            assert!((p - q).length() > 1e-3);
            changed += 1;
        } else {
            assert_eq!(p, q);
        }
    }
    assert_eq!(changed, 5); // the split quad's four sides and its diagonal
                            // Loop ignores the option.
    let tri = Mesh::icosphere(1.0, 1);
    let mut o = tri.clone();
    o.set_subdiv_options(smooth_tri.subdiv_options());
    assert_eq!(tri.loop_subdivide(2).unwrap().positions(), o.loop_subdivide(2).unwrap().positions());
}

#[test]
fn stencils_and_limits_follow_semi_sharp_rules() {
    let mut t = mixed_torus();
    t.crease_edges_sharpness(&[[0, 6], [6, 12]], 1.5).unwrap();
    t.set_corner_sharpness(30, 0.5);
    t.set_subdiv_options(SubdivOptions { triangles: TriangleSubdivision::Smooth, ..SubdivOptions::default() });
    let r = Refiner::new(&t, Scheme::CatmullClark, 3).unwrap();
    let direct = r.refine_positions(t.positions());
    for (a, b) in r.composed_stencils().apply(t.positions()).iter().zip(&direct) {
        assert_close(*a, *b, 1e-13);
    }
    // The limit refines until the sharpness is used up (2 levels here), then applies the masks:
    // the same as the limit of the level-2 mesh, and of the level-3 one.
    let l0 = t.catmull_clark_limit().unwrap();
    let l2 = t.catmull_clark(2).unwrap().catmull_clark_limit().unwrap();
    let l3 = t.catmull_clark(3).unwrap().catmull_clark_limit().unwrap();
    for v in 0..t.vertex_count() as u32 {
        assert_close(l0.position(v), l2.position(v), 1e-13);
        assert_close(l0.position(v), l3.position(v), 1e-13);
    }
    let st = super::catmull_clark_limit_stencils(&t).unwrap();
    for (v, p) in st.apply(t.positions()).iter().enumerate() {
        assert_close(*p, l0.position(v as u32), 1e-13);
    }
    // Loop likewise.
    let mut s = Mesh::icosphere(1.0, 1);
    let e: Vec<[u32; 2]> = all_edges(&s).into_iter().take(5).collect();
    s.crease_edges_sharpness(&e, 2.2).unwrap();
    let l0 = s.loop_limit().unwrap();
    let l3 = s.loop_subdivide(3).unwrap().loop_limit().unwrap();
    for v in 0..s.vertex_count() as u32 {
        assert_close(l0.position(v), l3.position(v), 1e-13);
    }
    // The evaluator refuses semi-sharp meshes, saying how many levels use the sharpness up.
    let q = t.catmull_clark(1).unwrap();
    assert_eq!(LimitEvaluator::new(&q).unwrap_err(), SubdivError::SemiSharp { levels: 1 });
    assert!(LimitEvaluator::new(&t.catmull_clark(2).unwrap()).is_ok());
}
