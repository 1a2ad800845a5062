//! The CSG tree (seed 000 §2.4.2) and its evaluation: leaves are block models (tessellated
//! first, so adaptive tessellation and crease tags come through), meshes, or other trees; inner
//! nodes are union, difference and intersection. Independent subtrees are evaluated in
//! parallel (rayon), and every output face keeps its source ([`FaceSource`]).
//!
//! Evaluation: the leaves are tessellated and checked, each grouped into faces (connected
//! coplanar triangles of one source, see `Prepared`; a mesh leaf that is a translated copy of
//! an earlier one takes its faces, see `Prepared::moved`); then a plan says what goes into the
//! engine together — a chain of unions is one batch union whose leaf pieces (a mesh, or one
//! connected part of a block model) are dealt into groups apart from each other, each group one
//! import. The imports run first, in parallel; in a group, the translated copies of one piece
//! (a pattern: one sphere placed at 21 pips) are imported once and placed by the engine
//! (`import_instances`), as Manifold's lazily transformed leaves share their topology. Then
//! the prepared leaves are dropped and the booleans run, both sides of each in parallel, the
//! root's without the engine's final spatial sort (its result is only exported); last, flat
//! zero-volume shells are dropped, and sources and creases are read back from the face tags.
//! Creases keep their sharpness (semi-sharp ones included; where pieces of several creases
//! cover an output edge, the sharpest at its middle), and an input vertex with a corner
//! sharpness that survives (an output vertex at exactly its position) keeps it.
//!
//! Cost: the leaves are tessellated and checked in O(n log n) for n input triangles (the
//! coincident-vertex check sorts); faces by union–find, O(n α(n)); dealing p pieces into g
//! groups O(p · g · group size) box tests; each boolean is Manifold's, O((n + k) log n) for k
//! intersecting triangle pairs; provenance costs O(1) per output triangle, creases O(s) per
//! output edge between two faces that share s crease segments. Finding translated copies
//! compares each mesh leaf with the first of each kind (linear per comparison, stopping at the
//! first difference); a copy then costs a linear pass instead of its import.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use super::engine::{self, ApartSolid, EngineError, FlatTriangles, PairedTriangles, Solid, Stop};
use super::shells::vertex_shells;
use super::{CsgError, CsgOp, Side};
use crate::blocks::{BlockError, BlockModel, MeshOptions};
use crate::limits::{check_memory, CancelToken, LimitError, StopReason};
use crate::math::{translation_between, Aabb, IdMap, Vec3};
use crate::mesh::{FacePart, FaceSource, Mesh, MeshError};

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
    /// [`FaceSource`]s and whose edges keep the crease sharpness of the inputs' edges they lie
    /// on; surviving input corners keep their corner sharpness.
    /// An empty result (e.g. `a − a`) is a mesh without faces.
    ///
    /// # Errors
    /// [`CsgError`] naming the operand: an open, empty or self-touching input, one with a
    /// non-finite coordinate, a block model that cannot be meshed.
    pub fn evaluate(&self) -> Result<Mesh, CsgError> {
        // On a worker of the thread pool: the parallel steps inside then share work with the
        // other workers directly, rather than each handing a job from this thread to the pool
        // and sleeping until it is done.
        // The pool's workers have no current cancellation token: hand them the caller's. The
        // engine's own stop flag follows it while the booleans run.
        let token = crate::limits::current();
        rayon::scope(|_| {
            let _current = crate::limits::install(token.clone());
            engine::watching(&token, |stop| self.evaluate_here(&token, stop))
        })
    }

    /// [`Csg::evaluate`] on the calling thread, checking `token` between its steps; `stop`
    /// (set when `token` stops) ends the engine's booleans early.
    fn evaluate_here(&self, token: &CancelToken, stop: &Stop) -> Result<Mesh, CsgError> {
        let mut leaves = Vec::new();
        collect_leaves(self, Side::Left, &mut leaves);
        // Mesh leaves that are translated copies of an earlier one (a pattern of one part) take
        // its preparation, moved ([`Prepared::moved`]).
        let copy_of = translated_copies(&leaves);
        let mut prepared: Vec<Option<Prepared>> = leaves
            .par_iter()
            .enumerate()
            .map(|(k, (leaf, side))| {
                if copy_of[k].is_some() {
                    return Ok(None);
                }
                // The workers' block tessellation and checks charge the caller's token.
                let _current = crate::limits::install(token.clone());
                prepare(leaf, *side, k as u32).map(Some)
            })
            .collect::<Result<_, _>>()?;
        // Each first with copies: its vertices in the order of their x coordinates, for the
        // copies' check ([`Prepared::moved`]).
        let mut firsts: Vec<usize> = copy_of.iter().flatten().copied().collect();
        firsts.sort_unstable();
        firsts.dedup();
        let by_x: HashMap<usize, Vec<u32>> = firsts
            .par_iter()
            .filter_map(|&f| match leaves[f].0 {
                Csg::Mesh(m) => {
                    let _current = crate::limits::install(token.clone());
                    Some(order_by_x(m.positions()).map(|order| (f, order)))
                }
                _ => None,
            })
            .collect::<Result<_, _>>()?;
        let moved: Vec<(usize, Prepared)> = copy_of
            .par_iter()
            .enumerate()
            .filter_map(|(k, first)| Some((k, (*first)?)))
            .filter_map(|(k, first)| match (leaves[k], &prepared[first], by_x.get(&first)) {
                ((Csg::Mesh(m), side), Some(p), Some(by_x)) => {
                    let _current = crate::limits::install(token.clone());
                    Some(p.moved(m, side, k as u32, by_x).map(|p| (k, p)))
                }
                _ => None,
            })
            .collect::<Result<_, _>>()?;
        for (k, p) in moved {
            prepared[k] = Some(p);
        }
        let prepared: Vec<Prepared> = prepared.into_iter().flatten().collect();
        if prepared.len() != leaves.len() {
            return Err(CsgError::Engine { reason: "a leaf's preparation is missing".into() });
        }
        // Leaf numbers and the global face tags: leaf k's faces (coplanar groups, see
        // `Prepared::faces`) are tagged from offsets[k], its leaf ids start at first_leaf[k].
        let total: usize = prepared.iter().map(|p| p.triangles.len()).sum();
        if total >= i32::MAX as usize {
            return Err(CsgError::TooLarge { triangles: total });
        }
        check_memory(|| format!("a boolean of {total} triangles"), total as f64 * ENGINE_BYTES_PER_TRIANGLE)?;
        let mut offsets = Vec::with_capacity(prepared.len());
        // Face parts (colours, origins): the leaves' tables joined, and the joined part of every
        // face tag (a leaf without parts gets one default part).
        let any_parts = prepared.iter().any(|p| !p.parts.is_empty());
        let (mut part_table, mut tag_parts) = (Vec::new(), Vec::new());
        let mut first_leaf = 0u32;
        let mut tag = 0u32;
        let mut sources = Vec::new();
        let mut creases: HashMap<[u32; 2], Vec<([Vec3; 2], f64)>> = HashMap::new();
        let mut corners: HashMap<[u64; 3], f64> = HashMap::new();
        for p in &prepared {
            offsets.push(tag);
            sources.extend(p.face_sources.iter().map(|s| s.shifted(first_leaf)));
            for &(f, g, seg, s) in &p.creases {
                creases.entry(edge_key(f + tag, g + tag)).or_default().push((seg, s));
            }
            for &(x, s) in &p.corners {
                let c = corners.entry(x.to_array().map(f64::to_bits)).or_insert(0.0);
                *c = c.max(s);
            }
            tag += p.face_sources.len() as u32;
            first_leaf += p.leaf_span;
            if any_parts {
                let base = part_table.len() as u32;
                if p.parts.is_empty() {
                    part_table.push(FacePart::default());
                    tag_parts.extend(std::iter::repeat_n(base, p.face_sources.len()));
                } else {
                    part_table.extend_from_slice(&p.parts);
                    tag_parts.extend(p.group_parts.iter().map(|&g| base + g));
                }
            }
        }
        // The import plan: which pieces (a mesh leaf, or one connected part of a block model)
        // go into the engine together, with engine ids reserved in plan order so the same tree
        // gives the same mesh whatever order the parallel imports finish in.
        let bounds: Vec<Vec<Aabb>> = prepared.par_iter().map(Prepared::component_bounds).collect();
        let mut leaf_no = 0usize;
        let plan = plan(self, &bounds, &mut leaf_no);
        // Every import first, all in parallel; then the leaves' prepared arrays go, before the
        // booleans (in the stress case of kernel/benches/csg.rs, about 90 MB: the positions,
        // triangles, faces and pairing of 1,000 spheres).
        let mut groups = Vec::new();
        plan.import_groups(&mut groups);
        let inputs = Inputs { prepared: &prepared, bounds: &bounds, leaves: &leaves, offsets: &offsets, token, stop };
        let imported: Vec<Solid> =
            groups.par_iter().map(|&(pieces, id)| import_group(pieces, id, &inputs)).collect::<Result<_, _>>()?;
        drop(prepared);
        let imported = Imported {
            slot_of: groups.iter().enumerate().map(|(k, &(_, id))| (id, k)).collect(),
            solids: imported.into_iter().map(|s| Mutex::new(Some(s))).collect(),
            token,
            stop,
        };
        let solid = run(&plan, &imported, true)?;
        drop(imported);
        token.charge(solid_size(&solid))?;
        // The result's half-edge mesh from the engine's own pairing of its half-edges: one
        // linear pass, no search for twins.
        let PairedTriangles { positions, corners: triangles, pairs, tags } =
            without_flat_shells(solid.paired_triangles());
        drop(solid);
        token.charge(tags.len() as u64)?;
        let mut mesh = Mesh::from_paired_triangles(positions, triangles, pairs)
            .map_err(|e| CsgError::Engine { reason: e.to_string() })?;
        let face_sources: Vec<FaceSource> =
            tags.iter().map(|&t| sources.get(t as usize).copied().unwrap_or(FaceSource::Unknown)).collect();
        // An output edge between two input faces is a crease when it lies along a crease those
        // two faces shared.
        if !creases.is_empty() {
            let tol = 1e-9 * mesh.bounds().size().max_element().max(f64::MIN_POSITIVE);
            let tagged: Vec<(u32, f64)> = mesh
                .edges()
                .filter_map(|h| {
                    let (f, g) = (mesh.face(h), mesh.face(mesh.twin(h)));
                    let (tf, tg) = (tags[f as usize], tags[g as usize]);
                    let segments = (tf != tg).then(|| creases.get(&edge_key(tf, tg))).flatten()?;
                    let (p, q) = (mesh.position(mesh.origin(h)), mesh.position(mesh.target(h)));
                    let on = |x: Vec3| segments.iter().any(|&([a, b], _)| on_segment(x, a, b, tol));
                    if !(on(p) && on(q)) {
                        return None;
                    }
                    let m = (p + q) * 0.5;
                    segments
                        .iter()
                        .filter(|&&([a, b], _)| on_segment(m, a, b, tol))
                        .map(|&(_, s)| s)
                        .reduce(f64::max)
                        .map(|s| (h, s))
                })
                .collect();
            for (h, s) in tagged {
                mesh.set_edge_sharpness_halfedge(h, s);
            }
            token.charge(mesh.edge_count() as u64)?;
        }
        if !corners.is_empty() {
            for v in 0..mesh.vertex_count() as u32 {
                if let Some(&s) = corners.get(&mesh.position(v).to_array().map(f64::to_bits)) {
                    mesh.set_corner_sharpness(v, s);
                }
            }
        }
        mesh.set_face_sources(Some(face_sources)).map_err(|e| CsgError::Engine { reason: e.to_string() })?;
        if any_parts {
            let ids = tags.iter().map(|&t| tag_parts.get(t as usize).copied().unwrap_or(0)).collect();
            mesh.set_face_parts(ids, part_table).map_err(|e| CsgError::Engine { reason: e.to_string() })?;
        }
        Ok(mesh)
    }
}

