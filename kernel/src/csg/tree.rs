//! The CSG tree (seed 000 §2.4.2) and its evaluation: leaves are block models (tessellated
//! first, so adaptive tessellation and crease tags come through), meshes, or other trees; inner
//! nodes are union, difference and intersection. Independent subtrees are evaluated in
//! parallel (rayon), and every output face keeps its source ([`FaceSource`]).
//!
//! Cost: the leaves are tessellated and checked in O(n log n) for n input triangles (the
//! coincident-vertex check sorts); each boolean is Manifold's, O((n + k) log n) for k
//! intersecting triangle pairs; provenance and crease tags cost O(1) per output triangle.

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use rayon::prelude::*;

use super::engine::Solid;
use super::{CsgError, CsgOp, Side};
use crate::blocks::{BlockModel, MeshOptions};
use crate::math::Vec3;
use crate::mesh::{FaceSource, Mesh};

/// A CSG tree. Cloning is cheap (inputs are shared).
#[derive(Clone, Debug)]
pub enum Csg {
    /// A block model, tessellated with these options.
    Blocks(Arc<BlockModel>, MeshOptions),
    /// A closed mesh. When it has face sources (an earlier boolean result), they are kept and
    /// its leaves are renumbered after the leaves to its left.
    Mesh(Arc<Mesh>),
    /// A boolean of two trees.
    Op(CsgOp, Box<Csg>, Box<Csg>),
}

impl Csg {
    /// A block-model leaf.
    #[must_use]
    pub fn blocks(model: BlockModel, options: MeshOptions) -> Csg {
        Csg::Blocks(Arc::new(model), options)
    }

    /// A mesh leaf.
    #[must_use]
    pub fn mesh(mesh: Mesh) -> Csg {
        Csg::Mesh(Arc::new(mesh))
    }

    /// `self ∪ other`.
    #[must_use]
    pub fn union(self, other: Csg) -> Csg {
        Csg::Op(CsgOp::Union, Box::new(self), Box::new(other))
    }

    /// `self − other`.
    #[must_use]
    pub fn difference(self, other: Csg) -> Csg {
        Csg::Op(CsgOp::Difference, Box::new(self), Box::new(other))
    }

    /// `self ∩ other`.
    #[must_use]
    pub fn intersection(self, other: Csg) -> Csg {
        Csg::Op(CsgOp::Intersection, Box::new(self), Box::new(other))
    }

    /// The union of all `parts` as a balanced tree (so its halves evaluate in parallel);
    /// `None` when there are none.
    #[must_use]
    pub fn union_all(mut parts: Vec<Csg>) -> Option<Csg> {
        while parts.len() > 1 {
            let mut next = Vec::with_capacity(parts.len().div_ceil(2));
            let mut it = parts.into_iter();
            while let Some(a) = it.next() {
                next.push(match it.next() {
                    Some(b) => a.union(b),
                    None => a,
                });
            }
            parts = next;
        }
        parts.pop()
    }

