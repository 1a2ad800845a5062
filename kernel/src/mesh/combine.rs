//! Disjoint union: several meshes gathered into one without joining them.

use super::face_part::{joined_id, joined_parts};
use super::{FaceSource, Mesh, MeshError};

impl Mesh {
    /// One mesh holding every mesh of `parts` side by side: vertex and face ids of part k are
    /// offset by the counts of the parts before it; crease tags, corners, colours, face sources and
    /// face parts are kept (parts without colours get white where another part has colours, parts
    /// without sources [`FaceSource::Unknown`], meshes without face parts a default part each).
    ///
    /// No intersection is resolved: overlapping parts stay overlapping (see the CSG module for
    /// booleans).
    ///
    /// # Errors
    /// [`MeshError::TooLarge`] when the result would exceed 32-bit ids.
    pub fn combine(parts: &[&Mesh]) -> Result<Mesh, MeshError> {
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        let mut arities = Vec::new();
        let mut creases = Vec::new();
        let mut corners = Vec::new();
        let any_colors = parts.iter().any(|m| m.vertex_colors.is_some());
        let mut colors = Vec::new();
        let any_sources = parts.iter().any(|m| m.face_sources.is_some());
        let mut sources = Vec::new();
        for m in parts {
            if any_sources {
                match &m.face_sources {
                    Some(s) => sources.extend_from_slice(s),
                    None => sources.extend(std::iter::repeat_n(FaceSource::Unknown, m.face_count())),
                }
            }
            let offset = u32::try_from(positions.len())
                .map_err(|_| MeshError::TooLarge { what: "combined vertex count".into() })?;
            let (idx, ar) = m.to_indexed();
            indices.extend(idx.iter().map(|&v| v + offset));
            arities.extend(ar);
            creases.extend(m.crease_sharpnesses().into_iter().map(|([a, b], s)| ([a + offset, b + offset], s)));
            corners.extend(m.vertex_sharpness.iter().copied());
            if any_colors {
                match &m.vertex_colors {
                    Some(c) => colors.extend_from_slice(c),
                    None => colors.extend(std::iter::repeat_n([1.0f32; 4], m.vertex_count())),
                }
            }
            positions.extend_from_slice(&m.positions);
        }
        let mut out = Mesh::from_indexed(positions, &indices, &arities)?;
        if let Some((table, offsets)) = joined_parts(parts) {
            let ids = parts
                .iter()
                .zip(&offsets)
                .flat_map(|(m, &o)| (0..m.face_count() as u32).map(move |f| joined_id(m, o, f)))
                .collect();
            out.face_parts = Some(ids);
            out.parts = table;
        }
        for ([a, b], s) in creases {
            let h = out.find_halfedge(a, b).ok_or(MeshError::NotAnEdge { a, b })?;
            out.set_edge_sharpness_halfedge(h, s);
        }
        out.vertex_sharpness = corners;
        out.subdiv_options = parts.first().map(|m| m.subdiv_options).unwrap_or_default();
        if any_colors {
            out.vertex_colors = Some(colors);
        }
        if any_sources {
            out.face_sources = Some(sources);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use crate::{Mesh, Vec3};

    #[test]
    fn combined_parts_add_counts_volumes_and_components() {
        let a = Mesh::cube(2.0);
        let b = Mesh::torus(2.0, 0.5, 12, 8).translate(Vec3::X * 10.0);
        let mut a_creased = a.clone();
        a_creased.crease_all();
        let m = Mesh::combine(&[&a_creased, &b]).unwrap();
        assert_eq!(m.vertex_count(), a.vertex_count() + b.vertex_count());
        assert_eq!(m.face_count(), a.face_count() + b.face_count());
        assert_eq!(m.component_count(), 2);
        // χ adds: 2 (sphere) + 0 (torus); genus adds: 0 + 1.
        assert_eq!(m.euler(), 2);
        assert_eq!(m.genus(), 1);
        assert!((m.volume() - (a.volume() + b.volume())).abs() < 1e-12);
        assert_eq!(m.crease_count(), 12);
    }
}