/// The boolean engine's memory per input triangle (its half-edges, normals, collider and the
/// intersection's intermediate arrays), for the budget check before importing.
const ENGINE_BYTES_PER_TRIANGLE: f64 = 1024.0;

/// No vertex yet (in [`run`]'s renumbering).
const NONE: u32 = u32::MAX;

/// Shells thinner than this fraction of the result's size (volume / area) are flat.
const FLAT_SHELL: f64 = 1e-9;

/// Triangles per run of [`without_flat_shells`]'s parallel sums.
const SHELL_SUM_RUN: usize = 16_384;

/// The engine's triangles without their flat shells: Manifold resolves solids that only touch
/// (two boxes meeting face to face, intersected) with symbolic perturbation and may leave a
/// closed shell of no volume there — two coincident sheets facing apart. CSG is regularised
/// (the closure of the interior, as CGAL's Nef polyhedra and OpenSCAD give): such a shell
/// bounds nothing and is dropped, its triangles' pairs renumbered (a shell is closed: no pair
/// leaves it). A shell counts as flat when its volume over its area is below [`FLAT_SHELL`] of
/// the result's largest extent.
fn without_flat_shells(t: PairedTriangles) -> PairedTriangles {
    let n = t.positions.len();
    // Each vertex's shell, named by its smallest vertex ([`vertex_shells`], on all threads).
    let shell = vertex_shells(n, &t.corners);
    let size = Aabb::from_points(&t.positions).size().max_element();
    // Each shell's volume and area: runs of triangles summed in parallel, each into its own
    // table (shells in order of first triangle), then the runs' sums added in run order — the
    // same sums whatever the number of threads.
    let runs: Vec<Vec<(u32, f64, f64)>> = t
        .corners
        .par_chunks(3 * SHELL_SUM_RUN)
        .map(|run| {
            let mut sums: Vec<(u32, f64, f64)> = Vec::new();
            let mut slot: IdMap<u32, usize> = IdMap::default();
            for tri in run.chunks_exact(3) {
                let r = shell[tri[0] as usize];
                let [a, b, c] = [0, 1, 2].map(|i| t.positions[tri[i] as usize]);
                // Relative to the shell's root vertex, so a far-off shell's volume keeps its digits.
                let o = t.positions[r as usize];
                let volume = (a - o).dot((b - o).cross(c - o)) / 6.0;
                let area = (b - a).cross(c - a).length() / 2.0;
                let k = match sums.last() {
                    Some(&(last, _, _)) if last == r => sums.len() - 1,
                    _ => *slot.entry(r).or_insert_with(|| {
                        sums.push((r, 0.0, 0.0));
                        sums.len() - 1
                    }),
                };
                sums[k].1 += volume;
                sums[k].2 += area;
            }
            sums
        })
        .collect();
    let mut volume = vec![0.0; n];
    let mut area = vec![0.0; n];
    for &(r, v, a) in runs.iter().flatten() {
        volume[r as usize] += v;
        area[r as usize] += a;
    }
    let flat = |r: u32| volume[r as usize].abs() <= FLAT_SHELL * size * area[r as usize];
    if !runs.iter().flatten().any(|&(r, _, _)| flat(r)) {
        return t;
    }
    let roots: Vec<u32> = t.corners.chunks_exact(3).map(|tri| shell[tri[0] as usize]).collect();
    // Each kept triangle's new number.
    let mut renumber = vec![u32::MAX; roots.len()];
    let mut kept = 0u32;
    for (new, &r) in renumber.iter_mut().zip(&roots) {
        if !flat(r) {
            *new = kept;
            kept += 1;
        }
    }
    let mut map = vec![u32::MAX; n];
    let mut out = PairedTriangles {
        positions: Vec::new(),
        corners: Vec::with_capacity(3 * kept as usize),
        pairs: Vec::with_capacity(3 * kept as usize),
        tags: Vec::with_capacity(kept as usize),
    };
    for (f, &new) in renumber.iter().enumerate() {
        if new == u32::MAX {
            continue;
        }
        out.tags.push(t.tags[f]);
        for i in 3 * f..3 * f + 3 {
            // Renumber the vertices still used, in order of first use.
            let v = t.corners[i] as usize;
            if map[v] == u32::MAX {
                map[v] = out.positions.len() as u32;
                out.positions.push(t.positions[v]);
            }
            out.corners.push(map[v]);
            // (A pair outside the kept triangles, which a closed shell never has, stays
            // unpaired: the mesh build refuses it rather than panic.)
            let p = t.pairs[i];
            out.pairs.push(match renumber.get(p as usize / 3) {
                Some(&n) if n != u32::MAX => 3 * n + p % 3,
                _ => u32::MAX,
            });
        }
    }
    out
}