    /// Evaluates the tree into a closed, manifold triangle mesh whose faces carry their
    /// [`FaceSource`]s and whose edges keep the crease tags of the inputs' edges they lie on.
    /// An empty result (e.g. `a − a`) is a mesh without faces.
    ///
    /// # Errors
    /// [`CsgError`] naming the operand: an open, empty or self-touching input, one with a
    /// non-finite coordinate, a block model that cannot be meshed.
    pub fn evaluate(&self) -> Result<Mesh, CsgError> {
        let mut leaves = Vec::new();
        collect_leaves(self, Side::Left, &mut leaves);
        let prepared: Vec<Prepared> = leaves
            .par_iter()
            .enumerate()
            .map(|(k, (leaf, side))| prepare(leaf, *side, k as u32))
            .collect::<Result<_, _>>()?;
        // Leaf numbers and the global triangle tags: leaf k's triangles are tagged from
        // offsets[k], its leaf ids start at first_leaf[k].
        let total: usize = prepared.iter().map(|p| p.triangles.len()).sum();
        if total >= i32::MAX as usize {
            return Err(CsgError::TooLarge { triangles: total });
        }
        let mut offsets = Vec::with_capacity(prepared.len());
        let mut first_leaf = 0u32;
        let mut tag = 0u32;
        let mut sources = Vec::with_capacity(total);
        let mut corner_ids = Vec::with_capacity(total);
        let mut vertex_base = 0u32;
        for p in &prepared {
            offsets.push(tag);
            sources.extend(p.sources.iter().map(|s| s.shifted(first_leaf)));
            corner_ids.extend(p.triangles.iter().map(|t| t.map(|v| v + vertex_base)));
            vertex_base += p.positions.len() as u32;
            tag += p.triangles.len() as u32;
            first_leaf += p.leaf_span;
        }
        let mut creases: HashSet<[u32; 2]> = HashSet::new();
        let mut vb = 0u32;
        for p in &prepared {
            for &[a, b] in &p.creases {
                creases.insert(edge_key(a + vb, b + vb));
            }
            vb += p.positions.len() as u32;
        }
        // Engine ids in leaf and component order, reserved before the parallel import.
        let mut first_ids = Vec::with_capacity(prepared.len());
        for p in &prepared {
            first_ids.push(Solid::reserve_ids(p.components.len() as u32));
        }
        let solids: Vec<Solid> = prepared
            .par_iter()
            .zip(leaves.par_iter())
            .zip(offsets.par_iter().zip(first_ids.par_iter()))
            .map(|((p, (_, side)), (&off, &first_id))| {
                let refused = |reason: String| CsgError::NonManifold {
                    side: *side,
                    leaf: p.first_leaf_hint,
                    reason: format!("the boolean engine refuses it ({reason})"),
                };
                // A block model's separate solids (blocks side by side that the connection
                // search did not join) are unioned: the model is the union of its blocks.
                let parts: Vec<Solid> = p
                    .components
                    .par_iter()
                    .enumerate()
                    .map(|(k, tris)| {
                        let (positions, triangles) =
                            compact(&p.positions, tris.iter().map(|&t| p.triangles[t as usize]));
                        let tags: Vec<u32> = tris.iter().map(|&t| off + t).collect();
                        Solid::with_id(&positions, &triangles, &tags, first_id + k as u32).map_err(refused)
                    })
                    .collect::<Result<_, _>>()?;
                Solid::union_all(parts).map_err(|reason| CsgError::Engine { reason })
            })
            .collect::<Result<_, _>>()?;
        drop(prepared);
        let mut next = 0usize;
        let solid = eval(self, &solids, &mut next)?;
        let out = solid.triangles();
        let flat: Vec<u32> = out.triangles.as_flattened().to_vec();
        let mut mesh = Mesh::from_indexed(out.positions, &flat, &vec![3; out.triangles.len()])
            .map_err(|e| CsgError::Engine { reason: e.to_string() })?;
        let face_sources: Vec<FaceSource> =
            out.tags.iter().map(|&t| sources.get(t as usize).copied().unwrap_or(FaceSource::Unknown)).collect();
        // An output edge between pieces of two different input triangles lies on their common
        // input edge; it is a crease when that edge was.
        if !creases.is_empty() {
            let mut tagged = Vec::new();
            for h in mesh.edges() {
                let (f, g) = (mesh.face(h), mesh.face(mesh.twin(h)));
                let (tf, tg) = (out.tags[f as usize] as usize, out.tags[g as usize] as usize);
                if tf == tg || tf >= corner_ids.len() || tg >= corner_ids.len() {
                    continue;
                }
                let (a, b) = (corner_ids[tf], corner_ids[tg]);
                let shared: Vec<u32> = a.iter().copied().filter(|v| b.contains(v)).collect();
                if shared.len() == 2 && creases.contains(&edge_key(shared[0], shared[1])) {
                    tagged.push(h);
                }
            }
            for h in tagged {
                mesh.set_crease_halfedge(h, true);
            }
        }
        mesh.set_face_sources(Some(face_sources)).map_err(|e| CsgError::Engine { reason: e.to_string() })?;
        Ok(mesh)
    }
}

