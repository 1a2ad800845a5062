//! The Shape-Up local/global solver (Bouaziz et al. 2012, as seed 002 §4 uses it).
//!
//! Energy (Eqs. 1, 4, 10–12): Σ_c w_c ‖N_c X_c − P_c(N_c X_c)‖² over the constraints (N the
//! mean-centring matrix of Eq. 2), plus anchors Σ w‖xᵢ − aᵢ‖², closeness w Σ‖xᵢ − c(xᵢ)‖² to the
//! starting surface and the cotangent Laplacian of the displacement w Σ‖Σⱼ wᵢⱼ(dⱼ − dᵢ)‖². The
//! local step computes every projection P_c and closest point c(xᵢ) for the current X; the global
//! step solves the normal equations QᵀQ X = Qᵀ P, whose matrix does not depend on X: it is
//! factored once by a sparse Cholesky (faer) and every iteration is a back substitution. Each
//! step minimises the energy over its own variables, so the energy never increases.
//!
//! Closeness. c(xᵢ) is the closest point to xᵢ on the starting surface's triangles around
//! vertex i (its one-ring star): the local part of "the closest point on the original surface"
//! (Eq. 10), which keeps the projection cheap and well defined when a vertex moves far.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use super::projections::{centred, circle, plane, rigid};
use super::SolveError;
use crate::math::{closest_on_triangle, Vec3};
use crate::mesh::Mesh;

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// Keep this centred shape up to a rotation.
    Rigid(Vec<Vec3>),
    /// On a circle, of this radius when given.
    Circle(Option<f64>),
    Plane,
    /// Pin to these positions (not mean-centred).
    Anchor(Vec<Vec3>),
}

/// The size a circle constraint keeps.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum CircleSize {
    /// Any radius: the circle fitted to the current points (Shape-Up's circle projection).
    #[default]
    Free,
    /// This radius (seed 002's size projection, Eq. 18: the radial components scaled to it).
    Radius(f64),
    /// The radius of the circle fitted to the vertices' starting positions (see
    /// [`fit_circle`](super::fit_circle)).
    KeepSize,
}

#[derive(Clone, Debug, PartialEq)]
struct Constraint {
    verts: Vec<u32>,
    weight: f64,
    kind: Kind,
}

/// A constraint system on a mesh's vertices. Build it, then [`ShapeUp::factor`] and
/// [`Factored::solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeUp {
    /// The local origin every position is held and solved about: the centre of the mesh's
    /// bounds, so that a mesh far from the origin loses no digits in the global step (whose
    /// right-hand side would otherwise carry the large coordinates through the factored solve).
    origin: Vec3,
    /// The mesh's positions, less `origin`.
    start: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    stars: Vec<Vec<u32>>,
    constraints: Vec<Constraint>,
    closeness: f64,
    laplacian: f64,
}

/// A solve's result: the positions (by vertex id) and the energy before the first iteration and
/// after each one (non-increasing).
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    pub positions: Vec<Vec3>,
    pub energies: Vec<f64>,
}

/// A [`ShapeUp`] system with its normal matrix factored.
pub struct Factored<'a> {
    up: &'a ShapeUp,
    llt: Llt<usize, f64>,
}

fn check_weight(w: f64) -> Result<(), SolveError> {
    if w.is_finite() && w > 0.0 {
        Ok(())
    } else {
        Err(SolveError::BadWeight { weight: w })
    }
}