/// The root of `x` in the union–find forest `parent` (path halving on the way).
fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

fn edge_key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

/// Whether `x` lies on the segment `a b`, within `tol`.
fn on_segment(x: Vec3, a: Vec3, b: Vec3, tol: f64) -> bool {
    let d = b - a;
    let len2 = d.length_squared();
    if len2 == 0.0 {
        return x.distance(a) <= tol;
    }
    let t = ((x - a).dot(d) / len2).clamp(0.0, 1.0);
    x.distance(a + d * t) <= tol
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

/// How a tree is carried out in the engine.
enum Plan {
    /// One engine import of these pieces, `(leaf, component)`, whose bounds are pairwise apart:
    /// side by side they are already their union, so the engine composes nothing.
    Import { pieces: Vec<(usize, usize)>, id: u32 },
    /// The union of all (Manifold's batch union).
    Union(Vec<Plan>),
    /// Any other boolean; both sides run in parallel.
    Op(CsgOp, Box<Plan>, Box<Plan>),
}

/// The plan of `node`, whose leaves are numbered from `*next` (left to right). A chain of
/// unions becomes one batch union whose leaf pieces are dealt into groups apart from each
/// other, each group one import: Manifold would otherwise import every piece and then compose
/// the disjoint ones, which costs as much again as importing them.
fn plan(node: &Csg, bounds: &[Vec<Aabb>], next: &mut usize) -> Plan {
    match node {
        Csg::Op(CsgOp::Union, ..) => {
            let mut operands = Vec::new();
            union_operands(node, &mut operands);
            let mut pieces = Vec::new();
            let mut subtrees = Vec::new();
            for o in operands {
                if let Csg::Op(..) = o {
                    subtrees.push(plan(o, bounds, next));
                } else {
                    pieces.extend((0..bounds[*next].len()).map(|c| (*next, c)));
                    *next += 1;
                }
            }
            let mut parts = imports(pieces, bounds);
            parts.extend(subtrees);
            if parts.len() == 1 {
                parts.pop().unwrap_or(Plan::Union(Vec::new()))
            } else {
                Plan::Union(parts)
            }
        }
        Csg::Op(op, a, b) => {
            let a = plan(a, bounds, next);
            let b = plan(b, bounds, next);
            Plan::Op(*op, Box::new(a), Box::new(b))
        }
        _ => {
            let k = *next;
            *next += 1;
            let mut parts = imports((0..bounds[k].len()).map(|c| (k, c)).collect(), bounds);
            if parts.len() == 1 {
                parts.pop().unwrap_or(Plan::Union(Vec::new()))
            } else {
                Plan::Union(parts)
            }
        }
    }
}

/// Deals `pieces` into groups whose members' bounds are pairwise apart, in order (each piece
/// joins the first group it is apart from), one import each.
fn imports(pieces: Vec<(usize, usize)>, bounds: &[Vec<Aabb>]) -> Vec<Plan> {
    let mut groups: Vec<Vec<(usize, usize)>> = Vec::new();
    for p in pieces {
        let b = bounds[p.0][p.1];
        match groups.iter_mut().find(|g| g.iter().all(|q| b.is_apart(&bounds[q.0][q.1]))) {
            Some(g) => g.push(p),
            None => groups.push(vec![p]),
        }
    }
    groups.into_iter().map(|pieces| Plan::Import { pieces, id: Solid::reserve_ids(1) }).collect()
}

/// Appends the half-edge pairing of component `c` of `p` to `pairs`, numbered as the import
/// numbers the component's triangles (in component order, after those already in `pairs`);
/// `false` when a half-edge's pair lies outside the component (never for a closed one).
/// `place` is scratch space, left ready for the next piece.
fn pair_piece(p: &Prepared, c: usize, place: &mut Vec<u32>, pairs: &mut Vec<u32>) -> bool {
    if place.len() < p.triangles.len() {
        place.resize(p.triangles.len(), NONE);
    }
    let first = (pairs.len() / 3) as u32;
    let component = &p.components[c];
    for (i, &t) in component.iter().enumerate() {
        place[t as usize] = first + i as u32;
    }
    let mut whole = true;
    for &t in component {
        for &q in &p.pairs[3 * t as usize..3 * t as usize + 3] {
            let at = place[(q / 3) as usize];
            whole &= at != NONE;
            pairs.push(if at == NONE { NONE } else { 3 * at + q % 3 });
        }
    }
    for &t in component {
        place[t as usize] = NONE;
    }
    whole
}

/// What the imports ([`import_group`]) read: the prepared leaves with the bounds of each one's
/// components (the plan's), the leaves themselves with their sides, each leaf's first face tag,
/// and the caller's token with the engine's stop flag.
struct Inputs<'a> {
    prepared: &'a [Prepared],
    bounds: &'a [Vec<Aabb>],
    leaves: &'a [(&'a Csg, Side)],
    offsets: &'a [u32],
    token: &'a CancelToken,
    stop: &'a Stop,
}

