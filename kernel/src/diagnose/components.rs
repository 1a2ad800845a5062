//! A mesh's connected pieces as meshes of their own, and its boundary loops as vertex lists.

use crate::mesh::{Mesh, MeshError, NONE};

/// Each connected component of `mesh` (faces joined across edges) as a mesh of its own, in
/// the order of their first faces ([`Mesh::face_components`]). Vertices are renumbered in the
/// order of first use by the component's faces (faces in increasing id); positions are copied
/// exactly, with vertex colours, crease and corner sharpness, face parts and face sources.
///
/// # Errors
/// [`MeshError::Limit`] when the current cancellation token stops (polled per component).
pub fn components(mesh: &Mesh) -> Result<Vec<Mesh>, MeshError> {
    let mut out = Vec::new();
    let mut new_id = vec![NONE; mesh.vertex_count()];
    for faces in mesh.face_components() {
        crate::limits::poll()?;
        let mut positions = Vec::new();
        let mut old: Vec<u32> = Vec::new();
        let mut polys: Vec<Vec<u32>> = Vec::with_capacity(faces.len());
        for &f in &faces {
            polys.push(
                mesh.face_vertices(f)
                    .map(|v| {
                        if new_id[v as usize] == NONE {
                            new_id[v as usize] = old.len() as u32;
                            old.push(v);
                            positions.push(mesh.position(v));
                        }
                        new_id[v as usize]
                    })
                    .collect(),
            );
        }
        let mut m = Mesh::from_polygons(positions, &polys)?;
        m.set_subdiv_options(mesh.subdiv_options());
        if let Some(c) = mesh.vertex_colors() {
            m.set_vertex_colors(Some(old.iter().map(|&v| c[v as usize]).collect()))?;
        }
        for (new, &v) in old.iter().enumerate() {
            let s = mesh.corner_sharpness(v);
            if s != 0.0 {
                m.set_corner_sharpness(new as u32, s);
            }
        }
        for ([a, b], s) in mesh.crease_sharpnesses() {
            let (na, nb) = (new_id[a as usize], new_id[b as usize]);
            if na != NONE && nb != NONE {
                if let Some(h) = m.find_halfedge(na, nb) {
                    m.set_edge_sharpness_halfedge(h, s);
                }
            }
        }
        if let (Some(ids), parts) = (mesh.face_part_ids(), mesh.parts()) {
            m.set_face_parts(faces.iter().map(|&f| ids[f as usize]).collect(), parts.to_vec())?;
        }
        if let Some(src) = mesh.face_sources() {
            m.set_face_sources(Some(faces.iter().map(|&f| src[f as usize]).collect()))?;
        }
        for &v in &old {
            new_id[v as usize] = NONE;
        }
        out.push(m);
    }
    Ok(out)
}

/// Each boundary loop of `mesh` as its vertex ids, in the order its boundary half-edges run
/// (against the faces beside them), loops in the order of their first boundary half-edge.
#[must_use]
pub fn boundary_loops(mesh: &Mesh) -> Vec<Vec<u32>> {
    mesh.boundary_loops().into_iter().map(|l| l.into_iter().map(|h| mesh.origin(h)).collect()).collect()
}
