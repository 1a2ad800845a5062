//! Isotropic remeshing (Botsch and Kobbelt, "A remeshing approach to multiresolution
//! modeling", SGP 2004, §4; as pmp-library, CGAL and MeshLab do it): for a target edge length
//! L, each iteration
//! 1. splits every edge longer than 4/3 L at its midpoint,
//! 2. collapses every edge shorter than 4/5 L whose collapse makes no edge longer than 4/3 L,
//! 3. flips edges that bring the valences of their four vertices closer to 6,
//! 4. moves every free vertex towards the centroid of its neighbours within its tangent plane
//!    (tangential relaxation), and
//! 5. projects it back onto the input surface (nearest point).
//!
//! Features are kept: crease-tagged edges, edges sharper than `sharp_angle` and the borders
//! between parts (colours) are never flipped, collapses slide only along them, their corners
//! never move. Each step is linear in the mesh size (the projection a grid lookup per vertex).

use crate::limits;
use crate::math::{closest_on_triangle, fmt_num, IdMap, Vec3};
use crate::mesh::Mesh;

use super::tri_mesh::{next, prev, TriMesh};
use super::{FinishError, MAX_TRIANGLES};

/// What [`remesh`] is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RemeshOptions {
    /// The target edge length (> 0).
    pub edge_length: f64,
    /// Rounds of split, collapse, flip, relax and project (1 to 100).
    pub iterations: u32,
    /// Edges whose faces' normals differ by more than this (degrees) are features.
    pub sharp_angle: f64,
}

impl Default for RemeshOptions {
    fn default() -> RemeshOptions {
        RemeshOptions { edge_length: 1.0, iterations: 10, sharp_angle: super::DEFAULT_SHARP_ANGLE }
    }
}

/// What [`remesh`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct RemeshReport {
    /// The enclosed volume before and after.
    pub volume_before: f64,
    pub volume_after: f64,
    /// The largest distance of a result vertex from the input surface.
    pub distance_to_input: f64,
    /// The smallest angle of any result triangle, degrees.
    pub min_angle: f64,
    /// The mean and standard deviation of the result's edge lengths.
    pub mean_edge: f64,
    pub edge_deviation: f64,
}

/// Nearest points on the input surface: the input triangles binned in a uniform grid.
struct Reference {
    tris: Vec<[Vec3; 3]>,
    cell: f64,
    origin: Vec3,
    bins: IdMap<u64, Vec<u32>>,
    /// Grid extent in cells along each axis.
    dims: [i64; 3],
}

impl Reference {
    fn new(t: &Mesh, cell: f64) -> Result<Reference, FinishError> {
        let b = t.bounds();
        let origin = b.min - Vec3::splat(cell);
        let ext = (b.max - b.min) / cell + Vec3::splat(3.0);
        let dims = [ext.x.ceil() as i64, ext.y.ceil() as i64, ext.z.ceil() as i64];
        let mut tris = Vec::with_capacity(t.face_count());
        let mut bins: IdMap<u64, Vec<u32>> = IdMap::default();
        let mut entries = 0.0;
        for f in 0..t.face_count() as u32 {
            let mut it = t.face_vertices(f).map(|v| t.position(v));
            let (Some(a), Some(b), Some(c)) = (it.next(), it.next(), it.next()) else { continue };
            let id = tris.len() as u32;
            tris.push([a, b, c]);
            let lo = ((a.min(b).min(c) - origin) / cell).floor();
            let hi = ((a.max(b).max(c) - origin) / cell).floor();
            let n = (hi - lo + Vec3::ONE).element_product();
            entries += n;
            if entries > 4.0 * MAX_TRIANGLES {
                return Err(FinishError::TooLarge {
                    what: "the input's search grid for this edge length".into(),
                    estimate: entries,
                    limit: 4.0 * MAX_TRIANGLES,
                });
            }
            for x in lo.x as i64..=hi.x as i64 {
                for y in lo.y as i64..=hi.y as i64 {
                    for z in lo.z as i64..=hi.z as i64 {
                        bins.entry(key(x, y, z)).or_default().push(id);
                    }
                }
            }
        }
        Ok(Reference { tris, cell, origin, bins, dims })
    }