/// The engine's error as a [`CsgError`]: stopped by `token`, whose reason is read again (a
/// deadline or count, once passed, stays passed; an interrupt flag is never cleared by the
/// kernel), or failed.
fn engine_error(token: &CancelToken, e: EngineError) -> CsgError {
    match e {
        EngineError::Stopped => {
            CsgError::Limit(LimitError::Stopped(token.stopped().unwrap_or(StopReason::Interrupted)))
        }
        EngineError::Failed(reason) => CsgError::Engine { reason },
    }
}

/// What [`run`] reads: the plan's imports, done ([`Plan::import_groups`]), each taken by the
/// boolean that uses it (by its engine id), and the caller's token with the engine's stop flag.
struct Imported<'a> {
    slot_of: HashMap<u32, usize>,
    solids: Vec<Mutex<Option<Solid>>>,
    token: &'a CancelToken,
    stop: &'a Stop,
}

impl Plan {
    /// The imports of the plan, left to right: their pieces and engine ids.
    fn import_groups<'a>(&'a self, out: &mut Vec<(&'a [(usize, usize)], u32)>) {
        match self {
            Plan::Import { pieces, id } => out.push((pieces, *id)),
            Plan::Union(parts) => parts.iter().for_each(|p| p.import_groups(out)),
            Plan::Op(_, a, b) => {
                a.import_groups(out);
                b.import_groups(out);
            }
        }
    }
}

/// Carries out `plan`: imports in parallel, both sides of every boolean in parallel. The
/// result is for export only when `for_export` (the root's boolean skips the engine's spatial
/// sort, see [`Solid::into_boolean_for_export_until`]).
fn run(plan: &Plan, inputs: &Imported<'_>, for_export: bool) -> Result<Solid, CsgError> {
    if let Some(reason) = inputs.token.stopped() {
        return Err(LimitError::Stopped(reason).into());
    }
    let engine_error = |e| engine_error(inputs.token, e);
    match plan {
        Plan::Import { id, .. } => inputs
            .slot_of
            .get(id)
            .and_then(|&k| inputs.solids[k].lock().ok()?.take())
            .ok_or_else(|| CsgError::Engine { reason: format!("import {id} is missing or used twice") }),
        Plan::Union(parts) => {
            let solids: Vec<Solid> = parts.par_iter().map(|p| run(p, inputs, false)).collect::<Result<_, _>>()?;
            check_precision(&solids.iter().collect::<Vec<_>>())?;
            inputs.token.charge(solids.iter().map(solid_size).sum())?;
            Solid::union_all_until(solids, inputs.stop).map_err(engine_error)
        }
        Plan::Op(op, a, b) => {
            let (ra, rb) = rayon::join(|| run(a, inputs, false), || run(b, inputs, false));
            let (ra, rb) = (ra?, rb?);
            check_precision(&[&ra, &rb])?;
            inputs.token.charge(solid_size(&ra) + solid_size(&rb))?;
            let result = if for_export {
                ra.into_boolean_for_export_until(rb, *op, inputs.stop)
            } else {
                ra.into_boolean_until(rb, *op, inputs.stop)
            };
            result.map_err(engine_error)
        }
    }
}

/// Imports one group of pieces (see [`Plan::Import`]). Pieces that are translated copies of
/// another piece of the group (an instanced pattern: one sphere placed at 21 pips) are imported
/// once and copied ([`import_instances`]); the others, or all when that does not apply, in one
/// import ([`import_flat`]).
fn import_group(pieces: &[(usize, usize)], id: u32, inputs: &Inputs<'_>) -> Result<Solid, CsgError> {
    if pieces.len() > 1 {
        if let Some(solid) = import_instances(pieces, id, inputs)? {
            return Ok(solid);
        }
    }
    import_flat(pieces, id, 0.0, inputs)
}

/// [`import_group`] by classes of translated copies: each class's first piece is imported (the
/// pieces of no class together, in parallel with them), at the epsilon of the whole group so
/// the clean-up is the one a single import would run; each copy takes its first piece's
/// engine form with its own vertex positions, found through the positions' correspondence (a
/// closed input never has two vertices at one point, see [`check_solid`]); and the parts are
/// put side by side (engine patch 16).
///
/// `Ok(None)` when no two pieces are copies, or a condition of the copy does not hold (the
/// import merged a vertex; the engine refuses the composition): the caller imports as one.
fn import_instances(pieces: &[(usize, usize)], id: u32, inputs: &Inputs<'_>) -> Result<Option<Solid>, CsgError> {
    let prepared = inputs.prepared;
    // Each piece's bounds, the whole group's, and the engine's epsilon for them.
    let piece_bounds: Vec<Aabb> = pieces.iter().map(|&(k, c)| inputs.bounds[k][c]).collect();
    let bounds = piece_bounds.iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
    let (span, magnitude) = box_span_and_magnitude(bounds);
    let epsilon = ENGINE_PRECISION * magnitude;
    let classes = instance_classes(pieces, prepared, epsilon);
    if classes.is_empty() {
        return Ok(None);
    }
    if span > 0.0 && span < MIN_SPAN_RESOLUTIONS * epsilon {
        return Err(CsgError::Precision { side: inputs.leaves[pieces[0].0].1, span, magnitude });
    }
    let mut in_class = vec![false; pieces.len()];
    classes.iter().flatten().for_each(|&i| in_class[i] = true);
    let rest: Vec<(usize, usize)> = pieces.iter().zip(&in_class).filter(|(_, &c)| !c).map(|(&p, _)| p).collect();
    let mut jobs: Vec<Vec<(usize, usize)>> = classes.iter().map(|c| vec![pieces[c[0]]]).collect();
    // The other pieces in one import when their bounds together stay apart from every copy's
    // (the parts of the composition must be), else one import each.
    let rest_bounds = (0..pieces.len()).filter(|&i| !in_class[i]).fold(Aabb::EMPTY, |a, i| a.union(piece_bounds[i]));
    let rest_apart = classes.iter().flatten().all(|&i| piece_bounds[i].is_apart(&rest_bounds));
    if rest_apart && !rest.is_empty() {
        jobs.push(rest);
    } else {
        jobs.extend(rest.into_iter().map(|p| vec![p]));
    }
    let solids: Vec<Solid> =
        jobs.par_iter().map(|job| import_flat(job, id, epsilon, inputs)).collect::<Result<_, _>>()?;
    // Each class's first piece, then its copies: their own positions, read in the engine's
    // vertex order of the first piece.
    let mut orders = Vec::with_capacity(classes.len());
    for (class, first) in classes.iter().zip(&solids) {
        let p0 = &prepared[pieces[class[0]].0];
        let Some(order) = engine_vertex_order(p0, first) else { return Ok(None) };
        inputs.token.charge((p0.triangles.len() * (class.len() - 1)) as u64)?;
        orders.push(order);
    }
    let mut parts = Vec::with_capacity(pieces.len());
    for ((class, first), order) in classes.iter().zip(&solids).zip(&orders) {
        let k0 = pieces[class[0]].0;
        parts.push(ApartSolid { solid: first, moved_to: None, tag_shift: 0 });
        parts.extend(class[1..].iter().map(|&i| {
            let k = pieces[i].0;
            ApartSolid {
                solid: first,
                moved_to: Some((&prepared[k].positions, order)),
                tag_shift: inputs.offsets[k] as i32 - inputs.offsets[k0] as i32,
            }
        }));
    }
    parts.extend(solids[classes.len()..].iter().map(|solid| ApartSolid { solid, moved_to: None, tag_shift: 0 }));
    Ok(Solid::compose_apart(&parts))
}

