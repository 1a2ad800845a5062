//! Smooth refinement through Manifold's tangents (Manifold's `SmoothByNormals` + `Refine`,
//! after Lévy's and Vlachos et al.'s curved PN triangles: each triangle becomes a cubic
//! Bézier patch whose edge tangents follow the vertex normals; the refined vertices are
//! placed on those patches).
//!
//! The vertex normals are computed per sector: around a vertex the faces between two crease
//! edges share one normal (angle-weighted), so the surface bends smoothly everywhere except
//! across creases ([`super::sharp_edges`] tags them by angle), which stay sharp and straight
//! where they were straight. Positions go to the engine in double precision.

use manifold_rust::manifold::Manifold;
use manifold_rust::types::{Error as EngineStatus, MeshGLP};

use crate::limits;
use crate::math::{IdMap, Vec3};
use crate::mesh::Mesh;

use super::{FinishError, MAX_TRIANGLES};

/// The largest `n` [`refine`] takes.
pub const MAX_REFINE: u32 = 1000;

/// `mesh` with every edge split into `n` pieces and each triangle into n², the new vertices on
/// the smooth surface through the mesh; crease-tagged edges stay sharp (see the module notes).
/// Faces keep the part of the face they came from, and the creases are kept (each sub-edge of
/// a crease is one). Vertex colours are dropped.
///
/// # Errors
/// [`FinishError::BadOption`] for `n` of 0 or over [`MAX_REFINE`]; [`FinishError::NotClosed`]
/// for a mesh with a boundary; [`FinishError::TooLarge`] when n² times the triangle count is
/// over [`super::MAX_TRIANGLES`] (refused before allocating); [`FinishError::Engine`] when the
/// engine refuses the mesh.
pub fn refine(mesh: &Mesh, n: u32) -> Result<Mesh, FinishError> {
    if !(1..=MAX_REFINE).contains(&n) {
        return Err(FinishError::bad("n", f64::from(n), format!("between 1 and {MAX_REFINE}")));
    }
    let estimate = mesh.triangle_count() as f64 * f64::from(n) * f64::from(n);
    check_size(|| format!("refine({n}) of {} triangles", mesh.triangle_count()), estimate)?;
    through_engine(mesh, "refine", |m| m.refine(n as i32))
}

/// `mesh` refined so that no edge is longer than about `length`: each edge is split into
/// ⌊its length / `length`⌋ + 1 pieces (Manifold's `RefineToLength`), the new vertices on the
/// smooth surface as [`refine`] places them.
///
/// # Errors
/// As [`refine`], with `length` not finite or not above 0 refused by name, and the estimate of
/// Σ over triangles of (longest edge / `length` + 1)² refused when too large.
pub fn refine_to_length(mesh: &Mesh, length: f64) -> Result<Mesh, FinishError> {
    if !(length.is_finite() && length > 0.0) {
        return Err(FinishError::bad("length", length, "a finite number above 0"));
    }
    let mut estimate = 0.0;
    for f in 0..mesh.face_count() as u32 {
        let longest = mesh
            .face_halfedges(f)
            .map(|h| mesh.position(mesh.origin(h)).distance(mesh.position(mesh.target(h))))
            .fold(0.0f64, f64::max);
        let k = (longest / length).floor() + 1.0;
        estimate += k * k * (mesh.face_arity(f) - 2) as f64;
    }
    check_size(
        || format!("refine_to_length({}) of a mesh of {} faces", crate::math::fmt_num(length), mesh.face_count()),
        estimate,
    )?;
    through_engine(mesh, "refine_to_length", |m| m.refine_to_length(length))
}

fn check_size(what: impl Fn() -> String, triangles: f64) -> Result<(), FinishError> {
    if triangles > MAX_TRIANGLES {
        return Err(FinishError::TooLarge { what: what(), estimate: triangles, limit: MAX_TRIANGLES });
    }
    // About half as many vertices as triangles; three half-edges a triangle.
    crate::mesh::check_mesh_size(what, triangles / 2.0, 3.0 * triangles, triangles)?;
    Ok(())
}

