//! Meshing a block model (seed 000 §2.4.1, §2.4.3): every quad of the control mesh is a patch of
//! the Catmull–Clark limit surface ([`LimitEvaluator`]), cut adaptively and anisotropically into
//! sub-patches by a kd-tree, optionally displaced, and triangulated without cracks.
//!
//! # Sub-patches (Fig. 10)
//! A sub-patch is sampled on a 5 × 5 grid of "texels" (displaced surface points). It is split in
//! u when, in some row, a texel lies farther than the tolerance from the segment joining the
//! row's first and last texels; in v likewise by columns; in both when both ask; always at its
//! middle. (The distance is measured along the surface normal, so that flat patches with curved
//! iso-lines are not split; see `flatness`.) Rows and columns can all be straight while the
//! sub-patch is twisted (a saddle `z = uv` has straight iso-lines), and the two triangles that
//! will replace it then miss its middle by a quarter of the twist: so a sub-patch whose texels
//! lie farther than the tolerance from those two triangles is split in both directions too.
//! Each direction stops at `max_depth` splits. Parameters are integers on a 2^max_depth grid per
//! patch, so every corner of every sub-patch is exact.
//!
//! # No cracks (§2.4.3)
//! A patch edge is sampled at the union of the sub-patch corners both patches sharing it put
//! there (the finer of the two sides wherever they differ), and every vertex is computed once,
//! from the first patch that needs it, and shared: patches never disagree about a point. A
//! sub-patch whose sides carry such extra points (T-vertices, from a finer neighbour inside or
//! outside the patch) is triangulated as a fan about its centre; one without is two triangles
//! across its shorter diagonal. The result is a closed, manifold triangle mesh.
//!
//! # Creases
//! A triangle edge along a sharp side of its patch (a sharp or semi-sharp block edge,
//! [`ControlMesh::edge_sharpness`]) is tagged a crease of the output mesh with the block edge's
//! sharpness, so that booleans, exporters and later subdivision see the block's sharp edges as
//! the mesh's.
//!
//! # Displacement
//! A closure `d(p, n, u, v)` moves each point `p` of the limit surface along its unit normal `n`
//! by `d`, where `(u, v)` is the block-face parameter (see [`super::block`]) the point inherits
//! from its sub-face (seed 000 §2.4.1: the parameterisation inherited from the block faces).
//! Across block edges the parameters of the two faces differ; each vertex takes the one of the
//! patch that computed it, so the mesh stays closed whatever the closure does.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::limits::{check_memory, CancelToken, LimitError};
use crate::math::Vec3;
use crate::mesh::{mesh_bytes, FacePart, Mesh};
use crate::subdiv::LimitEvaluator;

use super::{BlockError, BlockModel, ControlMesh, SubFaceRef};

/// A displacement function: `(position, unit normal, u, v) -> offset along the normal`. An
/// `Err` aborts the meshing with its message.
pub type Displacement<'a> = &'a dyn Fn(Vec3, Vec3, f64, f64) -> Result<f64, String>;

/// A progress report of a long meshing: called now and then with `(done, total)` work units
/// (each patch counts twice: once for its kd-tree, once for its triangles), `done` increasing and
/// ending at `total`. The kernel draws nothing; a front end may show a bar.
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize);

/// The deepest kd-tree the options accept (per direction).
pub const MAX_DEPTH: u32 = 14;

/// Texels per row and column of the flatness test.
const TEXELS: usize = 5;

/// Patches whose kd-trees are built between two progress reports.
const PATCH_CHUNK: usize = 512;

/// Options of [`BlockModel::tessellate`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct MeshOptions {
    /// The largest distance allowed between a texel and the chord of its row or column.
    ///
    /// Default value: `None`, meaning 0.001 × the diagonal of the control mesh's bounds.
    pub tolerance: Option<f64>,
    /// The most times a patch is halved in each of u and v.
    ///
    /// Default value: 8.
    pub max_depth: u32,
}

impl MeshOptions {
    /// The default options.
    pub const DEFAULT: MeshOptions = MeshOptions { tolerance: None, max_depth: 8 };

    /// These options with the tolerance set.
    #[must_use]
    pub fn with_tolerance(mut self, tolerance: f64) -> MeshOptions {
        self.tolerance = Some(tolerance);
        self
    }

    /// These options with the depth limit set.
    #[must_use]
    pub fn with_max_depth(mut self, max_depth: u32) -> MeshOptions {
        self.max_depth = max_depth;
        self
    }

    fn check(&self) -> Result<(), BlockError> {
        if let Some(t) = self.tolerance {
            if !(t.is_finite() && t > 0.0) {
                return Err(BlockError::BadOption { name: "tolerance", value: t, reason: "must be a positive number" });
            }
        }
        if self.max_depth > MAX_DEPTH {
            return Err(BlockError::BadOption {
                name: "max_depth",
                value: f64::from(self.max_depth),
                reason: "must be between 0 and 14",
            });
        }
        Ok(())
    }
}

impl Default for MeshOptions {
    fn default() -> MeshOptions {
        MeshOptions::DEFAULT
    }
}

/// Counts of one meshing, as the paper reports them (Figs. 15, 18–20).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BlockStats {
    /// Blocks in the model.
    pub blocks: usize,
    /// Patches: quads of the control mesh.
    pub patches: usize,
    /// Leaves of the patches' kd-trees.
    pub sub_patches: usize,
    /// Triangles of the final mesh.
    pub triangles: usize,
}

/// A meshed model: the closed triangle mesh, its counts and where each triangle comes from.
#[derive(Clone, Debug)]
pub struct Tessellation {
    /// The closed, manifold triangle mesh.
    pub mesh: Mesh,
    /// Its counts.
    pub stats: BlockStats,
    /// For every triangle of `mesh`, in face order, the block sub-face it lies on: the
    /// [`PatchSource::subface`](super::PatchSource) of the patch that emitted it.
    pub triangle_sources: Vec<SubFaceRef>,
    /// The control mesh the surface was made from ([`BlockModel::control_mesh`]'s polygons).
    pub control: Mesh,
}

/// A tessellated control mesh ([`tessellate_control`]).
#[derive(Clone, Debug)]
pub struct ControlTessellation {
    /// The closed, manifold triangle mesh.
    pub mesh: Mesh,
    /// Leaves of all the patches' kd-trees.
    pub sub_patches: usize,
    /// For every triangle of `mesh`, in face order, the patch (control-mesh face) it lies on;
    /// its sub-face is that patch's [`PatchSource::subface`](super::PatchSource).
    pub triangle_patches: Vec<u32>,
}

impl BlockModel {
    /// The model's surface as a closed, manifold triangle mesh: the control mesh
    /// ([`BlockModel::control_mesh`]) tessellated by [`tessellate_control`].
    ///
    /// # Errors
    /// Those of [`BlockModel::control_mesh`] and [`tessellate_control`].
    pub fn tessellate(
        &self,
        options: &MeshOptions,
        displacement: Option<Displacement<'_>>,
    ) -> Result<Tessellation, BlockError> {
        self.tessellate_with_progress(options, displacement, &mut |_, _| {})
    }