/// The pieces of a group that are whole mesh leaves (one component, with a half-edge pairing),
/// dealt into classes of translated copies, as indices into `pieces`: each class starts with
/// its first member, whose triangles, pairing and faces the others repeat exactly, with
/// positions that are its own moved by one vector within `epsilon`. Only classes of two or more.
fn instance_classes(pieces: &[(usize, usize)], prepared: &[Prepared], epsilon: f64) -> Vec<Vec<usize>> {
    let mut classes: Vec<Vec<usize>> = Vec::new();
    for (i, &(k, _)) in pieces.iter().enumerate() {
        let p = &prepared[k];
        if p.components.len() != 1 || p.pairs.is_empty() {
            continue;
        }
        match classes.iter_mut().find(|class| is_translated_copy(&prepared[pieces[class[0]].0], p, epsilon)) {
            Some(class) => class.push(i),
            None => classes.push(vec![i]),
        }
    }
    classes.retain(|c| c.len() > 1);
    classes
}

/// Whether `b` is `a` moved by one vector (within `epsilon` per coordinate): the same triangles,
/// half-edge pairing and faces.
fn is_translated_copy(a: &Prepared, b: &Prepared, epsilon: f64) -> bool {
    // Shared when one was prepared as the other moved: equal without a look.
    fn same<T: PartialEq>(a: &Arc<Vec<T>>, b: &Arc<Vec<T>>) -> bool {
        Arc::ptr_eq(a, b) || a == b
    }
    a.positions.len() == b.positions.len()
        && same(&a.triangles, &b.triangles)
        && same(&a.pairs, &b.pairs)
        && same(&a.faces, &b.faces)
        && translation_between(&a.positions, &b.positions, epsilon).is_some()
}

/// For each vertex of `solid` (the engine's import of the whole of `p`), in the engine's order,
/// the vertex of `p` at its position; `None` when the import did not keep `p`'s vertices one
/// for one (it merged or dropped some).
fn engine_vertex_order(p: &Prepared, solid: &Solid) -> Option<Vec<u32>> {
    let key = |x: Vec3| x.to_array().map(f64::to_bits);
    let mut at: IdMap<[u64; 3], u32> = IdMap::with_capacity_and_hasher(p.positions.len(), Default::default());
    for &v in p.triangles.iter().flatten() {
        at.insert(key(p.positions[v as usize]), v);
    }
    let positions = solid.vertex_positions();
    if positions.len() != at.len() {
        return None;
    }
    positions.iter().map(|&x| at.get(&key(x)).copied()).collect()
}

/// One engine import of `pieces` (each piece brings the vertices its triangles use, numbered in
/// order of first use, written straight into the arrays the engine reads), cleaned up at
/// `tolerance` when above the engine's automatic epsilon ([`FlatTriangles::tolerance`]).
fn import_flat(pieces: &[(usize, usize)], id: u32, tolerance: f64, inputs: &Inputs<'_>) -> Result<Solid, CsgError> {
    let Inputs { prepared, leaves, offsets, token, stop, .. } = *inputs;
    let n: usize = pieces.iter().map(|&(k, c)| prepared[k].components[c].len()).sum();
    let mut flat = FlatTriangles {
        coordinates: Vec::with_capacity(3 * (n / 2 + 2)),
        corners: Vec::with_capacity(3 * n),
        tags: Vec::with_capacity(n),
        pairs: Vec::with_capacity(3 * n),
        tolerance,
    };
    // A piece's triangle -> its number in the import, for the half-edge pairing.
    let mut place: Vec<u32> = Vec::new();
    let mut paired = pieces.iter().all(|&(k, _)| !prepared[k].pairs.is_empty());
    // A piece's vertex -> its number in the import (`NONE` when not yet used), and
    // the piece's vertices, to clear the map for the next piece.
    let mut number: Vec<u32> = Vec::new();
    let mut used: Vec<u32> = Vec::new();
    for &(k, c) in pieces {
        let p = &prepared[k];
        if number.len() < p.positions.len() {
            number.resize(p.positions.len(), NONE);
        }
        for (i, &t) in p.components[c].iter().enumerate() {
            // This runs on any worker of the pool: read the token itself.
            if i.is_multiple_of(crate::limits::POLL_EVERY) {
                if let Some(reason) = token.stopped() {
                    return Err(LimitError::Stopped(reason).into());
                }
            }
            for v in p.triangles[t as usize] {
                let slot = &mut number[v as usize];
                if *slot == NONE {
                    *slot = (flat.coordinates.len() / 3) as u32;
                    flat.coordinates.extend_from_slice(&p.positions[v as usize].to_array());
                    used.push(v);
                }
                flat.corners.push(*slot);
            }
            flat.tags.push(offsets[k] + p.faces[t as usize]);
        }
        for v in used.drain(..) {
            number[v as usize] = NONE;
        }
        if paired {
            paired = pair_piece(p, c, &mut place, &mut flat.pairs);
        }
    }
    if !paired {
        flat.pairs = Vec::new();
    }
    let triangles = flat.tags.len();
    token.charge(triangles as u64)?;
    // An operand too small for the precision where it lies is merged away by the
    // engine's import itself (a unit box at 1e12 became empty, and a union of two of
    // them 0 faces): refused before, as the boolean's own check would refuse it.
    let side = leaves[pieces[0].0].1;
    let (span, magnitude) = span_and_magnitude(&flat.coordinates);
    if span > 0.0 && span < MIN_SPAN_RESOLUTIONS * (ENGINE_PRECISION * magnitude).max(tolerance) {
        return Err(CsgError::Precision { side, span, magnitude });
    }
    let solid = Solid::from_flat_until(flat, id, stop).map_err(|e| match e {
        EngineError::Stopped => engine_error(token, e),
        EngineError::Failed(reason) => {
            let (k, _) = pieces[0];
            CsgError::NonManifold {
                side: leaves[k].1,
                leaf: prepared[k].first_leaf_hint,
                reason: format!("the boolean engine refuses it ({reason})"),
            }
        }
    })?;
    // Never an empty operand from a solid one: whatever merged it away was precision.
    if solid.is_empty() && triangles > 0 && span > 0.0 {
        return Err(CsgError::Precision { side, span, magnitude });
    }
    Ok(solid)
}

