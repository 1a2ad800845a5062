//! Tests of face parts (colours) through booleans: each output face keeps its operand's part,
//! including the faces of `b` that `a − b` exposes.

use super::Csg;
use crate::mesh::{FacePart, Mesh, Rgba};
use crate::Vec3;

const RED: Rgba = [1.0, 0.0, 0.0, 1.0];
const BLUE: Rgba = [0.0, 0.0, 1.0, 1.0];
const GREEN: Rgba = [0.0, 1.0, 0.0, 1.0];

fn coloured(mut m: Mesh, c: Rgba) -> Mesh {
    m.set_color(c).unwrap();
    m
}

fn eval(c: &Csg) -> Mesh {
    let m = c.evaluate().unwrap();
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!(m.face_part_ids().map(<[u32]>::len), Some(m.face_count()), "one part per face");
    m
}

/// The area of the faces of each colour, in the order of `colours`.
fn areas(m: &Mesh, colours: &[Option<Rgba>]) -> Vec<f64> {
    colours
        .iter()
        .map(|c| (0..m.face_count() as u32).filter(|&f| m.face_color(f) == *c).map(|f| m.face_area(f)).sum())
        .collect()
}

#[test]
fn red_cube_minus_blue_sphere_is_blue_in_the_bite() {
    // The sphere (radius 1) centred on the +z face of the ±1 cube bites a hemisphere out of it.
    let cube = coloured(Mesh::cube(2.0), RED);
    let ball = coloured(Mesh::uv_sphere(1.0, 32, 16).translate(Vec3::Z), BLUE);
    let m = eval(&Csg::mesh(cube).difference(Csg::mesh(ball)));
    let mut blue = 0;
    for f in 0..m.face_count() as u32 {
        let c = m.face_centroid(f);
        // Why: a face on one of the cube's planes came from the cube; any other face lies on the
        // sphere's (polygonal) surface, at most its radius from the centre.
        let on_cube = c.abs().max_element() > 1.0 - 1e-9;
        if on_cube {
            assert_eq!(m.face_color(f), Some(RED), "face {f} at {c} lies on the cube");
        } else {
            assert!((c - Vec3::Z).length() <= 1.0 + 1e-9, "face {f} at {c}");
            assert_eq!(m.face_color(f), Some(BLUE), "face {f} at {c} lies in the bite");
            blue += 1;
        }
    }
    assert!(blue > 100, "the bite has {blue} faces");
    // Why: the bite's surface is the inside of a half sphere of radius 1, about 2π (a little
    // less for the polygon).
    let [red, blue_area] = areas(&m, &[Some(RED), Some(BLUE)])[..] else { unreachable!() };
    assert!((blue_area - std::f64::consts::TAU).abs() < 0.1, "bite area {blue_area}");
    assert!((red - (24.0 - std::f64::consts::PI)).abs() < 0.05, "cube area left {red}");
}

#[test]
fn nested_booleans_keep_every_operands_colour_and_plain_operands_stay_plain() {
    let cube = coloured(Mesh::cube(2.0), RED);
    let ball = coloured(Mesh::uv_sphere(0.8, 24, 12).translate(Vec3::Z), BLUE);
    let bitten = eval(&Csg::mesh(cube).difference(Csg::mesh(ball)));
    // An earlier result as an operand: its faces keep their parts, not its sources' leaves'.
    let drill = coloured(Mesh::cylinder(0.3, 4.0, 16).translate(Vec3::new(0.5, 0.5, -2.0)), GREEN);
    let plain = Mesh::cube(0.5).translate(Vec3::new(-1.0, -1.0, -1.0));
    let m = eval(&Csg::mesh(bitten).difference(Csg::mesh(drill)).union(Csg::mesh(plain)));
    let a = areas(&m, &[Some(RED), Some(BLUE), Some(GREEN), None]);
    assert!(a.iter().all(|&x| x > 0.1), "every operand shows: {a:?}");
    // Why: the plain cube [-1.25, -0.75]³ overlaps the red one in the cube [-1, -0.75]³: its
    // three far faces (0.5² each) are outside whole, its three near faces less a 0.25² corner.
    let expected_plain = 3.0 * 0.25 + 3.0 * (0.25 - 0.0625);
    assert!((a[3] - expected_plain).abs() < 1e-9, "plain area {} vs {expected_plain}", a[3]);
}

#[test]
fn coplanar_triangles_of_two_colours_stay_apart() {
    // A triangulated cube whose +z face is two triangles of different colours: the engine's
    // coplanar face groups must not merge them, or one colour would take the whole face.
    let tri = Mesh::cube(2.0).triangulate().unwrap();
    let top: Vec<u32> = (0..tri.face_count() as u32).filter(|&f| tri.face_normal(f).z > 0.5).collect();
    assert_eq!(top.len(), 2);
    let ids = (0..tri.face_count() as u32).map(|f| u32::from(f == top[1])).collect();
    let mut m = tri.clone();
    m.set_face_parts(ids, vec![FacePart::with_color(RED), FacePart::with_color(BLUE)]).unwrap();
    let out = eval(&Csg::mesh(m).difference(Csg::mesh(Mesh::cube(0.5).translate(Vec3::new(0.0, 0.0, -1.0)))));
    let on_top = |c: Rgba| -> f64 {
        (0..out.face_count() as u32)
            .filter(|&f| {
                out.face_normal(f).z > 0.5 && out.face_centroid(f).z > 1.0 - 1e-9 && out.face_color(f) == Some(c)
            })
            .map(|f| out.face_area(f))
            .sum()
    };
    // Why: each triangle of the 2 × 2 top face has area 2.
    assert!((on_top(RED) - 2.0).abs() < 1e-9 && (on_top(BLUE) - 2.0).abs() < 1e-9, "{} {}", on_top(RED), on_top(BLUE));
}
