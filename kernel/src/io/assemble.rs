//! From a file's faces to a mesh: welded where welding keeps the surface manifold, and
//! repaired (without moving a vertex) where the file itself is not.
//!
//! The fast path welds by the rule and builds, as readers always did: a valid file costs
//! nothing more. When that build fails, the faces are taken again in two stages:
//! 1. **The file's own topology**: its indices (OBJ, 3MF, indexed glTF, PLY), or for a
//!    triangle soup (STL, glTF without indices, or indexed faces of which no two share a
//!    vertex) its corners joined where their coordinates are equal. If that is not a
//!    manifold surface, it is repaired by
//!    [`repair_polygons`](crate::diagnose::repair_polygons) with re-orientation — vertices
//!    split per fan, faces beyond two on an edge separated, components re-oriented, faces
//!    repeating a vertex dropped — and each repair is reported (the loader's warnings); with
//!    `repair: false` the file is refused instead ([`IoError::NotManifold`]).
//! 2. **The weld**: the manifold result is welded by the rule, and whatever the weld made
//!    non-manifold (two sheets joined at a bowtie vertex or an edge of three or four faces, two
//!    sheets of opposite orientations joined along a seam) is split back, pairing first the
//!    edges the file paired: a weld never turns a manifold file non-manifold. This stage
//!    reports nothing; it never flips a face.

use super::weld::{weld, Weld};
use super::IoError;
use crate::diagnose::{repair_polygons, RepairOptions, Repairs};
use crate::math::Vec3;
use crate::mesh::{Mesh, MeshError};
use std::path::Path;

/// How a file names its shared corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Topology {
    /// Faces index shared vertices (OBJ, PLY, 3MF, indexed glTF).
    Indexed,
    /// Each face has corners of its own (STL, glTF without indices): corners at equal
    /// coordinates are the file's shared vertices.
    Soup,
}

/// A file's mesh, with where each vertex and face came from and what was repaired.
pub(crate) struct Assembled {
    pub mesh: Mesh,
    /// For each mesh vertex, the input vertex it comes from.
    pub vertex_from: Vec<u32>,
    /// For each mesh face, the input face (index into `arities`) it comes from: faces welding
    /// collapses or repair drops are gone, the others keep their order.
    pub face_from: Vec<u32>,
    /// The repairs of the file's own topology (empty for a valid file).
    pub repairs: Repairs,
}

/// The mesh of `indices` (split by `arities`) over `positions`: see the module documentation.
///
/// # Errors
/// The build's errors ([`IoError::NonFinite`], [`IoError::Mesh`]); [`IoError::NotManifold`]
/// when `repair` is false and the file is not a manifold surface as written.
pub(crate) fn assemble(
    positions: &[Vec3],
    indices: &[u32],
    arities: &[u32],
    topology: Topology,
    rule: Weld,
    repair: bool,
    path: &Path,
) -> Result<Assembled, IoError> {
    let io = |e: MeshError| IoError::from_mesh(path, e);
    // Fast path: weld and build.
    let (map, kept) = weld(positions, rule).map_err(|e| io(e.into()))?;
    let merged = kept.len() < positions.len();
    let welded;
    let (idx, ar, fast_from): (&[u32], &[u32], Option<Vec<u32>>) = if merged {
        let (i, a, f) = super::weld::remap_faces(indices, arities, &map);
        welded = (i, a);
        (&welded.0, &welded.1, Some(f))
    } else {
        (indices, arities, None)
    };
    let pos: Vec<Vec3> =
        if merged { kept.iter().map(|&i| positions[i as usize]).collect() } else { positions.to_vec() };
    match Mesh::from_indexed_stoppable(pos, idx, ar) {
        Ok(mesh) => {
            let face_from = fast_from.unwrap_or_else(|| (0..arities.len() as u32).collect());
            return Ok(Assembled { vertex_from: kept, face_from, mesh, repairs: Repairs::default() });
        }
        Err(
            MeshError::NonManifoldEdge { .. } | MeshError::NonManifoldVertex { .. } | MeshError::DegenerateFace { .. },
        ) => {}
        Err(e) => return Err(io(e)),
    }

    // 1. The file's own topology. Indexed faces of which no two share a vertex (an OBJ or
    // 3MF converted from an STL) name no topology: they are a soup.
    let topology = match topology {
        Topology::Indexed if shares_no_vertex(indices, positions.len()) => Topology::Soup,
        t => t,
    };
    let (a_idx, a_ar, a_from, a_vertex_from, a_pos) = match topology {
        Topology::Indexed => (indices.to_vec(), arities.to_vec(), None, None, positions.to_vec()),
        Topology::Soup => {
            let (m, k) = weld(positions, Weld::Relative(0.0)).map_err(|e| io(e.into()))?;
            let (i, a, f) = super::weld::remap_faces(indices, arities, &m);
            let p = k.iter().map(|&v| positions[v as usize]).collect();
            (i, a, Some(f), Some(k), p)
        }
    };
    let file = match Mesh::from_indexed_stoppable(a_pos.clone(), &a_idx, &a_ar) {
        Ok(mesh) => {
            let faces = (0..mesh.face_count() as u32).collect::<Vec<u32>>();
            (mesh, (0..a_pos.len() as u32).collect::<Vec<u32>>(), faces, Repairs::default())
        }
        Err(
            e @ (MeshError::NonManifoldEdge { .. }
            | MeshError::NonManifoldVertex { .. }
            | MeshError::DegenerateFace { .. }),
        ) if !repair => {
            return Err(IoError::NotManifold { path: path.into(), source: e });
        }
        Err(
            MeshError::NonManifoldEdge { .. } | MeshError::NonManifoldVertex { .. } | MeshError::DegenerateFace { .. },
        ) => {
            let r = repair_polygons(&a_pos, &a_idx, &a_ar, RepairOptions::DEFAULT.with_reorient(true)).map_err(io)?;
            // Name the file's faces and vertices in the report (a soup's faces are the file's
            // triangles; its vertices the first corner at each position).
            let mut repairs = r.repairs;
            if let Some(f) = &a_from {
                for d in &mut repairs.dropped_faces {
                    d.0 = f[d.0 as usize];
                }
                for c in &mut repairs.flipped {
                    for x in &mut c.faces {
                        *x = f[*x as usize];
                    }
                }
            }
            (r.mesh, r.vertex_from, r.face_from, repairs)
        }
        Err(e) => return Err(io(e)),
    };
    let (file_mesh, file_vertex_from, file_face_from, repairs) = file;
    // A face of the file's topology as an input face.
    let to_input_face = |f: u32| {
        let g = file_face_from[f as usize];
        a_from.as_ref().map_or(g, |from| from[g as usize])
    };
    // Back to the input's ids.
    let to_input_vertex = |v: u32| match &a_vertex_from {
        Some(k) => k[file_vertex_from[v as usize] as usize],
        None => file_vertex_from[v as usize],
    };

    // 2. The weld, split back where it breaks the surface.
    if rule == Weld::Off {
        let vertex_from = (0..file_mesh.vertex_count() as u32).map(to_input_vertex).collect();
        let face_from = (0..file_mesh.face_count() as u32).map(to_input_face).collect();
        return Ok(Assembled { mesh: file_mesh, vertex_from, face_from, repairs });
    }
    let (fi, fa) = file_mesh.to_indexed();
    let (map, kept) = weld(file_mesh.positions(), rule).map_err(|e| io(e.into()))?;
    let (w_idx, w_ar, w_prior, w_from) = remap_with_prior(&fi, &fa, &map);
    let w_pos: Vec<Vec3> = kept.iter().map(|&i| file_mesh.position(i)).collect();
    let r = repair_polygons(&w_pos, &w_idx, &w_ar, RepairOptions::DEFAULT.with_prior(&w_prior)).map_err(io)?;
    let vertex_from = r.vertex_from.iter().map(|&v| to_input_vertex(kept[v as usize])).collect();
    let face_from = r.face_from.iter().map(|&f| to_input_face(w_from[f as usize])).collect();
    Ok(Assembled { mesh: r.mesh, vertex_from, face_from, repairs })
}

