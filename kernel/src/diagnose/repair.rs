//! Repair of polygons that do not make a 2-manifold, without moving a vertex: the nearest
//! valid mesh by splitting and re-orienting only.
//!
//! Steps, each linear after one sort of the edges:
//! 1. Faces with fewer than three corners or a corner repeated are dropped.
//! 2. Each edge's uses are paired: two uses pair when they run opposite ways (or, when
//!    re-orienting, any two); of more than two, first the pairs an earlier topology had
//!    (`prior`: a weld's input), then the faces next to each other around the edge whose
//!    solid lies between them (sorted by angle about the edge; a face running along the edge
//!    has its solid on its clockwise side, so it pairs with the face before it), the rest
//!    become sheets of their own along that edge.
//! 3. When re-orienting, faces joined by pairs get orientations that agree (a breadth-first
//!    walk); in each component the fewer faces are flipped. A pair that no orientation
//!    satisfies (a Möbius band) is cut.
//! 4. Each vertex is split into one vertex per fan: corners joined across paired edges form
//!    one fan; the first fan keeps the id, the others get new ids at the same position.
//!
//! What cannot be made into a fan this way (a face whose edge is shared beyond two after all,
//! around a vertex whose fan wraps back onto it) is cut out as its own sheet, as the build
//! reports it; this ends after at most one cut per face.

use crate::math::Vec3;
use crate::mesh::{Mesh, MeshError};

/// What [`repair_polygons`] may change.
#[derive(Clone, Copy, Debug, Default)]
#[non_exhaustive]
pub struct RepairOptions<'a> {
    /// Re-orient faces so that neighbours agree (otherwise two uses of an edge running the
    /// same way are never paired). Default value: `false`.
    pub reorient: bool,
    /// For each corner of the input (indexed like `indices`), the vertex it had in an earlier
    /// topology (before a weld): an edge's uses that were paired there are paired first.
    /// Default value: `None`.
    pub prior: Option<&'a [u32]>,
}

impl<'a> RepairOptions<'a> {
    /// Nothing re-oriented, no prior topology.
    pub const DEFAULT: RepairOptions<'static> = RepairOptions { reorient: false, prior: None };

    /// With re-orientation on or off.
    #[must_use]
    pub fn with_reorient(mut self, reorient: bool) -> Self {
        self.reorient = reorient;
        self
    }

    /// With the corners' vertices in an earlier topology.
    #[must_use]
    pub fn with_prior(self, prior: &'a [u32]) -> RepairOptions<'a> {
        RepairOptions { reorient: self.reorient, prior: Some(prior) }
    }
}

/// A vertex split into one vertex per fan.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitVertex {
    /// The input vertex.
    pub vertex: u32,
    /// Its fans (the vertices it became).
    pub fans: usize,
    /// Its position.
    pub at: Vec3,
}

/// An edge used by more faces than two (or by two running the same way that could not be
/// re-oriented), whose extra faces were separated into sheets of their own.
#[derive(Clone, Debug, PartialEq)]
pub struct SeparatedEdge {
    /// The input vertices of the edge.
    pub vertices: [u32; 2],
    /// How many faces used it.
    pub faces: usize,
    /// How many of them were separated from it (left with a boundary there).
    pub separated: usize,
    /// Its midpoint.
    pub at: Vec3,
}

/// A component some of whose faces were flipped to agree with the rest.
#[derive(Clone, Debug, PartialEq)]
pub struct FlippedComponent {
    /// Faces flipped (input face ids).
    pub faces: Vec<u32>,
    /// Faces in the component.
    pub of: usize,
    /// The centre of the first flipped face.
    pub at: Vec3,
}

/// Everything [`repair_polygons`] changed, with where.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Repairs {
    /// Input faces dropped (fewer than three corners, or a corner repeated), with the centre
    /// of each.
    pub dropped_faces: Vec<(u32, Vec3)>,
    /// Edges whose faces beyond a pair were separated.
    pub separated_edges: Vec<SeparatedEdge>,
    /// Components re-oriented in part.
    pub flipped: Vec<FlippedComponent>,
    /// Edges cut because no orientation of their faces agrees (non-orientable components).
    pub unorientable_cuts: usize,
    /// Vertices split into one per fan.
    pub split_vertices: Vec<SplitVertex>,
    /// Faces cut out as sheets of their own because no fan could hold them.
    pub isolated_faces: usize,
}

