//! The Catmull–Clark limit surface at any (face, u, v) of an all-quad mesh: [`LimitEvaluator`].
//!
//! Built once per mesh, evaluated many times (the block tessellator's inner loop):
//! - **Regular faces** — all four corners regular: smooth with valence 4; or on a straight crease
//!   or boundary with the face's side of it two faces wide; or a corner (three or more sharp edges,
//!   or marked) with the face alone in its sector — are exact bicubic B-spline patches, their 16
//!   control points precomputed (mirrored "phantom" points across sharp edges reproduce the crease
//!   rules exactly). Evaluation costs the same at every (u, v).
//! - **Irregular faces** keep the one-rings ("fans") of their four corners. Evaluation refines them
//!   locally, one quadrant per level, until (u, v) falls in a sub-face whose corners are all regular,
//!   then evaluates that sub-face's B-spline patch: feature-adaptive subdivision (Nießner et al.
//!   2012, as OpenSubdiv's `Far::PatchTable` with infinite isolation). Each level halves the distance
//!   to the irregular corner, so the result is exact to rounding for every (u, v) whose distance to an
//!   irregular corner is above 2^-40 of the face; exactly at the corner, the limit position and
//!   normal come from the limit masks (see [`super::masks`]). The cost grows with
//!   log₂(1 / distance to the irregular corner): one level for 3/4 of a face's area, two for
//!   3/16, …
//!
//! # Parameters
//! Face `f` with vertices `[q0, q1, q2, q3]` (as [`Mesh::face_vertices`] lists them) is
//! parametrised over [0, 1]²: (0, 0) at q0, (1, 0) at q1, (1, 1) at q2, (0, 1) at q3 — u runs along
//! the face's first half-edge (q0 → q1), v along q0 → q3. `du × dv` points outward for a
//! counter-clockwise face.

use crate::math::Vec3;
use crate::mesh::{Mesh, NONE};

use super::masks::{limit_normal_in_slot, position_mask, MaskScheme};
use super::patch;
use super::ring::{mesh_ring, RingTopo};
use super::topology::Rule;
use super::SubdivError;

/// Deepest local refinement before falling back to the irregular corner's limit masks.
const MAX_DEPTH: u32 = 40;

/// The limit surface at one parameter point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitSample {
    /// The point on the limit surface.
    pub position: Vec3,
    /// ∂position/∂u.
    pub du: Vec3,
    /// ∂position/∂v.
    pub dv: Vec3,
    /// The unit normal (du × dv normalised; one-sided at creases, from the face's own side).
    pub normal: Vec3,
}

/// The one-ring of one corner of a quad: slot 0 is the edge toward the quad's next corner
/// (counter-clockwise), face slot 0 is the quad itself, slot 1 the edge toward its previous corner.
#[derive(Clone, Debug, PartialEq)]
struct Fan {
    topo: RingTopo,
    c: Vec3,
    e: Vec<Vec3>,
    f: Vec<Vec3>,
}

/// How a corner enters a regular patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CornerKind {
    /// Smooth, valence 4.
    Smooth,
    /// Crease rule, the quad's sector bounded by sharp edges 0 and 2 (a crease along edge 0).
    CreaseAlong0,
    /// Crease rule, the quad's sector bounded by sharp edges n−1 and 1 (a crease along edge 1).
    CreaseAlong1,
    /// Corner rule, the quad alone in its sector (edges 0 and 1 sharp).
    Corner,
}

impl Fan {
    fn n(&self) -> usize {
        self.topo.valence()
    }

    fn kind(&self) -> Option<CornerKind> {
        let t = &self.topo;
        let n = t.valence();
        if n < 2 {
            return None;
        }
        let sharp_count = t.sharp.iter().filter(|&&s| s).count();
        match t.rule() {
            Rule::Smooth if n == 4 && sharp_count == 0 && !t.corner && t.face.iter().all(|&f| f) => {
                Some(CornerKind::Smooth)
            }
            Rule::Crease if n >= 3 && t.sharp[0] && !t.sharp[1] && t.sharp[2] && t.face[1] => {
                Some(CornerKind::CreaseAlong0)
            }
            Rule::Crease if n >= 3 && t.sharp[1] && !t.sharp[0] && t.sharp[n - 1] && t.face[n - 1] => {
                Some(CornerKind::CreaseAlong1)
            }
            Rule::Corner if t.sharp[0] && t.sharp[1] => Some(CornerKind::Corner),
            _ => None,
        }
    }

