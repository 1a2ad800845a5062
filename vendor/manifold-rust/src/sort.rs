// sort.rs — Phase 5: SortGeometry, Morton codes, vertex/face sorting
//
// Ports src/sort.cpp from the Manifold C++ library.
// The Collider is stubbed (Phase 10 will implement it fully).

use crate::impl_mesh::ManifoldImpl;
use crate::linalg::Vec3;
use crate::types::Box as BBox;

// -----------------------------------------------------------------------
// Morton code (30-bit, 10 bits per axis)
// -----------------------------------------------------------------------

const K_NO_CODE: u32 = 0xFFFF_FFFFu32;

/// Element count from which the passes below run in parallel; above C++'s
/// `kSeqThreshold` (1e4), as they are cheap per element. Each is a per-element
/// map or update or a stable integer-key sort, so the result is sequential's.
const PAR_THRESHOLD: usize = 10_000;

/// The indices `0..codes.len()` ordered by `codes`, equal codes in index order: what a stable
/// sort of `0..n` by `codes[i]` gives. blocksmith patch (PATCHES.md, 3): the comparison sort it
/// replaces was a fifth of an import.
pub(crate) fn stable_order_by_code(codes: &[u32]) -> Vec<usize> {
    stable_order_by_key(codes.len(), 32, |i| u64::from(codes[i]))
}

/// The indices `0..n` ordered by `key(i)` (whose significant bits are the low `bits`), equal
/// keys in index order — a stable sort of `0..n` by key — by an LSD radix sort in 11-bit
/// digits, a pass skipped when every key has the same digit there: linear in `n`.
/// blocksmith patch (PATCHES.md, 14): the keys travel with their indices, so every pass reads
/// its input in order (an index alone sent each pass to `keys[i]` at random), and one read of
/// the keys counts the digits of every pass.
pub(crate) fn stable_order_by_key(n: usize, bits: u32, key: impl Fn(usize) -> u64) -> Vec<usize> {
    const DIGIT: u32 = 11;
    const BUCKETS: usize = 1 << DIGIT;
    if n < 64 {
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| key(i));
        return order;
    }
    // blocksmith patch (PATCHES.md, 22): keys already in order (a boolean's triangles for
    // export come in runs of one mesh ID) are their own order, without the passes; other keys
    // leave this scan at their first descent.
    let mut last = key(0);
    if (1..n).all(|i| {
        let k = key(i);
        let in_order = k >= last;
        last = k;
        in_order
    }) {
        return (0..n).collect();
    }
    let shifts: Vec<u32> = (0..bits).step_by(DIGIT as usize).collect();
    let digit = |k: u64, shift: u32| ((k >> shift) as usize) & (BUCKETS - 1);
    // blocksmith patch (PATCHES.md, 7): built a chunk at a time, a cancel seen between chunks.
    let mut items: Vec<(u64, usize)> = Vec::with_capacity(n);
    let mut counts = vec![[0usize; BUCKETS]; shifts.len()];
    for start in (0..n).step_by(crate::cancel::CHECKPOINT_EVERY) {
        crate::cancel::checkpoint();
        for i in start..(start + crate::cancel::CHECKPOINT_EVERY).min(n) {
            let k = key(i);
            for (count, &shift) in counts.iter_mut().zip(&shifts) {
                count[digit(k, shift)] += 1;
            }
            items.push((k, i));
        }
    }
    let mut next = vec![(0u64, 0usize); n];
    for (count, &shift) in counts.iter_mut().zip(&shifts) {
        if count.iter().any(|&c| c == n) {
            continue;
        }
        let mut start = 0;
        for c in count.iter_mut() {
            let k = *c;
            *c = start;
            start += k;
        }
        // blocksmith patch (PATCHES.md, 7): a cancel ends a long sort between chunks.
        for part in items.chunks(crate::cancel::CHECKPOINT_EVERY) {
            crate::cancel::checkpoint();
            for &item in part {
                let d = digit(item.0, shift);
                next[count[d]] = item;
                count[d] += 1;
            }
        }
        std::mem::swap(&mut items, &mut next);
    }
    items.into_iter().map(|(_, i)| i).collect()
}

