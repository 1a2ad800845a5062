//! A closed triangle mesh built for many local edits (the working mesh of [`super::remesh`] and
//! [`super::decimate`]): corners in a flat table (half-edge `3t + i` runs from corner `i` of
//! triangle `t` to corner `i + 1`), twins stored per half-edge, deleted triangles and vertices
//! only marked, so split, collapse and flip cost O(valence) and ids never move until
//! [`TriMesh::to_mesh`] compacts them.
//!
//! Every triangle remembers the input face it came from (`parent`), and every half-edge
//! whether it lies on a feature (a crease, a sharp edge, a border between two parts), which
//! the edits keep: features are never flipped, and collapses slide only along them.

use crate::math::{IdMap, Vec3};
use crate::mesh::{Mesh, MeshError};

use super::FinishError;

pub(crate) const NONE: u32 = u32::MAX;

#[inline]
pub(crate) fn next(h: u32) -> u32 {
    if h % 3 == 2 {
        h - 2
    } else {
        h + 1
    }
}

#[inline]
pub(crate) fn prev(h: u32) -> u32 {
    if h.is_multiple_of(3) {
        h + 2
    } else {
        h - 1
    }
}

/// The working mesh (see the module notes).
pub(crate) struct TriMesh {
    pub pos: Vec<Vec3>,
    /// Corner vertices, three per triangle.
    pub tv: Vec<u32>,
    /// The twin of each half-edge.
    pub twin: Vec<u32>,
    /// Whether each half-edge's edge is a feature (equal on both halves).
    pub feature: Vec<bool>,
    /// The input face of each triangle.
    pub parent: Vec<u32>,
    pub tri_alive: Vec<bool>,
    pub vert_alive: Vec<bool>,
    /// One outgoing half-edge of each vertex.
    pub vout: Vec<u32>,
    /// The number of feature edges at each vertex: 0 free, 2 on a feature line, else a corner.
    pub feature_degree: Vec<u32>,
    pub alive_tris: usize,
}

impl TriMesh {
    /// The working mesh of the closed triangle mesh `t` whose face `f` came from input face
    /// `sources[f]`; the edges `is_feature` picks (by half-edge of `t`) are features.
    pub fn new(t: &Mesh, sources: &[u32], is_feature: impl Fn(u32) -> bool) -> TriMesh {
        let nt = t.face_count();
        let mut tv = Vec::with_capacity(3 * nt);
        let mut he_of = Vec::with_capacity(3 * nt);
        for f in 0..nt as u32 {
            for h in t.face_halfedges(f) {
                tv.push(t.origin(h));
                he_of.push(h);
            }
        }
        // The mesh half-edge h sits at table index index_of[h].
        let mut index_of = vec![NONE; t.halfedge_count()];
        for (i, &h) in he_of.iter().enumerate() {
            index_of[h as usize] = i as u32;
        }
        let twin: Vec<u32> = he_of.iter().map(|&h| index_of[t.twin(h) as usize]).collect();
        let feature: Vec<bool> = he_of.iter().map(|&h| is_feature(h)).collect();
        let nv = t.vertex_count();
        let mut vout = vec![NONE; nv];
        for (i, &v) in tv.iter().enumerate() {
            if vout[v as usize] == NONE {
                vout[v as usize] = i as u32;
            }
        }
        let mut m = TriMesh {
            pos: t.positions().to_vec(),
            tv,
            twin,
            feature,
            parent: sources.to_vec(),
            tri_alive: vec![true; nt],
            vert_alive: vout.iter().map(|&h| h != NONE).collect(),
            vout,
            feature_degree: vec![0; nv],
            alive_tris: nt,
        };
        for h in 0..m.tv.len() as u32 {
            if m.feature[h as usize] && h < m.twin[h as usize] {
                let (a, b) = (m.orig(h) as usize, m.dest(h) as usize);
                m.feature_degree[a] += 1;
                m.feature_degree[b] += 1;
            }
        }
        m
    }

    #[inline]
    pub fn dest(&self, h: u32) -> u32 {
        self.tv[next(h) as usize]
    }

    #[inline]
    pub fn orig(&self, h: u32) -> u32 {
        self.tv[h as usize]
    }

    pub fn len(&self, h: u32) -> f64 {
        self.pos[self.orig(h) as usize].distance(self.pos[self.dest(h) as usize])
    }