fn edge_key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

/// The leaves left to right, each with the side of its parent boolean it sits on.
fn collect_leaves<'a>(node: &'a Csg, side: Side, out: &mut Vec<(&'a Csg, Side)>) {
    match node {
        Csg::Op(_, a, b) => {
            collect_leaves(a, Side::Left, out);
            collect_leaves(b, Side::Right, out);
        }
        leaf => out.push((leaf, side)),
    }
}

/// Evaluates `node` from the imported leaves (`next` counts leaves left to right): the operands
/// of a chain of unions all at once (Manifold's batch union), the two sides of any other
/// boolean in parallel.
fn eval(node: &Csg, solids: &[Solid], next: &mut usize) -> Result<Solid, CsgError> {
    match node {
        Csg::Op(CsgOp::Union, ..) => {
            let mut operands = Vec::new();
            union_operands(node, &mut operands);
            let mut starts = Vec::with_capacity(operands.len());
            for o in &operands {
                starts.push(*next);
                *next += count_leaves(o);
            }
            let parts: Vec<Solid> = operands
                .par_iter()
                .zip(starts.par_iter())
                .map(|(o, &start)| eval(o, solids, &mut { start }))
                .collect::<Result<_, _>>()?;
            Solid::union_all(parts).map_err(|reason| CsgError::Engine { reason })
        }
        Csg::Op(op, a, b) => {
            let leaves_a = count_leaves(a);
            let (start_a, start_b) = (*next, *next + leaves_a);
            *next += leaves_a + count_leaves(b);
            let (ra, rb) = rayon::join(|| eval(a, solids, &mut { start_a }), || eval(b, solids, &mut { start_b }));
            ra?.boolean(&rb?, *op).map_err(|reason| CsgError::Engine { reason })
        }
        _ => {
            let s = solids[*next].clone();
            *next += 1;
            Ok(s)
        }
    }
}

/// The operands of the chain of unions at `node`, left to right.
fn union_operands<'a>(node: &'a Csg, out: &mut Vec<&'a Csg>) {
    match node {
        Csg::Op(CsgOp::Union, a, b) => {
            union_operands(a, out);
            union_operands(b, out);
        }
        other => out.push(other),
    }
}

/// The vertices `triangles` use, renumbered from 0 in order of first use.
fn compact(positions: &[Vec3], triangles: impl Iterator<Item = [u32; 3]>) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut map: HashMap<u32, u32> = HashMap::new();
    let mut out = Vec::new();
    let tris = triangles
        .map(|t| {
            t.map(|v| {
                *map.entry(v).or_insert_with(|| {
                    out.push(positions[v as usize]);
                    (out.len() - 1) as u32
                })
            })
        })
        .collect();
    (out, tris)
}

fn count_leaves(node: &Csg) -> usize {
    match node {
        Csg::Op(_, a, b) => count_leaves(a) + count_leaves(b),
        _ => 1,
    }
}

/// One leaf as indexed triangles with a source per triangle (leaf ids from 0).
struct Prepared {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    sources: Vec<FaceSource>,
    /// Crease edges as vertex pairs.
    creases: Vec<[u32; 2]>,
    /// How many leaf ids the input occupies (more than one for an earlier boolean result).
    leaf_span: u32,
    /// The leaf number used in errors raised after preparation.
    first_leaf_hint: u32,
    /// The triangles of each solid to union (one for a mesh; one per connected component for
    /// a block model).
    components: Vec<Vec<u32>>,
}