/// A solid's work units for the operation count: its triangles.
fn solid_size(s: &Solid) -> u64 {
    s.triangle_count() as u64
}

/// The engine resolves [`ENGINE_PRECISION`] of the operands' largest coordinate (Manifold's
/// `kPrecision`); closer points are merged.
pub const ENGINE_PRECISION: f64 = 1e-12;

/// How many times the engine's resolution an operand must span in every direction: smaller
/// operands are merged away (two boxes 2 across at 1e12 from the origin united into 5.3 of
/// volume, their difference emptied).
pub const MIN_SPAN_RESOLUTIONS: f64 = 100.0;

/// The smallest extent of the bounding box of the points whose x, y, z follow one another in
/// `coordinates`, and their largest coordinate in absolute value (0 and 0 for none).
fn span_and_magnitude(coordinates: &[f64]) -> (f64, f64) {
    let mut points = coordinates.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2]));
    let Some(first) = points.next() else { return (0.0, 0.0) };
    box_span_and_magnitude(points.fold(Aabb { min: first, max: first }, Aabb::grow))
}

/// The smallest extent of the box `b` and its largest coordinate in absolute value.
fn box_span_and_magnitude(b: Aabb) -> (f64, f64) {
    ((b.max - b.min).min_element(), b.min.abs().max(b.max.abs()).max_element())
}

/// Refuses a boolean whose operands are too small for the precision at their distance from the
/// origin, rather than return a wrong result. The first operand is the left one.
fn check_precision(operands: &[&Solid]) -> Result<(), CsgError> {
    let bounds: Vec<(Vec3, Vec3)> = operands.iter().filter(|s| !s.is_empty()).map(|s| s.bounds()).collect();
    if bounds.len() < 2 {
        return Ok(());
    }
    let magnitude = bounds.iter().map(|(lo, hi)| lo.abs().max(hi.abs()).max_element()).fold(0.0, f64::max);
    let resolution = ENGINE_PRECISION * magnitude;
    for (i, (lo, hi)) in bounds.iter().enumerate() {
        // A flat operand (span 0, as an intermediate boolean can leave) has no volume to lose.
        let span = (*hi - *lo).min_element();
        if span > 0.0 && span < MIN_SPAN_RESOLUTIONS * resolution {
            let side = if i == 0 { Side::Left } else { Side::Right };
            return Err(CsgError::Precision { side, span, magnitude });
        }
    }
    Ok(())
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

/// One leaf as indexed triangles grouped into faces, with a source per face (leaf ids from 0).
///
/// A face is a connected set of coplanar triangles of one source, bounded by crease edges,
/// source changes and bends: the engine gets one face id per face, which lets it merge the
/// face's triangles in its result as Manifold does for its own faces (about half the triangles
/// on flat faces, and faster booleans), while every output triangle still names its source.
///
/// A translated copy ([`Prepared::moved`]) shares its first's triangles, faces, sources, parts,
/// components and pairing (`Arc`); its positions, creases and corners are its own.
struct Prepared {
    positions: Vec<Vec3>,
    triangles: Arc<Vec<[u32; 3]>>,
    /// The face of each triangle, numbered from 0 in order of first triangle.
    faces: Arc<Vec<u32>>,
    /// The source of each face.
    face_sources: Arc<Vec<FaceSource>>,
    /// The part (colour, origin) of each face, indexing `parts`; both empty when the input has
    /// no parts. Looked up by face tag rather than through the sources, which name the leaves of
    /// an earlier boolean rather than this input's faces.
    group_parts: Arc<Vec<u32>>,
    parts: Arc<Vec<FacePart>>,
    /// Crease edges: the faces on their two sides, the segment and its sharpness.
    creases: Vec<(u32, u32, [Vec3; 2], f64)>,
    /// Vertices with a corner sharpness: position and sharpness.
    corners: Vec<(Vec3, f64)>,
    /// How many leaf ids the input occupies (more than one for an earlier boolean result).
    leaf_span: u32,
    /// The leaf number used in errors raised after preparation.
    first_leaf_hint: u32,
    /// The triangles of each solid to union (one for a mesh; one per connected component for
    /// a block model).
    components: Arc<Vec<Vec<u32>>>,
    /// The half-edge pairing of `triangles` as the engine numbers half-edges (`pairs[3t + i]`
    /// opposite the edge from corner `i` to `i + 1` of triangle `t`), from the mesh's twins.
    pairs: Arc<Vec<u32>>,
}

impl Prepared {
    /// The preparation of `mesh`, leaf `leaf_no`, a translated copy of the mesh this one was
    /// prepared from (see [`translated_copies`]): its faces, sources, parts, pairing and
    /// components are this one's; its positions, creases and corners its own, and it is checked
    /// as [`prepare`] checks a leaf (closed, not touching itself). What `prepare` would give,
    /// without grouping faces again. `by_x`: the first's vertices in the order of their x
    /// coordinates ([`order_by_x`]), along which a copy's positions are seen to be apart in one
    /// pass ([`apart_along`]); only when that walk cannot tell is each position looked up.
    fn moved(&self, mesh: &Mesh, side: Side, leaf_no: u32, by_x: &[u32]) -> Result<Prepared, CsgError> {
        crate::limits::charge(self.triangles.len() as u64)?;
        let earlier_result = mesh.face_sources().is_some();
        let check_touching = !earlier_result && !apart_along(mesh.positions(), by_x)?;
        check_solid(mesh, &self.triangles, &self.components, check_touching, side, leaf_no)?;
        Ok(Prepared {
            positions: mesh.positions().to_vec(),
            triangles: Arc::clone(&self.triangles),
            faces: Arc::clone(&self.faces),
            face_sources: Arc::clone(&self.face_sources),
            group_parts: Arc::clone(&self.group_parts),
            parts: Arc::clone(&self.parts),
            creases: crease_segments(mesh, &self.faces),
            corners: corner_list(mesh),
            leaf_span: self.leaf_span,
            first_leaf_hint: leaf_no,
            components: Arc::clone(&self.components),
            pairs: Arc::clone(&self.pairs),
        })
    }

    /// The bounds of each component.
    fn component_bounds(&self) -> Vec<Aabb> {
        self.components
            .iter()
            .map(|tris| {
                tris.iter()
                    .flat_map(|&t| self.triangles[t as usize])
                    .fold(Aabb::EMPTY, |b, v| b.grow(self.positions[v as usize]))
            })
            .collect()
    }
}

/// The vertices in the order of their x coordinates (ties in vertex order).
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (seen before and after the
/// sort, a stable sort on the pool's threads).
fn order_by_x(positions: &[Vec3]) -> Result<Vec<u32>, LimitError> {
    crate::limits::check()?;
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.par_sort_by(|&a, &b| positions[a as usize].x.total_cmp(&positions[b as usize].x));
    crate::limits::check()?;
    Ok(order)
}

/// Whether no two of `positions` are equal (bit for bit, as [`check_solid`] compares them),
/// seen in one walk along `order` (a permutation of the vertices): when their x coordinates
/// never fall along it, equal ones are neighbours there, and only runs of one x need their y
/// and z compared. A translated copy walked in its original's x order ([`order_by_x`]) keeps
/// that order, rounding being monotone. `false` when the walk cannot tell (an x falls, or two
/// positions are equal): the caller then checks each position by lookup.
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] positions).
fn apart_along(positions: &[Vec3], order: &[u32]) -> Result<bool, LimitError> {
    if order.len() != positions.len() {
        return Ok(false);
    }
    let at = |k: usize| positions[order[k] as usize];
    // One buffer for every run's y and z.
    let mut yz: Vec<[u64; 2]> = Vec::new();
    let mut start = 0;
    for k in 1..=order.len() {
        crate::limits::poll_at(k)?;
        if k < order.len() {
            let (a, b) = (at(k - 1).x, at(k).x);
            if a.total_cmp(&b).is_gt() {
                return Ok(false);
            }
            if a.to_bits() == b.to_bits() {
                continue;
            }
        }
        // One run of a single x: order[start..k].
        let run = &order[start..k];
        if run.len() > 1 {
            yz.clear();
            yz.extend(run.iter().map(|&v| [positions[v as usize].y.to_bits(), positions[v as usize].z.to_bits()]));
            yz.sort_unstable();
            if yz.windows(2).any(|w| w[0] == w[1]) {
                return Ok(false);
            }
        }
        start = k;
    }
    Ok(true)
}

