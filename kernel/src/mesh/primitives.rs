//! Primitive solids: cube, box, icosphere, UV sphere, cylinder, torus. All closed, manifold and
//! outward-facing (counter-clockwise seen from outside).

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use super::{Mesh, MeshError};
use crate::math::Vec3;

/// Corner `i` of the unit cube: bit 0 is x, bit 1 is y, bit 2 is z.
const BOX_FACES: [[u32; 4]; 6] = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];

fn built(positions: Vec<Vec3>, faces: &[Vec<u32>]) -> Mesh {
    // The primitives are constructed manifold; a failure here is a bug in this file.
    Mesh::from_polygons(positions, faces).expect("primitive construction is manifold by design")
}

/// Faces as one flat index list with their arities, as [`Mesh::from_indexed`] takes them: the
/// large primitives write their faces straight into it (no vector per face to flatten).
struct FlatFaces {
    indices: Vec<u32>,
    arities: Vec<u32>,
}

impl FlatFaces {
    fn with_capacity(faces: usize, corners: usize) -> FlatFaces {
        FlatFaces { indices: Vec::with_capacity(corners), arities: Vec::with_capacity(faces) }
    }

    fn push<const N: usize>(&mut self, face: [u32; N]) {
        self.indices.extend_from_slice(&face);
        self.arities.push(N as u32);
    }

    /// The mesh of these faces, built charging the current token when `stoppable` (else it
    /// never fails: the primitives are constructed manifold).
    fn build(self, positions: Vec<Vec3>, stoppable: bool) -> Result<Mesh, MeshError> {
        indexed(positions, &self.indices, &self.arities, stoppable)
    }
}

/// The mesh of a flat index list, built charging the current token when `stoppable`.
fn indexed(positions: Vec<Vec3>, indices: &[u32], arities: &[u32], stoppable: bool) -> Result<Mesh, MeshError> {
    if stoppable {
        Mesh::from_indexed_stoppable(positions, indices, arities)
    } else {
        Mesh::from_indexed(positions, indices, arities)
    }
}

/// Polls the current cancellation token once per row of a primitive being generated, when
/// `stoppable` (rows hold at most 100,000 faces, a millisecond of work).
fn poll_row(stoppable: bool) -> Result<(), MeshError> {
    if stoppable {
        crate::limits::poll()?;
    }
    Ok(())
}

impl Mesh {
    /// An axis-aligned cube of side `size` centred at the origin: 8 vertices, 6 quads.
    ///
    /// Vertex `i` has x = ±size/2 by bit 0 of `i`, y by bit 1, z by bit 2. Faces in the order
    /// −x, +x, −y, +y, −z, +z.
    #[must_use]
    pub fn cube(size: f64) -> Mesh {
        let h = size * 0.5;
        Mesh::cuboid(Vec3::splat(-h), Vec3::splat(h))
    }

    /// The axis-aligned box spanning `min` to `max` (corners may come in any order), with the
    /// vertex and face layout of [`Mesh::cube`].
    #[must_use]
    pub fn cuboid(min: Vec3, max: Vec3) -> Mesh {
        let (lo, hi) = (min.min(max), min.max(max));
        let positions = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let faces: Vec<Vec<u32>> = BOX_FACES.iter().map(|f| f.to_vec()).collect();
        built(positions, &faces)
    }

    /// A geodesic sphere: the icosahedron with each triangle split in four `subdivisions` times,
    /// every vertex projected onto the sphere of `radius` at each level (as trimesh does).
    /// 10·4ˢ + 2 vertices and 20·4ˢ triangles.
    #[must_use]
    pub fn icosphere(radius: f64, subdivisions: u32) -> Mesh {
        Mesh::icosphere_with(radius, subdivisions, false).expect("primitive construction is manifold by design")
    }