/// `leaf_no` is the input's position among the tree's inputs, left to right (named in errors).
fn prepare(leaf: &Csg, side: Side, leaf_no: u32) -> Result<Prepared, CsgError> {
    let (mesh, sources, union_parts): (Cow<'_, Mesh>, Vec<FaceSource>, bool) = match leaf {
        Csg::Blocks(model, options) => {
            if model.blocks().is_empty() {
                return Err(CsgError::EmptyOperand { side, leaf: leaf_no });
            }
            let t =
                model.tessellate(options, None).map_err(|source| CsgError::Blocks { side, leaf: leaf_no, source })?;
            let sources = t.triangle_sources.iter().map(|&sub_face| FaceSource::Block { leaf: 0, sub_face }).collect();
            (Cow::Owned(t.mesh), sources, true)
        }
        Csg::Mesh(m) => {
            if m.face_count() == 0 {
                return Err(CsgError::EmptyOperand { side, leaf: leaf_no });
            }
            if let Some(vertex) = m.positions().iter().position(|p| !p.is_finite()) {
                return Err(CsgError::NonFinite { side, leaf: leaf_no, vertex });
            }
            // A triangle mesh is used as it is; triangulation carries the sources of an earlier
            // boolean result.
            let (tri, from) = if m.is_triangle_mesh() {
                (Cow::Borrowed(m.as_ref()), None)
            } else {
                let (t, from) = m.triangulate_with_sources().map_err(|source| CsgError::Triangulation {
                    side,
                    leaf: leaf_no,
                    source,
                })?;
                (Cow::Owned(t), Some(from))
            };
            let sources = match (tri.face_sources(), from) {
                (Some(fs), _) => fs.to_vec(),
                (None, Some(from)) => from.iter().map(|&face| FaceSource::Mesh { leaf: 0, face }).collect(),
                (None, None) => (0..tri.face_count() as u32).map(|face| FaceSource::Mesh { leaf: 0, face }).collect(),
            };
            (tri, sources, false)
        }
        Csg::Op(..) => unreachable!("collect_leaves yields leaves only"),
    };
    let leaf_span = sources.iter().filter_map(FaceSource::leaf).max().map_or(1, |m| m + 1);
    let triangles: Vec<[u32; 3]> = (0..mesh.face_count() as u32)
        .map(|f| {
            let mut it = mesh.face_vertices(f);
            [it.next().unwrap_or(0), it.next().unwrap_or(0), it.next().unwrap_or(0)]
        })
        .collect();
    let components = if union_parts { mesh.face_components() } else { vec![(0..triangles.len() as u32).collect()] };
    // An earlier boolean result is the engine's own valid output: where two solids met along
    // an edge it keeps two vertices at one point, which is no self-touching for it.
    let earlier_result = matches!(leaf, Csg::Mesh(m) if m.face_sources().is_some());
    check_solid(&mesh, &triangles, &components, !earlier_result, side, leaf_no)?;
    Ok(Prepared {
        positions: mesh.positions().to_vec(),
        triangles,
        sources,
        creases: mesh.crease_pairs(),
        leaf_span,
        first_leaf_hint: leaf_no,
        components,
    })
}

/// Refuses an input that bounds no solid: open, or touching itself (two vertices of one of its
/// `components` at one point — the engine would see two surfaces there; checked when
/// `check_touching`). Non-finite coordinates are refused earlier, in [`prepare`].
fn check_solid(
    mesh: &Mesh,
    triangles: &[[u32; 3]],
    components: &[Vec<u32>],
    check_touching: bool,
    side: Side,
    leaf: u32,
) -> Result<(), CsgError> {
    if !mesh.is_closed() {
        let boundary_edges = mesh.boundary_loops().iter().map(Vec::len).sum();
        return Err(CsgError::OpenMesh { side, leaf, boundary_edges });
    }
    let key = |v: u32| {
        let p = mesh.position(v);
        [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
    };
    for tris in components.iter().filter(|_| check_touching) {
        let mut order: Vec<u32> = tris.iter().flat_map(|&t| triangles[t as usize]).collect();
        order.sort_unstable();
        order.dedup();
        order.sort_unstable_by_key(|&v| key(v));
        if let Some(w) = order.windows(2).find(|w| key(w[0]) == key(w[1])) {
            let p = mesh.position(w[0]);
            return Err(CsgError::NonManifold {
                side,
                leaf,
                reason: format!(
                    "vertices {} and {} are both at ({}, {}, {}): the surface touches itself there",
                    w[0].min(w[1]),
                    w[0].max(w[1]),
                    p.x,
                    p.y,
                    p.z
                ),
            });
        }
    }
    Ok(())
}