/// Spread the low 10 bits of v into bits 0,3,6,9,...,27 (every 3rd bit).
/// This is the inverse of the interleaving needed for a 3D Morton code.
#[inline]
fn spread_bits3(mut v: u32) -> u32 {
    v = 0xFF0000FFu32 & v.wrapping_mul(0x00010001u32);
    v = 0x0F00F00Fu32 & v.wrapping_mul(0x00000101u32);
    v = 0xC30C30C3u32 & v.wrapping_mul(0x00000011u32);
    v = 0x49249249u32 & v.wrapping_mul(0x00000005u32);
    v
}

/// Compute a 30-bit Morton code for a position within the given bounding box.
/// Returns K_NO_CODE for NaN positions (unreferenced vertices).
pub fn morton_code(position: Vec3, bbox: &BBox) -> u32 {
    if position.x.is_nan() {
        return K_NO_CODE;
    }
    morton_code_impl(position, bbox)
}

fn morton_code_impl(position: Vec3, bbox: &BBox) -> u32 {
    let range = bbox.max - bbox.min;
    let xyz = (position - bbox.min) / range;
    let x_f = (1024.0 * xyz.x).min(1023.0).max(0.0);
    let y_f = (1024.0 * xyz.y).min(1023.0).max(0.0);
    let z_f = (1024.0 * xyz.z).min(1023.0).max(0.0);
    let x = spread_bits3(x_f as u32);
    let y = spread_bits3(y_f as u32);
    let z = spread_bits3(z_f as u32);
    x * 4 + y * 2 + z
}

// -----------------------------------------------------------------------
// SortVerts
// -----------------------------------------------------------------------

/// Sorts vertices by their Morton code and removes NaN-flagged vertices.
/// Updates all halfedge vertex references accordingly.
pub fn sort_verts(mesh: &mut ManifoldImpl) {
    let num_vert = mesh.vert_pos.len();
    let bbox = mesh.bbox;

    // Compute Morton code for each vertex
    let vert_pos = &mesh.vert_pos;
    let vert_morton: Vec<u32> =
        crate::par::maybe_par_map(num_vert, PAR_THRESHOLD, |v| morton_code(vert_pos[v], &bbox));

    // Build sorted index array (a stable sort, so equal codes keep index order)
    let vert_new2old: Vec<i32> = stable_order_by_code(&vert_morton).into_iter().map(|v| v as i32).collect();

    // Find how many survive (NaN verts get K_NO_CODE, sort to end)
    let new_num_vert = vert_new2old.partition_point(|&v| vert_morton[v as usize] < K_NO_CODE);
    let vert_new2old_trimmed = &vert_new2old[..new_num_vert];

    reindex_verts(mesh, vert_new2old_trimmed, num_vert);

    // Permute vert positions (only surviving verts)
    let old_pos = std::mem::take(&mut mesh.vert_pos);
    mesh.vert_pos = crate::par::maybe_par_map(new_num_vert, PAR_THRESHOLD, |v| {
        old_pos[vert_new2old_trimmed[v] as usize]
    });

    // Permute vert normals if present
    if mesh.vert_normal.len() == num_vert {
        let old_n = std::mem::take(&mut mesh.vert_normal);
        mesh.vert_normal = crate::par::maybe_par_map(new_num_vert, PAR_THRESHOLD, |v| {
            old_n[vert_new2old_trimmed[v] as usize]
        });
    }
}

/// Updates halfedge start/end vert indices from old→new index mapping.
/// `vert_new2old[new] = old` — we invert to get `vert_old2new[old] = new`.
pub fn reindex_verts(mesh: &mut ManifoldImpl, vert_new2old: &[i32], old_num_vert: usize) {
    let mut vert_old2new = vec![-1i32; old_num_vert];
    for (new_idx, &old_idx) in vert_new2old.iter().enumerate() {
        vert_old2new[old_idx as usize] = new_idx as i32;
    }
    let has_prop = mesh.num_prop > 0;
    crate::par::maybe_par_for_each_mut(&mut mesh.halfedge, PAR_THRESHOLD, |edge| {
        if edge.start_vert < 0 {
            return;
        }
        edge.start_vert = vert_old2new[edge.start_vert as usize];
        edge.end_vert = vert_old2new[edge.end_vert as usize];
        if !has_prop {
            edge.prop_vert = edge.start_vert;
        }
    });
}

// -----------------------------------------------------------------------
// GetFaceBoxMorton
// -----------------------------------------------------------------------