    /// The outgoing half-edges of `v` into `out` (cleared first), clockwise.
    pub fn ring(&self, v: u32, out: &mut Vec<u32>) {
        out.clear();
        let start = self.vout[v as usize];
        let mut h = start;
        loop {
            out.push(h);
            h = self.twin[prev(h) as usize];
            if h == start || out.len() > 10_000 {
                break;
            }
        }
    }

    /// The mean length of the live triangles' edges (0 for none).
    pub fn mean_edge_length(&self) -> f64 {
        let (mut sum, mut n) = (0.0, 0usize);
        for h in 0..self.tv.len() as u32 {
            if self.tri_alive[(h / 3) as usize] {
                sum += self.len(h);
                n += 1;
            }
        }
        if n == 0 {
            0.0
        } else {
            sum / n as f64
        }
    }

    /// The least quality `4√3·area / (a² + b² + c²)` (1 for an equilateral triangle, 0 for a
    /// degenerate one) of the triangles around the two ends of `h` once the edge is collapsed
    /// and its kept end placed at `p`; the two triangles the collapse removes are not counted.
    pub fn worst_quality_after(&self, h: u32, p: Vec3) -> f64 {
        let g = self.twin[h as usize];
        let (t0, t1) = (h / 3, g / 3);
        let mut worst = 1.0f64;
        for v in [self.orig(h), self.dest(h)] {
            let start = self.vout[v as usize];
            let mut o = start;
            for _ in 0..10_000 {
                let t = o / 3;
                if t != t0 && t != t1 {
                    let mut c = self.corners(t);
                    c[(o % 3) as usize] = p;
                    let area2 = (c[1] - c[0]).cross(c[2] - c[0]).length();
                    let squares =
                        c[0].distance_squared(c[1]) + c[1].distance_squared(c[2]) + c[2].distance_squared(c[0]);
                    let q = if squares > 0.0 { 2.0 * 3f64.sqrt() * area2 / squares } else { 0.0 };
                    worst = worst.min(q);
                }
                o = self.twin[prev(o) as usize];
                if o == start {
                    break;
                }
            }
        }
        worst
    }

    pub fn tri_normal(&self, t: u32) -> Vec3 {
        let [a, b, c] = self.corners(t);
        (b - a).cross(c - a)
    }

    pub fn corners(&self, t: u32) -> [Vec3; 3] {
        let i = 3 * t as usize;
        [self.pos[self.tv[i] as usize], self.pos[self.tv[i + 1] as usize], self.pos[self.tv[i + 2] as usize]]
    }

    fn set_twins(&mut self, a: u32, b: u32) {
        self.twin[a as usize] = b;
        self.twin[b as usize] = a;
    }

    /// Splits the edge of `h` at `p`, making two triangles out of each of its two; returns the
    /// new vertex.
    pub fn split(&mut self, h: u32, p: Vec3) -> u32 {
        let g = self.twin[h as usize];
        let (t0, t1) = (h / 3, g / 3);
        let (a, b, c) = (self.orig(h), self.dest(h), self.tv[prev(h) as usize]);
        let d = self.tv[prev(g) as usize];
        let (tw_bc, tw_ca) = (self.twin[next(h) as usize], self.twin[prev(h) as usize]);
        let (f_bc, f_ca) = (self.feature[next(h) as usize], self.feature[prev(h) as usize]);
        let (tw_ad, tw_db) = (self.twin[next(g) as usize], self.twin[prev(g) as usize]);
        let (f_ad, f_db) = (self.feature[next(g) as usize], self.feature[prev(g) as usize]);
        let f_ab = self.feature[h as usize];
        let m = self.pos.len() as u32;
        self.pos.push(p);
        self.vert_alive.push(true);
        self.vout.push(NONE);
        self.feature_degree.push(if f_ab { 2 } else { 0 });
        let t2 = (self.tv.len() / 3) as u32;
        let t3 = t2 + 1;
        for _ in 0..6 {
            self.tv.push(0);
            self.twin.push(NONE);
            self.feature.push(false);
        }
        self.parent.push(self.parent[t0 as usize]);
        self.parent.push(self.parent[t1 as usize]);
        self.tri_alive.push(true);
        self.tri_alive.push(true);
        self.alive_tris += 2;
        let set = |s: &mut TriMesh, t: u32, v: [u32; 3], f: [bool; 3]| {
            for i in 0..3 {
                s.tv[3 * t as usize + i] = v[i];
                s.feature[3 * t as usize + i] = f[i];
            }
        };
        set(self, t0, [a, m, c], [f_ab, false, f_ca]);
        set(self, t2, [m, b, c], [f_ab, f_bc, false]);
        set(self, t1, [b, m, d], [f_ab, false, f_db]);
        set(self, t3, [m, a, d], [f_ab, f_ad, false]);
        let (t0, t1, t2, t3) = (3 * t0, 3 * t1, 3 * t2, 3 * t3);
        self.set_twins(t0, t3); // a→m ↔ m→a
        self.set_twins(t2, t1); // m→b ↔ b→m
        self.set_twins(t0 + 1, t2 + 2); // m→c ↔ c→m
        self.set_twins(t1 + 1, t3 + 2); // m→d ↔ d→m
        self.set_twins(t2 + 1, tw_bc);
        self.set_twins(t0 + 2, tw_ca);
        self.set_twins(t3 + 1, tw_ad);
        self.set_twins(t1 + 2, tw_db);
        self.vout[a as usize] = t0;
        self.vout[b as usize] = t2 + 1;
        self.vout[c as usize] = t0 + 2;
        self.vout[d as usize] = t1 + 2;
        self.vout[m as usize] = t0 + 1;
        m
    }