/// `leaf_no` is the input's position among the tree's inputs, left to right (named in errors).
fn prepare(leaf: &Csg, side: Side, leaf_no: u32) -> Result<Prepared, CsgError> {
    let (mesh, sources, union_parts, raw): (Cow<'_, Mesh>, Vec<FaceSource>, bool, bool) = match leaf {
        Csg::Blocks(model, options) => {
            if model.blocks().is_empty() {
                return Err(CsgError::EmptyOperand { side, leaf: leaf_no });
            }
            let t = model.tessellate(options, None).map_err(|source| match source {
                BlockError::Limit(l) => CsgError::Limit(l),
                source => CsgError::Blocks { side, leaf: leaf_no, source },
            })?;
            let sources =
                t.triangle_sources.iter().map(|&r| FaceSource::Block { leaf: 0, sub_face: r.into() }).collect();
            (Cow::Owned(t.mesh), sources, true, false)
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
                let (t, from) = m.triangulate_with_sources().map_err(|source| match source {
                    MeshError::Limit(l) => CsgError::Limit(l),
                    source => CsgError::Triangulation { side, leaf: leaf_no, source },
                })?;
                (Cow::Owned(t), Some(from))
            };
            // A plain triangle mesh's faces are its coplanar regions (as Manifold's): a flat side
            // of an STL is one face, named by its first triangle.
            let (sources, raw) = match (tri.face_sources(), from) {
                (Some(fs), _) => (fs.to_vec(), false),
                (None, Some(from)) => (from.iter().map(|&face| FaceSource::Mesh { leaf: 0, face }).collect(), false),
                (None, None) => {
                    ((0..tri.face_count() as u32).map(|face| FaceSource::Mesh { leaf: 0, face }).collect(), true)
                }
            };
            (tri, sources, false, raw)
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
    crate::limits::charge(triangles.len() as u64)?;
    check_solid(&mesh, &triangles, &components, !earlier_result, side, leaf_no)?;
    crate::limits::charge(triangles.len() as u64)?;
    let (faces, face_sources, creases) = coplanar_faces(&mesh, &triangles, &sources, raw)?;
    crate::limits::charge(triangles.len() as u64)?;
    // Faces never span two parts (see `coplanar_faces`): each takes its first triangle's.
    let (group_parts, parts) = match mesh.face_part_ids() {
        Some(ids) => {
            let mut group_parts = vec![0; face_sources.len()];
            for (t, &g) in faces.iter().enumerate().rev() {
                group_parts[g as usize] = ids[t];
            }
            (group_parts, mesh.parts().to_vec())
        }
        None => (Vec::new(), Vec::new()),
    };
    let corners = corner_list(&mesh);
    Ok(Prepared {
        positions: mesh.positions().to_vec(),
        triangles: Arc::new(triangles),
        faces: Arc::new(faces),
        face_sources: Arc::new(face_sources),
        group_parts: Arc::new(group_parts),
        parts: Arc::new(parts),
        creases,
        corners,
        leaf_span,
        first_leaf_hint: leaf_no,
        components: Arc::new(components),
        pairs: Arc::new(corner_pairs(&mesh)),
    })
}

/// The vertices of `mesh` with a corner sharpness: position and sharpness.
fn corner_list(mesh: &Mesh) -> Vec<(Vec3, f64)> {
    (0..mesh.vertex_count() as u32)
        .filter(|&v| mesh.is_corner(v))
        .map(|v| (mesh.position(v), mesh.corner_sharpness(v)))
        .collect()
}

/// For each mesh leaf (a triangle mesh) that is a translated copy of an earlier mesh leaf
/// ([`Mesh::translation_from`], within the engine's resolution where it lies), that leaf;
/// `None` for the others: [`copies_in_order`]'s answer. A copy has its original's
/// counts of vertices, faces and half-edges, so it can only copy the first leaf of those counts;
/// when every leaf is a copy of the first of its counts (a pattern of one part), that is the
/// answer, found by comparing every leaf with that first in parallel (the pieces of a pattern
/// are compared all at once, not one after another); otherwise the leaves are compared in
/// order.
fn translated_copies(leaves: &[(&Csg, Side)]) -> Vec<Option<usize>> {
    let meshes: Vec<Option<&Mesh>> = leaves.par_iter().map(|(leaf, _)| copyable(leaf)).collect();
    let mut first_of_counts: HashMap<(usize, usize, usize), usize> = HashMap::new();
    let guess: Vec<Option<usize>> = meshes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let m = (*m)?;
            let first = *first_of_counts.entry((m.vertex_count(), m.face_count(), m.halfedge_count())).or_insert(k);
            (first != k).then_some(first)
        })
        .collect();
    let all_copies = guess.par_iter().zip(&meshes).all(|(first, m)| match (*first, *m) {
        (Some(first), Some(m)) => meshes[first].is_some_and(|o| is_copy(m, o, copy_tolerance(m))),
        _ => true,
    });
    if all_copies {
        guess
    } else {
        copies_in_order(&meshes)
    }
}

/// The mesh of a leaf that can be a translated copy or have some (a triangle mesh with faces).
fn copyable(leaf: &Csg) -> Option<&Mesh> {
    match leaf {
        Csg::Mesh(m) if m.face_count() > 0 && m.is_triangle_mesh() => Some(m),
        _ => None,
    }
}

/// Whether `m` is `o` moved, within `tolerance` ([`copy_tolerance`] of `m`).
fn is_copy(m: &Mesh, o: &Mesh, tolerance: f64) -> bool {
    m.translation_from(o, tolerance).is_some()
}

/// The engine's resolution at `m`: how far a copy's positions may be from its original's moved.
fn copy_tolerance(m: &Mesh) -> f64 {
    ENGINE_PRECISION * box_span_and_magnitude(m.bounds()).1
}

