//! Named test shapes shared by the subdivision tests (a small regression corpus, as OpenSubdiv's
//! `catmark_*` shapes).

use crate::math::Vec3;
use crate::mesh::Mesh;

/// The regular tetrahedron with corners at (1,1,1), (1,−1,−1), (−1,1,−1), (−1,−1,1).
pub(crate) fn tetrahedron() -> Mesh {
    let p = vec![
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(1.0, -1.0, -1.0),
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(-1.0, -1.0, 1.0),
    ];
    Mesh::from_polygons(p, &[[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]).unwrap()
}

/// An open n×n grid of unit quads in the xy-plane (counter-clockwise seen from +z), vertex
/// `i + (n+1) j` at (i, j, 0).
pub(crate) fn grid(n: u32) -> Mesh {
    let w = n + 1;
    let p = (0..w * w).map(|i| Vec3::new(f64::from(i % w), f64::from(i / w), 0.0)).collect();
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = i + w * j;
            faces.push(vec![a, a + 1, a + 1 + w, a + w]);
        }
    }
    Mesh::from_polygons(p, &faces).unwrap()
}

/// A torus with mixed valences and arities: the 8×6 quad torus with two neighbouring quads merged
/// into a hexagon (two valence-3 vertices) and one quad split into two triangles (two valence-5
/// vertices). Closed, genus 1.
pub(crate) fn mixed_torus() -> Mesh {
    let t = Mesh::torus(2.0, 0.7, 8, 6);
    let mut faces = t.to_polygons();
    // Faces are (i, j) → i·6 + j with vertices [id(i,j), id(i+1,j), id(i+1,j+1), id(i,j+1)].
    let (a, b) = (faces[0].clone(), faces[6].clone()); // (0,0) and (1,0) share edge id(1,0)-id(1,1)
    let hex = vec![a[0], a[1], b[1], b[2], b[3], a[3]];
    let q = faces[20].clone();
    let tri1 = vec![q[0], q[1], q[2]];
    let tri2 = vec![q[0], q[2], q[3]];
    let mut out: Vec<Vec<u32>> = Vec::new();
    for (i, f) in faces.drain(..).enumerate() {
        match i {
            0 => out.push(hex.clone()),
            6 => {}
            20 => {
                out.push(tri1.clone());
                out.push(tri2.clone());
            }
            _ => out.push(f),
        }
    }
    Mesh::from_polygons(t.positions().to_vec(), &out).unwrap()
}

/// The cube with corners at ±1 and the four edges of its +z face tagged as creases (one crease
/// loop).
pub(crate) fn cube_crease_loop() -> Mesh {
    let mut m = Mesh::cube(2.0);
    // Vertices with bit 2 set have z = +1: 4, 5, 7, 6 in order around the face.
    m.crease_edges(&[[4, 5], [5, 7], [7, 6], [6, 4]]).unwrap();
    m
}

/// Asserts two points agree to `tol`, printing both and the distance.
#[track_caller]
pub(crate) fn assert_close(got: Vec3, want: Vec3, tol: f64) {
    let d = (got - want).length();
    assert!(d <= tol, "got {got}, expected {want}, distance {d:e} > {tol:e}");
}