    /// The nearest point of the input surface to `p`.
    fn project(&self, p: Vec3) -> Vec3 {
        let c = ((p - self.origin) / self.cell).floor();
        let (cx, cy, cz) = (c.x as i64, c.y as i64, c.z as i64);
        let (mut best, mut best_d) = (p, f64::INFINITY);
        let max_r = self.dims.iter().copied().max().unwrap_or(1);
        for r in 0..=max_r {
            for x in cx - r..=cx + r {
                for y in cy - r..=cy + r {
                    for z in cz - r..=cz + r {
                        if (x - cx).abs().max((y - cy).abs()).max((z - cz).abs()) != r {
                            continue;
                        }
                        if let Some(ids) = self.bins.get(&key(x, y, z)) {
                            for &i in ids {
                                let [a, b, cc] = self.tris[i as usize];
                                let q = closest_on_triangle(p, a, b, cc);
                                let d = q.distance_squared(p);
                                if d < best_d {
                                    best_d = d;
                                    best = q;
                                }
                            }
                        }
                    }
                }
            }
            // Everything within r cells of p's cell has been seen.
            if best_d.sqrt() <= r as f64 * self.cell {
                break;
            }
        }
        best
    }
}

fn key(x: i64, y: i64, z: i64) -> u64 {
    ((x as u64 & 0x1F_FFFF) << 42) | ((y as u64 & 0x1F_FFFF) << 21) | (z as u64 & 0x1F_FFFF)
}

/// The largest estimated triangle count [`remesh`] makes: Σ area / (√3/4 · L²).
fn estimate(mesh: &Mesh, l: f64) -> f64 {
    mesh.area() / (3f64.sqrt() / 4.0 * l * l)
}

/// `mesh` remeshed to near-equilateral triangles of edge `options.edge_length` (see the module
/// notes), with a report of the volume before and after and the distance to the input.
/// Tells a listener ([`limits::listen`]) its steps: four an iteration (split, collapse, flip,
/// relax).
///
/// # Errors
/// [`FinishError::BadOption`] for an edge length that is not finite and above 0, iterations
/// outside 1–100 or an angle outside 0–180; [`FinishError::NotClosed`] for a mesh with a
/// boundary; [`FinishError::TooLarge`] when the surface area over the target triangle's area
/// is beyond [`MAX_TRIANGLES`] (refused before anything is made); a stop of the cancellation
/// token.
pub fn remesh(mesh: &Mesh, options: RemeshOptions) -> Result<(Mesh, RemeshReport), FinishError> {
    let l = options.edge_length;
    if !(l.is_finite() && l > 0.0) {
        return Err(FinishError::bad("edge_length", l, "a finite number above 0"));
    }
    if !(1..=100).contains(&options.iterations) {
        return Err(FinishError::bad("iterations", f64::from(options.iterations), "between 1 and 100"));
    }
    if !(0.0..=180.0).contains(&options.sharp_angle) {
        return Err(FinishError::bad("sharp_angle", options.sharp_angle, "between 0 and 180 degrees"));
    }
    if !mesh.is_closed() {
        let boundary_edges =
            mesh.edges().filter(|&h| mesh.is_boundary_halfedge(h) || mesh.is_boundary_halfedge(mesh.twin(h))).count();
        return Err(FinishError::NotClosed { what: "remesh", boundary_edges });
    }
    let estimate = estimate(mesh, l).max(mesh.triangle_count() as f64);
    if estimate > MAX_TRIANGLES {
        return Err(FinishError::TooLarge {
            what: format!("remesh with edge_length {} of a surface of area {}", fmt_num(l), fmt_num(mesh.area())),
            estimate,
            limit: MAX_TRIANGLES,
        });
    }
    crate::mesh::check_mesh_size(
        || format!("remesh with edge_length {}", fmt_num(l)),
        estimate,
        3.0 * estimate * 3.0,
        estimate,
    )?;
    let (t, sources) = mesh.triangulate_with_sources()?;
    let cos_sharp = options.sharp_angle.to_radians().cos();
    let normals: Vec<Vec3> = (0..t.face_count() as u32).map(|f| t.face_normal(f)).collect();
    let part = |f: u32| mesh.face_part_ids().map(|ids| ids[sources[f as usize] as usize]);
    let is_feature = |h: u32| {
        let (f, g) = (t.face(h), t.face(t.twin(h)));
        t.is_crease(h) || normals[f as usize].dot(normals[g as usize]) < cos_sharp || part(f) != part(g)
    };
    let mut w = TriMesh::new(&t, &sources, is_feature);
    let reference = Reference::new(&t, l.max(mean_edge(&t) * 0.5))?;
    let (low, high) = (0.8 * l, 4.0 / 3.0 * l);
    let mut ring_a = Vec::new();
    let mut ring_b = Vec::new();
    // Progress: four steps an iteration (split, collapse, flip, relax).
    let work = limits::Work::start(4 * u64::from(options.iterations));
    for i in 0..u64::from(options.iterations) {
        limits::check()?;
        split_long(&mut w, high)?;
        work.set(4 * i + 1);
        limits::check()?;
        collapse_short(&mut w, low, high, &mut ring_a, &mut ring_b)?;
        work.set(4 * i + 2);
        limits::check()?;
        flip_to_valence(&mut w, &mut ring_a)?;
        work.set(4 * i + 3);
        limits::check()?;
        relax_and_project(&mut w, &reference, &mut ring_a)?;
        work.set(4 * i + 4);
    }
    let (mut out, parents) = w.to_mesh(&|_| true)?;
    out.inherit_parts(mesh, &parents)?;
    let report = report(mesh, &out, &reference);
    Ok((out, report))
}