/// Computes per-face bounding boxes and Morton codes.
/// Faces with removed halfedges (pairedHalfedge < 0) get K_NO_CODE.
pub fn get_face_box_morton(mesh: &ManifoldImpl) -> (Vec<BBox>, Vec<u32>) {
    let num_tri = mesh.num_tri();
    let bbox = mesh.bbox;
    crate::par::maybe_par_map(num_tri, PAR_THRESHOLD, |face| {
        let mut face_box = BBox::default();
        if mesh.halfedge[3 * face].paired_halfedge < 0 {
            return (face_box, K_NO_CODE);
        }
        let mut center = Vec3::new(0.0, 0.0, 0.0);
        for i in 0..3 {
            let pos = mesh.vert_pos[mesh.halfedge[3 * face + i].start_vert as usize];
            center = center + pos;
            face_box.union_point(pos);
        }
        center = center / 3.0;
        (face_box, morton_code_impl(center, &bbox))
    })
    .into_iter()
    .unzip()
}

// -----------------------------------------------------------------------
// SortFaces / GatherFaces
// -----------------------------------------------------------------------

/// Sorts faces by Morton code, removing faces flagged for removal (K_NO_CODE).
/// Updates `face_box` and `face_morton` in-place.
pub fn sort_faces(mesh: &mut ManifoldImpl, face_box: &mut Vec<BBox>, face_morton: &mut Vec<u32>) {
    // Stable sort by Morton code (removed tris get K_NO_CODE → sorted last)
    let mut face_new2old: Vec<usize> = stable_order_by_code(face_morton);

    // Trim removed faces
    let new_num_tri = face_new2old.partition_point(|&f| face_morton[f] < K_NO_CODE);
    face_new2old.truncate(new_num_tri);

    // Permute face_morton and face_box to match new order
    let old_morton = std::mem::take(face_morton);
    let old_box = std::mem::take(face_box);
    let order = &face_new2old;
    *face_morton = crate::par::maybe_par_map(new_num_tri, PAR_THRESHOLD, |f| old_morton[order[f]]);
    *face_box = crate::par::maybe_par_map(new_num_tri, PAR_THRESHOLD, |f| old_box[order[f]]);

    gather_faces(mesh, &face_new2old);
}

/// Reorders halfedges (and related arrays) according to face_new2old permutation.
pub fn gather_faces(mesh: &mut ManifoldImpl, face_new2old: &[usize]) {
    let num_tri = face_new2old.len();
    let old_num_tri = mesh.num_tri();

    // Permute tri_ref if present
    if mesh.mesh_relation.tri_ref.len() == old_num_tri {
        let old_tri_ref = std::mem::take(&mut mesh.mesh_relation.tri_ref);
        mesh.mesh_relation.tri_ref =
            crate::par::maybe_par_map(num_tri, PAR_THRESHOLD, |f| old_tri_ref[face_new2old[f]]);
    }

    // Permute face normals if present
    if mesh.face_normal.len() == old_num_tri {
        let old_normals = std::mem::take(&mut mesh.face_normal);
        mesh.face_normal =
            crate::par::maybe_par_map(num_tri, PAR_THRESHOLD, |f| old_normals[face_new2old[f]]);
    }

    // Build faceOld2New for pairedHalfedge remapping
    let mut face_old2new = vec![-1i32; old_num_tri];
    for (new_f, &old_f) in face_new2old.iter().enumerate() {
        face_old2new[old_f] = new_f as i32;
    }

    // Gather halfedges from old layout into new
    let old_halfedge = std::mem::take(&mut mesh.halfedge);
    let old_tangent = std::mem::take(&mut mesh.halfedge_tangent);
    let has_tangent = !old_tangent.is_empty();

    mesh.halfedge = crate::par::maybe_par_map(3 * num_tri, PAR_THRESHOLD, |new_edge_idx| {
        let old_edge_idx = 3 * face_new2old[new_edge_idx / 3] + new_edge_idx % 3;
        let mut edge = old_halfedge[old_edge_idx];
        // Remap pairedHalfedge
        if edge.paired_halfedge >= 0 {
            let paired_old_face = (edge.paired_halfedge / 3) as usize;
            let offset = edge.paired_halfedge % 3;
            edge.paired_halfedge = 3 * face_old2new[paired_old_face] + offset;
        }
        edge
    });
    if has_tangent {
        mesh.halfedge_tangent =
            crate::par::maybe_par_map(3 * num_tri, PAR_THRESHOLD, |new_edge_idx| {
                old_tangent[3 * face_new2old[new_edge_idx / 3] + new_edge_idx % 3]
            });
    }
}