/// The angle-weighted normal of every face corner, equal within each sector of faces between
/// two crease edges around a vertex, and one property vertex per (vertex, sector): returns
/// the property index of each half-edge's corner (its origin's) and the properties.
fn sector_normals(t: &Mesh) -> (Vec<u32>, Vec<[f64; 3]>, Vec<u32>) {
    let mut corner_prop = vec![u32::MAX; t.halfedge_count()];
    let mut normals: Vec<[f64; 3]> = Vec::with_capacity(t.vertex_count());
    let mut prop_vertex: Vec<u32> = Vec::with_capacity(t.vertex_count());
    let corner_weight = |h: u32| {
        // The face normal times the corner angle at origin(h).
        let o = t.position(t.origin(h));
        let a = t.position(t.target(h)) - o;
        let b = t.position(t.origin(t.prev(h))) - o;
        let angle = a.angle_between(b);
        let n = t.face_normal(t.face(h));
        if angle.is_finite() {
            n * angle
        } else {
            Vec3::ZERO
        }
    };
    for v in 0..t.vertex_count() as u32 {
        let outs: Vec<u32> = t.outgoing(v).collect();
        if outs.is_empty() {
            continue;
        }
        // Start a sector at a crease when there is one (the edge of h_{i+1} separates the faces
        // of h_i and h_{i+1}).
        let start = outs.iter().position(|&h| t.is_crease(h)).unwrap_or(0);
        let mut sector: Vec<u32> = Vec::new();
        let mut flush = |sector: &mut Vec<u32>, normals: &mut Vec<[f64; 3]>, prop_vertex: &mut Vec<u32>| {
            if sector.is_empty() {
                return;
            }
            let sum: Vec3 = sector.iter().map(|&h| corner_weight(h)).sum();
            let n = sum.try_normalize().unwrap_or(Vec3::Z);
            let id = normals.len() as u32;
            normals.push([n.x, n.y, n.z]);
            prop_vertex.push(v);
            for &h in sector.iter() {
                corner_prop[h as usize] = id;
            }
            sector.clear();
        };
        for i in 0..outs.len() {
            let h = outs[(start + i) % outs.len()];
            if i > 0 && t.is_crease(h) {
                flush(&mut sector, &mut normals, &mut prop_vertex);
            }
            sector.push(h);
        }
        flush(&mut sector, &mut normals, &mut prop_vertex);
    }
    (corner_prop, normals, prop_vertex)
}

