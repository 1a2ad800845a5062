//! `Mesh`: primitives, measures, transforms and triangulation (its subdivision tags are in
//! `api/subdiv.rs`).

use std::sync::Arc;

use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::{Mesh, Vec3};
use rhai::plugin::*;
use rhai::{Array, Map, INT};

use crate::convert::{
    count, factor3, fail, id_pairs, ids, kernel, number, type_name, vec3, Number, NumberOrVector, Options,
    ScriptResult, Vector,
};

/// A mesh as scripts hold it: shared and copied on write, so passing a mesh around is cheap
/// and no script ever sees another variable's mesh change. A subdivision surface also holds
/// the control mesh it was made from (the subdivision input, a block model's control mesh),
/// which the studio draws over it. Moves, turns, scales and mirrors move it with the surface,
/// triangulating keeps it, a boolean or `combine` keeps its operands' (see [`SharedMesh::controls`]);
/// other operations that make a new mesh from it drop it.
#[derive(Clone, Debug)]
pub struct SharedMesh(pub Arc<Mesh>, pub Option<Arc<Mesh>>);

impl SharedMesh {
    /// Wraps a kernel mesh.
    #[must_use]
    pub fn new(mesh: Mesh) -> SharedMesh {
        SharedMesh(Arc::new(mesh), None)
    }

    /// Wraps `mesh`, a surface made from the control mesh `control`.
    #[must_use]
    pub fn with_control(mesh: Mesh, control: Arc<Mesh>) -> SharedMesh {
        SharedMesh(Arc::new(mesh), Some(control))
    }

    /// The control mesh of a surface made from this mesh: this mesh's own, else this mesh.
    #[must_use]
    pub fn control_for_derived(&self) -> Arc<Mesh> {
        self.1.clone().unwrap_or_else(|| self.0.clone())
    }

    /// `mesh`, made from this one by `f` moving every point (a move, turn, scale or mirror):
    /// its control mesh, if any, moved the same way.
    #[must_use]
    pub fn moved(&self, mesh: Mesh, f: impl Fn(&Mesh) -> Mesh) -> SharedMesh {
        SharedMesh(Arc::new(mesh), self.1.as_ref().map(|c| Arc::new(f(c))))
    }

    /// The control meshes of `parts` that have one, side by side in one mesh (what a boolean or
    /// a combination of them shows over its surface); `None` when no part has one.
    #[must_use]
    pub fn controls<'a>(parts: impl IntoIterator<Item = &'a SharedMesh>) -> Option<Arc<Mesh>> {
        let controls: Vec<&Arc<Mesh>> = parts.into_iter().filter_map(|p| p.1.as_ref()).collect();
        match controls.as_slice() {
            [] => None,
            [one] => Some(Arc::clone(one)),
            many => Mesh::combine(&many.iter().map(|c| &***c).collect::<Vec<&Mesh>>()).ok().map(Arc::new),
        }
    }
}

/// The largest primitive resolution accepted (faces grow with its square).
const MAX_SEGMENTS: INT = 100_000;
/// The largest icosphere subdivision accepted (20·4⁹ ≈ 5M triangles).
const MAX_ICO_LEVEL: INT = 9;