/// Removes the vertices (NaN positions) and faces (unpaired first half-edge)
/// flagged for removal, keeping the others in their order, and leaves the
/// mesh without a collider: [`sort_geometry`]'s clean-up without its sort, for
/// a mesh that is only exported. blocksmith patch (PATCHES.md, 17).
///
/// In place: the flagged vertices and faces are found in parallel, the maps
/// from old to new indices built in parallel (a flagged item's references
/// becoming -1, as before), every half-edge remapped in one parallel pass, and
/// the kept runs between flagged items moved down within their arrays. A
/// simplification flags a few dozen items of a million; the serial scans and
/// the new copy of every array (each page of it faulted in afresh) cost a
/// large boolean's result a twentieth of its time. The same arrays as the
/// maps and gathers ([`reindex_verts`], [`gather_faces`]). blocksmith patch
/// (PATCHES.md, 25).
pub fn compact_in_order(mesh: &mut ManifoldImpl) {
    let num_vert = mesh.vert_pos.len();
    let num_tri = mesh.num_tri();
    let removed_verts = crate::par::maybe_par_filter(num_vert, PAR_THRESHOLD, |v| mesh.vert_pos[v].x.is_nan());
    let removed_faces =
        crate::par::maybe_par_filter(num_tri, PAR_THRESHOLD, |f| mesh.halfedge[3 * f].paired_halfedge < 0);
    let has_prop = mesh.num_prop > 0;
    let (verts, faces) = (!removed_verts.is_empty(), !removed_faces.is_empty());
    if verts || faces {
        let vert_map = if verts { moved_indices(num_vert, &removed_verts) } else { Vec::new() };
        let face_map = if faces { moved_indices(num_tri, &removed_faces) } else { Vec::new() };
        crate::par::maybe_par_for_each_mut(&mut mesh.halfedge, PAR_THRESHOLD, |edge| {
            if verts && edge.start_vert >= 0 {
                edge.start_vert = vert_map[edge.start_vert as usize];
                edge.end_vert = vert_map[edge.end_vert as usize];
                if !has_prop {
                    edge.prop_vert = edge.start_vert;
                }
            }
            if faces && edge.paired_halfedge >= 0 {
                let pair = edge.paired_halfedge as usize;
                edge.paired_halfedge = 3 * face_map[pair / 3] + (pair % 3) as i32;
            }
        });
    }
    if verts {
        remove_groups(&mut mesh.vert_pos, &removed_verts, 1);
        if mesh.vert_normal.len() == num_vert {
            remove_groups(&mut mesh.vert_normal, &removed_verts, 1);
        }
    }
    if faces {
        if mesh.mesh_relation.tri_ref.len() == num_tri {
            remove_groups(&mut mesh.mesh_relation.tri_ref, &removed_faces, 1);
        }
        if mesh.face_normal.len() == num_tri {
            remove_groups(&mut mesh.face_normal, &removed_faces, 1);
        }
        remove_groups(&mut mesh.halfedge, &removed_faces, 3);
        if mesh.halfedge_tangent.len() == 3 * num_tri {
            remove_groups(&mut mesh.halfedge_tangent, &removed_faces, 3);
        }
    }
    mesh.collider = crate::collider::Collider::default();
    compact_props(mesh);
}

/// Each index of `0..n` moved down by the flagged ones (`removed`, ascending) before it, or
/// -1 if it is flagged itself: a map as [`reindex_verts`] and [`gather_faces`] build from
/// the kept ones, built in parallel runs, each starting from one binary search.
/// blocksmith patch (PATCHES.md, 25).
fn moved_indices(n: usize, removed: &[usize]) -> Vec<i32> {
    const RUN: usize = 4096;
    let mut map = vec![0i32; n];
    let runs: Vec<(usize, &mut [i32])> = map.chunks_mut(RUN).enumerate().collect();
    crate::par::maybe_par_for_each(runs, PAR_THRESHOLD / RUN, |(r, run)| {
        let first = r * RUN;
        let mut before = removed.partition_point(|&x| x < first);
        for (i, slot) in (first..).zip(run.iter_mut()) {
            if removed.get(before) == Some(&i) {
                *slot = -1;
                before += 1;
            } else {
                *slot = (i - before) as i32;
            }
        }
    });
    map
}

