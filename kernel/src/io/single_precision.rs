//! Meshes written with 32-bit coordinates (glTF's `FLOAT` positions, binary STL) stay closed.
//!
//! A closed manifold mesh can hold two vertices, joined by an edge, that are distinct in 64 bits
//! but round to one 32-bit point: the short edges of the slivers a boolean leaves where two
//! surfaces nearly meet (a plant's solid, `PolarMesh::to_solid`, has a few at every branch base).
//! Written as they are, every reader that joins corners by position (trimesh, slicers, STL
//! readers, which have no indices to go by) finds the sliver's edges shared by four faces: the
//! file is not watertight although the mesh was. Rounding to 32 bits moves those two vertices to
//! one point anyway, so the writer collapses each such edge first (the collapse keeps the
//! manifold, [`Mesh::collapse_edge`]'s link condition, or is skipped): what the file holds is the
//! mesh as 32 bits can hold it, with the topology rounding implies. Edges whose ends stay apart
//! in 32 bits are never touched, so a mesh without such edges is written exactly as before.
//!
//! Cost: one pass over the edges (linear); each collapse is local, and a pass is repeated only
//! while collapses happen (a collapse can bring two ends of another edge together).

use std::borrow::Cow;

use crate::mesh::Mesh;

/// A position as the file stores it.
fn single(m: &Mesh, v: u32) -> [f32; 3] {
    let p = m.position(v);
    [p.x as f32, p.y as f32, p.z as f32]
}

/// Whether the ends of half-edge `h` round to one 32-bit point.
fn collapses(m: &Mesh, h: u32) -> bool {
    single(m, m.origin(h)) == single(m, m.target(h))
}

/// `mesh` with every edge whose ends round to one 32-bit point collapsed where the manifold
/// allows (see the module's documentation); borrowed unchanged when no edge does.
///
/// # Errors
/// [`crate::limits::LimitError`] when the run is stopped (polled once per half-edge scanned).
pub(crate) fn for_single_precision(mesh: &Mesh) -> Result<Cow<'_, Mesh>, crate::limits::LimitError> {
    let mut any = false;
    for h in 0..mesh.halfedge_count() as u32 {
        crate::limits::poll_at(h as usize)?;
        if collapses(mesh, h) {
            any = true;
            break;
        }
    }
    if !any {
        return Ok(Cow::Borrowed(mesh));
    }
    let mut m = mesh.clone();
    loop {
        let mut changed = false;
        let mut h = 0u32;
        while (h as usize) < m.halfedge_count() {
            crate::limits::poll_at(h as usize)?;
            if collapses(&m, h) {
                let keep = m.position(m.origin(h));
                if m.collapse_edge(h, keep).is_ok() {
                    // Ids may have moved into the freed slots: look at this one again.
                    changed = true;
                    continue;
                }
            }
            h += 1;
        }
        if !changed {
            return Ok(Cow::Owned(m));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// A cube whose corner 0 is split into two vertices 1e-9 apart by an edge (a quad's corner
    /// cut off by a sliver): closed and manifold in 64 bits.
    fn cube_with_a_sliver() -> Mesh {
        let cube = Mesh::cube(2.0).triangulate().unwrap();
        let h = (0..cube.halfedge_count() as u32).find(|&h| cube.origin(h) == 0).unwrap();
        let mut m = cube.clone();
        m.split_edge(h, 1e-9).unwrap();
        m
    }

    #[test]
    fn an_edge_shorter_than_single_precision_is_collapsed_and_the_rest_kept() {
        let m = cube_with_a_sliver();
        assert!(m.is_closed() && m.is_manifold());
        let written = for_single_precision(&m).unwrap();
        assert!(matches!(written, Cow::Owned(_)));
        assert_eq!(written.vertex_count(), m.vertex_count() - 1);
        assert!(written.is_closed() && written.is_manifold());
        // No two vertices of the written mesh share a 32-bit point.
        let mut points: Vec<[u32; 3]> =
            (0..written.vertex_count() as u32).map(|v| single(&written, v).map(f32::to_bits)).collect();
        points.sort_unstable();
        points.dedup();
        assert_eq!(points.len(), written.vertex_count());
        assert!((written.volume() - 8.0).abs() < 1e-6);
    }

    /// The triangles of a binary STL as 32-bit corners.
    fn stl_triangles(bytes: &[u8]) -> Vec<[[u32; 3]; 3]> {
        let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
        (0..n)
            .map(|t| {
                let at = 84 + 50 * t + 12;
                let f = |k: usize| f32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap()).to_bits();
                [[f(0), f(1), f(2)], [f(3), f(4), f(5)], [f(6), f(7), f(8)]]
            })
            .collect()
    }

    #[test]
    fn a_saved_stl_is_closed_for_a_reader_that_joins_corners_by_position() {
        // What trimesh or a slicer does with an STL: corners are joined by their 32-bit point,
        // and every edge must then be in exactly two triangles, none with two corners at one point.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sliver.stl");
        crate::io::save(&cube_with_a_sliver(), &path).unwrap();
        let tris = stl_triangles(&std::fs::read(&path).unwrap());
        let mut edges = std::collections::HashMap::new();
        for t in &tris {
            assert!(t[0] != t[1] && t[1] != t[2] && t[2] != t[0], "a triangle folded flat: {t:?}");
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry(if a < b { (a, b) } else { (b, a) }).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 2), "{edges:?}");
        assert_eq!(tris.len(), 12);
    }

    #[test]
    fn a_mesh_without_such_edges_is_written_as_it_is() {
        let m = Mesh::cube(2.0).translate(Vec3::new(1e6, 0.0, 0.0));
        assert!(matches!(for_single_precision(&m).unwrap(), Cow::Borrowed(_)));
    }
}