fn mean_edge(t: &Mesh) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for h in t.edges() {
        sum += t.position(t.origin(h)).distance(t.position(t.target(h)));
        n += 1;
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

/// Splits every edge longer than `high` at its midpoint, longest first, and only an edge that
/// is the longest of both its triangles (Rivara's longest-edge bisection): splitting a shorter
/// edge first can make a median as long as the longest side, and an endless fan.
fn split_long(w: &mut TriMesh, high: f64) -> Result<(), FinishError> {
    let mut ring = Vec::new();
    loop {
        let mut long: Vec<(f64, u32, u32)> = Vec::new();
        for h in 0..w.tv.len() as u32 {
            limits::poll_at(h as usize)?;
            if w.tri_alive[(h / 3) as usize] && h < w.twin[h as usize] {
                let l = w.len(h);
                if l > high {
                    long.push((l, w.orig(h), w.dest(h)));
                }
            }
        }
        if long.is_empty() {
            return Ok(());
        }
        long.sort_by(|x, y| y.0.total_cmp(&x.0));
        let mut split = 0usize;
        for (i, &(_, a, b)) in long.iter().enumerate() {
            limits::poll_at(i)?;
            w.ring(a, &mut ring);
            let Some(&h) = ring.iter().find(|&&o| w.dest(o) == b) else { continue };
            let l = w.len(h);
            let g = w.twin[h as usize];
            let longest = |e: u32| w.len(next(e)) <= l && w.len(prev(e)) <= l;
            if l <= high || !longest(h) || !longest(g) {
                continue;
            }
            let p = (w.pos[a as usize] + w.pos[b as usize]) * 0.5;
            w.split(h, p);
            split += 1;
            if w.alive_tris as f64 > MAX_TRIANGLES {
                return Err(FinishError::TooLarge {
                    what: "remesh".into(),
                    estimate: w.alive_tris as f64,
                    limit: MAX_TRIANGLES,
                });
            }
        }
        if split == 0 {
            return Ok(());
        }
    }
}

/// Whether collapsing `h` (its origin removed) respects the features, and where the kept
/// vertex goes.
fn collapse_target(w: &TriMesh, h: u32) -> Option<Vec3> {
    let (a, b) = (w.orig(h) as usize, w.dest(h) as usize);
    let (da, db) = (w.feature_degree[a], w.feature_degree[b]);
    let g = w.twin[h as usize];
    // Two feature edges of one side triangle would merge into one.
    let side = |e: u32| w.feature[next(e) as usize] && w.feature[prev(e) as usize];
    if side(h) || side(g) {
        return None;
    }
    match (da, db) {
        (0, 0) => Some((w.pos[a] + w.pos[b]) * 0.5),
        (0, _) => Some(w.pos[b]),
        (2, _) if w.feature[h as usize] => Some(w.pos[b]),
        _ => None,
    }
}

fn collapse_short(
    w: &mut TriMesh,
    low: f64,
    high: f64,
    ring_a: &mut Vec<u32>,
    ring_b: &mut Vec<u32>,
) -> Result<(), FinishError> {
    let high2 = high * high;
    for h0 in 0..w.tv.len() as u32 {
        limits::poll_at(h0 as usize)?;
        if !w.tri_alive[(h0 / 3) as usize] || w.len(h0) >= low {
            continue;
        }
        // Try both directions.
        for h in [h0, w.twin[h0 as usize]] {
            let Some(p) = collapse_target(w, h) else { continue };
            let a = w.orig(h);
            w.ring(a, ring_a);
            if !w.link_ok(h, ring_a, ring_b) {
                continue;
            }
            // No edge of the result longer than `high`, none folded.
            let b = w.dest(h);
            let far = ring_a.iter().any(|&o| w.pos[w.dest(o) as usize].distance_squared(p) > high2)
                || ring_b.iter().any(|&o| w.pos[w.dest(o) as usize].distance_squared(p) > high2);
            if far {
                continue;
            }
            let moved_b = (w.pos[b as usize] != p).then_some((ring_b.as_slice(), p));
            if !w.keeps_orientation(h, ring_a, p, moved_b) {
                continue;
            }
            w.collapse(h, p, ring_a);
            break;
        }
    }
    Ok(())
}

fn valence(w: &TriMesh, v: u32, ring: &mut Vec<u32>) -> i32 {
    w.ring(v, ring);
    ring.len() as i32
}

fn flip_to_valence(w: &mut TriMesh, ring: &mut Vec<u32>) -> Result<(), FinishError> {
    for h in 0..w.tv.len() as u32 {
        limits::poll_at(h as usize)?;
        if !w.tri_alive[(h / 3) as usize] || h > w.twin[h as usize] || w.feature[h as usize] {
            continue;
        }
        let g = w.twin[h as usize];
        let (a, b, c, d) = (w.orig(h), w.dest(h), w.tv[prev(h) as usize], w.tv[prev(g) as usize]);
        if c == d {
            continue;
        }
        let (va, vb, vc, vd) = (valence(w, a, ring), valence(w, b, ring), valence(w, c, ring), valence(w, d, ring));
        if va <= 3 || vb <= 3 {
            continue;
        }
        // c and d must not already be joined.
        w.ring(c, ring);
        if ring.iter().any(|&o| w.dest(o) == d) {
            continue;
        }
        let dev = |x: i32| (x - 6).abs();
        let before = dev(va) + dev(vb) + dev(vc) + dev(vd);
        let after = dev(va - 1) + dev(vb - 1) + dev(vc + 1) + dev(vd + 1);
        if after >= before {
            continue;
        }
        // The two new triangles must face the way the old ones did.
        let (pa, pb, pc, pd) = (w.pos[a as usize], w.pos[b as usize], w.pos[c as usize], w.pos[d as usize]);
        let n_old = (pb - pa).cross(pc - pa) + (pa - pb).cross(pd - pb);
        let n1 = (pd - pa).cross(pc - pa);
        let n2 = (pc - pb).cross(pd - pb);
        if n1.dot(n_old) <= 0.0 || n2.dot(n_old) <= 0.0 || n1.dot(n2) <= 0.0 {
            continue;
        }
        w.flip(h);
    }
    Ok(())
}

fn relax_and_project(w: &mut TriMesh, reference: &Reference, ring: &mut Vec<u32>) -> Result<(), FinishError> {
    let n = w.pos.len();
    let mut target = w.pos.clone();
    for (v, slot) in target.iter_mut().enumerate() {
        limits::poll_at(v)?;
        if !w.vert_alive[v] || w.feature_degree[v] != 0 {
            continue;
        }
        w.ring(v as u32, ring);
        let p = w.pos[v];
        let mut centroid = Vec3::ZERO;
        let mut normal = Vec3::ZERO;
        for &o in ring.iter() {
            centroid += w.pos[w.dest(o) as usize];
            normal += w.tri_normal(o / 3);
        }
        centroid /= ring.len() as f64;
        let Some(nrm) = normal.try_normalize() else { continue };
        // Tangential relaxation: the centroid's offset with its normal part removed.
        *slot = centroid + nrm * nrm.dot(p - centroid);
    }
    for (v, &t) in target.iter().enumerate().take(n) {
        limits::poll_at(v)?;
        if w.vert_alive[v] && w.feature_degree[v] == 0 && t != w.pos[v] {
            w.pos[v] = reference.project(t);
        }
    }
    Ok(())
}

fn report(input: &Mesh, out: &Mesh, reference: &Reference) -> RemeshReport {
    let mut min_angle = 180.0f64;
    let (mut sum, mut sum2, mut n) = (0.0, 0.0, 0.0);
    for f in 0..out.face_count() as u32 {
        let p: Vec<Vec3> = out.face_vertices(f).map(|v| out.position(v)).collect();
        for i in 0..3 {
            let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
            min_angle = min_angle.min((b - a).angle_between(c - a).to_degrees());
        }
    }
    for h in out.edges() {
        let l = out.position(out.origin(h)).distance(out.position(out.target(h)));
        sum += l;
        sum2 += l * l;
        n += 1.0;
    }
    let mean = sum / n;
    let distance_to_input = out.positions().iter().map(|&p| reference.project(p).distance(p)).fold(0.0, f64::max);
    RemeshReport {
        volume_before: input.volume(),
        volume_after: out.volume(),
        distance_to_input,
        min_angle,
        mean_edge: mean,
        edge_deviation: (sum2 / n - mean * mean).max(0.0).sqrt(),
    }
}

#[cfg(test)]
#[path = "tests_remesh.rs"]
mod tests;