/// Removes from `items` the groups of `stride` items at the group indices
/// `removed` (ascending), the kept runs between them moved down in place.
/// blocksmith patch (PATCHES.md, 25).
fn remove_groups<T: Copy>(items: &mut Vec<T>, removed: &[usize], stride: usize) {
    let Some(&first) = removed.first() else {
        return;
    };
    let mut write = first * stride;
    for (k, &group) in removed.iter().enumerate() {
        let start = (group + 1) * stride;
        let end = removed.get(k + 1).map_or(items.len(), |&next| next * stride);
        items.copy_within(start..end, write);
        write += end - start;
    }
    items.truncate(write);
}

// -----------------------------------------------------------------------
// CompactProps
// -----------------------------------------------------------------------

/// Removes unreferenced property vertices and reindexes propVerts.
pub fn compact_props(mesh: &mut ManifoldImpl) {
    if mesh.num_prop == 0 {
        return;
    }
    let num_prop = mesh.num_prop;
    let num_prop_verts = mesh.properties.len() / num_prop;

    // Mark which prop verts are referenced
    let mut keep = vec![false; num_prop_verts];
    for edge in &mesh.halfedge {
        if edge.prop_vert >= 0 && (edge.prop_vert as usize) < num_prop_verts {
            keep[edge.prop_vert as usize] = true;
        }
    }

    // Build prefix sum for old→new mapping
    let mut prop_old2new = vec![0i32; num_prop_verts + 1];
    for i in 0..num_prop_verts {
        prop_old2new[i + 1] = prop_old2new[i] + if keep[i] { 1 } else { 0 };
    }
    let new_num_prop_verts = prop_old2new[num_prop_verts] as usize;

    // Compact properties array
    let old_prop = mesh.properties.clone();
    mesh.properties.resize(num_prop * new_num_prop_verts, 0.0);
    for old_idx in 0..num_prop_verts {
        if !keep[old_idx] {
            continue;
        }
        let new_idx = prop_old2new[old_idx] as usize;
        for p in 0..num_prop {
            mesh.properties[new_idx * num_prop + p] = old_prop[old_idx * num_prop + p];
        }
    }

    // Remap propVert indices in halfedges
    for edge in mesh.halfedge.iter_mut() {
        if edge.prop_vert >= 0 {
            edge.prop_vert = prop_old2new[edge.prop_vert as usize];
        }
    }
}

// -----------------------------------------------------------------------
// SortGeometry — main entry point
// -----------------------------------------------------------------------

/// Sorts vertices and faces by Morton code, removes flagged-for-deletion
/// elements, and compacts property arrays. Should be called after
/// `create_halfedges()` to finalize the mesh topology.
///
/// Note: Collider construction is done in Phase 10.
/// [`sort_geometry`] checking `token` between its steps (vertices, face boxes, faces, the
/// collider); `false` when it was cancelled, the mesh then half sorted (to be discarded).
// blocksmith patch (PATCHES.md, 6): the import's sort is stoppable.
pub fn sort_geometry_with_token(mesh: &mut ManifoldImpl, token: Option<&crate::cancel::CancelToken>) -> bool {
    if token.is_none() {
        sort_geometry(mesh);
        return true;
    }
    let cancelled = || crate::cancel::is_cancelled(token);
    if mesh.halfedge.is_empty() {
        mesh.collider = crate::collider::Collider::default();
        return !cancelled();
    }
    sort_verts(mesh);
    if cancelled() {
        return false;
    }
    let (mut face_box, mut face_morton) = get_face_box_morton(mesh);
    if cancelled() {
        return false;
    }
    sort_faces(mesh, &mut face_box, &mut face_morton);
    if cancelled() {
        return false;
    }
    if mesh.halfedge.is_empty() {
        mesh.collider = crate::collider::Collider::default();
        return true;
    }
    mesh.collider = crate::collider::Collider::new(face_box, face_morton);
    if cancelled() {
        return false;
    }
    compact_props(mesh);
    !cancelled()
}