    /// One Catmull–Clark step of the fan's points into `out` (buffers reused). The rules are
    /// written relative to the centre, `c + Σ wᵢ (pᵢ − c)`, so that coordinates all the points
    /// share (a flat sharp face) come out exactly, as in [`Mesh::catmull_clark`].
    fn refine_points_into(&self, out: &mut Points) {
        let n = self.n();
        let t = &self.topo;
        let c = self.c;
        out.fp.clear();
        out.fp.extend((0..n).map(|i| {
            if t.face[i] {
                c + ((self.e[i] - c) + (self.f[i] - c) + (self.e[(i + 1) % n] - c)) * 0.25
            } else {
                Vec3::ZERO
            }
        }));
        out.ep.clear();
        for i in 0..n {
            let p = if t.sharp[i] {
                c + (self.e[i] - c) * 0.5
            } else {
                c + ((self.e[i] - c) + (out.fp[(i + n - 1) % n] - c) + (out.fp[i] - c)) * 0.25
            };
            out.ep.push(p);
        }
        out.vp = match t.rule() {
            Rule::Corner => c,
            Rule::Crease => {
                let mut ends = (0..n).filter(|&i| t.sharp[i]);
                let (a, b) = (ends.next().unwrap_or(0), ends.next().unwrap_or(0));
                c + ((self.e[a] - c) + (self.e[b] - c)) * 0.125
            }
            Rule::Smooth => {
                let nf = n as f64;
                let sum: Vec3 =
                    self.e.iter().map(|&e| e - c).sum::<Vec3>() + out.fp.iter().map(|&f| f - c).sum::<Vec3>();
                c + sum / (nf * nf)
            }
        };
    }

    /// Overwrites this fan, reusing its buffers.
    fn set(&mut self, c: Vec3, corner: bool, sharp: &[bool], face: &[bool], e: &[Vec3], f: &[Vec3]) {
        self.c = c;
        self.topo.corner = corner;
        self.topo.sharp.clear();
        self.topo.sharp.extend_from_slice(sharp);
        self.topo.face.clear();
        self.topo.face.extend_from_slice(face);
        self.e.clear();
        self.e.extend_from_slice(e);
        self.f.clear();
        self.f.extend_from_slice(f);
    }
}

/// A fan's points one level down: vertex point, edge points, face points.
#[derive(Clone, Debug, Default)]
struct Points {
    vp: Vec3,
    ep: Vec<Vec3>,
    fp: Vec<Vec3>,
}

impl Default for Fan {
    fn default() -> Fan {
        Fan { topo: RingTopo::default(), c: Vec3::ZERO, e: Vec::new(), f: Vec::new() }
    }
}

