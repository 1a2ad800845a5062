//! Colours by source, the studio's provenance view (`gltf::write_glb_provenance`; never what
//! `save` writes, as provenance is not the model's colour): a mesh whose faces carry
//! [`FaceSource`]s (a boolean result) is written with one colour per source — per input, and per block for block inputs — as
//! per-vertex `COLOR_0`, its vertices split where faces of different sources meet (glTF has no
//! per-face colours). The split only touches the file: positions and normals are those of the
//! mesh's vertices, so the surface stays closed when welded by position.

use std::collections::HashMap;

use crate::limits::LimitError;
use crate::math::hsv_rgba;
use crate::mesh::{FaceSource, Mesh};

/// The file's vertices after splitting: for each, the mesh vertex it copies and its colour; and
/// the triangles re-indexed to them.
pub(crate) struct SourceSplit {
    pub from: Vec<u32>,
    pub colors: Vec<[f32; 4]>,
    pub tris: Vec<u32>,
    /// Area-weighted normals of each file vertex over its own source's triangles only, so a
    /// seam between sources shades as the crease it is.
    pub normals: Vec<[f32; 3]>,
}

/// The colour of a source: a hue per (input, block) stepped by the golden ratio, so neighbours
/// in numbering differ clearly; unknown sources are grey.
#[must_use]
pub fn source_color(source: &FaceSource) -> [f32; 4] {
    let key = match *source {
        FaceSource::Block { leaf, sub_face } => u64::from(leaf) * 1_000_003 + u64::from(sub_face.block) + 1,
        FaceSource::Mesh { leaf, .. } => u64::from(leaf) * 1_000_003,
        FaceSource::Unknown => return [0.6, 0.6, 0.6, 1.0],
    };
    hsv_rgba(key as f64 * 0.618_033_988_749_895, 0.55, 0.92)
}

/// The split for `mesh` whose polygons triangulate to `tris` (with `arities`, as
/// `face_triangles` gives them); `None` when the mesh has no face sources or has its
/// own vertex colours (those win).
///
/// # Errors
/// [`LimitError::Stopped`] when the current cancellation token stops (polled every
/// [`crate::limits::POLL_EVERY`] faces).
pub(crate) fn split_by_source(mesh: &Mesh, tris: &[u32], arities: &[u32]) -> Result<Option<SourceSplit>, LimitError> {
    let Some(sources) = mesh.face_sources() else { return Ok(None) };
    if mesh.vertex_colors().is_some() {
        return Ok(None);
    }
    let mut palette: HashMap<[u32; 4], u32> = HashMap::new();
    let mut index: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.vertex_count() * 5 / 4);
    let mut out =
        SourceSplit { from: Vec::new(), colors: Vec::new(), tris: Vec::with_capacity(tris.len()), normals: Vec::new() };
    let mut sums: Vec<crate::Vec3> = Vec::new();
    let p = mesh.positions();
    let mut start = 0;
    for (f, &a) in arities.iter().enumerate() {
        crate::limits::poll_at(f)?;
        let color = source_color(&sources[f]);
        let n = palette.len() as u32;
        let c = *palette.entry(color.map(f32::to_bits)).or_insert(n);
        let t = &tris[start..start + 3 * (a as usize - 2)];
        start += t.len();
        for tri in t.chunks_exact(3) {
            let (a, b, d) = (p[tri[0] as usize], p[tri[1] as usize], p[tri[2] as usize]);
            let n = (b - a).cross(d - a);
            for &v in tri {
                let id = *index.entry((v, c)).or_insert_with(|| {
                    out.from.push(v);
                    out.colors.push(color);
                    sums.push(crate::Vec3::ZERO);
                    (out.from.len() - 1) as u32
                });
                sums[id as usize] += n;
                out.tris.push(id);
            }
        }
    }
    out.normals = sums
        .iter()
        .map(|s| {
            let n = s.normalize_or_zero();
            if n == crate::Vec3::ZERO {
                [0.0, 0.0, 1.0]
            } else {
                [n.x as f32, n.y as f32, n.z as f32]
            }
        })
        .collect();
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::csg::Csg;
    use crate::io::gltf::{read_gltf, read_gltf_with, write_glb, write_glb_provenance};
    use crate::io::Weld;
    use crate::mesh::Mesh;
    use crate::Vec3;

    #[test]
    fn a_boolean_result_is_written_with_a_colour_per_source_only_in_the_provenance_view() {
        let m = Csg::mesh(Mesh::cuboid(Vec3::ZERO, Vec3::ONE))
            .difference(Csg::mesh(Mesh::cuboid(Vec3::splat(0.5), Vec3::splat(1.5))))
            .evaluate()
            .unwrap();
        // What `save` writes: no colours at all.
        let mut saved = Vec::new();
        write_glb(&m, &mut saved, Path::new("t.glb")).unwrap();
        let plain = read_gltf_with(&saved, None, Path::new("t.glb"), Weld::Off).unwrap();
        assert!(plain.vertex_colors().is_none() && !plain.has_face_colors());
        assert_eq!(plain.vertex_count(), m.vertex_count());
        let mut bytes = Vec::new();
        write_glb_provenance(&m, &mut bytes, Path::new("t.glb")).unwrap();
        // Welded by position (the default), the file reads back as the closed result.
        let welded = read_gltf(&bytes, None, Path::new("t.glb")).unwrap();
        assert_eq!((welded.vertex_count(), welded.face_count()), (m.vertex_count(), m.face_count()));
        assert!(welded.is_closed() && welded.is_manifold());
        let back = read_gltf_with(&bytes, None, Path::new("t.glb"), Weld::Off).unwrap();
        assert_eq!(back.face_count(), m.face_count());
        // Each vertex is written once per source among its faces (doubled on the seams).
        let expected: usize = (0..m.vertex_count() as u32)
            .map(|v| {
                let mut leaves: Vec<u32> =
                    m.vertex_faces(v).map(|f| m.face_sources().unwrap()[f as usize].leaf().unwrap()).collect();
                leaves.sort_unstable();
                leaves.dedup();
                leaves.len()
            })
            .sum();
        assert_eq!(back.vertex_count(), expected);
        let colors = back.vertex_colors().unwrap();
        let mut distinct: Vec<[u32; 4]> = colors.iter().map(|c| c.map(f32::to_bits)).collect();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 2, "one colour per input");
    }
}