    /// Whether the edge of `h` may be collapsed topologically: its ends share exactly the two
    /// opposite vertices as neighbours and the mesh keeps more than four vertices.
    pub fn link_ok(&self, h: u32, ring_a: &[u32], ring_b: &mut Vec<u32>) -> bool {
        let b = self.dest(h);
        let g = self.twin[h as usize];
        let c = self.tv[prev(h) as usize];
        let d = self.tv[prev(g) as usize];
        if c == d {
            return false;
        }
        self.ring(b, ring_b);
        let mut shared = 0;
        for &ha in ring_a {
            let x = self.dest(ha);
            if x == b {
                continue;
            }
            if ring_b.iter().any(|&hb| self.dest(hb) == x) {
                if x != c && x != d {
                    return false;
                }
                shared += 1;
            }
        }
        shared == 2 && self.alive_tris > 4
    }

    /// Whether moving `a` (whose outgoing half-edges are `ring_a`) to `p` while collapsing the
    /// edge `h` keeps every remaining triangle around `a` facing the way it did (its normal
    /// turns by less than 90°) and not degenerate.
    pub fn keeps_orientation(&self, h: u32, ring_a: &[u32], p: Vec3, also: Option<(&[u32], Vec3)>) -> bool {
        let g = self.twin[h as usize];
        let (t0, t1) = (h / 3, g / 3);
        let check = |ring: &[u32], moved: u32, q: Vec3| {
            ring.iter().all(|&o| {
                let t = o / 3;
                if t == t0 || t == t1 {
                    return true;
                }
                let old = self.tri_normal(t);
                let mut c = self.corners(t);
                let k = (o % 3) as usize;
                c[k] = q;
                debug_assert_eq!(self.tv[o as usize], moved);
                let new = (c[1] - c[0]).cross(c[2] - c[0]);
                new.dot(old) > 0.0 && new.length_squared() > 1e-12 * old.length_squared()
            })
        };
        check(ring_a, self.orig(h), p) && also.is_none_or(|(ring_b, q)| check(ring_b, self.dest(h), q))
    }

    /// Collapses the edge of `h` (from a to b): a is removed, b moved to `p`. The caller checks
    /// [`TriMesh::link_ok`] first; `ring_a` is a's ring before the collapse.
    pub fn collapse(&mut self, h: u32, p: Vec3, ring_a: &[u32]) {
        let g = self.twin[h as usize];
        let (a, b) = (self.orig(h), self.dest(h));
        let c = self.tv[prev(h) as usize];
        let d = self.tv[prev(g) as usize];
        let (x1, x2) = (self.twin[next(h) as usize], self.twin[prev(h) as usize]);
        let (y1, y2) = (self.twin[next(g) as usize], self.twin[prev(g) as usize]);
        let fx = self.feature[next(h) as usize] || self.feature[prev(h) as usize];
        let fy = self.feature[next(g) as usize] || self.feature[prev(g) as usize];
        for &o in ring_a {
            self.tv[o as usize] = b;
        }
        self.set_twins(x1, x2);
        self.set_twins(y1, y2);
        for (e, f) in [(x1, fx), (y1, fy)] {
            self.feature[e as usize] = f;
            let t = self.twin[e as usize];
            self.feature[t as usize] = f;
        }
        let (t0, t1) = (h / 3, g / 3);
        self.tri_alive[t0 as usize] = false;
        self.tri_alive[t1 as usize] = false;
        self.alive_tris -= 2;
        self.vert_alive[a as usize] = false;
        self.pos[b as usize] = p;
        // x2 ran a→c and now runs b→c; y1 ran d→a and now d→b.
        self.vout[b as usize] = x2;
        self.vout[c as usize] = x1;
        self.vout[d as usize] = y1;
        // The feature edge a–b is gone: b keeps a's other feature edge instead.
        if self.feature[h as usize] {
            self.feature_degree[b as usize] = self.feature_degree[b as usize] + self.feature_degree[a as usize] - 2;
        } else {
            self.feature_degree[b as usize] += self.feature_degree[a as usize];
        }
    }