pub fn sort_geometry(mesh: &mut ManifoldImpl) {
    if mesh.halfedge.is_empty() {
        mesh.collider = crate::collider::Collider::default();
        return;
    }
    sort_verts(mesh);
    let (mut face_box, mut face_morton) = get_face_box_morton(mesh);
    sort_faces(mesh, &mut face_box, &mut face_morton);
    if mesh.halfedge.is_empty() {
        mesh.collider = crate::collider::Collider::default();
        return;
    }
    // Cache the face BVH on the mesh (C++ builds collider_ here in
    // SortGeometry); query sites reuse it instead of rebuilding per query.
    mesh.collider = crate::collider::Collider::new(face_box, face_morton);
    compact_props(mesh);

    debug_assert!(
        mesh.halfedge.len() % 6 == 0,
        "Not an even number of halfedges after sorting (expected multiple of 6, got {})",
        mesh.halfedge.len()
    );
}

/// Counts faces whose true bounding box cannot find its own leaf in the mesh's
/// cached collider.
///
/// A box always overlaps itself, so on a closed mesh with more than one face
/// this is zero exactly when the collider was built from the geometry the mesh
/// currently holds. Anything above zero means the impl is lying about itself:
/// some site moved or added geometry without re-running `sort_geometry`, and the
/// booleans that query this collider will silently miss real intersections
/// before failing somewhere else entirely.
///
/// **It reports false misses, so only assert on it for meshes that avoid both
/// cases.** Neither is a collider fault:
/// - Faces with an unpaired halfedge — soup, or anything mid-`remove_degenerates`
///   — get no box from `get_face_box_morton` (it returns `K_NO_CODE` and leaves
///   the default empty box), and `collisions_with_boxes` skips empty queries.
///   Every such face counts as a miss.
/// - A mesh of 0 or 1 faces builds a collider with no internal nodes, and the
///   query returns immediately. Its one face counts as a miss.
///
/// Test-only — production code never asks, because every site that changes
/// geometry is supposed to finish with `sort_geometry`.
#[cfg(test)]
pub(crate) fn collider_self_misses(mesh: &ManifoldImpl) -> usize {
    let (face_box, _) = get_face_box_morton(mesh);
    let mut found_itself = vec![false; face_box.len()];
    mesh.collider
        .collisions_with_boxes(&face_box, false, |query_idx, leaf_idx| {
            if query_idx == leaf_idx {
                found_itself[query_idx] = true;
            }
        });
    found_itself.iter().filter(|found| !**found).count()
}