    /// [`BlockModel::tessellate`], reporting its progress to `progress`.
    ///
    /// # Errors
    /// As [`BlockModel::tessellate`].
    pub fn tessellate_with_progress(
        &self,
        options: &MeshOptions,
        displacement: Option<Displacement<'_>>,
        progress: Progress<'_>,
    ) -> Result<Tessellation, BlockError> {
        options.check()?;
        let cm = self.control_mesh()?;
        let ControlTessellation { mut mesh, sub_patches, triangle_patches } =
            tessellate_control_with_progress(&cm, options, displacement, progress)?;
        let triangle_sources: Vec<SubFaceRef> =
            triangle_patches.iter().map(|&f| cm.sources[f as usize].subface).collect();
        self.color_triangles(&mut mesh, &triangle_sources)?;
        let stats = BlockStats {
            blocks: self.blocks().len(),
            patches: cm.mesh.face_count(),
            sub_patches,
            triangles: mesh.face_count(),
        };
        Ok(Tessellation { mesh, stats, triangle_sources, control: cm.mesh })
    }
}

impl BlockModel {
    /// Colours each triangle of `mesh` with the colour of the block it lies on (`sources`, one
    /// per triangle): one face part per colour, in the order first met, and one without a colour
    /// for the blocks that have none. Nothing when no block has a colour.
    fn color_triangles(&self, mesh: &mut Mesh, sources: &[SubFaceRef]) -> Result<(), BlockError> {
        if self.blocks().iter().all(|b| b.color().is_none()) {
            return Ok(());
        }
        let mut parts: Vec<FacePart> = Vec::new();
        let mut block_part: Vec<Option<u32>> = vec![None; self.blocks().len()];
        let mut ids = Vec::with_capacity(sources.len());
        for s in sources {
            let b = s.block as usize;
            let id = *block_part[b].get_or_insert_with(|| {
                let part = FacePart { color: self.blocks()[b].color(), ..FacePart::default() };
                match parts.iter().position(|p| *p == part) {
                    Some(i) => i as u32,
                    None => {
                        parts.push(part);
                        parts.len() as u32 - 1
                    }
                }
            });
            ids.push(id);
        }
        mesh.set_face_parts(ids, parts).map_err(|e| BlockError::Internal(format!("block colours: {e}")))
    }
}

/// The limit surface of a control mesh: shared (it is `Sync`) by the threads that build the
/// kd-trees of a model without displacement.
struct Limit<'a> {
    ev: LimitEvaluator,
    /// The limit position of every control-mesh vertex.
    limits: Vec<Vec3>,
    cm: &'a ControlMesh,
}

/// The limit surface of a control mesh, displaced.
struct Surface<'a> {
    limit: &'a Limit<'a>,
    displacement: Option<Displacement<'a>>,
}

impl Surface<'_> {
    /// The limit point and unit normal at (u, v) of patch `f`. At a true corner of the surface
    /// (a vertex with three or more creases) the normal is undefined: there the position is the
    /// vertex's exact limit position and the normal the patch's own one a hair inside.
    fn sample(&self, f: u32, u: f64, v: f64) -> Result<(Vec3, Vec3), BlockError> {
        let Limit { ev, limits, cm } = self.limit;
        let e = match ev.eval(f, u, v) {
            Ok(s) => return Ok((s.position, s.normal)),
            Err(e) => e,
        };
        let degenerate = || BlockError::Degenerate { reason: e.to_string() };
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let k = corners.iter().position(|&(a, b)| a == u && b == v).ok_or_else(degenerate)?;
        let q = cm.mesh.face_vertices(f).nth(k).ok_or_else(degenerate)?;
        // A hair inside, a little more, then the control quad's own normal.
        for inside in [1e-7, 1e-5, 1e-3] {
            let (ui, vi) = ((u - inside).abs().min(u + inside), (v - inside).abs().min(v + inside));
            if let Ok(s) = ev.eval(f, ui, vi) {
                return Ok((limits[q as usize], s.normal));
            }
        }
        let n = cm.mesh.face_normal(f);
        if n == Vec3::ZERO {
            return Err(degenerate());
        }
        Ok((limits[q as usize], n))
    }

    /// The displaced point at (u, v) of patch `f`.
    fn point(&self, f: u32, u: f64, v: f64) -> Result<Vec3, BlockError> {
        self.point_normal(f, u, v).map(|(p, _)| p)
    }

    /// The displaced point at (u, v) of patch `f` and the limit surface's normal there.
    fn point_normal(&self, f: u32, u: f64, v: f64) -> Result<(Vec3, Vec3), BlockError> {
        let (p, normal) = self.sample(f, u, v)?;
        let Some(d) = self.displacement else { return Ok((p, normal)) };
        let [a, b, c, e] = self.limit.cm.sources[f as usize].uv;
        let w = [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v];
        let fu = w[0] * a[0] + w[1] * b[0] + w[2] * c[0] + w[3] * e[0];
        let fv = w[0] * a[1] + w[1] * b[1] + w[2] * c[1] + w[3] * e[1];
        let h = d(p, normal, fu, fv).map_err(|m| BlockError::Displacement {
            reason: format!("failed at ({}, {}, {}), (u, v) = ({fu}, {fv}): {m}", p.x, p.y, p.z),
        })?;
        if !h.is_finite() {
            return Err(BlockError::Displacement {
                reason: format!(
                    "returned {h} at ({}, {}, {}), (u, v) = ({fu}, {fv}); it must return a finite number",
                    p.x, p.y, p.z
                ),
            });
        }
        Ok((p + normal * h, normal))
    }
}

/// How far `p` lies off the segment `a`–`b`, measured along the unit normal `n`.
fn chord_deviation(p: Vec3, n: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let dd = d.length_squared();
    let t = if dd > 0.0 { ((p - a).dot(d) / dd).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + d * t)).dot(n).abs()
}

/// A sub-patch `[x0, y0, x1, y1]` on the patch's integer grid.
type Rect = [u32; 4];