    /// Flips the edge of `h` (between triangles a b c and b a d) to c–d.
    pub fn flip(&mut self, h: u32) {
        let g = self.twin[h as usize];
        let (t0, t1) = (h / 3, g / 3);
        let (a, b, c) = (self.orig(h), self.dest(h), self.tv[prev(h) as usize]);
        let d = self.tv[prev(g) as usize];
        let (tw_bc, tw_ca) = (self.twin[next(h) as usize], self.twin[prev(h) as usize]);
        let (f_bc, f_ca) = (self.feature[next(h) as usize], self.feature[prev(h) as usize]);
        let (tw_ad, tw_db) = (self.twin[next(g) as usize], self.twin[prev(g) as usize]);
        let (f_ad, f_db) = (self.feature[next(g) as usize], self.feature[prev(g) as usize]);
        let set = |s: &mut TriMesh, t: u32, v: [u32; 3], f: [bool; 3]| {
            for i in 0..3 {
                s.tv[3 * t as usize + i] = v[i];
                s.feature[3 * t as usize + i] = f[i];
            }
        };
        set(self, t0, [a, d, c], [f_ad, false, f_ca]);
        set(self, t1, [b, c, d], [f_bc, false, f_db]);
        let (e0, e1) = (3 * t0, 3 * t1);
        self.set_twins(e0 + 1, e1 + 1);
        self.set_twins(e0, tw_ad);
        self.set_twins(e0 + 2, tw_ca);
        self.set_twins(e1, tw_bc);
        self.set_twins(e1 + 2, tw_db);
        self.vout[a as usize] = e0;
        self.vout[b as usize] = e1;
        self.vout[c as usize] = e0 + 2;
        self.vout[d as usize] = e1 + 2;
    }

    /// The live mesh as a [`Mesh`] with each face's input face; feature edges tagged as
    /// creases when `creases`.
    pub fn to_mesh(&self, creases: &dyn Fn(u32) -> bool) -> Result<(Mesh, Vec<u32>), FinishError> {
        let mut new_id = vec![NONE; self.pos.len()];
        let mut positions = Vec::new();
        let mut tris: Vec<[u32; 3]> = Vec::with_capacity(self.alive_tris);
        let mut parents = Vec::with_capacity(self.alive_tris);
        let mut kept_he = Vec::with_capacity(3 * self.alive_tris);
        for t in 0..self.tri_alive.len() {
            if !self.tri_alive[t] {
                continue;
            }
            let mut tri = [0; 3];
            for (i, slot) in tri.iter_mut().enumerate() {
                let v = self.tv[3 * t + i] as usize;
                if new_id[v] == NONE {
                    new_id[v] = positions.len() as u32;
                    positions.push(self.pos[v]);
                }
                *slot = new_id[v];
                kept_he.push((3 * t + i) as u32);
            }
            tris.push(tri);
            parents.push(self.parent[t]);
        }
        let mut m = Mesh::from_polygons(positions, &tris).map_err(|e| match e {
            MeshError::Limit(l) => FinishError::Limit(l),
            other => FinishError::Mesh(MeshError::Internal(format!("the edited mesh is broken: {other}"))),
        })?;
        // Tag creases: find each kept feature half-edge in the new mesh by its ends.
        let mut index: IdMap<u64, u32> = IdMap::default();
        for &h in &kept_he {
            if self.feature[h as usize] && creases(h) {
                let (a, b) = (new_id[self.orig(h) as usize], new_id[self.dest(h) as usize]);
                index.insert((u64::from(a) << 32) | u64::from(b), h);
            }
        }
        for (key, _) in index {
            let (a, b) = ((key >> 32) as u32, key as u32);
            if let Some(h) = m.find_halfedge(a, b) {
                m.set_crease_halfedge(h, true);
            }
        }
        Ok((m, parents))
    }
}