// -----------------------------------------------------------------------
// Tests
// -----------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;
    use crate::impl_mesh::ManifoldImpl;
    use crate::linalg::Mat3x4;

    /// The compaction as it was before patch 25: maps of every index, new arrays gathered.
    fn compact_by_maps(mesh: &mut ManifoldImpl) {
        let num_vert = mesh.vert_pos.len();
        let kept_verts: Vec<i32> = (0..num_vert)
            .filter(|&v| !mesh.vert_pos[v].x.is_nan())
            .map(|v| v as i32)
            .collect();
        if kept_verts.len() < num_vert {
            reindex_verts(mesh, &kept_verts, num_vert);
            let old_pos = std::mem::take(&mut mesh.vert_pos);
            mesh.vert_pos = kept_verts.iter().map(|&v| old_pos[v as usize]).collect();
            if mesh.vert_normal.len() == num_vert {
                let old_n = std::mem::take(&mut mesh.vert_normal);
                mesh.vert_normal = kept_verts.iter().map(|&v| old_n[v as usize]).collect();
            }
        }
        let num_tri = mesh.num_tri();
        let kept_faces: Vec<usize> =
            (0..num_tri).filter(|&f| mesh.halfedge[3 * f].paired_halfedge >= 0).collect();
        if kept_faces.len() < num_tri {
            gather_faces(mesh, &kept_faces);
        }
        mesh.collider = crate::collider::Collider::default();
        compact_props(mesh);
    }

    /// blocksmith patch (PATCHES.md, 25): the compaction in place gives the arrays the maps
    /// and gathers gave, with nothing flagged, vertices only, faces only and both (first and
    /// last ones among them, and kept half-edges pointing at flagged ones), below and above
    /// the parallel threshold, with and without properties.
    #[test]
    fn compaction_in_place_is_the_compaction_by_maps() {
        use crate::manifold::Manifold;
        let small = Manifold::sphere(1.0, 12);
        let large = Manifold::sphere(1.0, 128);
        let with_props = large.set_properties(4, |out, p, _| out.copy_from_slice(&[p.x, p.y, p.z, p.x * p.z]));
        for m in [&small, &large, &with_props] {
            let base = m.as_impl().clone();
            let (nv, nt) = (base.vert_pos.len(), base.num_tri());
            assert!(base.vert_normal.len() == nv && base.face_normal.len() == nt);
            let verts = [0, 5, 6, nv / 2, nv - 1];
            let faces = [0, 1, 9, nt / 3, nt - 1];
            for (flag_verts, flag_faces) in [(false, false), (true, false), (false, true), (true, true)] {
                let mut flagged = base.clone();
                if flag_verts {
                    for v in verts {
                        flagged.vert_pos[v] = Vec3::splat(f64::NAN);
                    }
                }
                if flag_faces {
                    for f in faces {
                        flagged.halfedge[3 * f].paired_halfedge = -1;
                    }
                }
                let (mut in_place, mut by_maps) = (flagged.clone(), flagged);
                compact_in_order(&mut in_place);
                compact_by_maps(&mut by_maps);
                let case = format!("{nt} triangles, vertices {flag_verts}, faces {flag_faces}");
                assert_eq!(in_place.halfedge, by_maps.halfedge, "{case}");
                let bits = |p: &[Vec3]| p.iter().map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]).collect::<Vec<_>>();
                assert_eq!(bits(&in_place.vert_pos), bits(&by_maps.vert_pos), "{case}");
                assert_eq!(bits(&in_place.vert_normal), bits(&by_maps.vert_normal), "{case}");
                assert_eq!(bits(&in_place.face_normal), bits(&by_maps.face_normal), "{case}");
                assert_eq!(in_place.mesh_relation.tri_ref, by_maps.mesh_relation.tri_ref, "{case}");
                assert_eq!(in_place.properties.len(), by_maps.properties.len(), "{case}");
                let removed = if flag_faces { faces.len() } else { 0 };
                assert_eq!(in_place.num_tri(), nt - removed, "{case}");
            }
        }
    }

    /// blocksmith patch (PATCHES.md, 22): keys in order are their own order, and keys that
    /// descend only at the end are sorted all the same.
    #[test]
    fn keys_in_order_give_their_order_and_a_late_descent_is_sorted() {
        for n in [64usize, 1000, 5000] {
            let runs = |i: usize| (i / 7) as u64;
            assert_eq!(stable_order_by_key(n, 64, runs), (0..n).collect::<Vec<_>>(), "n {n}");
            let late = |i: usize| if i == n - 1 { 3 } else { runs(i) + 5 };
            let mut expected: Vec<usize> = (0..n).collect();
            expected.sort_by_key(|&i| late(i));
            assert_eq!(expected[0], n - 1);
            assert_eq!(stable_order_by_key(n, 64, late), expected, "n {n}, late descent");
        }
    }

    #[test]
    fn stable_order_by_code_is_a_stable_sort() {
        let mut x = 12345u32;
        for n in [0usize, 1, 5, 63, 64, 1000, 5000] {
            for spread in [3u32, 1 << 11, 1 << 22, u32::MAX] {
                let codes: Vec<u32> = (0..n)
                    .map(|_| {
                        x ^= x << 13;
                        x ^= x >> 17;
                        x ^= x << 5;
                        if x % 7 == 0 { K_NO_CODE } else { x % spread }
                    })
                    .collect();
                let mut expected: Vec<usize> = (0..n).collect();
                expected.sort_by_key(|&i| codes[i]);
                assert_eq!(super::stable_order_by_code(&codes), expected, "n {n}, spread {spread}");
                let wide: Vec<u64> = codes.iter().map(|&c| (u64::from(c) << 32) | u64::from(c % 5)).collect();
                let mut expected: Vec<usize> = (0..n).collect();
                expected.sort_by_key(|&i| wide[i]);
                assert_eq!(super::stable_order_by_key(n, 64, |i| wide[i]), expected, "n {n}, 64 bits");
            }
        }
    }

    #[test]
    fn test_spread_bits3() {
        // SpreadBits3(0b1111111111) should interleave into alternating positions
        // Values verified against C++ constexpr evaluation
        assert_eq!(spread_bits3(0), 0);
        assert_eq!(spread_bits3(1), 1);
        // Each bit of the input lands 3 positions apart in the output
        assert_eq!(spread_bits3(0b10), 0b1000);
        assert_eq!(spread_bits3(0b11), 0b1001);
        assert_eq!(spread_bits3(0b100), 0b1000000);
    }

    #[test]
    fn test_morton_code_basic() {
        let bbox = BBox {
            min: Vec3::new(0.0, 0.0, 0.0),
            max: Vec3::new(1.0, 1.0, 1.0),
        };
        // Origin → all zeros → code 0
        let code_origin = morton_code(Vec3::new(0.0, 0.0, 0.0), &bbox);
        assert_eq!(code_origin, 0);

        // NaN → K_NO_CODE
        let code_nan = morton_code(Vec3::new(f64::NAN, 0.0, 0.0), &bbox);
        assert_eq!(code_nan, K_NO_CODE);

        // Center of cube should be a positive code less than K_NO_CODE
        let code_center = morton_code(Vec3::new(0.5, 0.5, 0.5), &bbox);
        assert!(code_center > 0 && code_center < K_NO_CODE);
    }

    #[test]
    fn test_morton_code_ordering() {
        // Points closer together should (generally) have closer Morton codes.
        // More specifically: points sorted by Morton code produce a Z-curve traversal.
        let bbox = BBox {
            min: Vec3::new(0.0, 0.0, 0.0),
            max: Vec3::new(8.0, 8.0, 8.0),
        };
        let p0 = morton_code(Vec3::new(0.0, 0.0, 0.0), &bbox);
        let p1 = morton_code(Vec3::new(1.0, 0.0, 0.0), &bbox);
        let p2 = morton_code(Vec3::new(2.0, 0.0, 0.0), &bbox);
        // These should be strictly increasing along x with y=z=0
        assert!(p0 < p1);
        assert!(p1 < p2);
    }

    #[test]
    fn test_sort_geometry_tetrahedron() {
        let mut m = ManifoldImpl::tetrahedron(&Mat3x4::identity());
        // Should have 4 vertices and 12 halfedges (4 triangles) before sort
        assert_eq!(m.vert_pos.len(), 4);
        assert_eq!(m.halfedge.len(), 12);
        sort_geometry(&mut m);
        // Sort shouldn't remove any valid verts/faces
        assert_eq!(m.vert_pos.len(), 4);
        assert_eq!(m.halfedge.len(), 12);
    }

    #[test]
    fn test_sort_geometry_cube() {
        let mut m = ManifoldImpl::cube(&Mat3x4::identity());
        let vert_count = m.vert_pos.len();
        let halfedge_count = m.halfedge.len();
        sort_geometry(&mut m);
        assert_eq!(m.vert_pos.len(), vert_count);
        assert_eq!(m.halfedge.len(), halfedge_count);
        // After sort, paired halfedges should still be valid
        for (i, edge) in m.halfedge.iter().enumerate() {
            assert!(
                edge.paired_halfedge >= 0,
                "halfedge {} has invalid paired_halfedge {}",
                i,
                edge.paired_halfedge
            );
            let paired = &m.halfedge[edge.paired_halfedge as usize];
            assert_eq!(
                paired.paired_halfedge, i as i32,
                "halfedge {} paired -> {} but paired doesn't point back",
                i, edge.paired_halfedge
            );
        }
    }

    #[test]
    fn test_reindex_verts_identity() {
        let mut m = ManifoldImpl::tetrahedron(&Mat3x4::identity());
        let n = m.vert_pos.len();
        // Identity permutation should not change anything
        let identity: Vec<i32> = (0..n as i32).collect();
        let before: Vec<_> = m
            .halfedge
            .iter()
            .map(|e| (e.start_vert, e.end_vert))
            .collect();
        reindex_verts(&mut m, &identity, n);
        let after: Vec<_> = m
            .halfedge
            .iter()
            .map(|e| (e.start_vert, e.end_vert))
            .collect();
        assert_eq!(before, after);
    }

    #[test]
    fn test_sort_faces_manifold_preserved() {
        // After sort_geometry, mesh must still be 2-manifold
        let mut m = ManifoldImpl::cube(&Mat3x4::identity());
        sort_geometry(&mut m);
        assert!(m.is_2_manifold());
    }
}