/// [`translated_copies`] one leaf after another (`meshes`: each leaf's mesh when
/// [`copyable`]): each is compared with the first of every kind seen so far, and the
/// comparison stops at the first array that differs.
fn copies_in_order(meshes: &[Option<&Mesh>]) -> Vec<Option<usize>> {
    let mut firsts: Vec<usize> = Vec::new();
    meshes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let m = (*m)?;
            let tolerance = copy_tolerance(m);
            let first = firsts.iter().copied().find(|&r| meshes[r].is_some_and(|o| is_copy(m, o, tolerance)));
            if first.is_none() {
                firsts.push(k);
            }
            first
        })
        .collect()
}

/// The pairing of a triangle mesh's half-edges as the engine numbers them (see
/// [`Prepared::pairs`]): the triangles' corners in the order `face_vertices` gives them.
/// Empty when some half-edge has no face across it (an open mesh, which the engine refuses).
fn corner_pairs(mesh: &Mesh) -> Vec<u32> {
    let mut slot = vec![NONE; mesh.halfedge_count()];
    for f in 0..mesh.face_count() as u32 {
        for (i, h) in mesh.face_halfedges(f).enumerate() {
            slot[h as usize] = 3 * f + i as u32;
        }
    }
    let mut pairs = Vec::with_capacity(3 * mesh.face_count());
    for f in 0..mesh.face_count() as u32 {
        for h in mesh.face_halfedges(f) {
            let q = slot[mesh.twin(h) as usize];
            if q == NONE {
                return Vec::new();
            }
            pairs.push(q);
        }
    }
    pairs
}

/// Sines of the angle between two triangles' normals below this count as coplanar.
const COPLANAR_SINE: f64 = 1e-10;

/// The faces of a leaf (see [`Prepared`]): triangles joined across every edge that is no crease,
/// between triangles of one source (any two, when `any_source`) and one part whose normals agree; with the
/// face sources (a face's first triangle's) and the crease edges between faces with their
/// sharpness.
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] triangles and edges).
#[allow(clippy::type_complexity)]
pub(super) fn coplanar_faces(
    mesh: &Mesh,
    triangles: &[[u32; 3]],
    sources: &[FaceSource],
    any_source: bool,
) -> Result<(Vec<u32>, Vec<FaceSource>, Vec<(u32, u32, [Vec3; 2], f64)>), LimitError> {
    use crate::limits::poll_at;
    // A zero-area triangle (three corners on a line, as a block's T-vertices make along a
    // sharp edge) has no plane: it joins the face of a neighbour, after the others are joined.
    let normal = |t: usize| {
        let [a, b, c] = triangles[t].map(|v| mesh.position(v));
        let n = (b - a).cross(c - a);
        if n.length() <= COPLANAR_SINE * (b - a).length() * (c - a).length() {
            Vec3::ZERO
        } else {
            n
        }
    };
    let normals: Vec<Vec3> = (0..triangles.len()).map(normal).collect();
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    let joinable = |h: u32| {
        let (f, g) = (mesh.face(h) as usize, mesh.face(mesh.twin(h)) as usize);
        let same_part = mesh.face_part_ids().is_none_or(|ids| ids[f] == ids[g]);
        (!mesh.is_crease(h) && (any_source || sources[f] == sources[g]) && same_part).then_some((f, g))
    };
    let join = |parent: &mut [u32], f: usize, g: usize| {
        let (a, b) = (root(parent, f as u32), root(parent, g as u32));
        // The smaller triangle is the root, so a face is named by its first triangle.
        parent[a.max(b) as usize] = a.min(b);
    };
    for (i, (f, g)) in mesh.edges().filter_map(joinable).enumerate() {
        poll_at(i)?;
        let (nf, ng) = (normals[f], normals[g]);
        let scale = nf.length() * ng.length();
        if nf.dot(ng) > 0.0 && nf.cross(ng).length() <= COPLANAR_SINE * scale {
            join(&mut parent, f, g);
        }
    }
    let mut attached = vec![false; triangles.len()];
    for (i, (f, g)) in mesh.edges().filter_map(joinable).enumerate() {
        poll_at(i)?;
        for (lone, other) in [(f, g), (g, f)] {
            if normals[lone] == Vec3::ZERO && !attached[lone] {
                attached[lone] = true;
                let r = root(&mut parent, other as u32);
                if r != lone as u32 {
                    parent[lone] = r;
                }
            }
        }
    }
    let mut number = vec![u32::MAX; triangles.len()];
    let mut face_sources = Vec::new();
    let mut faces = Vec::with_capacity(triangles.len());
    for t in 0..triangles.len() as u32 {
        poll_at(t as usize)?;
        let r = root(&mut parent, t) as usize;
        if number[r] == u32::MAX {
            number[r] = face_sources.len() as u32;
            face_sources.push(sources[r]);
        }
        faces.push(number[r]);
    }
    let creases = crease_segments(mesh, &faces);
    Ok((faces, face_sources, creases))
}

/// The crease edges of `mesh` between its faces `faces` (one per triangle, see
/// [`coplanar_faces`]): the faces on their two sides, the segment and its sharpness.
fn crease_segments(mesh: &Mesh, faces: &[u32]) -> Vec<(u32, u32, [Vec3; 2], f64)> {
    mesh.edges()
        .filter(|&h| mesh.is_crease(h))
        .map(|h| {
            let (f, g) = (faces[mesh.face(h) as usize], faces[mesh.face(mesh.twin(h)) as usize]);
            (f, g, [mesh.position(mesh.origin(h)), mesh.position(mesh.target(h))], mesh.edge_sharpness(h))
        })
        .collect()
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
    if !check_touching {
        return Ok(());
    }
    // Each component's vertices by position, in the order its triangles first use them: the
    // first vertex found at a position another one holds touches it. Linear, and stoppable.
    let mut seen_in = vec![usize::MAX; mesh.vertex_count()];
    for (c, tris) in components.iter().enumerate() {
        // A map of its own per component (clearing one would cost its largest size each time),
        // with the fast integer hasher: SipHash was a tenth of a boolean's leaf preparation.
        let mut at: IdMap<[u64; 3], u32> = IdMap::with_capacity_and_hasher(tris.len() / 2 + 3, Default::default());
        for (i, &t) in tris.iter().enumerate() {
            crate::limits::poll_at(i)?;
            for v in triangles[t as usize] {
                if std::mem::replace(&mut seen_in[v as usize], c) == c {
                    continue;
                }
                if let Some(&w) = at.get(&key(v)) {
                    let p = mesh.position(v);
                    return Err(CsgError::NonManifold {
                        side,
                        leaf,
                        reason: format!(
                            "vertices {} and {} are both at ({}, {}, {}): the surface touches itself there",
                            v.min(w),
                            v.max(w),
                            p.x,
                            p.y,
                            p.z
                        ),
                    });
                }
                at.insert(key(v), v);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "tests_instances.rs"]
mod tests_instances;

#[cfg(test)]
#[path = "tests_flat_shells.rs"]
mod tests_flat_shells;