/// Which directions sub-patch `r` of patch `f` must be split in (Fig. 10). The distance of a
/// texel from its row's chord is measured along the surface normal: a flat patch whose iso-lines
/// curve within its plane (every face of a sharp block) is flat, where the plain 3D distance
/// would split it without end.
fn flatness(s: &Surface<'_>, f: u32, r: Rect, scale: f64, tol: f64) -> Result<(bool, bool), BlockError> {
    let mut t = [[(Vec3::ZERO, Vec3::ZERO); TEXELS]; TEXELS];
    let last = (TEXELS - 1) as f64;
    for (j, row) in t.iter_mut().enumerate() {
        let v = (f64::from(r[1]) + f64::from(r[3] - r[1]) * j as f64 / last) / scale;
        for (i, texel) in row.iter_mut().enumerate() {
            let u = (f64::from(r[0]) + f64::from(r[2] - r[0]) * i as f64 / last) / scale;
            *texel = s.point_normal(f, u.min(1.0), v.min(1.0))?;
        }
    }
    let n = TEXELS - 1;
    let off = |p: (Vec3, Vec3), a: (Vec3, Vec3), b: (Vec3, Vec3)| chord_deviation(p.0, p.1, a.0, b.0) > tol;
    let split_u = t.iter().any(|row| (1..n).any(|i| off(row[i], row[0], row[n])));
    let split_v = (0..TEXELS).any(|i| (1..n).any(|j| off(t[j][i], t[0][i], t[n][i])));
    if split_u || split_v {
        return Ok((split_u, split_v));
    }
    // Twist: the texels against the two triangles across the shorter diagonal, at the same
    // parameters (as the triangulation of an unsplit sub-patch without T-vertices).
    let [p00, p10, p01, p11] = [t[0][0].0, t[0][n].0, t[n][0].0, t[n][n].0];
    let main = p00.distance(p11) <= p10.distance(p01);
    let twisted = (1..n).any(|j| {
        (1..n).any(|i| {
            let (a, b) = (i as f64 / last, j as f64 / last);
            let flat = if main {
                if a >= b {
                    p00 + (p10 - p00) * a + (p11 - p10) * b
                } else {
                    p00 + (p01 - p00) * b + (p11 - p01) * a
                }
            } else if a + b <= 1.0 {
                p00 + (p10 - p00) * a + (p01 - p00) * b
            } else {
                p11 + (p01 - p11) * (1.0 - a) + (p10 - p11) * (1.0 - b)
            };
            (t[j][i].0 - flat).dot(t[j][i].1).abs() > tol
        })
    });
    Ok((twisted, twisted))
}

/// The leaves of patch `f`'s kd-tree on a grid of `r` × `r` (Fig. 10), sorted.
///
/// Each split charges the cancellation `token` (this runs on worker threads, which have no
/// current token of their own), and every [`SPLITS_PER_CLOCK`] splits its deadline is read: a
/// split evaluates the limit surface at several points, so the charge's own clock reading
/// (every 1,024 units) would come a tenth of a second apart. Every 2^14 leaves, the mesh they
/// would make is checked against the memory budget.
fn kd_leaves(s: &Surface<'_>, f: u32, r: u32, tol: f64, token: &CancelToken) -> Result<Vec<Rect>, BlockError> {
    let scale = f64::from(r);
    let mut out = Vec::new();
    let mut stack = vec![[0, 0, r, r]];
    let mut checked = 0;
    let mut splits = 0usize;
    while let Some(rect) = stack.pop() {
        token.charge(1)?;
        splits += 1;
        if splits.is_multiple_of(SPLITS_PER_CLOCK) {
            if let Some(reason) = token.stopped() {
                return Err(LimitError::Stopped(reason).into());
            }
        }
        if out.len() >> 14 != checked {
            checked = out.len() >> 14;
            check_leaves(out.len() as f64)?;
        }
        let [x0, y0, x1, y1] = rect;
        let (can_u, can_v) = (x1 - x0 >= 2, y1 - y0 >= 2);
        let (su, sv) = if can_u || can_v { flatness(s, f, rect, scale, tol)? } else { (false, false) };
        let (su, sv) = (su && can_u, sv && can_v);
        let (xm, ym) = ((x0 + x1) / 2, (y0 + y1) / 2);
        match (su, sv) {
            (false, false) => out.push(rect),
            (true, false) => stack.extend([[x0, y0, xm, y1], [xm, y0, x1, y1]]),
            (false, true) => stack.extend([[x0, y0, x1, ym], [x0, ym, x1, y1]]),
            (true, true) => stack.extend([[x0, y0, xm, ym], [xm, y0, x1, ym], [x0, ym, xm, y1], [xm, ym, x1, y1]]),
        }
    }
    out.sort_unstable();
    Ok(out)
}

/// Splits of [`kd_leaves`] between two readings of the token's deadline (about a millisecond).
const SPLITS_PER_CLOCK: usize = 64;

/// Refuses `leaves` sub-patches when the triangle mesh they make (about two vertices and four
/// triangles each, with the leaves themselves) is over the memory budget.
fn check_leaves(leaves: f64) -> Result<(), LimitError> {
    check_memory(
        || format!("the tessellation's {} sub-patches", leaves as u64),
        mesh_bytes(2.0 * leaves, 12.0 * leaves, 4.0 * leaves) + 16.0 * leaves,
    )
}

/// Where a vertex of the tessellation lies, so that patches sharing it find the same one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum VKey {
    /// A vertex of the control mesh.
    Corner(u32),
    /// A point of a control-mesh edge (named by its lower half-edge), at a grid parameter along
    /// that half-edge.
    Edge(u32, u32),
    /// A grid point inside a patch.
    Inner(u32, u32, u32),
    /// The centre of a sub-patch (patch, leaf) triangulated as a fan.
    Centre(u32, u32),
}

/// Tessellates a control mesh into a triangle mesh, counting sub-patches and recording each
/// triangle's sub-face. See the [module documentation](self).
///
/// # Errors
/// - [`BlockError::BadOption`] for a tolerance that is not positive or a depth above
///   [`MAX_DEPTH`];
/// - [`BlockError::Displacement`] when the closure fails or returns a non-finite value;
/// - [`BlockError::Degenerate`] where the limit surface has no normal (squashed blocks).
pub fn tessellate_control(
    cm: &ControlMesh,
    options: &MeshOptions,
    displacement: Option<Displacement<'_>>,
) -> Result<ControlTessellation, BlockError> {
    tessellate_control_with_progress(cm, options, displacement, &mut |_, _| {})
}