fn positive(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<f64> {
    let x = number(func, arg, v)?;
    if x <= 0.0 {
        return fail(func, format!("argument `{arg}` must be positive, got {}", fmt_num(x)));
    }
    Ok(x)
}

fn segments(func: &str, arg: &str, v: INT) -> ScriptResult<u32> {
    if v < 3 {
        return fail(func, format!("argument `{arg}` must be at least 3, got {v}"));
    }
    count(func, arg, v, MAX_SEGMENTS)
}

fn nonzero(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec3> {
    let d = vec3(func, arg, v)?;
    if d == Vec3::ZERO {
        return fail(func, format!("argument `{arg}` is the zero vector, which has no direction"));
    }
    Ok(d)
}

/// `v` as `[x, y, z]` with numbers as messages print them.
fn fmt_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", fmt_num(v.x), fmt_num(v.y), fmt_num(v.z))
}

/// Checks `m`, the result of `func` with argument `arg` (`value`): an error naming the argument
/// and the vertex when the argument took a coordinate out of the numbers (±1.8e308).
fn finite(func: &str, arg: &str, value: &str, m: &Mesh) -> ScriptResult<()> {
    match m.positions().iter().position(|p| !p.is_finite()) {
        None => Ok(()),
        Some(v) => fail(
            func,
            format!(
                "argument `{arg}` {value} takes vertex {v} to {}, past the largest number (about 1.8e308)",
                fmt_vec(m.position(v as u32))
            ),
        ),
    }
}

fn array_option(v: &Dynamic, key: &str) -> ScriptResult<Array> {
    v.clone()
        .try_cast::<Array>()
        .ok_or_else(|| crate::convert::error("mesh", format!("option `{key}` must be an array, got {}", type_name(v))))
}

fn color(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<[f32; 4]> {
    let a = v.clone().try_cast::<Array>().unwrap_or_default();
    if a.len() != 3 && a.len() != 4 {
        return fail(func, format!("argument `{arg}` must be [r, g, b] or [r, g, b, a], got {}", type_name(v)));
    }
    let mut c = [1.0f32; 4];
    for (i, x) in a.iter().enumerate() {
        let n = number(func, &format!("{arg}[{i}]"), x)?;
        if !(0.0..=1.0).contains(&n) {
            return fail(func, format!("argument `{arg}[{i}]` must be between 0 and 1, got {}", fmt_num(n)));
        }
        c[i] = n as f32;
    }
    Ok(c)
}

#[export_module]
pub mod mesh_api {
    use super::*;

    /// A cube of side `size` centred at the origin: 8 vertices, 6 quads. Vertex `i` has
    /// x = ±size/2 by bit 0 of `i`, y by bit 1, z by bit 2; faces −x, +x, −y, +y, −z, +z.
    ///
    /// ```rhai
    /// let c = cube(2);
    /// assert_eq(c.vertex_count, 8);
    /// assert_near(c.volume(), 8.0, 1e-12);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn cube(size: Number) -> ScriptResult<SharedMesh> {
        kernel("cube", Mesh::try_cube(positive("cube", "size", &size)?)).map(SharedMesh::new)
    }

    /// The axis-aligned box from corner `min` to corner `max` (8 vertices, 6 quads).
    ///
    /// Topic: primitives
    ///
    /// ```rhai
    /// let b = box([0, 0, 0], [1, 2, 3]);
    /// assert_near(b.volume(), 6.0, 1e-12);
    /// ```
    #[rhai_fn(name = "box", return_raw)]
    pub fn box_(min: Vector, max: Vector) -> ScriptResult<SharedMesh> {
        let (a, b) = (vec3("box", "min", &min)?, vec3("box", "max", &max)?);
        if (a - b).abs().min_element() == 0.0 {
            return fail("box", format!("arguments `min` and `max` span no volume: {a} to {b}"));
        }
        kernel("box", Mesh::try_cuboid(a, b)).map(SharedMesh::new)
    }

    /// A geodesic sphere: the icosahedron split `subdivisions` times (0–9), vertices on the
    /// sphere. 10·4ˢ + 2 vertices, 20·4ˢ triangles.
    ///
    /// ```rhai
    /// let s = icosphere(1, 2);
    /// assert_eq(s.face_count, 320);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn icosphere(radius: Number, subdivisions: INT) -> ScriptResult<SharedMesh> {
        let r = positive("icosphere", "radius", &radius)?;
        let s = count("icosphere", "subdivisions", subdivisions, MAX_ICO_LEVEL)?;
        kernel("icosphere", Mesh::try_icosphere(r, s)).map(SharedMesh::new)
    }

    /// A latitude–longitude sphere around z: `segments` (≥ 3) around, `rings` (≥ 2) bands from
    /// pole to pole; triangles at the poles, quads between.
    ///
    /// ```rhai
    /// let s = uv_sphere(1, 16, 8);
    /// assert_eq(s.vertex_count, 16 * 7 + 2);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn uv_sphere(radius: Number, segments_: INT, rings: INT) -> ScriptResult<SharedMesh> {
        let r = positive("uv_sphere", "radius", &radius)?;
        let s = segments("uv_sphere", "segments", segments_)?;
        if rings < 2 {
            return fail("uv_sphere", format!("argument `rings` must be at least 2, got {rings}"));
        }
        let n = count("uv_sphere", "rings", rings, MAX_SEGMENTS)?;
        kernel("uv_sphere", Mesh::try_uv_sphere(r, s, n)).map(SharedMesh::new)
    }

    /// A closed cylinder around z, from −height/2 to +height/2: `segments` quads around and
    /// an n-gon cap at each end.
    ///
    /// ```rhai
    /// let c = cylinder(1, 2, 32);
    /// assert_eq(c.face_count, 34);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn cylinder(radius: Number, height: Number, segments_: INT) -> ScriptResult<SharedMesh> {
        let r = positive("cylinder", "radius", &radius)?;
        let h = positive("cylinder", "height", &height)?;
        let s = segments("cylinder", "segments", segments_)?;
        kernel("cylinder", Mesh::try_cylinder(r, h, s)).map(SharedMesh::new)
    }

    /// `cylinder(radius, height, segments)` with options: `center` (default `true`: from
    /// −height/2 to +height/2; `false`: from z = 0 to z = height, as OpenSCAD's default).
    ///
    /// ```rhai
    /// let c = cylinder(1, 2, 32, #{ center: false });
    /// assert_eq(c.bounds().min.z, 0.0);
    /// assert_eq(c.bounds().max.z, 2.0);
    /// ```
    #[rhai_fn(name = "cylinder", return_raw)]
    pub fn cylinder_with(radius: Number, height: Number, segments_: INT, options: Map) -> ScriptResult<SharedMesh> {
        let opts = Options::new("cylinder", options, &["center"])?;
        let center = opts.bool("center", true)?;
        let m = cylinder(radius, height, segments_)?;
        Ok(if center { m } else { SharedMesh::new(m.0.translate(Vec3::new(0.0, 0.0, m.0.bounds().max.z))) })
    }

    /// A closed cone or frustum around z from −height/2 (radius `bottom`) to +height/2 (radius
    /// `top`): `segments` quads around and an n-gon cap at each end; a radius of 0 makes a
    /// point (triangles meeting at the apex) instead of a cap. Not both radii 0.
    ///
    /// ```rhai
    /// let spike = cone(1, 0, 2, 32);
    /// assert(spike.is_closed(), "closed");
    /// assert_eq(spike.vertex_count, 33);
    /// let frustum = cone(2, 1, 1, 48);
    /// assert_eq(frustum.face_count, 50);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn cone(bottom: Number, top: Number, height: Number, segments_: INT) -> ScriptResult<SharedMesh> {
        let radius = |arg: &str, v: &Number| -> ScriptResult<f64> {
            let r = number("cone", arg, v)?;
            if r < 0.0 {
                return fail("cone", format!("argument `{arg}` must be 0 (a point) or positive, got {}", fmt_num(r)));
            }
            Ok(r)
        };
        let (b, t) = (radius("bottom", &bottom)?, radius("top", &top)?);
        let h = positive("cone", "height", &height)?;
        let s = segments("cone", "segments", segments_)?;
        kernel("cone", Mesh::try_cone(b, t, h, s)).map(SharedMesh::new)
    }

    /// `cone(bottom, top, height, segments)` with options: `center` (default `true`; `false`
    /// puts the base at z = 0 and the top at z = height).
    ///
    /// ```rhai
    /// let c = cone(1, 0, 3, 24, #{ center: false });
    /// assert_eq(c.bounds().min.z, 0.0);
    /// ```
    #[rhai_fn(name = "cone", return_raw)]
    pub fn cone_with(
        bottom: Number,
        top: Number,
        height: Number,
        segments_: INT,
        options: Map,
    ) -> ScriptResult<SharedMesh> {
        let opts = Options::new("cone", options, &["center"])?;
        let center = opts.bool("center", true)?;
        let m = cone(bottom, top, height, segments_)?;
        Ok(if center { m } else { SharedMesh::new(m.0.translate(Vec3::new(0.0, 0.0, m.0.bounds().max.z))) })
    }

    /// A closed cylinder of `radius` whose axis runs from point `a` to point `b` (its caps'
    /// centres), with 32 segments around: a rod, a strut, a pin between two holes.
    ///
    /// Topic: primitives
    ///
    /// ```rhai
    /// let rod = cylinder_between([0, 0, 0], [3, 4, 0], 0.5);
    /// assert_near(rod.volume(), cylinder(0.5, 5, 32).volume(), 1e-9);
    /// assert_near(rod.centroid().x, 1.5, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn cylinder_between(a: Vector, b: Vector, radius: Number) -> ScriptResult<SharedMesh> {
        cylinder_between_with(a, b, radius, 32)
    }

    /// `cylinder_between(a, b, radius)` with `segments` (≥ 3) around.
    ///
    /// Topic: primitives
    ///
    /// ```rhai
    /// let rod = cylinder_between([1, 1, 1], [1, 1, -2], 0.25, 8);
    /// assert_eq(rod.face_count, 10);
    /// assert_near(rod.bounds().min.z, -2.0, 1e-12);
    /// ```
    #[rhai_fn(name = "cylinder_between", return_raw)]
    pub fn cylinder_between_with(a: Vector, b: Vector, radius: Number, segments_: INT) -> ScriptResult<SharedMesh> {
        let (p, q) = (vec3("cylinder_between", "a", &a)?, vec3("cylinder_between", "b", &b)?);
        let d = q - p;
        let length = d.length();
        if length == 0.0 || !length.is_finite() {
            return fail(
                "cylinder_between",
                format!(
                    "arguments `a` and `b` must be two different finite points, got {} and {}",
                    fmt_vec(p),
                    fmt_vec(q)
                ),
            );
        }
        let r = positive("cylinder_between", "radius", &radius)?;
        let s = segments("cylinder_between", "segments", segments_)?;
        let c =
            kernel("cylinder_between", Mesh::try_cylinder(r, length, s))?.translate(Vec3::new(0.0, 0.0, length / 2.0));
        // Turn +z onto the direction a → b (about x by 180° when they are opposite), then move to a.
        let dir = d / length;
        let axis = Vec3::Z.cross(dir);
        let turned = if axis.length() > 1e-12 {
            c.rotate(axis, Vec3::Z.dot(dir).clamp(-1.0, 1.0).acos().to_degrees())
        } else if dir.z < 0.0 {
            c.rotate(Vec3::X, 180.0)
        } else {
            c
        };
        let m = turned.translate(p);
        finite("cylinder_between", "b", &fmt_vec(q), &m)?;
        Ok(SharedMesh::new(m))
    }

    /// A torus around z: tube centre at `major` from the axis, tube radius `minor` < `major`,
    /// `major_segments` × `minor_segments` quads. Genus 1.
    ///
    /// ```rhai
    /// let t = torus(2, 0.5, 24, 12);
    /// assert_eq(t.genus(), 1);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn torus(major: Number, minor: Number, major_segments: INT, minor_segments: INT) -> ScriptResult<SharedMesh> {
        let (a, b) = (positive("torus", "major", &major)?, positive("torus", "minor", &minor)?);
        if b >= a {
            return fail("torus", format!("argument `minor` ({b}) must be smaller than `major` ({a})"));
        }
        let n = segments("torus", "major_segments", major_segments)?;
        let m = segments("torus", "minor_segments", minor_segments)?;
        kernel("torus", Mesh::try_torus(a, b, n, m)).map(SharedMesh::new)
    }

    /// A mesh from indexed polygons: `positions` (an array of points) and `faces` (each an
    /// array of vertex ids, counter-clockwise seen from outside). Non-manifold input is an
    /// error naming the offending edge or vertex.
    ///
    /// ```rhai
    /// let m = mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]);
    /// assert_eq(m.face_count, 1);
    /// assert(!m.is_closed(), "a single triangle has a boundary");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn mesh(positions: Array, faces: Array) -> ScriptResult<SharedMesh> {
        mesh_with(positions, faces, Map::new())
    }

    /// A mesh from indexed polygons with attributes: options `creases` (an array of `[a, b]`
    /// vertex-id pairs tagged as sharp), `corners` (vertex ids kept sharp by subdivision) and
    /// `colors` (one `[r, g, b]` or `[r, g, b, a]` per vertex, components 0–1).
    ///
    /// ```rhai
    /// let m = mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]],
    ///              #{ creases: [[0, 1]], corners: [2] });
    /// assert_eq(m.crease_count(), 1);
    /// ```
    #[rhai_fn(name = "mesh", return_raw)]
    pub fn mesh_with(positions: Array, faces: Array, options: Map) -> ScriptResult<SharedMesh> {
        let opts = Options::new("mesh", options, &["creases", "corners", "colors"])?;
        let p = positions
            .iter()
            .enumerate()
            .map(|(i, v)| vec3("mesh", &format!("positions[{i}]"), v))
            .collect::<ScriptResult<Vec<_>>>()?;
        let mut f = Vec::with_capacity(faces.len());
        for (i, face) in faces.iter().enumerate() {
            let Some(a) = face.clone().try_cast::<Array>() else {
                return fail("mesh", format!("argument `faces[{i}]` must be an array of vertex ids"));
            };
            f.push(ids("mesh", &format!("faces[{i}]"), &a)?);
        }
        let mut m = kernel("mesh", Mesh::from_polygons(p, &f))?;
        if let Some(c) = opts.raw("creases") {
            let pairs = id_pairs("mesh", "creases", &array_option(c, "creases")?)?;
            kernel("mesh", m.crease_edges(&pairs))?;
        }
        if let Some(c) = opts.raw("corners") {
            for v in ids("mesh", "corners", &array_option(c, "corners")?)? {
                kernel("mesh", m.check_vertex(i64::from(v)))?;
                m.set_corner(v, true);
            }
        }
        if let Some(c) = opts.raw("colors") {
            let colors = array_option(c, "colors")?
                .iter()
                .enumerate()
                .map(|(i, c)| color("mesh", &format!("colors[{i}]"), c))
                .collect::<ScriptResult<Vec<_>>>()?;
            kernel("mesh", m.set_vertex_colors(Some(colors)))?;
        }
        Ok(SharedMesh::new(m))
    }

    /// One mesh holding all `meshes` side by side (ids offset part by part, attributes kept).
    /// Overlaps are not resolved: use `union` for a boolean.
    ///
    /// ```rhai
    /// let m = combine([cube(1), cube(1).translate([3, 0, 0])]);
    /// assert_eq(m.face_count, 12);
    /// assert_near(m.volume(), 2.0, 1e-12);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn combine(meshes: Array) -> ScriptResult<SharedMesh> {
        let parts = meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                m.clone().try_cast::<SharedMesh>().ok_or_else(|| {
                    crate::convert::error(
                        "combine",
                        format!("argument `meshes[{i}]` must be a Mesh, got {}", type_name(m)),
                    )
                })
            })
            .collect::<ScriptResult<Vec<_>>>()?;
        let refs: Vec<&Mesh> = parts.iter().map(|m| m.0.as_ref()).collect();
        kernel("combine", Mesh::combine(&refs)).map(|c| SharedMesh(Arc::new(c), SharedMesh::controls(&parts)))
    }

    /// Number of vertices.
    ///
    /// ```rhai
    /// assert_eq(cube(1).vertex_count, 8);
    /// ```
    #[rhai_fn(get = "vertex_count", pure)]
    pub fn vertex_count(m: &mut SharedMesh) -> INT {
        m.0.vertex_count() as INT
    }
    /// Number of faces.
    ///
    /// ```rhai
    /// assert_eq(cube(1).face_count, 6);
    /// ```
    #[rhai_fn(get = "face_count", pure)]
    pub fn face_count(m: &mut SharedMesh) -> INT {
        m.0.face_count() as INT
    }
    /// Number of edges.
    ///
    /// ```rhai
    /// assert_eq(cube(1).edge_count, 12);
    /// ```
    #[rhai_fn(get = "edge_count", pure)]
    pub fn edge_count(m: &mut SharedMesh) -> INT {
        m.0.edge_count() as INT
    }
    /// Number of triangles the mesh triangulates into: Σ (arity − 2).
    ///
    /// ```rhai
    /// assert_eq(cube(1).triangle_count(), 12);
    /// ```
    #[rhai_fn(pure)]
    pub fn triangle_count(m: &mut SharedMesh) -> INT {
        m.0.triangle_count() as INT
    }
    /// Whether the mesh has no boundary edge.
    ///
    /// ```rhai
    /// assert(cube(1).is_closed(), "a cube has no boundary");
    /// assert(!mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]).is_closed(), "a triangle has one");
    /// ```
    #[rhai_fn(pure)]
    pub fn is_closed(m: &mut SharedMesh) -> bool {
        m.0.is_closed()
    }
    /// Whether the connectivity is a 2-manifold (each edge in at most two faces, each vertex a
    /// single fan of faces).
    ///
    /// ```rhai
    /// assert(cube(1).is_manifold(), "manifold");
    /// ```
    #[rhai_fn(pure)]
    pub fn is_manifold(m: &mut SharedMesh) -> bool {
        m.0.is_manifold()
    }
    /// The Euler characteristic V − E + F.
    ///
    /// ```rhai
    /// assert_eq(cube(1).euler(), 2);
    /// ```
    #[rhai_fn(pure)]
    pub fn euler(m: &mut SharedMesh) -> INT {
        m.0.euler()
    }
    /// The genus (number of handles), from χ = 2c − 2g − b.
    ///
    /// ```rhai
    /// assert_eq(torus(3, 1, 16, 8).genus(), 1);
    /// ```
    #[rhai_fn(pure)]
    pub fn genus(m: &mut SharedMesh) -> INT {
        m.0.genus()
    }
    /// The signed enclosed volume (positive for an outward-facing closed mesh). An open mesh is
    /// an error: it encloses nothing.
    ///
    /// ```rhai
    /// assert_near(box([0, 0, 0], [2, 3, 4]).volume(), 24.0, 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn volume(m: &mut SharedMesh) -> ScriptResult<f64> {
        if !m.0.is_closed() {
            let b = m.0.boundary_loops().len();
            return fail("volume", format!("the mesh is not closed ({b} boundary loops), so it encloses no volume"));
        }
        Ok(m.0.volume())
    }
    /// The total surface area.
    ///
    /// ```rhai
    /// assert_near(cube(2).area(), 24.0, 1e-12);
    /// ```
    #[rhai_fn(pure)]
    pub fn area(m: &mut SharedMesh) -> f64 {
        m.0.area()
    }
    /// The centroid: the centre of mass of the enclosed solid (uniform density), or of the
    /// surface's area for a mesh that encloses no volume. Summed about the centre of the
    /// bounds, so a model far from the origin keeps its digits.
    ///
    /// ```rhai
    /// let c = box([0, 0, 0], [2, 4, 6]).translate([1e8, 0, 0]).centroid();
    /// assert_near(c.x, 1e8 + 1, 1e-6);
    /// assert_near(c.z, 3.0, 1e-9);
    /// ```
    #[rhai_fn(pure)]
    pub fn centroid(m: &mut SharedMesh) -> Vec3 {
        m.0.centroid()
    }
    /// The axis-aligned bounds `#{min, max}` of the vertices used by faces.
    ///
    /// ```rhai
    /// let b = cube(2).bounds();
    /// assert_eq(b.max, vec3(1, 1, 1));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn bounds(m: &mut SharedMesh) -> ScriptResult<Map> {
        let b = m.0.bounds();
        if b.is_empty() {
            return fail("bounds", "the mesh has no faces, so it has no bounds");
        }
        let mut map = Map::new();
        map.insert("min".into(), Dynamic::from(b.min));
        map.insert("max".into(), Dynamic::from(b.max));
        Ok(map)
    }
    /// The size of the bounds along x, y and z (`bounds().max - bounds().min`).
    ///
    /// ```rhai
    /// assert_eq(box([0, 0, 0], [2, 3, 4]).size(), vec3(2, 3, 4));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn size(m: &mut SharedMesh) -> ScriptResult<Vec3> {
        let b = m.0.bounds();
        if b.is_empty() {
            return fail("size", "the mesh has no faces, so it has no bounds");
        }
        Ok(b.max - b.min)
    }
    /// The centre of the bounds (half-way between `bounds().min` and `bounds().max`); see
    /// `centroid()` for the centre of mass.
    ///
    /// ```rhai
    /// let m = box([0, 0, 0], [2, 4, 6]);
    /// assert_eq(m.center(), vec3(1, 2, 3));
    /// let on_floor = m.translate([-m.center().x, -m.center().y, -m.bounds().min.z]);
    /// assert_eq(on_floor.bounds().min, vec3(-1, -2, 0));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn center(m: &mut SharedMesh) -> ScriptResult<Vec3> {
        let b = m.0.bounds();
        if b.is_empty() {
            return fail("center", "the mesh has no faces, so it has no bounds");
        }
        Ok((b.min + b.max) * 0.5)
    }
    /// The position of vertex `v` (an id as `faces()` gives them). Reads one point:
    /// `m.positions()[v]` copies every position first, which in a loop costs the mesh's size
    /// on every call.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// assert_eq(m.position(0), m.positions()[0]);
    /// let far = 0;
    /// for v in 0..m.vertex_count { if m.position(v).x > m.position(far).x { far = v; } }
    /// assert_eq(m.position(far).x, 1.0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn position(m: &mut SharedMesh, v: INT) -> ScriptResult<Vec3> {
        let v = kernel("position", m.0.check_vertex(v))?;
        Ok(m.0.position(v))
    }
    /// The vertex positions, indexed by vertex id.
    ///
    /// ```rhai
    /// let p = cube(2).positions();
    /// assert_eq(p.len(), 8);
    /// for q in p { assert_near(length(q), sqrt(3.0), 1e-12); }
    /// ```
    #[rhai_fn(pure)]
    pub fn positions(m: &mut SharedMesh) -> Array {
        m.0.positions().iter().map(|p| Dynamic::from(*p)).collect()
    }
    /// The faces, each an array of vertex ids, indexed by face id.
    ///
    /// ```rhai
    /// assert_eq(cube(1).faces()[0].len(), 4);
    /// ```
    #[rhai_fn(pure)]
    pub fn faces(m: &mut SharedMesh) -> Array {
        m.0.to_polygons()
            .into_iter()
            .map(|f| Dynamic::from_array(f.into_iter().map(|v| Dynamic::from(INT::from(v))).collect()))
            .collect()
    }
    /// Area-weighted unit vertex normals, indexed by vertex id.
    ///
    /// ```rhai
    /// let n = uv_sphere(1, 16, 8).normals();
    /// assert_eq(n.len(), uv_sphere(1, 16, 8).vertex_count);
    /// assert_near(length(n[0]), 1.0, 1e-12);
    /// ```
    #[rhai_fn(pure)]
    pub fn normals(m: &mut SharedMesh) -> Array {
        m.0.vertex_normals().into_iter().map(Dynamic::from).collect()
    }

    /// This mesh moved by `offset`. Ids are kept.
    ///
    /// ```rhai
    /// let m = cube(2).translate([1, 0, 0]);
    /// assert_eq(m.bounds().min, vec3(0, -1, -1));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn translate(m: &mut SharedMesh, offset: Vector) -> ScriptResult<SharedMesh> {
        let v = vec3("translate", "offset", &offset)?;
        let t = m.0.translate(v);
        finite("translate", "offset", &fmt_vec(v), &t)?;
        Ok(m.moved(t, |c| c.translate(v)))
    }
    /// This mesh turned by `degrees` about `axis` through the origin (right-handed). Ids are kept.
    ///
    /// ```rhai
    /// let m = box([1, 0, 0], [2, 1, 1]).rotate([0, 0, 1], 90);
    /// assert_near(m.bounds().min.y, 1.0, 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn rotate(m: &mut SharedMesh, axis: Vector, degrees: Number) -> ScriptResult<SharedMesh> {
        let a = nonzero("rotate", "axis", &axis)?;
        let d = number("rotate", "degrees", &degrees)?;
        Ok(m.moved(m.0.rotate(a, d), |c| c.rotate(a, d)))
    }
    /// This mesh scaled about the origin by a number or per axis by a vector. Mirroring
    /// scales (a negative product) keep the faces outward. A zero factor is an error.
    ///
    /// ```rhai
    /// assert_near(cube(1).scale([2, 3, 4]).volume(), 24.0, 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn scale(m: &mut SharedMesh, factor: NumberOrVector) -> ScriptResult<SharedMesh> {
        let f = factor3("scale", "factor", &factor)?;
        if f.x * f.y * f.z == 0.0 {
            return fail(
                "scale",
                format!("argument `factor` has a zero component ({f}), which would flatten the mesh"),
            );
        }
        let t = m.0.scale(f);
        finite("scale", "factor", &fmt_vec(f), &t)?;
        Ok(m.moved(t, |c| c.scale(f)))
    }
    /// This mesh reflected through the plane through the origin with normal `normal`; faces are
    /// reversed so they keep facing outward.
    ///
    /// ```rhai
    /// let m = box([1, 0, 0], [2, 1, 1]).mirror([1, 0, 0]);
    /// assert_near(m.volume(), 1.0, 1e-12);
    /// assert_eq(m.bounds().max.x, -1.0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn mirror(m: &mut SharedMesh, normal: Vector) -> ScriptResult<SharedMesh> {
        let n = nonzero("mirror", "normal", &normal)?;
        Ok(m.moved(m.0.mirror(n), |c| c.mirror(n)))
    }
    /// A triangle mesh of the same surface (vertex ids kept): convex faces by a fan, others by
    /// a constrained Delaunay triangulation in the face's plane.
    ///
    /// ```rhai
    /// let t = cube(1).triangulate();
    /// assert_eq(t.face_count, 12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn triangulate(m: &mut SharedMesh) -> ScriptResult<SharedMesh> {
        kernel("triangulate", m.0.triangulate()).map(|t| SharedMesh(Arc::new(t), m.1.clone()))
    }

    /// A one-line summary: `Mesh(V vertices, E edges, F faces)`.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(m: &mut SharedMesh) -> String {
        format!("Mesh({} vertices, {} edges, {} faces)", m.0.vertex_count(), m.0.edge_count(), m.0.face_count())
    }
}