/// Runs `op` on `mesh` smoothed by its sector normals inside the engine and builds the result.
fn through_engine(
    mesh: &Mesh,
    what: &'static str,
    op: impl FnOnce(&Manifold) -> Manifold,
) -> Result<Mesh, FinishError> {
    if !mesh.is_closed() {
        let boundary_edges =
            mesh.edges().filter(|&h| mesh.is_boundary_halfedge(h) || mesh.is_boundary_halfedge(mesh.twin(h))).count();
        return Err(FinishError::NotClosed { what, boundary_edges });
    }
    limits::check()?;
    let (t, sources) = mesh.triangulate_with_sources()?;
    let (corner_prop, normals, prop_vertex) = sector_normals(&t);
    let mut vert_properties = Vec::with_capacity(normals.len() * 6);
    for (n, &v) in normals.iter().zip(&prop_vertex) {
        let p = t.position(v);
        vert_properties.extend_from_slice(&[p.x, p.y, p.z, n[0], n[1], n[2]]);
    }
    let mut tri_verts = Vec::with_capacity(3 * t.face_count());
    for f in 0..t.face_count() as u32 {
        tri_verts.extend(t.face_halfedges(f).map(|h| corner_prop[h as usize]));
    }
    // Property vertices of one vertex are merged into its first.
    let mut first_prop = vec![u32::MAX; t.vertex_count()];
    let (mut merge_from_vert, mut merge_to_vert) = (Vec::new(), Vec::new());
    for (i, &v) in prop_vertex.iter().enumerate() {
        if first_prop[v as usize] == u32::MAX {
            first_prop[v as usize] = i as u32;
        } else {
            merge_from_vert.push(i as u32);
            merge_to_vert.push(first_prop[v as usize]);
        }
    }
    let gl = MeshGLP::<f64, u32> {
        num_prop: 6,
        vert_properties,
        tri_verts,
        merge_from_vert,
        merge_to_vert,
        face_id: (0..t.face_count() as u32).collect(),
        ..Default::default()
    };
    let input = Manifold::from_mesh_glp(&gl);
    if input.status() != EngineStatus::NoError {
        return Err(FinishError::Engine(format!("the mesh was refused: {}", input.status().to_str())));
    }
    // Property 0 is the first after the position: the normal.
    let smooth = input.smooth_by_normals(0);
    limits::check()?;
    let out = op(&smooth);
    if out.status() != EngineStatus::NoError {
        return Err(FinishError::Engine(out.status().to_str().to_string()));
    }
    limits::check()?;
    build(&t, mesh, &sources, &out.get_mesh_glp::<f64, u32>(-1))
}

/// The engine's output as a mesh: property seams merged, each triangle's part from the input
/// face its tag names, creases where the two triangles on an edge came from two triangles on
/// either side of a crease.
fn build(t: &Mesh, mesh: &Mesh, sources: &[u32], m: &MeshGLP<f64, u32>) -> Result<Mesh, FinishError> {
    let np = m.num_prop as usize;
    let count = m.vert_properties.len() / np;
    let mut to: Vec<u32> = (0..count as u32).collect();
    for (&f, &g) in m.merge_from_vert.iter().zip(&m.merge_to_vert) {
        to[f as usize] = g;
    }
    let mut keep = vec![u32::MAX; count];
    let mut positions = Vec::with_capacity(count);
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(m.tri_verts.len() / 3);
    for c in m.tri_verts.chunks_exact(3) {
        let mut tri = [0u32; 3];
        for (k, &pv) in c.iter().enumerate() {
            let v = to[pv as usize] as usize;
            if keep[v] == u32::MAX {
                keep[v] = positions.len() as u32;
                positions.push(Vec3::new(
                    m.vert_properties[v * np],
                    m.vert_properties[v * np + 1],
                    m.vert_properties[v * np + 2],
                ));
            }
            tri[k] = keep[v];
        }
        triangles.push(tri);
    }
    if m.face_id.len() != triangles.len() || m.face_id.iter().any(|&f| f as usize >= sources.len()) {
        return Err(FinishError::Engine("the refined triangles lost their source faces".into()));
    }
    let mut out = Mesh::from_polygons(positions, &triangles)?;
    let parents: Vec<u32> = m.face_id.iter().map(|&f| sources[f as usize]).collect();
    out.inherit_parts(mesh, &parents)?;
    // Creases: the pairs of input triangles across a crease edge.
    let mut creased: IdMap<u64, ()> = IdMap::default();
    for h in t.edges() {
        if t.is_crease(h) {
            let (a, b) = (t.face(h), t.face(t.twin(h)));
            creased.insert(pair_key(a, b), ());
        }
    }
    if !creased.is_empty() {
        for h in out.edges().collect::<Vec<_>>() {
            let (a, b) = (m.face_id[out.face(h) as usize], m.face_id[out.face(out.twin(h)) as usize]);
            if a != b && creased.contains_key(&pair_key(a, b)) {
                out.set_crease_halfedge(h, true);
            }
        }
    }
    Ok(out)
}

fn pair_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

#[cfg(test)]
#[path = "tests_refine.rs"]
mod tests;