/// [`tessellate_control`], reporting its progress to `progress`.
///
/// # Errors
/// As [`tessellate_control`].
pub fn tessellate_control_with_progress(
    cm: &ControlMesh,
    options: &MeshOptions,
    displacement: Option<Displacement<'_>>,
    progress: Progress<'_>,
) -> Result<ControlTessellation, BlockError> {
    options.check()?;
    let mesh = &cm.mesh;
    let ev = LimitEvaluator::new(mesh).map_err(|e| BlockError::internal("", e))?;
    let tol = options.tolerance.unwrap_or_else(|| 1e-3 * mesh.bounds().size().length());
    let limits = mesh.catmull_clark_limit().map_err(|e| BlockError::internal("", e))?.positions().to_vec();
    let limit = Limit { ev, limits, cm };
    let surface = Surface { limit: &limit, displacement };
    let r: u32 = 1 << options.max_depth;
    let scale = f64::from(r);
    let nf = mesh.face_count() as u32;
    let token = crate::limits::current();

    // 1. The kd-tree of every patch: in parallel, chunk by chunk, when no script closure is
    // involved (a closure runs on the caller's thread); the same trees either way.
    let total = 2 * nf as usize;
    let mut leaves: Vec<Vec<Rect>> = Vec::with_capacity(nf as usize);
    for start in (0..nf).step_by(PATCH_CHUNK) {
        let end = (start + PATCH_CHUNK as u32).min(nf);
        let chunk: Vec<Result<Vec<Rect>, BlockError>> = if displacement.is_none() {
            (start..end)
                .into_par_iter()
                .map(|f| kd_leaves(&Surface { limit: &limit, displacement: None }, f, r, tol, &token))
                .collect()
        } else {
            (start..end).map(|f| kd_leaves(&surface, f, r, tol, &token)).collect()
        };
        for l in chunk {
            leaves.push(l?);
        }
        progress(end as usize, total);
    }
    check_leaves(leaves.iter().map(|l| l.len() as f64).sum())?;

    // 2. The points along every control-mesh edge: the union of both sides' sub-patch corners,
    // as parameters along its lower half-edge.
    let hes: Vec<[u32; 4]> = (0..nf)
        .map(|f| {
            let mut h = [0u32; 4];
            for (k, x) in mesh.face_halfedges(f).take(4).enumerate() {
                h[k] = x;
            }
            h
        })
        .collect();
    let to_key = |h: u32, t: u32| -> (u32, u32) {
        let e = mesh.edge_key(h);
        (e, if e == h { t } else { r - t })
    };
    let mut edge_pts: Vec<Vec<u32>> = vec![Vec::new(); mesh.halfedge_count()];
    for (patch, h) in leaves.iter().zip(&hes) {
        for rect in patch {
            for (k, t) in side_points(*rect, r) {
                if t > 0 && t < r {
                    let (e, te) = to_key(h[k], t);
                    edge_pts[e as usize].push(te);
                }
            }
        }
    }
    for pts in &mut edge_pts {
        pts.sort_unstable();
        pts.dedup();
    }

    // 3. Vertices, shared through their keys, and triangles.
    let mut ids: HashMap<VKey, u32> = HashMap::new();
    let mut positions: Vec<Vec3> = Vec::new();
    let mut tris: Vec<u32> = Vec::new();
    let mut triangle_patches: Vec<u32> = Vec::new();
    let mut creases: Vec<([u32; 2], f64)> = Vec::new();
    let mut sub_patches = 0usize;
    for f in 0..nf {
        let h = hes[f as usize];
        let key_of = |x: u32, y: u32| -> VKey {
            let corner = |k: usize| VKey::Corner(mesh.origin(h[k]));
            match (x, y) {
                (0, 0) => corner(0),
                (x, 0) if x == r => corner(1),
                (x, y) if x == r && y == r => corner(2),
                (0, y) if y == r => corner(3),
                _ => {
                    let side = if y == 0 {
                        Some((0, x))
                    } else if x == r {
                        Some((1, y))
                    } else if y == r {
                        Some((2, r - x))
                    } else if x == 0 {
                        Some((3, r - y))
                    } else {
                        None
                    };
                    match side {
                        Some((k, t)) => {
                            let (e, te) = to_key(h[k], t);
                            VKey::Edge(e, te)
                        }
                        None => VKey::Inner(f, x, y),
                    }
                }
            }
        };
        // Every grid point of this patch: sub-patch corners and the points of its four edges.
        let mut rows: HashMap<u32, Vec<u32>> = HashMap::new();
        let mut cols: HashMap<u32, Vec<u32>> = HashMap::new();
        let mut add = |x: u32, y: u32| {
            rows.entry(y).or_default().push(x);
            cols.entry(x).or_default().push(y);
        };
        for rect in &leaves[f as usize] {
            let [x0, y0, x1, y1] = *rect;
            for (x, y) in [(x0, y0), (x1, y0), (x1, y1), (x0, y1)] {
                add(x, y);
            }
        }
        for (k, &hk) in h.iter().enumerate() {
            let e = mesh.edge_key(hk);
            for &te in &edge_pts[e as usize] {
                let t = if e == hk { te } else { r - te };
                let (x, y) = match k {
                    0 => (t, 0),
                    1 => (r, t),
                    2 => (r - t, r),
                    _ => (0, r - t),
                };
                add(x, y);
            }
        }
        for list in rows.values_mut().chain(cols.values_mut()) {
            list.sort_unstable();
            list.dedup();
        }
        let between = |list: Option<&Vec<u32>>, a: u32, b: u32| -> Vec<u32> {
            let Some(l) = list else { return Vec::new() };
            let (lo, hi) = (a.min(b), a.max(b));
            let mut out: Vec<u32> = l.iter().copied().filter(|&z| z > lo && z < hi).collect();
            if a > b {
                out.reverse();
            }
            out
        };
        let vertex = |ids: &mut HashMap<VKey, u32>,
                      positions: &mut Vec<Vec3>,
                      k: VKey,
                      u: f64,
                      v: f64|
         -> Result<u32, BlockError> {
            if let Some(&id) = ids.get(&k) {
                return Ok(id);
            }
            let p = surface.point(f, u, v)?;
            positions.push(p);
            let id = (positions.len() - 1) as u32;
            ids.insert(k, id);
            Ok(id)
        };
        for (li, rect) in leaves[f as usize].iter().enumerate() {
            sub_patches += 1;
            let [x0, y0, x1, y1] = *rect;
            // The boundary in (u, v) counter-clockwise order, T-vertices included.
            let mut ring: Vec<(u32, u32)> = vec![(x0, y0)];
            ring.extend(between(rows.get(&y0), x0, x1).into_iter().map(|x| (x, y0)));
            ring.push((x1, y0));
            ring.extend(between(cols.get(&x1), y0, y1).into_iter().map(|y| (x1, y)));
            ring.push((x1, y1));
            ring.extend(between(rows.get(&y1), x1, x0).into_iter().map(|x| (x, y1)));
            ring.push((x0, y1));
            ring.extend(between(cols.get(&x0), y1, y0).into_iter().map(|y| (x0, y)));
            let mut vid = Vec::with_capacity(ring.len());
            for &(x, y) in &ring {
                let id = vertex(&mut ids, &mut positions, key_of(x, y), f64::from(x) / scale, f64::from(y) / scale)?;
                vid.push(id);
            }
            // Ring edges along a sharp side of the patch lie on the crease: tag them.
            for k in 0..ring.len() {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                let side = [a.1 == 0 && b.1 == 0, a.0 == r && b.0 == r, a.1 == r && b.1 == r, a.0 == 0 && b.0 == 0];
                let s = side
                    .iter()
                    .zip(&h)
                    .filter(|&(&on, _)| on)
                    .map(|(_, &hk)| cm.edge_sharpness[hk as usize])
                    .fold(0.0, f64::max);
                if s > 0.0 {
                    creases.push(([vid[k], vid[(k + 1) % vid.len()]], s));
                }
            }
            if vid.len() == 4 {
                let p: Vec<Vec3> = vid.iter().map(|&i| positions[i as usize]).collect();
                if p[0].distance(p[2]) <= p[1].distance(p[3]) {
                    tris.extend([vid[0], vid[1], vid[2], vid[0], vid[2], vid[3]]);
                } else {
                    tris.extend([vid[0], vid[1], vid[3], vid[1], vid[2], vid[3]]);
                }
            } else {
                let (u, v) = (f64::from(x0 + x1) * 0.5 / scale, f64::from(y0 + y1) * 0.5 / scale);
                let c = vertex(&mut ids, &mut positions, VKey::Centre(f, li as u32), u, v)?;
                for k in 0..vid.len() {
                    tris.extend([c, vid[k], vid[(k + 1) % vid.len()]]);
                }
            }
            triangle_patches.resize(tris.len() / 3, f);
        }
        progress(nf as usize + f as usize + 1, total);
    }
    let arities = vec![3u32; tris.len() / 3];
    let mut out = Mesh::from_indexed(positions, &tris, &arities)
        .map_err(|e| BlockError::internal("the tessellation is not a manifold mesh", e))?;
    for ([a, b], s) in creases {
        let h = out
            .find_halfedge(a, b)
            .ok_or_else(|| BlockError::Internal(format!("a crease of the tessellation ({a}, {b}) is no edge")))?;
        out.set_edge_sharpness_halfedge(h, s);
    }
    if out.face_count() != triangle_patches.len() {
        return Err(BlockError::Internal(format!(
            "{} triangle sources for {} triangles",
            triangle_patches.len(),
            out.face_count()
        )));
    }
    Ok(ControlTessellation { mesh: out, sub_patches, triangle_patches })
}