    /// [`Mesh::icosphere`] charging its work to the current cancellation token: every 16,384
    /// faces split, and while building the mesh ([`Mesh::from_indexed_stoppable`]).
    ///
    /// # Errors
    /// [`MeshError::Limit`] when the token stops the work.
    pub fn icosphere_stoppable(radius: f64, subdivisions: u32) -> Result<Mesh, MeshError> {
        Mesh::icosphere_with(radius, subdivisions, true)
    }

    /// The icosphere, charging the current token when `stoppable` (else it never fails).
    fn icosphere_with(radius: f64, subdivisions: u32, stoppable: bool) -> Result<Mesh, MeshError> {
        let t = (1.0 + 5f64.sqrt()) / 2.0;
        let mut positions: Vec<Vec3> = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ]
        .iter()
        .map(|p| Vec3::from_array(*p).normalize() * radius)
        .collect();
        let mut faces: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..subdivisions {
            let mut midpoint: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
            let mut next_faces = Vec::with_capacity(faces.len() * 4);
            for (k, [a, b, c]) in faces.into_iter().enumerate() {
                if stoppable && k % 16_384 == 0 {
                    crate::limits::charge(16_384)?;
                }
                let mut mid = |x: u32, y: u32| -> u32 {
                    *midpoint.entry((x.min(y), x.max(y))).or_insert_with(|| {
                        positions.push(((positions[x as usize] + positions[y as usize]) * 0.5).normalize() * radius);
                        positions.len() as u32 - 1
                    })
                };
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                next_faces.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
            }
            faces = next_faces;
        }
        let indices: Vec<u32> = faces.iter().flatten().copied().collect();
        let arities = vec![3; faces.len()];
        indexed(positions, &indices, &arities, stoppable)
    }

    /// A latitude–longitude sphere: `segments` ≥ 3 around z, `rings` ≥ 2 bands from the south
    /// pole (−z) to the north pole; triangle fans at the poles, quads between.
    #[must_use]
    pub fn uv_sphere(radius: f64, segments: u32, rings: u32) -> Mesh {
        Mesh::uv_sphere_with(radius, segments, rings, false).expect("primitive construction is manifold by design")
    }

    /// The UV sphere, polling and charging the current token when `stoppable` (else it never
    /// fails).
    pub(crate) fn uv_sphere_with(radius: f64, segments: u32, rings: u32, stoppable: bool) -> Result<Mesh, MeshError> {
        let (s, r) = (segments.max(3), rings.max(2));
        let mut positions = vec![Vec3::new(0.0, 0.0, -radius)];
        for j in 1..r {
            poll_row(stoppable)?;
            let theta = PI * f64::from(j) / f64::from(r) - PI / 2.0;
            for i in 0..s {
                let phi = TAU * f64::from(i) / f64::from(s);
                positions.push(Vec3::new(theta.cos() * phi.cos(), theta.cos() * phi.sin(), theta.sin()) * radius);
            }
        }
        positions.push(Vec3::new(0.0, 0.0, radius));
        let north = positions.len() as u32 - 1;
        let ring = |j: u32, i: u32| 1 + (j - 1) * s + i % s;
        let quads = s as usize * (r as usize - 2);
        let mut faces = FlatFaces::with_capacity(quads + 2 * s as usize, 4 * quads + 6 * s as usize);
        for i in 0..s {
            faces.push([0, ring(1, i + 1), ring(1, i)]);
        }
        for j in 1..r - 1 {
            poll_row(stoppable)?;
            for i in 0..s {
                faces.push([ring(j, i), ring(j, i + 1), ring(j + 1, i + 1), ring(j + 1, i)]);
            }
        }
        for i in 0..s {
            faces.push([ring(r - 1, i), ring(r - 1, i + 1), north]);
        }
        faces.build(positions, stoppable)
    }

    /// A closed cylinder of `radius` around the z axis from z = −height/2 to +height/2, with
    /// `segments` ≥ 3 quads around and one `segments`-gon cap at each end.
    #[must_use]
    pub fn cylinder(radius: f64, height: f64, segments: u32) -> Mesh {
        let s = segments.max(3);
        let mut positions = Vec::with_capacity(2 * s as usize);
        for z in [-height / 2.0, height / 2.0] {
            for i in 0..s {
                let phi = TAU * f64::from(i) / f64::from(s);
                positions.push(Vec3::new(radius * phi.cos(), radius * phi.sin(), z));
            }
        }
        let mut faces: Vec<Vec<u32>> = (0..s).map(|i| vec![i, (i + 1) % s, s + (i + 1) % s, s + i]).collect();
        faces.push((0..s).rev().collect());
        faces.push((s..2 * s).collect());
        built(positions, &faces)
    }

    /// A closed cone or frustum around the z axis from z = −height/2 (radius `bottom`) to
    /// +height/2 (radius `top`), `segments` ≥ 3 quads around; a radius of 0 makes an apex (a fan
    /// of triangles meeting at one vertex on the axis) in place of that end's cap. At most one
    /// radius may be 0 (the caller checks).
    #[must_use]
    pub fn cone(bottom: f64, top: f64, height: f64, segments: u32) -> Mesh {
        let s = segments.max(3);
        let mut positions = Vec::with_capacity(2 * s as usize);
        // Each end: a ring of `s` vertices, or one apex vertex.
        let mut ends = [(0u32, false); 2];
        for (k, (r, z)) in [(bottom, -height / 2.0), (top, height / 2.0)].into_iter().enumerate() {
            ends[k] = (positions.len() as u32, r == 0.0);
            if r == 0.0 {
                positions.push(Vec3::new(0.0, 0.0, z));
            } else {
                for i in 0..s {
                    let phi = TAU * f64::from(i) / f64::from(s);
                    positions.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
                }
            }
        }
        let at = |end: usize, i: u32| if ends[end].1 { ends[end].0 } else { ends[end].0 + i % s };
        let mut faces: Vec<Vec<u32>> = (0..s)
            .map(|i| {
                let mut f = vec![at(0, i), at(0, i + 1), at(1, i + 1), at(1, i)];
                f.dedup();
                if f.first() == f.last() {
                    f.pop();
                }
                f
            })
            .collect();
        if !ends[0].1 {
            faces.push((0..s).rev().map(|i| at(0, i)).collect());
        }
        if !ends[1].1 {
            faces.push((0..s).map(|i| at(1, i)).collect());
        }
        built(positions, &faces)
    }

    /// A torus around the z axis: tube centre at distance `major` from the axis, tube radius
    /// `minor`, `major_segments` × `minor_segments` quads. Genus 1.
    #[must_use]
    pub fn torus(major: f64, minor: f64, major_segments: u32, minor_segments: u32) -> Mesh {
        Mesh::torus_with(major, minor, major_segments, minor_segments, false)
            .expect("primitive construction is manifold by design")
    }

    /// The torus, polling and charging the current token when `stoppable` (else it never
    /// fails).
    pub(crate) fn torus_with(
        major: f64,
        minor: f64,
        major_segments: u32,
        minor_segments: u32,
        stoppable: bool,
    ) -> Result<Mesh, MeshError> {
        let (n, m) = (major_segments.max(3), minor_segments.max(3));
        let mut positions = Vec::with_capacity((n * m) as usize);
        for i in 0..n {
            poll_row(stoppable)?;
            let u = TAU * f64::from(i) / f64::from(n);
            for j in 0..m {
                let v = TAU * f64::from(j) / f64::from(m);
                let rr = major + minor * v.cos();
                positions.push(Vec3::new(rr * u.cos(), rr * u.sin(), minor * v.sin()));
            }
        }
        let id = |i: u32, j: u32| (i % n) * m + j % m;
        let quads = n as usize * m as usize;
        let mut faces = FlatFaces::with_capacity(quads, 4 * quads);
        for i in 0..n {
            poll_row(stoppable)?;
            for j in 0..m {
                faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        faces.build(positions, stoppable)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_rel(a: f64, b: f64, tol: f64) {
        let d = (a - b).abs() / b.abs();
        assert!(d <= tol, "got {a}, expected {b}, relative difference {d:e}");
    }

    #[test]
    fn every_primitive_is_closed_manifold_and_outward() {
        for m in [
            Mesh::cube(1.0),
            Mesh::cuboid(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO),
            Mesh::icosphere(1.0, 2),
            Mesh::uv_sphere(1.0, 16, 8),
            Mesh::cylinder(1.0, 2.0, 12),
        ] {
            assert!(m.is_closed() && m.is_manifold());
            assert_eq!(m.genus(), 0);
            assert!(m.volume() > 0.0);
        }
        let t = Mesh::torus(2.0, 0.5, 24, 12);
        assert!(t.is_closed() && t.is_manifold());
        assert_eq!(t.genus(), 1);
        assert!(t.volume() > 0.0);
    }

    #[test]
    fn icosphere_counts_follow_four_to_the_s() {
        let m = Mesh::icosphere(1.0, 3);
        assert_eq!(m.vertex_count(), 10 * 64 + 2);
        assert_eq!(m.face_count(), 20 * 64);
        assert!(m.positions().iter().all(|p| (p.length() - 1.0).abs() < 1e-12));
    }

    #[test]
    fn cylinder_matches_prism_formulas() {
        // A regular n-gon of circumradius r has area (n/2) r² sin(2π/n); the side is
        // n quads of width 2 r sin(π/n) and height h.
        let (r, h, n) = (1.5, 3.0, 16u32);
        let m = Mesh::cylinder(r, h, n);
        let nf = f64::from(n);
        let cap = nf / 2.0 * r * r * (TAU / nf).sin();
        assert_rel(m.volume(), cap * h, 1e-13);
        assert_rel(m.area(), 2.0 * cap + nf * 2.0 * r * (PI / nf).sin() * h, 1e-13);
    }

    #[test]
    fn box_volume_is_product_of_sides() {
        let m = Mesh::cuboid(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(2.0, 0.5, 6.0));
        assert_rel(m.volume(), 3.0 * 0.5 * 4.0, 1e-15);
        assert_rel(m.area(), 2.0 * (3.0 * 0.5 + 0.5 * 4.0 + 3.0 * 4.0), 1e-15);
    }

    #[test]
    fn cones_and_frustums_are_closed_with_the_volume_of_their_polygon_frustum() {
        // The solid between two regular n-gons of circumradii a and b, height h, is a prismatoid:
        // V = h/3 (A + √(A B) + B) with A = n/2 a² sin(2π/n) (similar polygons).
        let n = 24u32;
        let poly = |r: f64| f64::from(n) / 2.0 * r * r * (TAU / f64::from(n)).sin();
        for (a, b, h) in [(1.0, 0.5, 2.0), (1.0, 0.0, 3.0), (0.0, 2.0, 1.0), (1.5, 1.5, 1.0)] {
            let m = Mesh::cone(a, b, h, n);
            assert!(m.is_closed() && m.is_manifold(), "({a}, {b}, {h})");
            assert_eq!(m.genus(), 0);
            let v = h / 3.0 * (poly(a) + (poly(a) * poly(b)).sqrt() + poly(b));
            assert_rel(m.volume(), v, 1e-12);
            // An apex is one vertex and a fan of triangles; a ring end has a cap.
            let apexes = usize::from(a == 0.0) + usize::from(b == 0.0);
            assert_eq!(m.vertex_count(), 2 * n as usize - apexes * (n as usize - 1));
            assert_eq!(m.face_count(), n as usize + 2 - apexes);
            let bb = m.bounds();
            assert_rel(bb.max.z - bb.min.z, h, 1e-15);
        }
    }
}