/// Buffers for adaptive evaluation, kept per thread so evaluation allocates nothing once warm.
#[derive(Default)]
struct Scratch {
    cur: [Fan; 4],
    next: [Fan; 4],
    pts: [Points; 4],
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// The fans of the child quad in quadrant `k` (0: u,v < ½; 1: u ≥ ½, v < ½; 2: both ≥ ½; 3: u < ½,
/// v ≥ ½) into `out`, with corners ordered so the child keeps the parent's (u, v) orientation.
fn refine_fans(fans: &[Fan; 4], k: usize, pts: &mut [Points; 4], out: &mut [Fan; 4]) {
    for (fan, p) in fans.iter().zip(pts.iter_mut()) {
        fan.refine_points_into(p);
    }
    let (k1, k2, k3) = ((k + 1) % 4, (k + 2) % 4, (k + 3) % 4);
    let (pk, pk1, pk2, pk3) = (&pts[k], &pts[k1], &pts[k2], &pts[k3]);
    let (vk, ek, fk) = (pk.vp, &pk.ep, &pk.fp);
    let ff = fk[0];
    let (nk, nk1, nk3) = (fans[k].n(), fans[k1].n(), fans[k3].n());
    let tk = &fans[k].topo;
    // `out[j]` receives child corner j; corner k is the vertex point, k+1 the edge point of
    // (q_k, q_k+1), k+2 the face point, k+3 the edge point of (q_k-1, q_k).

    // Corner k: the vertex point's fan, same topology.
    out[k].set(vk, tk.corner, &tk.sharp, &tk.face, ek, fk);

    // Corner k+1: around the edge point: face point, V_k, [face point of the face G across the
    // edge], V_k+1.
    let s0 = tk.sharp[0];
    if tk.face[nk - 1] {
        out[k1].set(
            ek[0],
            false,
            &[false, s0, false, s0],
            &[true; 4],
            &[ff, vk, fk[nk - 1], pk1.vp],
            &[ek[1], ek[nk - 1], pk1.ep[2 % nk1], pk1.ep[0]],
        );
    } else {
        out[k1].set(
            ek[0],
            false,
            &[false, true, true],
            &[true, false, true],
            &[ff, vk, pk1.vp],
            &[ek[1], Vec3::ZERO, pk1.ep[0]],
        );
    }

    // Corner k+2: the face point, around it the edge points of the quad's four edges.
    out[k2].set(
        ff,
        false,
        &[false; 4],
        &[true; 4],
        &[pk3.ep[0], ek[0], pk1.ep[0], pk2.ep[0]],
        &[vk, pk1.vp, pk2.vp, pk3.vp],
    );

    // Corner k+3: around the edge point of (q_k-1, q_k): V_k, face point, V_k-1, [face point of the
    // face H across the edge].
    let s1 = tk.sharp[1];
    if tk.face[1] {
        out[k3].set(
            ek[1],
            false,
            &[s1, false, s1, false],
            &[true; 4],
            &[vk, ff, pk3.vp, fk[1]],
            &[ek[0], pk3.ep[1], pk3.ep[nk3 - 1], ek[2 % nk]],
        );
    } else {
        out[k3].set(
            ek[1],
            false,
            &[true, false, true],
            &[true, true, false],
            &[vk, ff, pk3.vp],
            &[ek[0], pk3.ep[1], Vec3::ZERO],
        );
    }
}

/// Grid position of quad corner j: (0,0), (1,0), (1,1), (0,1).
const GRID: [(i32, i32); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// The 16 B-spline control points of a quad whose four corners are regular, or `None`.
fn patch_from_fans(fans: &[Fan; 4]) -> Option<[Vec3; 16]> {
    let kinds: [CornerKind; 4] = [fans[0].kind()?, fans[1].kind()?, fans[2].kind()?, fans[3].kind()?];
    let mut p = [Vec3::ZERO; 16];
    let at = |(i, j): (i32, i32)| ((i + 1) + 4 * (j + 1)) as usize;
    let add = |a: (i32, i32), b: (i32, i32)| (a.0 + b.0, a.1 + b.1);
    let sub = |a: (i32, i32), b: (i32, i32)| (a.0 - b.0, a.1 - b.1);
    for j in 0..4 {
        p[at(GRID[j])] = fans[j].c;
    }
    // Edge-adjacent points: real, or mirrored across a sharp quad edge.
    for j in 0..4 {
        let g = GRID[j];
        let d = sub(GRID[(j + 1) % 4], g);
        let dp = sub(GRID[(j + 3) % 4], g);
        let (fan, n) = (&fans[j], fans[j].n());
        let sharp0 = fan.topo.sharp[0];
        let sharp1 = fan.topo.sharp[1];
        if sharp0 {
            p[at(sub(g, dp))] = p[at(g)] * 2.0 - p[at(add(g, dp))];
            p[at(sub(add(g, d), dp))] = p[at(add(g, d))] * 2.0 - p[at(add(add(g, d), dp))];
        } else {
            p[at(sub(g, dp))] = fan.e[n - 1];
            p[at(sub(add(g, d), dp))] = fan.f[n - 1];
        }
        if sharp1 {
            p[at(sub(g, d))] = p[at(g)] * 2.0 - p[at(add(g, d))];
            p[at(sub(add(g, dp), d))] = p[at(add(g, dp))] * 2.0 - p[at(add(add(g, dp), d))];
        } else {
            p[at(sub(g, d))] = fan.e[2 % n];
            p[at(sub(add(g, dp), d))] = fan.f[1];
        }
    }
    // Outer diagonals.
    for j in 0..4 {
        let g = GRID[j];
        let d = sub(GRID[(j + 1) % 4], g);
        let dp = sub(GRID[(j + 3) % 4], g);
        let diag = sub(sub(g, d), dp);
        p[at(diag)] = match kinds[j] {
            CornerKind::Smooth => fans[j].f[2],
            CornerKind::CreaseAlong0 | CornerKind::Corner => p[at(sub(g, d))] * 2.0 - p[at(add(sub(g, d), dp))],
            CornerKind::CreaseAlong1 => p[at(sub(g, dp))] * 2.0 - p[at(add(sub(g, dp), d))],
        };
    }
    Some(p)
}

/// Where a face's limit surface comes from.
#[derive(Clone, Debug)]
enum FaceData {
    Regular(u32),
    Irregular(u32),
}

/// The Catmull–Clark limit surface of an all-quad mesh, evaluable at any (face, u, v).
///
/// See the [module documentation](self) for the method and the (u, v) orientation of a face.
#[derive(Clone, Debug)]
pub struct LimitEvaluator {
    faces: Vec<FaceData>,
    patches: Vec<[Vec3; 16]>,
    fans: Vec<[Fan; 4]>,
}

impl LimitEvaluator {
    /// Precomputes the patches of `mesh` (O(faces)); positions are copied, so later changes to the
    /// mesh are not seen.
    ///
    /// # Errors
    /// [`SubdivError::NotQuads`] naming the first face that is not a quad (apply one
    /// [`Mesh::catmull_clark`] step first); [`SubdivError::SemiSharp`] for a mesh with semi-sharp
    /// creases or corners, whose patches change from level to level (refine until the sharpness
    /// runs out first, as OpenSubdiv's adaptive refinement does).
    pub fn new(mesh: &Mesh) -> Result<LimitEvaluator, SubdivError> {
        if let Some(f) = (0..mesh.face_count() as u32).find(|&f| mesh.face_arity(f) != 4) {
            return Err(SubdivError::NotQuads { face: f as usize, arity: mesh.face_arity(f) });
        }
        if mesh.has_semi_sharp() {
            let most = mesh
                .edges()
                .map(|h| mesh.edge_sharpness(h))
                .chain((0..mesh.vertex_count() as u32).map(|v| mesh.corner_sharpness(v)))
                .filter(|s| s.is_finite())
                .fold(0.0, f64::max);
            return Err(SubdivError::SemiSharp { levels: most.min(10.0).ceil() as u32 });
        }
        let p = mesh.positions();
        // Each vertex's ring once; a face's corner fan is its vertex's ring turned to the face.
        let rings: Vec<_> = (0..mesh.vertex_count() as u32).map(|v| mesh_ring(mesh, v)).collect();
        let mut ev =
            LimitEvaluator { faces: Vec::with_capacity(mesh.face_count()), patches: Vec::new(), fans: Vec::new() };
        for f in 0..mesh.face_count() as u32 {
            let qs: Vec<u32> = mesh.face_vertices(f).collect();
            let mut fans: Vec<Fan> = Vec::with_capacity(4);
            for j in 0..4 {
                let r = &rings[qs[j] as usize];
                let n = r.edges.len();
                let s = r.faces.iter().position(|&x| x == f).ok_or_else(|| {
                    SubdivError::Internal(format!("face {f} missing from the ring of vertex {}", qs[j]))
                })?;
                let rot = |i: usize| (i + s) % n;
                if r.edges[rot(0)] != qs[(j + 1) % 4] {
                    return Err(SubdivError::Internal(format!("ring of vertex {} is not counter-clockwise", qs[j])));
                }
                fans.push(Fan {
                    topo: RingTopo {
                        sharp: (0..n).map(|i| r.topo.sharp[rot(i)]).collect(),
                        face: (0..n).map(|i| r.topo.face[rot(i)]).collect(),
                        corner: r.topo.corner,
                    },
                    c: p[qs[j] as usize],
                    e: (0..n).map(|i| p[r.edges[rot(i)] as usize]).collect(),
                    f: (0..n)
                        .map(|i| {
                            let o = r.opposite[rot(i)];
                            if o == NONE {
                                Vec3::ZERO
                            } else {
                                p[o as usize]
                            }
                        })
                        .collect(),
                });
            }
            let fans: [Fan; 4] = fans.try_into().map_err(|_| SubdivError::Internal("four fans".into()))?;
            match patch_from_fans(&fans) {
                Some(patch) => {
                    ev.faces.push(FaceData::Regular(ev.patches.len() as u32));
                    ev.patches.push(patch);
                }
                None => {
                    ev.faces.push(FaceData::Irregular(ev.fans.len() as u32));
                    ev.fans.push(fans);
                }
            }
        }
        Ok(ev)
    }

    /// Number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Whether face `face` is one exact bicubic patch (constant-cost evaluation).
    ///
    /// # Panics
    /// When `face` is out of range (a caller bug; [`LimitEvaluator::eval`] checks it).
    #[must_use]
    pub fn is_regular(&self, face: u32) -> bool {
        matches!(self.faces[face as usize], FaceData::Regular(_))
    }

    /// Number of faces that are one exact bicubic patch.
    #[must_use]
    pub fn regular_count(&self) -> usize {
        self.patches.len()
    }

    /// The limit surface at (u, v) of face `face`: position, ∂/∂u, ∂/∂v and unit normal.
    ///
    /// At an extraordinary, crease-end or dart corner itself (u, v ∈ {0, 1} on that corner) the
    /// derivatives of the face's parametrisation vanish or diverge; there `du` and `dv` are
    /// finite directions along the face's two edges (twice the next level's half-edge chords,
    /// projected onto the tangent plane) and the normal comes from the limit masks.
    ///
    /// # Errors
    /// - [`SubdivError::NoSuchFace`] for a face id out of range;
    /// - [`SubdivError::BadParameter`] for u or v outside [0, 1] or not finite;
    /// - [`SubdivError::DegenerateNormal`] where du × dv vanishes (zero-area faces).
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<LimitSample, SubdivError> {
        let data = self
            .faces
            .get(face as usize)
            .ok_or(SubdivError::NoSuchFace { face: u64::from(face), count: self.faces.len() })?;
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(SubdivError::BadParameter { u, v });
        }
        let degenerate = || SubdivError::DegenerateNormal { at: format!("face {face} (u, v) = ({u}, {v})") };
        match data {
            FaceData::Regular(i) => {
                let (position, du, dv) = patch::eval(&self.patches[*i as usize], u, v);
                let normal = du.cross(dv).try_normalize().ok_or_else(degenerate)?;
                Ok(LimitSample { position, du, dv, normal })
            }
            FaceData::Irregular(i) => self.eval_irregular(&self.fans[*i as usize], u, v).ok_or_else(degenerate),
        }
    }

    /// Adaptive evaluation of an irregular face; `None` for a degenerate normal.
    fn eval_irregular(&self, base: &[Fan; 4], u: f64, v: f64) -> Option<LimitSample> {
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let sc = &mut *guard;
            for (dst, src) in sc.cur.iter_mut().zip(base) {
                dst.clone_from(src);
            }
            let (mut u, mut v, mut scale) = (u, v, 1.0);
            for _ in 0..MAX_DEPTH {
                if let Some(j) = exact_corner(u, v) {
                    if sc.cur[j].kind().is_none() {
                        return corner_sample(&sc.cur, j, scale, &mut sc.pts[0]);
                    }
                }
                let k = nearest_corner(u, v);
                refine_fans(&sc.cur, k, &mut sc.pts, &mut sc.next);
                std::mem::swap(&mut sc.cur, &mut sc.next);
                u = 2.0 * u - if k == 1 || k == 2 { 1.0 } else { 0.0 };
                v = 2.0 * v - if k >= 2 { 1.0 } else { 0.0 };
                scale *= 2.0;
                if let Some(p) = patch_from_fans(&sc.cur) {
                    let (position, du, dv) = patch::eval(&p, u, v);
                    let (du, dv) = (du * scale, dv * scale);
                    let normal = du.cross(dv).try_normalize()?;
                    return Some(LimitSample { position, du, dv, normal });
                }
            }
            // (u, v) within 2^-40 of an irregular corner: use that corner's limit.
            let j = nearest_corner(u, v);
            corner_sample(&sc.cur, j, scale, &mut sc.pts[0])
        })
    }
}