/// The corners of sub-patch `rect` lying on the patch's four sides: `(side, parameter along the
/// side's half-edge)`. Side 0 runs along v = 0 (q0 → q1), 1 along u = 1, 2 along v = 1
/// (q2 → q3), 3 along u = 0.
fn side_points(rect: Rect, r: u32) -> Vec<(usize, u32)> {
    let [x0, y0, x1, y1] = rect;
    let mut out = Vec::new();
    if y0 == 0 {
        out.extend([(0, x0), (0, x1)]);
    }
    if x1 == r {
        out.extend([(1, y0), (1, y1)]);
    }
    if y1 == r {
        out.extend([(2, r - x0), (2, r - x1)]);
    }
    if x0 == 0 {
        out.extend([(3, r - y0), (3, r - y1)]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::test_models::{along_box_edge, boxed, sharp_box};
    use crate::blocks::{Block, Face};

    #[test]
    fn each_block_gives_its_colour_to_the_faces_made_from_it() {
        let (red, blue) = ([1.0, 0.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]);
        let mut a = Block::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap();
        a.set_color(Some(red)).unwrap();
        let mut b = Block::from_bounds(Vec3::new(3.0, 0.0, 0.0), Vec3::new(4.0, 1.0, 1.0)).unwrap();
        b.set_color(Some(blue)).unwrap();
        let c = Block::from_bounds(Vec3::new(6.0, 0.0, 0.0), Vec3::new(7.0, 1.0, 1.0)).unwrap();
        let mut model = BlockModel::new();
        for blk in [a.clone(), b, c] {
            model.add(blk);
        }
        let t = model.tessellate(&MeshOptions::DEFAULT, None).unwrap();
        check_solid(&t.mesh);
        for (f, s) in t.triangle_sources.iter().enumerate() {
            let want = [Some(red), Some(blue), None][s.block as usize];
            assert_eq!(t.mesh.face_color(f as u32), want, "face {f} of block {}", s.block);
        }
        // No colour on any block: no parts at all.
        let mut plain = BlockModel::new();
        plain.add(Block::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap());
        assert!(plain.tessellate(&MeshOptions::DEFAULT, None).unwrap().mesh.face_part_ids().is_none());
        // A bad colour is refused and the block keeps its own.
        assert!(matches!(a.set_color(Some([0.0, 1.5, 0.0, 1.0])), Err(BlockError::BadColor { component: 1, .. })));
        assert_eq!(a.color(), Some(red));
    }

    fn check_solid(m: &Mesh) {
        assert!(m.is_triangle_mesh());
        assert!(m.is_closed(), "not closed");
        assert!(m.is_manifold(), "not manifold");
        assert_eq!(m.genus(), 0);
    }

    #[test]
    fn an_all_sharp_block_is_its_exact_box() {
        // Creases all round make every face a plane bounded by straight creases: the limit
        // surface is the box itself, and no sub-patch needs splitting.
        let mut b = boxed([0.0; 3], [1.0, 2.0, 3.0]);
        b.sharp_all();
        b.subdivide(Face::PosZ, 3, 2).unwrap();
        let mut m = BlockModel::new();
        m.add(b);
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(1e-6), None).unwrap();
        check_solid(&t.mesh);
        assert!((t.mesh.volume() - 6.0).abs() < 1e-9, "volume {}", t.mesh.volume());
        let bb = t.mesh.bounds();
        assert!(bb.min.distance(Vec3::ZERO) < 1e-12 && bb.max.distance(Vec3::new(1.0, 2.0, 3.0)) < 1e-12);
        assert_eq!(t.stats.sub_patches, t.stats.patches);
    }

    #[test]
    fn semi_sharp_block_edges_bevel_between_smooth_and_sharp() {
        // Every edge of a 1 × 2 × 3 box at sharpness 0, 1, 2.5 and infinity: the volume grows
        // strictly with the sharpness (smooth rounds the box most, sharp is the box), the
        // semi-sharp control meshes are refined until no semi-sharp crease is left, and the
        // surface's edges along the box's edges carry the sharpness the block set.
        let opts = MeshOptions::DEFAULT.with_tolerance(1e-4);
        let (lo, hi) = ([0.0; 3], [1.0, 2.0, 3.0]);
        let mut volumes = Vec::new();
        for s in [0.0, 1.0, 2.5, f64::INFINITY] {
            let mut b = boxed(lo, hi);
            for e in crate::blocks::Edge::all() {
                b.set_sharpness(e, s).unwrap();
            }
            let mut m = BlockModel::new();
            m.add(b);
            let cm = m.control_mesh().unwrap();
            assert!(!cm.mesh.has_semi_sharp());
            // One step of the 6 quads, then ⌈s⌉ − 1 more while semi-sharp creases remain.
            let levels = if s.is_finite() && s > 1.0 { s.ceil() as u32 } else { 1 };
            assert_eq!(cm.mesh.face_count(), 24 * 4usize.pow(levels - 1), "sharpness {s}");
            assert_eq!(cm.sources.len(), cm.mesh.face_count());
            let t = m.tessellate(&opts, None).unwrap();
            check_solid(&t.mesh);
            let p = t.mesh.positions();
            let creases = t.mesh.crease_sharpnesses();
            let length: f64 = creases.iter().map(|&([a, b], _)| p[a as usize].distance(p[b as usize])).sum();
            if s == 0.0 {
                assert!(creases.is_empty());
            } else {
                assert!(creases.iter().all(|&(_, x)| x == s), "sharpness {s}");
                // A sharp crease is the box's edge; a semi-sharp one is rounded off it, and as
                // long as the rounded edges (between the smooth block's and the box's).
                if s.is_finite() {
                    assert!(length > 12.0 && length < 24.0, "sharpness {s}: crease length {length}");
                } else {
                    assert!(creases.iter().all(|&([a, b], _)| along_box_edge(p[a as usize], p[b as usize], lo, hi)));
                    assert!((length - 24.0).abs() < 1e-12, "crease length {length}");
                }
            }
            volumes.push(t.mesh.volume());
        }
        assert!(volumes.windows(2).all(|w| w[0] < w[1]), "volumes {volumes:?}");
        assert!((volumes[3] - 6.0).abs() < 1e-9);
        // The sources still name the box's six faces with (u, v) inside [0, 1].
        let mut b = boxed(lo, hi);
        b.set_sharpness(crate::blocks::Edge::parse("+x+y").unwrap(), 2.5).unwrap();
        let mut m = BlockModel::new();
        m.add(b);
        let cm = m.control_mesh().unwrap();
        assert!(cm.sources.iter().all(|s| s.uv.iter().flatten().all(|&x| (0.0..=1.0).contains(&x))));
        let faces: std::collections::HashSet<Face> = cm.sources.iter().map(|s| s.subface.face).collect();
        assert_eq!(faces.len(), 6);
        // Bad sharpness is refused and leaves the block as it was.
        let mut b = boxed(lo, hi);
        let e = crate::blocks::Edge::parse("+x+y").unwrap();
        assert!(matches!(b.set_sharpness(e, -1.0), Err(BlockError::BadSharpness { .. })));
        assert!(b.set_sharpness(e, f64::NAN).is_err());
        assert_eq!(b.sharpness(e), 0.0);
    }

    #[test]
    fn sharp_block_faces_lie_exactly_on_their_planes() {
        // Bounds that are not binary fractions (0.3, 0.7, -0.1 …) and uneven grids: every vertex
        // of a triangle on a face must have that face's coordinate to the last bit, or faces of
        // two blocks meant to touch miss by an ulp (a sliver in a boolean).
        let (lo, hi) = (Vec3::new(-0.1, 0.2, 0.3), Vec3::new(0.3, 0.7, 1.1));
        let grids = [(Face::PosX, 3, 7), (Face::NegY, 5, 3), (Face::PosZ, 6, 9)];
        let m = sharp_box(lo.to_array(), hi.to_array(), &grids);
        let t = m.tessellate(&MeshOptions::DEFAULT, None).unwrap();
        check_solid(&t.mesh);
        let bounds = [lo, hi];
        let mut off = 0;
        for (f, src) in t.triangle_sources.iter().enumerate() {
            let a = src.face.axis();
            let plane = bounds[usize::from(src.face.is_high())].to_array()[a];
            for v in t.mesh.face_vertices(f as u32) {
                let x = t.mesh.positions()[v as usize].to_array()[a];
                off += usize::from(x != plane);
            }
        }
        assert_eq!(off, 0, "vertices off their face's plane");
    }

    #[test]
    fn sharp_block_edges_are_tagged_creases() {
        // An all-sharp 1 × 2 × 3 box: its twelve edges, 24 long in all, are creases, and no
        // other edge is (the sub-face seams inside a face are smooth).
        let (lo, hi) = ([0.0; 3], [1.0, 2.0, 3.0]);
        let t = sharp_box(lo, hi, &[(Face::PosZ, 3, 2)]).tessellate(&MeshOptions::DEFAULT, None).unwrap();
        let p = t.mesh.positions();
        let creases = t.mesh.crease_pairs();
        assert!(creases.iter().all(|&[a, b]| along_box_edge(p[a as usize], p[b as usize], lo, hi)));
        let length: f64 = creases.iter().map(|&[a, b]| p[a as usize].distance(p[b as usize])).sum();
        assert!((length - 24.0).abs() < 1e-12, "crease length {length}");
        // A smooth block has none.
        let mut m = BlockModel::new();
        m.add(boxed([0.0; 3], [1.0, 2.0, 3.0]));
        assert_eq!(m.tessellate(&MeshOptions::DEFAULT, None).unwrap().mesh.crease_count(), 0);
    }

    #[test]
    fn every_triangle_knows_its_sub_face() {
        // An all-sharp box is never split: each sub-face of nu × nv polygons is 4 Catmull–Clark
        // quads (one per polygon corner), each two triangles, lying in the plane of its face.
        let mut b = boxed([0.0; 3], [1.0, 2.0, 3.0]);
        b.sharp_all();
        b.subdivide(Face::PosZ, 3, 2).unwrap();
        b.subdivide(Face::NegX, 2, 1).unwrap();
        let mut m = BlockModel::new();
        m.add(b);
        let t = m.tessellate(&MeshOptions::DEFAULT, None).unwrap();
        assert_eq!(t.triangle_sources.len(), t.mesh.face_count());
        let cm = m.control_mesh().unwrap();
        let mut per: HashMap<SubFaceRef, usize> = HashMap::new();
        for s in &t.triangle_sources {
            *per.entry(*s).or_default() += 1;
        }
        // 4 sub-faces on each of 4 faces, 6 on +z, 2 on -x; each polygon has 4 corners (the
        // T-vertices lie on the crease of the neighbouring face, so only its quads gain corners).
        assert_eq!(per.len(), 6 + 2 + 4);
        for (k, &src) in cm.polygon_sources.iter().enumerate() {
            let arity = cm.polygons.face_vertices(k as u32).count();
            assert_eq!(per[&src], 2 * arity, "{src:?}");
        }
        let bb = [Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)];
        for (f, src) in t.triangle_sources.iter().enumerate() {
            assert_eq!(src.block, 0);
            let c = t.mesh.face_vertices(f as u32).map(|v| t.mesh.positions()[v as usize]).sum::<Vec3>() / 3.0;
            let a = src.face.axis();
            let plane = bb[usize::from(src.face.is_high())].to_array()[a];
            assert!((c.to_array()[a] - plane).abs() < 1e-12, "triangle {f} of {src:?} at {c:?}");
            let (nu, nv) = m.blocks()[0].divisions(src.face);
            let (au, av) = src.face.uv_axes();
            let (i, j) = (src.sub % nu, src.sub / nu);
            let size = bb[1] - bb[0];
            let (u, v) = (c.to_array()[au] / size.to_array()[au], c.to_array()[av] / size.to_array()[av]);
            assert!(u >= f64::from(i) / f64::from(nu) && u <= f64::from(i + 1) / f64::from(nu), "{src:?} u {u}");
            assert!(v >= f64::from(j) / f64::from(nv) && v <= f64::from(j + 1) / f64::from(nv), "{src:?} v {v}");
        }
        // Connected, smooth and split models: still one source per triangle, each from a patch.
        let hand = crate::blocks::test_models::hand();
        let t = hand.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.02), None).unwrap();
        assert_eq!(t.triangle_sources.len(), t.stats.triangles);
        let cm = hand.control_mesh().unwrap();
        let patch_sources: std::collections::HashSet<SubFaceRef> = cm.sources.iter().map(|s| s.subface).collect();
        let tri_sources: std::collections::HashSet<SubFaceRef> = t.triangle_sources.iter().copied().collect();
        assert_eq!(patch_sources, tri_sources);
        assert!((0..6).all(|b| tri_sources.iter().any(|s| s.block == b)));
    }

    #[test]
    fn sharp_blocks_with_t_vertices_on_any_face_are_exact_boxes() {
        // A T-vertex on a crease is a corner of a quad whose two edges there are collinear: its
        // normal is undefined at that corner, and meshing must still go through.
        for f in Face::ALL {
            let mut b = boxed([0.0; 3], [1.0, 2.0, 3.0]);
            b.sharp_all();
            b.subdivide(f, 2, 3).unwrap();
            let mut m = BlockModel::new();
            m.add(b);
            let t = m.tessellate(&MeshOptions::DEFAULT, None).unwrap_or_else(|e| panic!("face {}: {e}", f.name()));
            check_solid(&t.mesh);
            assert!((t.mesh.volume() - 6.0).abs() < 1e-9, "face {}: volume {}", f.name(), t.mesh.volume());
        }
    }

    #[test]
    fn a_smooth_block_is_rounded_closed_and_finer_with_a_smaller_tolerance() {
        let mut m = BlockModel::new();
        m.add(boxed([-1.0; 3], [1.0; 3]));
        let coarse = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.02), None).unwrap();
        let fine = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.002), None).unwrap();
        for t in [&coarse, &fine] {
            check_solid(&t.mesh);
            assert_eq!(t.stats.patches, 24);
            assert_eq!(t.stats.blocks, 1);
            // The limit surface of the cube lies inside it and outside the octahedron.
            let v = t.mesh.volume();
            assert!(v < 8.0 && v > 4.0 / 3.0, "volume {v}");
        }
        assert!(fine.stats.triangles > coarse.stats.triangles);
        // The face centre of the ±1 cube's limit surface is at 68/81 (see subdiv::limit).
        let top = fine.mesh.positions().iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((top - 68.0 / 81.0).abs() < 1e-3, "top {top}");
    }

    /// The largest distance from a dense sampling of the exact limit surface (`n + 1` × `n + 1`
    /// points per patch) to the triangles the tessellation made of that patch and of the patches around it
    /// (sharing a control-mesh vertex): an upper bound on the distance to the whole mesh.
    fn limit_distance(cm: &ControlMesh, t: &ControlTessellation, n: u32) -> f64 {
        let ev = LimitEvaluator::new(&cm.mesh).unwrap();
        let nf = cm.mesh.face_count();
        let mut per_patch: Vec<Vec<[Vec3; 3]>> = vec![Vec::new(); nf];
        let p = t.mesh.positions();
        for (tri, &f) in t.triangle_patches.iter().enumerate() {
            let v: Vec<Vec3> = t.mesh.face_vertices(tri as u32).map(|i| p[i as usize]).collect();
            per_patch[f as usize].push([v[0], v[1], v[2]]);
        }
        let mut worst = 0.0f64;
        for f in 0..nf as u32 {
            let mut around: Vec<u32> = cm.mesh.face_vertices(f).flat_map(|v| cm.mesh.vertex_faces(v)).collect();
            around.sort_unstable();
            around.dedup();
            let tris: Vec<[Vec3; 3]> = around.iter().flat_map(|&g| per_patch[g as usize].iter().copied()).collect();
            for j in 0..=n {
                for i in 0..=n {
                    let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    let Ok(s) = ev.eval(f, u, v) else { continue };
                    let d = tris
                        .iter()
                        .map(|t| s.position.distance(crate::math::closest_on_triangle(s.position, t[0], t[1], t[2])))
                        .fold(f64::MAX, f64::min);
                    worst = worst.max(d);
                }
            }
        }
        worst
    }

    /// The tolerance-halving curve of the smooth cube (24 patches) and the connected hand of
    /// Fig. 5c: `halvings` times halved from 0.04, the distance from `n + 1` × `n + 1` limit
    /// points per patch to the mesh. The flatness test bounds texels against row and column
    /// chords and the two triangles; what the surface does between texels is not tested, so the
    /// distance may exceed the tolerance, but only a little, and it must shrink with it.
    fn tolerance_curve(halvings: u32, n: u32) {
        for (name, m) in [("cube", single(boxed([-1.0; 3], [1.0; 3]))), ("hand", crate::blocks::test_models::hand())] {
            let cm = m.control_mesh().unwrap();
            let (mut first, mut last) = (None, f64::MAX);
            eprintln!("{name}: tolerance, triangles, max distance, distance / tolerance");
            for k in 0..=halvings {
                let tol = 0.04 / f64::from(1u32 << k);
                let t = tessellate_control(&cm, &MeshOptions::DEFAULT.with_tolerance(tol).with_max_depth(12), None)
                    .unwrap();
                let d = limit_distance(&cm, &t, n);
                eprintln!("{name}: {tol:.6} {} {d:.3e} {:.3}", t.mesh.face_count(), d / tol);
                assert!(d <= 1.5 * tol, "{name}: tolerance {tol}: distance {d}");
                // Refinement is nested (a split made at a tolerance is made at any smaller one),
                // so the distance never grows; a halving may add no split where the deviations
                // sit between the two tolerances.
                assert!(d <= last * 1.01, "{name}: tolerance {tol}: distance {d} grew from {last}");
                last = d;
                first.get_or_insert(d);
            }
            let shrink = f64::from(1u32 << halvings) / 4.0;
            assert!(last * shrink < first.unwrap_or(0.0), "{name}: {first:?} -> {last}");
        }
    }

    #[test]
    fn halving_the_tolerance_bounds_the_distance_to_the_limit_surface() {
        tolerance_curve(5, 16);
    }

    /// The curve for the notes: seven halvings, 33 × 33 points per patch (about a minute).
    /// `cargo test -p blocksmith-kernel --release tolerance_curve_in_full -- --ignored --nocapture`
    #[test]
    #[ignore = "slow: the full curve, printed"]
    fn tolerance_curve_in_full() {
        tolerance_curve(7, 32);
    }

    #[test]
    fn progress_is_reported_in_order_up_to_the_total() {
        let mut m = BlockModel::new();
        m.add(boxed([0.0; 3], [1.0; 3]));
        let mut seen = Vec::new();
        let t = m.tessellate_with_progress(&MeshOptions::DEFAULT, None, &mut |d, n| seen.push((d, n))).unwrap();
        // One report per chunk of kd-trees (24 patches: one chunk), then one per patch.
        let n = 2 * t.stats.patches;
        assert_eq!(seen.len(), 1 + t.stats.patches);
        assert_eq!(seen[0], (t.stats.patches, n));
        assert!(seen.windows(2).all(|w| w[0].0 < w[1].0) && seen.iter().all(|&(_, m)| m == n));
        assert_eq!(seen.last(), Some(&(n, n)));
    }

    #[test]
    fn parallel_kd_trees_give_the_serial_mesh() {
        // Without displacement the kd-trees are built on rayon's pool; a closure returning 0
        // forces the serial path and moves nothing: the meshes must be the same, bit for bit.
        let mut m = crate::blocks::building::building(&crate::blocks::building::BuildingPlan {
            storeys: 1,
            rooms_x: 3,
            rooms_y: 2,
        });
        m.add(boxed([-3.0; 3], [-1.0; 3]));
        let zero = |_p: Vec3, _n: Vec3, _u: f64, _v: f64| -> Result<f64, String> { Ok(0.0) };
        let o = MeshOptions::DEFAULT.with_tolerance(0.01);
        let (a, b) = (m.tessellate(&o, None).unwrap(), m.tessellate(&o, Some(&zero)).unwrap());
        assert!(a.stats.patches > PATCH_CHUNK, "{} patches: more than one chunk", a.stats.patches);
        assert_eq!(a.mesh.positions(), b.mesh.positions());
        assert_eq!(a.stats, b.stats);
        assert!((0..a.mesh.face_count() as u32).all(|f| a.mesh.face_vertices(f).eq(b.mesh.face_vertices(f))));
    }

    fn single(b: crate::blocks::Block) -> BlockModel {
        let mut m = BlockModel::new();
        m.add(b);
        m
    }

    #[test]
    fn sub_patches_split_anisotropically() {
        // A long smooth bar: its long faces curve across the bar much more than along it, so
        // some sub-patches are split in one direction only (Fig. 11).
        let mut m = BlockModel::new();
        m.add(boxed([0.0; 3], [8.0, 1.0, 1.0]));
        let cm = m.control_mesh().unwrap();
        let limits = cm.mesh.catmull_clark_limit().unwrap().positions().to_vec();
        let limit = Limit { ev: LimitEvaluator::new(&cm.mesh).unwrap(), limits, cm: &cm };
        let s = Surface { limit: &limit, displacement: None };
        let r = 1 << 6;
        let mut oblong = 0;
        let mut total = 0;
        for f in 0..cm.mesh.face_count() as u32 {
            let leaves = kd_leaves(&s, f, r, 1e-3, &CancelToken::new()).unwrap();
            // The leaves tile the patch.
            let area: u64 = leaves.iter().map(|l| u64::from(l[2] - l[0]) * u64::from(l[3] - l[1])).sum();
            assert_eq!(area, u64::from(r) * u64::from(r));
            oblong += leaves.iter().filter(|l| l[2] - l[0] != l[3] - l[1]).count();
            total += leaves.len();
        }
        assert!(oblong > 0 && oblong < total, "{oblong} of {total}");
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(1e-3).with_max_depth(3), None).unwrap();
        check_solid(&t.mesh);
        // Depth 3 allows at most 8 × 8 sub-patches per patch.
        assert!(t.stats.sub_patches <= t.stats.patches * 64);
    }

    #[test]
    fn displacement_moves_points_along_the_normal_and_stays_closed() {
        let mut m = BlockModel::new();
        let mut b = boxed([-1.0; 3], [1.0; 3]);
        b.sharp_all();
        m.add(b);
        // A bump on every face, zero at the face's border so creases stay straight.
        let bump = |_p: Vec3, _n: Vec3, u: f64, v: f64| -> Result<f64, String> {
            Ok(0.2 * (std::f64::consts::PI * u).sin() * (std::f64::consts::PI * v).sin())
        };
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.005), Some(&bump)).unwrap();
        check_solid(&t.mesh);
        let v = t.mesh.volume();
        assert!(v > 8.0 + 0.1, "volume {v}");
        let top = t.mesh.positions().iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((top - 1.2).abs() < 0.01, "top {top}");
        assert!(t.stats.sub_patches > t.stats.patches);
    }

    #[test]
    fn displacement_errors_and_nans_are_reported() {
        let mut m = BlockModel::new();
        m.add(boxed([0.0; 3], [1.0; 3]));
        let fails = |_p: Vec3, _n: Vec3, _u: f64, _v: f64| -> Result<f64, String> { Err("boom".into()) };
        let e = m.tessellate(&MeshOptions::DEFAULT, Some(&fails)).unwrap_err();
        assert!(matches!(&e, BlockError::Displacement { reason } if reason.contains("boom")), "{e}");
        let nan = |_p: Vec3, _n: Vec3, _u: f64, _v: f64| -> Result<f64, String> { Ok(f64::NAN) };
        let e = m.tessellate(&MeshOptions::DEFAULT, Some(&nan)).unwrap_err();
        assert!(matches!(&e, BlockError::Displacement { reason } if reason.contains("NaN")), "{e}");
        let e = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(-1.0), None).unwrap_err();
        assert!(matches!(e, BlockError::BadOption { name: "tolerance", .. }));
        let e = m.tessellate(&MeshOptions::DEFAULT.with_max_depth(40), None).unwrap_err();
        assert!(matches!(e, BlockError::BadOption { name: "max_depth", .. }));
    }

    #[test]
    fn connected_models_tessellate_watertight() {
        // Two blocks with mismatched grids, and the hand of Fig. 5: cracks would open boundaries.
        let mut m = BlockModel::new();
        m.allow(0, 0);
        let mut a = boxed([0.0; 3], [1.0; 3]);
        a.subdivide(Face::PosY, 1, 2).unwrap();
        a.set_sharp(crate::blocks::Edge::parse("-y-z").unwrap(), true);
        m.add(a);
        m.add(boxed([1.0, 0.0, 0.0], [3.0, 1.0, 1.0]));
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.005), None).unwrap();
        check_solid(&t.mesh);
        let hand = crate::blocks::test_models::hand();
        let t = hand.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.01), None).unwrap();
        check_solid(&t.mesh);
        assert_eq!(t.stats.blocks, 6);
    }

    #[test]
    fn a_die_body_is_a_rounded_closed_solid() {
        // Fig. 13: one block with every face divided 4 × 4, all edges smooth.
        let mut b = boxed([-1.0; 3], [1.0; 3]);
        for f in Face::ALL {
            b.subdivide(f, 4, 4).unwrap();
        }
        let mut m = BlockModel::new();
        m.add(b);
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.005), None).unwrap();
        check_solid(&t.mesh);
        // 96 sub-faces, 4 quads each.
        assert_eq!(t.stats.patches, 384);
        // Finer grids round less: the volume lies between the coarse limit surface and the cube.
        assert!(t.mesh.volume() < 8.0 && t.mesh.volume() > 6.0, "{}", t.mesh.volume());
    }
}