impl ShapeUp {
    /// A system on `mesh`'s vertices, starting from (and measuring closeness to) its positions.
    ///
    /// # Errors
    /// [`SolveError::NonFinite`] for a NaN coordinate.
    pub fn new(mesh: &Mesh) -> Result<ShapeUp, SolveError> {
        if mesh.positions().iter().any(|p| !p.is_finite()) {
            return Err(SolveError::NonFinite { what: "the mesh" });
        }
        let origin = if mesh.vertex_count() == 0 { Vec3::ZERO } else { mesh.bounds().center() };
        let start: Vec<Vec3> = mesh.positions().iter().map(|p| *p - origin).collect();
        let mut triangles = Vec::new();
        for f in 0..mesh.face_count() as u32 {
            let vs: Vec<u32> = mesh.face_vertices(f).collect();
            for k in 1..vs.len().saturating_sub(1) {
                triangles.push([vs[0], vs[k], vs[k + 1]]);
            }
        }
        let mut stars = vec![Vec::new(); start.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                stars[v as usize].push(t as u32);
            }
        }
        Ok(ShapeUp { origin, start, triangles, stars, constraints: Vec::new(), closeness: 0.0, laplacian: 0.0 })
    }

    /// The number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.start.len()
    }

    fn check_verts(&self, what: &'static str, verts: &[u32], needed: usize) -> Result<(), SolveError> {
        if verts.len() < needed {
            return Err(SolveError::TooFewVertices { what, needed, got: verts.len() });
        }
        let n = self.start.len();
        if let Some(&v) = verts.iter().find(|&&v| v as usize >= n) {
            return Err(SolveError::NoSuchVertex { vertex: v, count: n });
        }
        let mut sorted = verts.to_vec();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(SolveError::RepeatedVertex { what, vertex: w[0] });
        }
        Ok(())
    }

    /// Keeps `verts` in the shape `target` (default: their starting positions) up to a rotation
    /// and a translation (Eqs. 5–9).
    ///
    /// # Errors
    /// Bad or repeated ids, fewer than 2 vertices, a target of another length or non-finite, a
    /// bad weight.
    pub fn rigid(&mut self, verts: &[u32], target: Option<&[Vec3]>, weight: f64) -> Result<(), SolveError> {
        self.check_verts("a rigid", verts, 2)?;
        check_weight(weight)?;
        let target: Vec<Vec3> = match target {
            Some(t) if t.len() != verts.len() => {
                return Err(SolveError::AnchorCount { verts: verts.len(), count: t.len() })
            }
            Some(t) if t.iter().any(|p| !p.is_finite()) => return Err(SolveError::NonFinite { what: "the target" }),
            Some(t) => t.to_vec(),
            None => verts.iter().map(|&v| self.start[v as usize]).collect(),
        };
        self.constraints.push(Constraint { verts: verts.to_vec(), weight, kind: Kind::Rigid(centred(&target)) });
        Ok(())
    }

    /// Keeps `verts` on a circle (any centre, radius and plane): [`ShapeUp::circle_sized`] with
    /// [`CircleSize::Free`].
    ///
    /// # Errors
    /// Bad or repeated ids, fewer than 3 vertices, a bad weight.
    pub fn circle(&mut self, verts: &[u32], weight: f64) -> Result<(), SolveError> {
        self.circle_sized(verts, weight, CircleSize::Free)
    }

    /// Keeps `verts` on a circle of any centre and plane whose radius is free, given, or the
    /// starting radius (`size`). The local step fits the circle to the current points (least
    /// squares, see [`fit_circle`](super::fit_circle)) and projects each point radially onto the
    /// circle of that centre and the kept radius.
    ///
    /// # Errors
    /// Bad or repeated ids, fewer than 3 vertices, a bad weight; a radius that is not finite and
    /// positive ([`SolveError::BadRadius`]); for [`CircleSize::KeepSize`], starting positions on
    /// one line or at one place ([`SolveError::NoCircle`]).
    pub fn circle_sized(&mut self, verts: &[u32], weight: f64, size: CircleSize) -> Result<(), SolveError> {
        self.check_verts("a circle", verts, 3)?;
        check_weight(weight)?;
        let radius = match size {
            CircleSize::Free => None,
            CircleSize::Radius(r) if r.is_finite() && r > 0.0 => Some(r),
            CircleSize::Radius(r) => return Err(SolveError::BadRadius { radius: r }),
            CircleSize::KeepSize => {
                let start: Vec<Vec3> = verts.iter().map(|&v| self.start[v as usize]).collect();
                Some(super::fit_circle(&start)?.radius)
            }
        };
        self.constraints.push(Constraint { verts: verts.to_vec(), weight, kind: Kind::Circle(radius) });
        Ok(())
    }

    /// Keeps `verts` on a plane.
    ///
    /// # Errors
    /// Bad or repeated ids, fewer than 3 vertices, a bad weight.
    pub fn plane(&mut self, verts: &[u32], weight: f64) -> Result<(), SolveError> {
        self.check_verts("a plane", verts, 3)?;
        check_weight(weight)?;
        self.constraints.push(Constraint { verts: verts.to_vec(), weight, kind: Kind::Plane });
        Ok(())
    }

    /// Pins `verts` to `positions`.
    ///
    /// # Errors
    /// Bad or repeated ids, no vertex, a position count that differs, non-finite positions, a
    /// bad weight.
    pub fn anchor(&mut self, verts: &[u32], positions: &[Vec3], weight: f64) -> Result<(), SolveError> {
        self.check_verts("an anchor", verts, 1)?;
        check_weight(weight)?;
        if positions.len() != verts.len() {
            return Err(SolveError::AnchorCount { verts: verts.len(), count: positions.len() });
        }
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(SolveError::NonFinite { what: "the anchor positions" });
        }
        self.constraints.push(Constraint {
            verts: verts.to_vec(),
            weight,
            kind: Kind::Anchor(positions.iter().map(|p| *p - self.origin).collect()),
        });
        Ok(())
    }

    /// Sets the weight of the closeness energy (Eq. 10); 0 turns it off.
    ///
    /// # Errors
    /// A weight that is negative or not finite.
    pub fn closeness(&mut self, weight: f64) -> Result<(), SolveError> {
        if weight != 0.0 {
            check_weight(weight)?;
        }
        self.closeness = weight;
        Ok(())
    }

    /// Sets the weight of the cotangent Laplacian of the displacement (Eq. 11); 0 turns it off.
    ///
    /// # Errors
    /// A weight that is negative or not finite.
    pub fn laplacian(&mut self, weight: f64) -> Result<(), SolveError> {
        if weight != 0.0 {
            check_weight(weight)?;
        }
        self.laplacian = weight;
        Ok(())
    }

    /// Rows of the cotangent Laplacian: for each vertex, (neighbour, weight) pairs and the
    /// diagonal −Σ weights. Degenerate triangles contribute cotangents clamped to ±1e6.
    fn cotangent_rows(&self) -> Vec<Vec<(u32, f64)>> {
        let n = self.start.len();
        let mut rows: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        let p = &self.start;
        for t in &self.triangles {
            for k in 0..3 {
                let (i, j, o) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let (a, b) = (p[i as usize] - p[o as usize], p[j as usize] - p[o as usize]);
                let cot = (a.dot(b) / a.cross(b).length().max(1e-300)).clamp(-1e6, 1e6) / 2.0;
                rows[i as usize].push((j, cot));
                rows[j as usize].push((i, cot));
            }
        }
        rows.into_iter()
            .enumerate()
            .map(|(i, mut r)| {
                r.sort_unstable_by_key(|e| e.0);
                let mut merged: Vec<(u32, f64)> = Vec::with_capacity(r.len() + 1);
                for (j, w) in r {
                    match merged.last_mut() {
                        Some(last) if last.0 == j => last.1 += w,
                        _ => merged.push((j, w)),
                    }
                }
                let diag: f64 = -merged.iter().map(|e| e.1).sum::<f64>();
                merged.push((i as u32, diag));
                merged
            })
            .collect()
    }

    /// Factors the normal matrix QᵀQ (once per system; see [`Factored::solve`]).
    ///
    /// # Errors
    /// [`SolveError::Unanchored`] without anchors or closeness; [`SolveError::Singular`] when the
    /// matrix is not positive definite (e.g. vertices no term touches).
    pub fn factor(&self) -> Result<Factored<'_>, SolveError> {
        if self.closeness == 0.0 && !self.constraints.iter().any(|c| matches!(c.kind, Kind::Anchor(_))) {
            return Err(SolveError::Unanchored);
        }
        let n = self.start.len();
        let mut entries: Vec<(usize, usize, f64)> = Vec::new();
        for c in &self.constraints {
            let w = c.weight;
            match c.kind {
                Kind::Anchor(_) => entries.extend(c.verts.iter().map(|&v| (v as usize, v as usize, w))),
                _ => {
                    // Sᵀ N S with N = I − 1/n (idempotent, so NᵀN = N).
                    let inv = 1.0 / c.verts.len() as f64;
                    for &a in &c.verts {
                        for &b in &c.verts {
                            let nab = if a == b { 1.0 - inv } else { -inv };
                            entries.push((a as usize, b as usize, w * nab));
                        }
                    }
                }
            }
        }
        if self.closeness > 0.0 {
            entries.extend((0..n).map(|i| (i, i, self.closeness)));
        }
        if self.laplacian > 0.0 {
            for row in self.cotangent_rows() {
                for &(a, la) in &row {
                    for &(b, lb) in &row {
                        entries.push((a as usize, b as usize, self.laplacian * la * lb));
                    }
                }
            }
        }
        entries.sort_unstable_by_key(|e| (e.1, e.0));
        let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(entries.len());
        for (r, c, v) in entries {
            match triplets.last_mut() {
                Some(t) if t.row == r && t.col == c => t.val += v,
                _ => triplets.push(Triplet::new(r, c, v)),
            }
        }
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
            .map_err(|e| SolveError::Singular(format!("{e:?}")))?;
        let symbolic =
            SymbolicLlt::try_new(a.symbolic(), Side::Lower).map_err(|e| SolveError::Singular(format!("{e:?}")))?;
        let llt = Llt::try_new_with_symbolic(symbolic, a.as_ref(), Side::Lower)
            .map_err(|e| SolveError::Singular(format!("{e:?}")))?;
        Ok(Factored { up: self, llt })
    }

    /// The closest point to `x` on the starting surface's triangles around vertex `v`.
    fn closest_on_star(&self, v: usize, x: Vec3) -> Vec3 {
        let mut best = self.start[v];
        let mut best_d = (best - x).length_squared();
        for &t in &self.stars[v] {
            let [a, b, c] = self.triangles[t as usize].map(|i| self.start[i as usize]);
            let q = closest_on_triangle(x, a, b, c);
            let d = (q - x).length_squared();
            if d < best_d {
                best = q;
                best_d = d;
            }
        }
        best
    }

    /// The local step for positions `x`: each constraint's projected (centred or absolute)
    /// points and the closeness targets; with the energy of `x` against them.
    fn local(&self, x: &[Vec3]) -> (Vec<Vec<Vec3>>, Vec<Vec3>, f64) {
        let mut energy = 0.0;
        let mut projected = Vec::with_capacity(self.constraints.len());
        for c in &self.constraints {
            let current: Vec<Vec3> = c.verts.iter().map(|&v| x[v as usize]).collect();
            let (now, p) = match &c.kind {
                Kind::Anchor(a) => (current, a.clone()),
                kind => {
                    let now = centred(&current);
                    let p = match kind {
                        Kind::Rigid(target) => rigid(target, &now),
                        Kind::Circle(r) => circle(&now, *r),
                        _ => plane(&now),
                    };
                    (now, p)
                }
            };
            energy += c.weight * now.iter().zip(&p).map(|(a, b)| (*a - *b).length_squared()).sum::<f64>();
            projected.push(p);
        }
        let close: Vec<Vec3> = if self.closeness > 0.0 {
            (0..x.len()).map(|i| self.closest_on_star(i, x[i])).collect()
        } else {
            Vec::new()
        };
        energy += self.closeness * x.iter().zip(&close).map(|(a, b)| (*a - *b).length_squared()).sum::<f64>();
        if self.laplacian > 0.0 {
            for row in &self.cotangent_rows() {
                let l: Vec3 = row.iter().map(|&(j, w)| (x[j as usize] - self.start[j as usize]) * w).sum();
                energy += self.laplacian * l.length_squared();
            }
        }
        (projected, close, energy)
    }
}