/// The quad corner (u, v) sits on exactly, if any.
fn exact_corner(u: f64, v: f64) -> Option<usize> {
    match (u, v) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ => None,
    }
}

fn nearest_corner(u: f64, v: f64) -> usize {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

/// The limit at quad corner `j` from its fan's masks; derivatives as documented on
/// [`LimitEvaluator::eval`], scaled by `scale` (2^depth).
fn corner_sample(fans: &[Fan; 4], j: usize, scale: f64, pts: &mut Points) -> Option<LimitSample> {
    let fan = &fans[j];
    let cc = MaskScheme::CatmullClark;
    let position = position_mask(cc, &fan.topo).apply(fan.c, &fan.e, &fan.f);
    let normal = limit_normal_in_slot(cc, &fan.topo, fan.c, &fan.e, &fan.f, 0)?;
    fan.refine_points_into(pts);
    let flat = |t: Vec3| (t - normal * t.dot(normal)) * 2.0 * scale;
    let (t0, t1) = (flat(pts.ep[0] - pts.vp), flat(pts.ep[1] - pts.vp));
    // Slot 0 points to the next corner, slot 1 to the previous one (see GRID).
    let (du, dv) = match j {
        0 => (t0, t1),
        1 => (-t1, t0),
        2 => (-t0, -t1),
        _ => (t1, -t0),
    };
    Some(LimitSample { position, du, dv, normal })
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{assert_close, cube_crease_loop, grid, mixed_torus};
    use super::*;

    #[test]
    fn non_quads_and_bad_arguments_are_refused() {
        let t = Mesh::icosphere(1.0, 0);
        assert_eq!(LimitEvaluator::new(&t).unwrap_err(), SubdivError::NotQuads { face: 0, arity: 3 });
        let ev = LimitEvaluator::new(&Mesh::cube(2.0)).unwrap();
        assert_eq!(ev.eval(6, 0.5, 0.5).unwrap_err(), SubdivError::NoSuchFace { face: 6, count: 6 });
        assert!(matches!(ev.eval(0, -0.1, 0.5), Err(SubdivError::BadParameter { .. })));
        assert!(matches!(ev.eval(0, 0.5, f64::NAN), Err(SubdivError::BadParameter { .. })));
    }

    #[test]
    fn cube_values_match_the_closed_forms() {
        // Every cube face is irregular (valence-3 corners). Corner limit 1/2, face-centre limit
        // 68/81 and edge-midpoint limit 395/648 (see limit.rs), from every face that touches them.
        let cube = Mesh::cube(2.0);
        let ev = LimitEvaluator::new(&cube).unwrap();
        assert_eq!(ev.regular_count(), 0);
        for f in 0..6u32 {
            let qs: Vec<u32> = cube.face_vertices(f).collect();
            for (j, (u, v)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].into_iter().enumerate() {
                let s = ev.eval(f, u, v).unwrap();
                assert_close(s.position, cube.position(qs[j]) * 0.5, 1e-14);
                assert_close(s.normal, cube.position(qs[j]).normalize(), 1e-14);
            }
            let s = ev.eval(f, 0.5, 0.5).unwrap();
            assert_close(s.position, cube.face_normal(f) * (68.0 / 81.0), 1e-14);
            assert_close(s.normal, cube.face_normal(f), 1e-14);
            let s = ev.eval(f, 0.5, 0.0).unwrap();
            let mid = (cube.position(qs[0]) + cube.position(qs[1])) * 0.5;
            assert_close(s.position, mid * (395.0 / 648.0), 1e-14);
        }
    }

    #[test]
    fn evaluation_matches_limits_of_refined_vertices() {
        // Refine L levels and take exact limit positions (masks): the level-L vertex of face f at
        // grid (i, j) lies at (u, v) = (i, j)/2^L of f. Irregular faces of every kind are here:
        // valence 3, 5 and 6 vertices, creases with darts at their ends, a 3-crease corner, a
        // marked corner, boundaries and boundary corners of valence 2.
        let mut t = mixed_torus();
        t.crease_edges(&[[0, 6], [6, 12], [20, 26], [20, 21], [20, 14]]).unwrap();
        t.set_corner(40, true);
        let t = t.catmull_clark(1).unwrap();
        let ev = LimitEvaluator::new(&t).unwrap();
        assert!(ev.regular_count() > 0 && ev.regular_count() < t.face_count());
        check_against_refinement(&t, &ev, 3, 1e-12);
        let mut g = grid(3);
        g.crease_edges(&[[5, 6]]).unwrap();
        let g = g.catmull_clark(1).unwrap();
        check_against_refinement(&g, &LimitEvaluator::new(&g).unwrap(), 3, 1e-12);
        let c = cube_crease_loop();
        check_against_refinement(&c, &LimitEvaluator::new(&c).unwrap(), 3, 1e-12);
    }

    fn check_against_refinement(m: &Mesh, ev: &LimitEvaluator, levels: u32, tol: f64) {
        let fine = m.catmull_clark(levels).unwrap();
        let lim = fine.catmull_clark_limit().unwrap();
        let n = 1u32 << levels;
        for f in 0..m.face_count() as u32 {
            for j in 0..=n {
                for i in 0..=n {
                    let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    let vid = vertex_at(&fine, f, levels, u, v);
                    let s = ev.eval(f, u, v).unwrap();
                    let d = (s.position - lim.position(vid)).length();
                    assert!(
                        d <= tol,
                        "face {f} (u, v) = ({u}, {v}): evaluator {} vs limit {} (distance {d:e})",
                        s.position,
                        lim.position(vid)
                    );
                }
            }
        }
    }

    /// The id of the vertex at (u, v) (multiples of 2^-levels) of base face `f` in `fine`, the
    /// all-quad mesh `levels` Catmull–Clark steps down: child k of quad g is face 4g + k, starts at
    /// corner k and runs its own u from corner k toward corner k+1 (see `refiner`).
    fn vertex_at(fine: &Mesh, f: u32, levels: u32, u: f64, v: f64) -> u32 {
        let (mut face, mut u, mut v) = (f, u, v);
        for _ in 0..levels {
            let k = nearest_corner(u, v);
            let (cu, cv) =
                (2.0 * u - if k == 1 || k == 2 { 1.0 } else { 0.0 }, 2.0 * v - if k >= 2 { 1.0 } else { 0.0 });
            (u, v) = match k {
                0 => (cu, cv),
                1 => (cv, 1.0 - cu),
                2 => (1.0 - cu, 1.0 - cv),
                _ => (1.0 - cv, cu),
            };
            face = 4 * face + k as u32;
        }
        let qs: Vec<u32> = fine.face_vertices(face).collect();
        qs[nearest_corner(u, v)]
    }

    #[test]
    fn derivatives_and_normals_agree_with_differences_and_vertex_normals() {
        let mut t = mixed_torus();
        t.crease_edges(&[[0, 6], [6, 12]]).unwrap();
        let t = t.catmull_clark(1).unwrap();
        let ev = LimitEvaluator::new(&t).unwrap();
        let h = 1e-6;
        for f in (0..t.face_count() as u32).step_by(7) {
            for (u, v) in [(0.3, 0.6), (0.05, 0.1), (0.9, 0.01), (0.51, 0.49)] {
                let s = ev.eval(f, u, v).unwrap();
                let du = (ev.eval(f, u + h, v).unwrap().position - ev.eval(f, u - h, v).unwrap().position) / (2.0 * h);
                let dv = (ev.eval(f, u, v + h).unwrap().position - ev.eval(f, u, v - h).unwrap().position) / (2.0 * h);
                // Central differences are O(h²) accurate; rounding adds ~1e-16/h.
                assert_close(s.du, du, 1e-7 * (1.0 + du.length()));
                assert_close(s.dv, dv, 1e-7 * (1.0 + dv.length()));
                assert_close(s.normal, s.du.cross(s.dv).normalize(), 1e-14);
            }
        }
        // At face centres (regular level-1 face points), the normal is the limit-mask normal.
        let fine = t.catmull_clark(1).unwrap();
        let normals = fine.catmull_clark_limit_normals().unwrap();
        let (nv, ne) = (t.vertex_count() as u32, t.edge_count() as u32);
        for f in 0..t.face_count() as u32 {
            let s = ev.eval(f, 0.5, 0.5).unwrap();
            assert_close(s.normal, normals[(nv + ne + f) as usize], 1e-12);
        }
    }

    #[test]
    fn refined_vertices_converge_to_the_limit_at_four_to_the_minus_level() {
        // Vertices of level L sit at (u, v) = (i, j)/2^L; their distance to the limit there shrinks
        // like 4^-L (the second differences of the control net) over regular regions. Measured on
        // the ±1 cube (all eight corners extraordinary). Deeper down the vertices next to the
        // valence-3 corners take over, decaying only like λ^L with Catmull–Clark's subdominant
        // eigenvalue λ = 0.410 for n = 3: 6.2e-5 at level 7, 2.5e-5 at level 8 (ratios 2.9, 2.5).
        let cube = Mesh::cube(2.0);
        let ev = LimitEvaluator::new(&cube).unwrap();
        let dist = |levels: u32| {
            let fine = cube.catmull_clark(levels).unwrap();
            let n = 1u32 << levels;
            let mut worst = 0.0f64;
            for f in 0..6 {
                for j in 0..=n {
                    for i in 0..=n {
                        let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                        let p = ev.eval(f, u, v).unwrap().position;
                        worst = worst.max((p - fine.position(vertex_at(&fine, f, levels, u, v))).length());
                    }
                }
            }
            worst
        };
        let d: Vec<f64> = (2..=6).map(dist).collect();
        eprintln!("max distance level 2..6: {d:?}");
        for w in d.windows(2) {
            let ratio = w[0] / w[1];
            assert!((3.5..4.5).contains(&ratio), "convergence ratio {ratio} (distances {d:?})");
        }
    }

    /// Level 8 of the cube (393,216 quads); well under a second in the debug suite.
    #[test]
    fn level_eight_limits_match_the_evaluator() {
        // The limit positions (masks) of level-8 vertices equal the evaluator at the same (u, v).
        // The raw level-8 vertices are still 2.5e-5 away next to the valence-3 corners, where the
        // distance decays like 0.410^L (see the convergence test): 1e-6 would take level 12.
        let cube = Mesh::cube(2.0);
        let ev = LimitEvaluator::new(&cube).unwrap();
        let fine = cube.catmull_clark(8).unwrap();
        let lim = fine.catmull_clark_limit().unwrap();
        let n = 256u32;
        let (mut worst_limit, mut worst_raw) = (0.0f64, 0.0f64);
        for f in 0..6 {
            for j in (0..=n).step_by(3) {
                for i in (0..=n).step_by(3) {
                    let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    let id = vertex_at(&fine, f, 8, u, v);
                    let p = ev.eval(f, u, v).unwrap().position;
                    worst_limit = worst_limit.max((p - lim.position(id)).length());
                    worst_raw = worst_raw.max((p - fine.position(id)).length());
                }
            }
        }
        eprintln!("level 8: limit masks vs evaluator {worst_limit:e}, raw vertices vs evaluator {worst_raw:e}");
        assert!(worst_limit < 1e-12, "{worst_limit:e}");
        assert!(worst_raw < 3e-5, "{worst_raw:e}");
    }
}
