//! The pairs of faces of a mesh that cross or touch each other away from what they share.
//!
//! Each face is cut into triangles as the writers cut it ([`Mesh::triangulate_faces`]); the
//! triangles' boxes go into a [`Bvh`](super::bvh::Bvh), whose overlapping pairs are tested
//! exactly ([`super::triangle_pair`]). Two triangles of one face are never a pair. Corners are
//! compared by position, not by id, so that the sheets a repair split apart at a vertex or an
//! edge (same position, different ids) count as sharing it: touching there is not reported,
//! crossing is. Degenerate triangles (collinear corners) are left out; [`super::defects`]
//! reports them on their own.
//!
//! Cost: O(n log n) to build the tree and O(n log n + k) to find the k overlapping boxes for
//! meshes of triangles of similar sizes (quadratic only when every box overlaps every other);
//! each test is a fixed number of exact orientations. The pairs are tested in parallel.

use rayon::prelude::*;

use super::bvh::Bvh;
use super::triangle_pair::{is_degenerate, meeting_point, shared_corner_meets, shared_edge_meets, triangles_meet};
use crate::limits::LimitError;
use crate::math::{IdMap, Vec3};
use crate::mesh::{Mesh, MeshError};

/// One crossing: two faces (the smaller id first) and a point where they meet (on both, up to
/// rounding: the mean of the points where an edge of one of their triangles crosses the other).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The two faces, `faces[0] < faces[1]`.
    pub faces: [u32; 2],
    /// A point of the crossing.
    pub at: Vec3,
}

/// The pairs of faces of `mesh` whose surfaces meet anywhere but at the corners and edges
/// they share, as `[f, g]` with `f < g`, in increasing order, each pair once.
///
/// Faces of more than three corners are cut into triangles first (as the writers cut them);
/// triangles with collinear corners are left out. Touching counts: a corner resting on another
/// face is a pair. Corners at bit-identical positions count as one (so sheets split apart at a
/// vertex do not touch there).
///
/// Exact: every decision is a sign of Shewchuk's adaptive `orient3d`/`orient2d`. Cost: see
/// the module documentation (a bounding-volume hierarchy, near-linear on meshes of
/// similar-sized faces).
///
/// # Errors
/// [`MeshError::Limit`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] faces and pair tests).
///
/// See also [`crossings`] (with a position for each pair).
pub fn self_intersections(mesh: &Mesh) -> Result<Vec<[u32; 2]>, MeshError> {
    Ok(crossings(mesh)?.into_iter().map(|c| c.faces).collect())
}

/// [`self_intersections`] with a point near each crossing.
///
/// # Errors
/// As [`self_intersections`].
pub fn crossings(mesh: &Mesh) -> Result<Vec<Crossing>, MeshError> {
    let plan = mesh.plan_triangles()?;
    let nv = mesh.vertex_count();
    let mut positions: Vec<Vec3> = mesh.positions().to_vec();
    positions.extend(plan.centres.iter().map(|&(_, c)| c));
    let canon = canonical_ids(&positions)?;
    // Triangles (canonical corners) with their face, degenerate ones left out.
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(plan.tris.len() / 3);
    let mut face_of: Vec<u32> = Vec::with_capacity(plan.tris.len() / 3);
    let mut boxes: Vec<(Vec3, Vec3)> = Vec::with_capacity(plan.tris.len() / 3);
    let mut t = 0usize;
    for (f, &count) in plan.counts().iter().enumerate() {
        crate::limits::poll_at(f)?;
        for _ in 0..count {
            let ids = [plan.tris[3 * t], plan.tris[3 * t + 1], plan.tris[3 * t + 2]];
            t += 1;
            let c = ids.map(|v| canon[v as usize]);
            let p = c.map(|v| positions[v as usize]);
            if is_degenerate(p) {
                continue;
            }
            tris.push(c);
            face_of.push(f as u32);
            boxes.push((p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2])));
        }
    }
    debug_assert!(nv <= positions.len());
    let bvh = Bvh::build(&boxes);
    let token = crate::limits::current();
    let tasks = bvh.tasks(256);
    let found: Result<Vec<Vec<Crossing>>, LimitError> = tasks
        .par_iter()
        .map(|&task| {
            let mut out = Vec::new();
            let mut tested = 0usize;
            bvh.overlapping_pairs(task, &boxes, &mut |i, j| {
                let (fi, fj) = (face_of[i as usize], face_of[j as usize]);
                if fi == fj {
                    return Ok(());
                }
                tested += 1;
                if tested.is_multiple_of(crate::limits::POLL_EVERY) {
                    if let Some(reason) = token.stopped() {
                        return Err(LimitError::Stopped(reason));
                    }
                }
                let (a, b) = (tris[i as usize], tris[j as usize]);
                if meet(a, b, &positions) {
                    let p = |t: [u32; 3]| t.map(|v| positions[v as usize]);
                    out.push(Crossing { faces: [fi.min(fj), fi.max(fj)], at: meeting_point(p(a), p(b)) });
                }
                Ok(())
            })?;
            Ok(out)
        })
        .collect();
    let mut all: Vec<Crossing> = found?.into_iter().flatten().collect();
    // One entry per face pair: the one of the lowest position (a deterministic choice, as the
    // threads find pairs in any order).
    all.sort_unstable_by(|a, b| {
        a.faces
            .cmp(&b.faces)
            .then(a.at.x.total_cmp(&b.at.x))
            .then(a.at.y.total_cmp(&b.at.y))
            .then(a.at.z.total_cmp(&b.at.z))
    });
    all.dedup_by(|b, a| a.faces == b.faces);
    Ok(all)
}

/// Whether triangles `a` and `b` (canonical corner ids, neither degenerate) meet anywhere but
/// at the corners they share.
fn meet(a: [u32; 3], b: [u32; 3], positions: &[Vec3]) -> bool {
    let p = |v: u32| positions[v as usize];
    let shared: Vec<(usize, usize)> =
        (0..3).flat_map(|i| (0..3).filter(move |&j| a[i] == b[j]).map(move |j| (i, j))).collect();
    match shared.len() {
        0 => triangles_meet(a.map(p), b.map(p)),
        1 => {
            let (i, j) = shared[0];
            shared_corner_meets(p(a[i]), p(a[(i + 1) % 3]), p(a[(i + 2) % 3]), p(b[(j + 1) % 3]), p(b[(j + 2) % 3]))
        }
        2 => {
            let (u, v) = (a[shared[0].0], a[shared[1].0]);
            let other = |t: [u32; 3]| t.into_iter().find(|&x| x != u && x != v).unwrap_or(u);
            shared_edge_meets(p(u), p(v), p(other(a)), p(other(b)))
        }
        // The same triangle twice.
        _ => true,
    }
}

/// For each vertex the smallest id at a bit-identical position (−0 = +0).
fn canonical_ids(positions: &[Vec3]) -> Result<Vec<u32>, LimitError> {
    let key = |p: Vec3| [p.x, p.y, p.z].map(|c| if c == 0.0 { 0u64 } else { c.to_bits() });
    let mut first: IdMap<[u64; 3], u32> = IdMap::default();
    first.reserve(positions.len());
    let mut out = Vec::with_capacity(positions.len());
    for (i, &p) in positions.iter().enumerate() {
        crate::limits::poll_at(i)?;
        out.push(*first.entry(key(p)).or_insert(i as u32));
    }
    Ok(out)
}