impl Repairs {
    /// Whether nothing was changed.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.dropped_faces.is_empty()
            && self.separated_edges.is_empty()
            && self.flipped.is_empty()
            && self.unorientable_cuts == 0
            && self.split_vertices.is_empty()
            && self.isolated_faces == 0
    }

    /// One line per kind of repair, with counts and the first place: for warnings.
    #[must_use]
    pub fn summary(&self) -> Vec<String> {
        let at = |p: Vec3| format!("({}, {}, {})", short(p.x), short(p.y), short(p.z));
        let mut out = Vec::new();
        if let Some(&(f, p)) = self.dropped_faces.first() {
            out.push(format!(
                "dropped {} face{} that repeat a vertex or have fewer than 3 (first: face {f} at {})",
                self.dropped_faces.len(),
                plural(self.dropped_faces.len()),
                at(p)
            ));
        }
        if let Some(e) = self.separated_edges.first() {
            let faces: usize = self.separated_edges.iter().map(|e| e.separated).sum();
            out.push(format!(
                "separated {faces} face{} from {} edge{} shared by more than two faces into their own sheets \
                 (first: edge ({}, {}) of {} faces at {})",
                plural(faces),
                self.separated_edges.len(),
                plural(self.separated_edges.len()),
                e.vertices[0],
                e.vertices[1],
                e.faces,
                at(e.at)
            ));
        }
        if let Some(c) = self.flipped.first() {
            let faces: usize = self.flipped.iter().map(|c| c.faces.len()).sum();
            out.push(format!(
                "flipped {faces} face{} in {} component{} to agree with their neighbours (first: face {} at {})",
                plural(faces),
                self.flipped.len(),
                plural(self.flipped.len()),
                c.faces[0],
                at(c.at)
            ));
        }
        if self.unorientable_cuts > 0 {
            out.push(format!(
                "cut {} edge{} of non-orientable components (no orientation of their faces agrees)",
                self.unorientable_cuts,
                plural(self.unorientable_cuts)
            ));
        }
        if let Some(v) = self.split_vertices.first() {
            let extra: usize = self.split_vertices.iter().map(|v| v.fans - 1).sum();
            out.push(format!(
                "split {} non-manifold vertex{} into one per fan ({extra} added at the same positions; first: \
                 vertex {} of {} fans at {})",
                self.split_vertices.len(),
                if self.split_vertices.len() == 1 { "" } else { "es" },
                v.vertex,
                v.fans,
                at(v.at)
            ));
        }
        if self.isolated_faces > 0 {
            out.push(format!(
                "cut out {} face{} as sheets of their own (their edges could not be shared as a surface)",
                self.isolated_faces,
                plural(self.isolated_faces)
            ));
        }
        out
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// A coordinate as a message shows it: up to 6 significant digits.
fn short(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// A repaired mesh and what was changed to make it.
#[derive(Clone, Debug)]
pub struct Repaired {
    /// The mesh: no position moved; vertices split at the same positions.
    pub mesh: Mesh,
    /// For each vertex of `mesh`, the input vertex it comes from (the first copy keeps its
    /// id: `vertex_from[v] == v` for every input vertex).
    pub vertex_from: Vec<u32>,
    /// For each face of `mesh`, the input face it comes from.
    pub face_from: Vec<u32>,
    /// For each face of `mesh`, whether its corners run the other way from the input's.
    pub flipped: Vec<bool>,
    /// What was changed.
    pub repairs: Repairs,
}

/// One use of an edge by a face: the kept face, the corner the edge leaves from, and whether
/// it runs from the smaller vertex id to the larger.
#[derive(Clone, Copy)]
struct Use {
    key: (u32, u32),
    face: u32,
    corner: u32,
    forward: bool,
}

/// The nearest 2-manifold mesh to the polygons `indices` (split by `arities`) over
/// `positions`, by splitting vertices and edges and (if `options.reorient`) flipping faces,
/// never moving a vertex. See the module documentation for the steps.
///
/// Inputs: `positions` (#V), `indices` (Σ arities), `arities` (#F).
///
/// # Errors
/// [`MeshError::IndexOutOfRange`], [`MeshError::NonFinite`], [`MeshError::TooLarge`] as
/// [`Mesh::from_indexed`]; [`MeshError::Limit`] when the current cancellation token stops.
pub fn repair_polygons(
    positions: &[Vec3],
    indices: &[u32],
    arities: &[u32],
    options: RepairOptions<'_>,
) -> Result<Repaired, MeshError> {
    let nv = positions.len();
    let total: u64 = arities.iter().map(|&a| u64::from(a)).sum();
    if total != indices.len() as u64 {
        return Err(MeshError::DegenerateFace {
            face: arities.len(),
            reason: format!("face arities add up to {total} but {} indices were given", indices.len()),
        });
    }
    let mut repairs = Repairs::default();
    let centre = |c: &[u32]| c.iter().map(|&v| positions[v as usize]).sum::<Vec3>() / c.len().max(1) as f64;
    // 1. Kept faces: (input face, start in indices, arity).
    let mut faces: Vec<(u32, u32, u32)> = Vec::with_capacity(arities.len());
    let mut start = 0usize;
    for (f, &a) in arities.iter().enumerate() {
        crate::limits::poll_at(f)?;
        let corners = &indices[start..start + a as usize];
        if let Some(&v) = corners.iter().find(|&&v| v as usize >= nv) {
            return Err(MeshError::IndexOutOfRange { face: f, index: u64::from(v), vertex_count: nv });
        }
        let repeated = (1..corners.len()).any(|i| corners[..i].contains(&corners[i]));
        if a < 3 || repeated {
            repairs.dropped_faces.push((f as u32, centre(corners)));
        } else {
            faces.push((f as u32, start as u32, a));
        }
        start += a as usize;
    }
    let corner_at = |k: u32, i: u32| {
        let (_, s, a) = faces[k as usize];
        indices[(s + i % a) as usize]
    };
    let prior_at = |k: u32, i: u32| {
        let (_, s, a) = faces[k as usize];
        options.prior.map(|p| p[(s + i % a) as usize])
    };

    // 2. Uses of each edge, sorted by edge.
    let mut uses: Vec<Use> = Vec::with_capacity(indices.len());
    for (k, &(_, _, a)) in faces.iter().enumerate() {
        for i in 0..a {
            let (p, q) = (corner_at(k as u32, i), corner_at(k as u32, i + 1));
            uses.push(Use { key: (p.min(q), p.max(q)), face: k as u32, corner: i, forward: p < q });
        }
    }
    uses.sort_unstable_by_key(|u| (u.key, u.face, u.corner));
    // Pairs of uses (indices into `uses`), and whether they run the same way.
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(uses.len() / 2);
    let mut g = 0;
    while g < uses.len() {
        if g & 0xffff == 0 {
            crate::limits::poll()?;
        }
        let mut e = g + 1;
        while e < uses.len() && uses[e].key == uses[g].key {
            e += 1;
        }
        let group = g as u32..e as u32;
        let n = e - g;
        if n == 2 && (options.reorient || uses[g].forward != uses[g + 1].forward) {
            pairs.push((g as u32, g as u32 + 1));
        } else if n >= 2 {
            let before = pairs.len();
            pair_group(&uses, group, positions, &corner_at, &prior_at, &mut pairs);
            let paired = 2 * (pairs.len() - before);
            let (a, b) = uses[g].key;
            repairs.separated_edges.push(SeparatedEdge {
                vertices: [a, b],
                faces: n,
                separated: n - paired,
                at: (positions[a as usize] + positions[b as usize]) * 0.5,
            });
        }
        g = e;
    }

    // 3. Orientation.
    let mut flip = vec![false; faces.len()];
    if options.reorient {
        let cut = orient(&uses, &mut pairs, faces.len(), &mut flip, &mut repairs, |k| {
            let (_, s, a) = faces[k as usize];
            centre(&indices[s as usize..(s + a) as usize])
        })?;
        repairs.unorientable_cuts = cut;
        for c in &mut repairs.flipped {
            for f in &mut c.faces {
                *f = faces[*f as usize].0;
            }
        }
    }

    // 4. Fans: corners joined across paired edges. Corner ids: face start offsets in `indices`.
    let mut uf = UnionFind::new(indices.len());
    let gid = |k: u32, i: u32| {
        let (_, s, a) = faces[k as usize];
        (s + i % a) as usize
    };
    for &(x, y) in &pairs {
        let (u, w) = (uses[x as usize], uses[y as usize]);
        // u runs corner_at(u.corner) → corner_at(u.corner + 1); w likewise.
        let (u0, u1) = (gid(u.face, u.corner), gid(u.face, u.corner + 1));
        let (w0, w1) = (gid(w.face, w.corner), gid(w.face, w.corner + 1));
        if u.forward == w.forward {
            uf.union(u0, w0);
            uf.union(u1, w1);
        } else {
            uf.union(u0, w1);
            uf.union(u1, w0);
        }
    }
    let mut isolated: Vec<bool> = vec![false; faces.len()];
    let mut vertex_from: Vec<u32> = (0..nv as u32).collect();
    let mut pos: Vec<Vec3> = positions.to_vec();
    loop {
        let corner_vertex =
            assign_fans(&faces, indices, &mut uf, &isolated, nv, &mut vertex_from, &mut repairs, positions);
        pos.truncate(nv);
        pos.extend(vertex_from[nv..].iter().map(|&v| positions[v as usize]));
        let mut out = Vec::with_capacity(indices.len());
        let mut out_arities = Vec::with_capacity(faces.len());
        for (k, &(_, s, a)) in faces.iter().enumerate() {
            let ids = &corner_vertex[s as usize..(s + a) as usize];
            out.push(ids[0]);
            if flip[k] {
                out.extend(ids[1..].iter().rev());
            } else {
                out.extend_from_slice(&ids[1..]);
            }
            out_arities.push(a);
        }
        match Mesh::from_indexed_stoppable(pos.clone(), &out, &out_arities) {
            Ok(mesh) => {
                repairs.isolated_faces = isolated.iter().filter(|&&x| x).count();
                return Ok(Repaired {
                    mesh,
                    vertex_from,
                    face_from: faces.iter().map(|f| f.0).collect(),
                    flipped: flip,
                    repairs,
                });
            }
            Err(MeshError::NonManifoldEdge { first, second, .. }) => {
                // Cut out the later face (a sheet of its own), or the earlier when the later
                // already is.
                let k = if isolated[second] { first } else { second };
                if isolated[k] {
                    return Err(MeshError::Internal(format!("repair: faces {first} and {second} still share an edge")));
                }
                isolated[k] = true;
            }
            Err(MeshError::NonManifoldVertex { vertex, .. }) => {
                // Cut out the first face at that vertex not cut out yet.
                let k = (0..faces.len()).find(|&k| {
                    !isolated[k] && {
                        let (_, s, a) = faces[k];
                        corner_vertex[s as usize..(s + a) as usize].contains(&vertex)
                    }
                });
                match k {
                    Some(k) => isolated[k] = true,
                    None => return Err(MeshError::Internal(format!("repair: vertex {vertex} stays non-manifold"))),
                }
            }
            Err(e) => return Err(e),
        }
        vertex_from.truncate(nv);
        repairs.split_vertices.clear();
    }
}

/// Pairs the uses of one edge (more than two, or two running the same way): first the pairs
/// of the prior topology, then neighbours around the edge whose solid lies between them.
fn pair_group(
    uses: &[Use],
    group: std::ops::Range<u32>,
    positions: &[Vec3],
    corner_at: &impl Fn(u32, u32) -> u32,
    prior_at: &impl Fn(u32, u32) -> Option<u32>,
    pairs: &mut Vec<(u32, u32)>,
) {
    let mut free: Vec<u32> = group.collect();
    // Prior pairs: same prior edge, opposite ways.
    let prior_key = |x: u32| {
        let u = uses[x as usize];
        let (a, b) = (prior_at(u.face, u.corner)?, prior_at(u.face, u.corner + 1)?);
        Some((a.min(b), a.max(b)))
    };
    let mut i = 0;
    while i < free.len() {
        let x = free[i];
        let found = prior_key(x).and_then(|kx| {
            free.iter().enumerate().skip(i + 1).find_map(|(j, &y)| {
                (uses[y as usize].forward != uses[x as usize].forward && prior_key(y) == Some(kx)).then_some(j)
            })
        });
        if let Some(j) = found {
            pairs.push((x, free[j]));
            free.remove(j);
            free.remove(i);
        } else {
            i += 1;
        }
    }
    if free.len() < 2 {
        return;
    }
    // Around the edge a → b (a the smaller id): each face's direction away from the edge, as
    // an angle in a frame perpendicular to it.
    let (a, b) = uses[free[0] as usize].key;
    let (pa, pb) = (positions[a as usize], positions[b as usize]);
    let d = (pb - pa).normalize_or_zero();
    let e1 = d.any_orthonormal_vector();
    let e2 = d.cross(e1);
    let angle = |x: u32| {
        let u = uses[x as usize];
        // The corner after the edge's end in the face (its other corner for a triangle).
        let w = positions[corner_at(u.face, u.corner + 2) as usize] - pa;
        let w = w - d * d.dot(w);
        w.dot(e2).atan2(w.dot(e1))
    };
    let mut around: Vec<(f64, u32)> = free.iter().map(|&x| (angle(x), x)).collect();
    around.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let far = |x: u32| positions[corner_at(uses[x as usize].face, uses[x as usize].corner + 2) as usize];
    order_coincident_faces(&mut around, pa, pb, &far, &|x| uses[x as usize].forward);
    let n = around.len();
    let mut taken = vec![false; n];
    for k in 0..n {
        let x = around[k].1;
        if taken[k] || !uses[x as usize].forward {
            continue;
        }
        // A face running a → b has its solid clockwise of it: its partner is the face before.
        let j = (k + n - 1) % n;
        let y = around[j].1;
        if j != k && !taken[j] && !uses[y as usize].forward {
            taken[k] = true;
            taken[j] = true;
            pairs.push((x, y));
        }
    }
}

/// Faces leaving an edge at angles closer than this (radians) leave it in one direction: the
/// rounding of a transform, far below any angle a model draws.
const COINCIDENT_ANGLE: f64 = 1e-9;

/// Orders the faces that leave the edge `pa → pb` in one direction (two solids touching along
/// a face: an STL of stacked boxes) so that each pairs with its own solid: of such a run, the
/// faces running along the edge (whose partner is the face before) come first, those running
/// against it (whose partner is the face after) last, and the faces of two touching solids are
/// never paired with each other. `around` is sorted by angle. A run is found exactly (Shewchuk's
/// `orient3d`: the far corners lie in one plane with the edge, on one side of it), as rounded
/// angles of one direction may differ, or within [`COINCIDENT_ANGLE`], as a file's node
/// transform in floating point tilts a face it rotates by rounding (a glTF's −90° about x
/// turns a plane by 2e-16). A run across the angle's wrap at ±π is brought to the front.
fn order_coincident_faces(
    around: &mut [(f64, u32)],
    pa: Vec3,
    pb: Vec3,
    far: &impl Fn(u32) -> Vec3,
    forward: &impl Fn(u32) -> bool,
) {
    let n = around.len();
    let d = (pb - pa).normalize_or_zero();
    let away = |x: u32| {
        let w = far(x) - pa;
        (w - d * d.dot(w)).normalize_or_zero()
    };
    let same = |x: u32, y: u32| {
        let (u, w) = (away(x), away(y));
        u.dot(w) > 0.0
            && (u.cross(w).length() < COINCIDENT_ANGLE
                || crate::diagnose::triangle_pair::o3(pa, pb, far(x), far(y)) == 0)
    };
    // Start at a face not in one direction with the face before it.
    let Some(start) = (0..n).find(|&k| !same(around[(k + n - 1) % n].1, around[k].1)) else { return };
    around.rotate_left(start);
    let mut k = 0;
    while k < n {
        let mut end = k + 1;
        while end < n && same(around[end - 1].1, around[end].1) {
            end += 1;
        }
        around[k..end].sort_by_key(|e| !forward(e.1));
        k = end;
    }
}

/// Gives the faces joined by `pairs` orientations that agree: `flip[k]` for each kept face.
/// Returns the number of pairs cut because no orientation satisfies them (removed from
/// `pairs`), and lists in `repairs.flipped` the components with flipped faces (by kept face;
/// the caller renames them to input faces).
fn orient(
    uses: &[Use],
    pairs: &mut Vec<(u32, u32)>,
    nf: usize,
    flip: &mut [bool],
    repairs: &mut Repairs,
    centre: impl Fn(u32) -> Vec3,
) -> Result<usize, MeshError> {
    // Adjacency (CSR) of faces by pairs: (other face, pair index).
    let mut deg = vec![0u32; nf + 1];
    for &(x, y) in pairs.iter() {
        deg[uses[x as usize].face as usize + 1] += 1;
        deg[uses[y as usize].face as usize + 1] += 1;
    }
    for i in 0..nf {
        deg[i + 1] += deg[i];
    }
    let mut fill = deg.clone();
    let mut adj = vec![(0u32, 0u32); 2 * pairs.len()];
    for (p, &(x, y)) in pairs.iter().enumerate() {
        let (fx, fy) = (uses[x as usize].face, uses[y as usize].face);
        adj[fill[fx as usize] as usize] = (fy, p as u32);
        fill[fx as usize] += 1;
        adj[fill[fy as usize] as usize] = (fx, p as u32);
        fill[fy as usize] += 1;
    }
    let mut seen = vec![false; nf];
    let mut cut = vec![false; pairs.len()];
    let mut queue = std::collections::VecDeque::new();
    let mut ncut = 0;
    for f0 in 0..nf {
        if seen[f0] {
            continue;
        }
        crate::limits::poll()?;
        let mut component = vec![f0 as u32];
        seen[f0] = true;
        queue.push_back(f0 as u32);
        while let Some(f) = queue.pop_front() {
            for &(g, p) in &adj[deg[f as usize] as usize..deg[f as usize + 1] as usize] {
                let (x, y) = pairs[p as usize];
                // Agreeing faces use the edge in opposite ways once flips are applied.
                let same = uses[x as usize].forward == uses[y as usize].forward;
                let want = flip[f as usize] ^ same;
                if !seen[g as usize] {
                    seen[g as usize] = true;
                    flip[g as usize] = want;
                    component.push(g);
                    queue.push_back(g);
                } else if flip[g as usize] != want && !cut[p as usize] {
                    cut[p as usize] = true;
                    ncut += 1;
                }
            }
        }
        let flipped = component.iter().filter(|&&k| flip[k as usize]).count();
        if 2 * flipped > component.len() {
            for &k in &component {
                flip[k as usize] = !flip[k as usize];
            }
        }
        let mut faces: Vec<u32> = component.iter().copied().filter(|&k| flip[k as usize]).collect();
        if !faces.is_empty() {
            faces.sort_unstable();
            repairs.flipped.push(FlippedComponent { at: centre(faces[0]), faces, of: component.len() });
        }
    }
    if ncut > 0 {
        let mut p = 0;
        pairs.retain(|_| {
            p += 1;
            !cut[p - 1]
        });
    }
    Ok(ncut)
}

/// For every corner (by its index in `indices`) the output vertex: one per fan of each input
/// vertex (the first fan, of the lowest corner, keeps the id; later ones get ids from `nv`
/// on, appended to `vertex_from`); corners of isolated faces get vertices of their own.
#[allow(clippy::too_many_arguments)]
fn assign_fans(
    faces: &[(u32, u32, u32)],
    indices: &[u32],
    uf: &mut UnionFind,
    isolated: &[bool],
    nv: usize,
    vertex_from: &mut Vec<u32>,
    repairs: &mut Repairs,
    positions: &[Vec3],
) -> Vec<u32> {
    let mut corner_vertex = vec![u32::MAX; indices.len()];
    // The output vertex of each fan, by its root corner.
    let mut fan_vertex: crate::math::IdMap<u32, u32> = crate::math::IdMap::default();
    // The fans each input vertex has had so far (the first keeps the id).
    let mut fans = vec![0u32; nv];
    for (k, &(_, s, a)) in faces.iter().enumerate() {
        for c in s..s + a {
            let v = indices[c as usize];
            let id = if isolated[k] {
                None
            } else {
                let root = uf.find(c as usize) as u32;
                fan_vertex.get(&root).copied().map(Some).unwrap_or_else(|| {
                    let id = new_fan(v, &mut fans, vertex_from);
                    fan_vertex.insert(root, id);
                    Some(id)
                })
            };
            corner_vertex[c as usize] = id.unwrap_or_else(|| new_fan(v, &mut fans, vertex_from));
        }
    }
    repairs.split_vertices = fans
        .iter()
        .enumerate()
        .filter(|&(_, &n)| n > 1)
        .map(|(v, &n)| SplitVertex { vertex: v as u32, fans: n as usize, at: positions[v] })
        .collect();
    corner_vertex
}

/// The output vertex of a new fan of input vertex `v`.
fn new_fan(v: u32, fans: &mut [u32], vertex_from: &mut Vec<u32>) -> u32 {
    fans[v as usize] += 1;
    if fans[v as usize] == 1 {
        v
    } else {
        vertex_from.push(v);
        (vertex_from.len() - 1) as u32
    }
}

/// Disjoint sets over `0..n` (path halving, union by size).
struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind { parent: (0..n as u32).collect(), size: vec![1; n] }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] as usize != x {
            let p = self.parent[x] as usize;
            self.parent[x] = self.parent[p];
            x = self.parent[x] as usize;
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a as u32;
        self.size[a] += self.size[b];
    }
}