impl Factored<'_> {
    /// Runs `iterations` local/global steps from `start` (#V positions).
    ///
    /// # Errors
    /// [`SolveError::NonFinite`] for a start of the wrong length or with NaN (reported as
    /// non-finite), or a solve that diverges; [`SolveError::Limit`] when the current
    /// cancellation token stops it (checked every iteration).
    pub fn solve(&self, start: &[Vec3], iterations: usize) -> Result<Solution, SolveError> {
        let up = self.up;
        let n = up.start.len();
        if start.len() != n || start.iter().any(|p| !p.is_finite()) {
            return Err(SolveError::NonFinite { what: "the start positions" });
        }
        let lap_rhs: Vec<Vec3> = if up.laplacian > 0.0 {
            // w LᵀL x₀: the Laplacian of the displacement is zero at the start shape.
            let rows = up.cotangent_rows();
            let lx0: Vec<Vec3> = rows.iter().map(|r| r.iter().map(|&(j, w)| up.start[j as usize] * w).sum()).collect();
            let mut out = vec![Vec3::ZERO; n];
            for (i, r) in rows.iter().enumerate() {
                for &(j, w) in r {
                    out[j as usize] += lx0[i] * (w * up.laplacian);
                }
            }
            out
        } else {
            Vec::new()
        };
        let mut x: Vec<Vec3> = start.iter().map(|p| *p - up.origin).collect();
        let mut energies = Vec::with_capacity(iterations + 1);
        for _ in 0..iterations {
            // One unit per vertex and constraint vertex: a long solve stops with its token.
            crate::limits::charge((n + up.constraints.iter().map(|c| c.verts.len()).sum::<usize>()) as u64)?;
            let (projected, close, energy) = up.local(&x);
            energies.push(energy);
            let mut rhs = Mat::<f64>::zeros(n, 3);
            let mut add = |i: usize, v: Vec3| {
                rhs[(i, 0)] += v.x;
                rhs[(i, 1)] += v.y;
                rhs[(i, 2)] += v.z;
            };
            for (c, p) in up.constraints.iter().zip(&projected) {
                match c.kind {
                    Kind::Anchor(_) => c.verts.iter().zip(p).for_each(|(&v, q)| add(v as usize, *q * c.weight)),
                    _ => {
                        // Sᵀ Nᵀ P: the projections are centred already, so N P = P.
                        let p = centred(p);
                        c.verts.iter().zip(&p).for_each(|(&v, q)| add(v as usize, *q * c.weight));
                    }
                }
            }
            for (i, q) in close.iter().enumerate() {
                add(i, *q * up.closeness);
            }
            for (i, q) in lap_rhs.iter().enumerate() {
                add(i, *q);
            }
            self.llt.solve_in_place(rhs.as_mut());
            x = (0..n).map(|i| Vec3::new(rhs[(i, 0)], rhs[(i, 1)], rhs[(i, 2)])).collect();
            if x.iter().any(|p| !p.is_finite()) {
                return Err(SolveError::NonFinite { what: "the solution" });
            }
        }
        energies.push(up.local(&x).2);
        Ok(Solution { positions: x.into_iter().map(|p| p + up.origin).collect(), energies })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;

    #[test]
    fn a_rigid_set_moved_by_anchors_keeps_its_shape() {
        // The whole icosphere rigid, two vertices pulled by anchors to where a rigid motion
        // takes them: the optimum is that motion. Local/global converges linearly, hence the
        // many (cheap) iterations.
        let m = Mesh::icosphere(1.0, 1);
        let mut up = ShapeUp::new(&m).unwrap();
        let all: Vec<u32> = (0..m.vertex_count() as u32).collect();
        up.rigid(&all, None, 10.0).unwrap();
        let q = Quat::from_axis_angle(Vec3::Z, 0.4);
        let moved = |v: u32| q * m.position(v) + Vec3::new(0.5, 0.0, 0.0);
        up.anchor(&[0, 5], &[moved(0), moved(5)], 100.0).unwrap();
        let s = up.factor().unwrap().solve(m.positions(), 2000).unwrap();
        for i in 0..m.vertex_count() {
            for j in (i + 1)..m.vertex_count() {
                let (a, b) = (s.positions[i].distance(s.positions[j]), m.positions()[i].distance(m.positions()[j]));
                assert!((a - b).abs() < 1e-6, "pair {i} {j}: {a} vs {b}");
            }
        }
        assert!(s.positions[0].distance(moved(0)) < 1e-6);
    }

    #[test]
    fn a_solve_stops_with_its_token_and_charges_every_iteration() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicU64;
        use std::sync::Arc;
        let m = Mesh::icosphere(1.0, 1);
        let mut up = ShapeUp::new(&m).unwrap();
        up.closeness(1.0).unwrap();
        let f = up.factor().unwrap();
        // 42 vertices, no constraint: 42 units an iteration, so 100 iterations pass 4,000.
        let counter = Arc::new(AtomicU64::new(0));
        let _current = install(CancelToken::with(None, None, Some((counter.clone(), 4000))));
        let e = f.solve(m.positions(), 100).unwrap_err();
        assert_eq!(e, SolveError::Limit(LimitError::Stopped(StopReason::Operations { max: 4000 })));
        assert_eq!(counter.load(std::sync::atomic::Ordering::Relaxed), 96 * 42);
    }

    #[test]
    fn the_energy_never_increases() {
        let m = Mesh::uv_sphere(1.0, 12, 8);
        let mut up = ShapeUp::new(&m).unwrap();
        // A ring kept planar and rigid, anchors pulling two others apart, closeness and a Laplacian.
        let ring: Vec<u32> = (1 + 12 * 3..1 + 12 * 4).collect();
        up.plane(&ring, 5.0).unwrap();
        up.rigid(&ring, None, 10.0).unwrap();
        up.anchor(&[0, m.vertex_count() as u32 - 1], &[Vec3::new(0.3, 0.0, -1.6), Vec3::new(0.0, 0.4, 1.5)], 20.0)
            .unwrap();
        up.closeness(1.0).unwrap();
        up.laplacian(1.0).unwrap();
        let s = up.factor().unwrap().solve(m.positions(), 30).unwrap();
        assert_eq!(s.energies.len(), 31);
        for w in s.energies.windows(2) {
            assert!(w[1] <= w[0] * (1.0 + 1e-12) + 1e-15, "energy went up: {:?}", s.energies);
        }
        assert!(s.energies[30] < s.energies[0]);
    }

    #[test]
    fn a_circle_constraint_rounds_a_squashed_ring() {
        let m = Mesh::uv_sphere(1.0, 16, 8).scale(Vec3::new(1.0, 0.6, 1.0));
        let mut up = ShapeUp::new(&m).unwrap();
        let ring: Vec<u32> = (1 + 16 * 3..1 + 16 * 4).collect();
        up.circle(&ring, 50.0).unwrap();
        up.closeness(0.01).unwrap();
        let s = up.factor().unwrap().solve(m.positions(), 100).unwrap();
        let pts: Vec<Vec3> = ring.iter().map(|&v| s.positions[v as usize]).collect();
        let c = centred(&pts);
        let r: Vec<f64> = c.iter().map(|p| p.length()).collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        assert!(r.iter().all(|x| (x - mean).abs() < 1e-3 * mean), "{r:?}");
    }

    /// A flat annulus (a plate with a hole) whose hole is squashed to an ellipse of semi-axes
    /// 5.3 and 4.8, as a triangle mesh; the ids of the hole's ring.
    fn plate_with_squashed_hole() -> (Mesh, Vec<u32>) {
        let (n, rings) = (24usize, 4usize);
        let mut pos = Vec::new();
        for k in 0..rings {
            let t = k as f64 / (rings - 1) as f64;
            for i in 0..n {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                let (rx, ry) = (5.3 + 6.0 * t, 4.8 + 6.5 * t);
                pos.push(Vec3::new(rx * a.cos(), ry * a.sin(), 0.0));
            }
        }
        let mut faces = Vec::new();
        for k in 0..rings - 1 {
            for i in 0..n {
                let (a, b) = ((k * n + i) as u32, (k * n + (i + 1) % n) as u32);
                let (c, d) = (a + n as u32, b + n as u32);
                faces.extend([a, b, d, a, d, c]);
            }
        }
        let m = Mesh::from_indexed(pos, &faces, &vec![3; faces.len() / 3]).unwrap();
        (m, (0..n as u32).collect())
    }

    #[test]
    fn a_sized_circle_constraint_sets_or_keeps_the_radius() {
        let (m, ring) = plate_with_squashed_hole();
        let start = crate::solve::fit_circle(&ring.iter().map(|&v| m.position(v)).collect::<Vec<_>>()).unwrap();
        // A free circle rounds the hole at whatever radius the compromise gives.
        let solve = |size: CircleSize| {
            let mut up = ShapeUp::new(&m).unwrap();
            up.circle_sized(&ring, 1e6, size).unwrap();
            up.closeness(1.0).unwrap();
            let s = up.factor().unwrap().solve(m.positions(), 60).unwrap();
            crate::solve::fit_circle(&ring.iter().map(|&v| s.positions[v as usize]).collect::<Vec<_>>()).unwrap()
        };
        let free = solve(CircleSize::Free);
        assert!(free.deviation < 1e-5, "{free:?}");
        for (size, want) in [(CircleSize::Radius(5.0), 5.0), (CircleSize::KeepSize, start.radius)] {
            let c = solve(size);
            assert!((c.radius - want).abs() < 1e-6, "{size:?}: radius {} vs {want}", c.radius);
            assert!(c.deviation < 1e-5, "{size:?}: {c:?}");
            assert!(c.normal.z.abs() > 1.0 - 1e-9, "{c:?}");
        }
        let mut up = ShapeUp::new(&m).unwrap();
        for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(up.circle_sized(&ring, 1.0, CircleSize::Radius(r)), Err(SolveError::BadRadius { .. })));
        }
    }

    #[test]
    fn bad_systems_are_refused() {
        let m = Mesh::icosphere(1.0, 0);
        let mut up = ShapeUp::new(&m).unwrap();
        assert_eq!(up.rigid(&[0, 99], None, 1.0), Err(SolveError::NoSuchVertex { vertex: 99, count: 12 }));
        assert_eq!(up.circle(&[0, 1], 1.0), Err(SolveError::TooFewVertices { what: "a circle", needed: 3, got: 2 }));
        assert_eq!(up.plane(&[0, 1, 1], 1.0), Err(SolveError::RepeatedVertex { what: "a plane", vertex: 1 }));
        assert_eq!(up.anchor(&[0], &[], 1.0), Err(SolveError::AnchorCount { verts: 1, count: 0 }));
        assert_eq!(up.circle(&[0, 1, 2], -1.0), Err(SolveError::BadWeight { weight: -1.0 }));
        assert!(matches!(up.anchor(&[0], &[Vec3::NAN], 1.0), Err(SolveError::NonFinite { .. })));
        // Nothing anchors the system: refused with the reason, not a NaN.
        up.rigid(&[0, 1, 2], None, 1.0).unwrap();
        assert!(matches!(up.factor(), Err(SolveError::Unanchored)));
        // Anchors that leave some vertices untouched: singular.
        up.anchor(&[0], &[Vec3::ZERO], 1.0).unwrap();
        assert!(matches!(up.factor(), Err(SolveError::Singular(_))));
    }
}