/// Whether no vertex is a corner of two faces (nor twice of one) in `indices`, which index
/// `vertex_count` vertices: a soup written with indices (an OBJ or 3MF converted from an STL).
fn shares_no_vertex(indices: &[u32], vertex_count: usize) -> bool {
    let mut used = vec![false; vertex_count];
    indices.iter().all(|&v| used.get_mut(v as usize).is_some_and(|u| !std::mem::replace(u, true)))
}

/// [`super::weld::remap_faces`] that also gives, for each kept corner, the vertex it had before
/// the weld, and for each kept face the face it comes from: (indices, arities, prior vertex of
/// each corner, face from).
fn remap_with_prior(indices: &[u32], arities: &[u32], map: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>) {
    let mut from = Vec::with_capacity(arities.len());
    let mut out = Vec::with_capacity(indices.len());
    let mut prior = Vec::with_capacity(indices.len());
    let mut out_ar = Vec::with_capacity(arities.len());
    let mut start = 0;
    for (f, &a) in arities.iter().enumerate() {
        let face = &indices[start..start + a as usize];
        start += a as usize;
        let begin = out.len();
        for &v in face {
            let w = map[v as usize];
            if out.len() == begin || out[out.len() - 1] != w {
                out.push(w);
                prior.push(v);
            }
        }
        while out.len() > begin + 1 && out[out.len() - 1] == out[begin] {
            out.pop();
            prior.pop();
        }
        let n = out.len() - begin;
        let corners = &out[begin..];
        if n < 3 || (1..n).any(|i| corners[..i].contains(&corners[i])) {
            out.truncate(begin);
            prior.truncate(begin);
            continue;
        }
        out_ar.push(n as u32);
        from.push(f as u32);
    }
    (out, out_ar, prior, from)
}

impl Assembled {
    /// Gives the mesh the face parts of the input faces: `input_parts[f]` is input face f's id
    /// into `table` (a reader's colours per face).
    ///
    /// # Errors
    /// [`IoError::Mesh`] when an id is past the table or a colour is out of range.
    pub(crate) fn set_input_parts(
        &mut self,
        input_parts: &[u32],
        table: Vec<crate::mesh::FacePart>,
        path: &Path,
    ) -> Result<(), IoError> {
        let ids = self.face_from.iter().map(|&f| input_parts.get(f as usize).copied().unwrap_or(0)).collect();
        self.mesh.set_face_parts(ids, table).map_err(|e| IoError::from_mesh(path, e))
    }
}
