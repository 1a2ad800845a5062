//! What is wrong with a model on show, as the page draws it: the kernel's
//! [`blocksmith_kernel::diagnose::defects`] turned into geometry in the kernel's frame — open
//! boundaries and handle loops as line segments, edges and vertices where sheets touch as
//! segments and points, self-crossing faces as their triangles, degenerate faces as points —
//! and the components, which the page shows one by one (their faces from
//! `GET /model/V/I.faces?component=K`).

use blocksmith_kernel::diagnose::{defects, Defect, DefectKind};
use blocksmith_kernel::{Mesh, Vec3};
use serde_json::{json, Value};

use super::recipe_lines;

/// The most crossing faces whose triangles are sent; the rest are counted
/// (`crossing_faces_shown` < `crossing_faces`).
pub const MAX_CROSSING_FACES: usize = 20_000;

/// `mesh`'s defects as the page draws them (see the module's doc):
///
/// ```json
/// {"counts": {"boundary": 1, "handle": 1, ...},
///  "boundaries": [x, y, z, x, y, z, ...], "handles": [...], "non_manifold_edges": [...],
///  "non_manifold_vertices": [x, y, z, ...], "degenerate_faces": [x, y, z, ...],
///  "crossings": [x, y, z of each triangle corner], "crossing_faces": 12, "crossing_faces_shown": 12,
///  "components": [{"component": 0, "faces": 96, "genus": 1}, ...]}
/// ```
///
/// Segments are pairs of ends (a loop of n vertices gives n segments). `components` is empty
/// when the mesh is one closed component without handles.
///
/// # Errors
/// The kernel's reason when the mesh cannot be examined.
pub fn json(mesh: &Mesh) -> Result<Value, String> {
    let found = defects(mesh).map_err(|e| e.to_string())?;
    let of = |kind: DefectKind| found.iter().filter(move |d| d.kind == kind);
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    for d in &found {
        *counts.entry(d.kind.name()).or_default() += 1;
    }
    let loops = |kind| of(kind).flat_map(|d: &Defect| loop_segments(mesh, &d.elements)).collect::<Vec<f32>>();
    let edges: Vec<f32> = of(DefectKind::NonManifoldEdge)
        .flat_map(|d| {
            d.elements
                .chunks_exact(2)
                .flat_map(|pair| point(mesh.position(pair[0])).into_iter().chain(point(mesh.position(pair[1]))))
        })
        .collect();
    let vertices: Vec<f32> = of(DefectKind::NonManifoldVertex)
        .flat_map(|d| d.elements.iter().flat_map(|&v| point(mesh.position(v))))
        .collect();
    let degenerate: Vec<f32> = of(DefectKind::DegenerateFace).flat_map(|d| point(d.position)).collect();
    let mut crossing: Vec<u32> = of(DefectKind::SelfIntersection).flat_map(|d| d.elements.iter().copied()).collect();
    crossing.sort_unstable();
    crossing.dedup();
    let shown = crossing.len().min(MAX_CROSSING_FACES);
    let components: Vec<Value> = of(DefectKind::Component)
        .map(|d| json!({ "component": d.component, "faces": d.elements.len(), "genus": d.genus }))
        .collect();
    Ok(json!({
        "counts": counts,
        "boundaries": loops(DefectKind::Boundary),
        "handles": loops(DefectKind::Handle),
        "non_manifold_edges": edges,
        "non_manifold_vertices": vertices,
        "degenerate_faces": degenerate,
        "crossings": recipe_lines::triangles(mesh, &crossing[..shown]),
        "crossing_faces": crossing.len(),
        "crossing_faces_shown": shown,
        "components": components,
    }))
}

/// The faces of component `k` of `mesh` (numbered as [`Mesh::face_components`] and the
/// `component` of `json`'s components), or none past the last.
#[must_use]
pub fn component_faces(mesh: &Mesh, k: usize) -> Vec<u32> {
    mesh.face_components().into_iter().nth(k).unwrap_or_default()
}

/// The closed loop through `vertices` as segments: each vertex to the next, the last back to
/// the first.
fn loop_segments(mesh: &Mesh, vertices: &[u32]) -> Vec<f32> {
    let n = vertices.len();
    (0..n)
        .flat_map(|i| point(mesh.position(vertices[i])).into_iter().chain(point(mesh.position(vertices[(i + 1) % n]))))
        .collect()
}

fn point(p: Vec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

#[cfg(test)]
mod tests {
    use blocksmith_kernel::{Mesh, Vec3};

    /// An open square (one face) beside a closed cube and a torus, combined without a union.
    fn three_parts() -> Mesh {
        let square = Mesh::from_indexed(
            vec![
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(6.0, 0.0, 0.0),
                Vec3::new(6.0, 1.0, 0.0),
                Vec3::new(5.0, 1.0, 0.0),
            ],
            &[0, 1, 2, 3],
            &[4],
        )
        .unwrap();
        let cube = Mesh::cube(1.0);
        let torus = Mesh::torus(2.0, 0.5, 24, 12).translate(Vec3::new(-6.0, 0.0, 0.0));
        Mesh::combine(&[&square, &cube, &torus]).unwrap()
    }

    #[test]
    fn a_models_defects_come_as_geometry_to_draw_and_its_components_by_number() {
        let mesh = three_parts();
        let j = super::json(&mesh).unwrap();
        assert_eq!(j["counts"]["boundary"], 1, "{}", j["counts"]);
        assert_eq!(j["counts"]["handle"], 1, "{}", j["counts"]);
        assert_eq!(j["counts"]["component"], 3, "{}", j["counts"]);
        // The square's boundary: four segments of six numbers, each of length 1.
        let b: Vec<f64> = j["boundaries"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert_eq!(b.len(), 4 * 6);
        for s in b.chunks_exact(6) {
            let len = ((s[0] - s[3]).powi(2) + (s[1] - s[4]).powi(2) + (s[2] - s[5]).powi(2)).sqrt();
            assert!((len - 1.0).abs() < 1e-6, "{s:?}");
        }
        // The handle loop lies on the torus: each end 0.5 from its core circle of radius 2.
        let h: Vec<f64> = j["handles"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert!(!h.is_empty() && h.len().is_multiple_of(6));
        for p in h.chunks_exact(3) {
            let (x, y, z) = (p[0] + 6.0, p[1], p[2]);
            let tube = (((x * x + y * y).sqrt() - 2.0).powi(2) + z * z).sqrt();
            assert!((tube - 0.5).abs() < 1e-5, "{p:?} is {tube} from the core");
        }
        let genus: Vec<i64> =
            j["components"].as_array().unwrap().iter().map(|c| c["genus"].as_i64().unwrap()).collect();
        assert_eq!(genus.iter().filter(|&&g| g == 1).count(), 1, "{genus:?}");
        // Each listed component's faces, by its number, partition the mesh.
        let total: usize = j["components"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let faces = super::component_faces(&mesh, c["component"].as_u64().unwrap() as usize);
                assert_eq!(faces.len() as u64, c["faces"].as_u64().unwrap());
                faces.len()
            })
            .sum();
        assert_eq!(total, mesh.face_count());
        assert!(super::component_faces(&mesh, 3).is_empty());
        assert_eq!(j["crossing_faces"], 0);
    }

    #[test]
    fn crossing_faces_come_as_their_triangles() {
        let a = Mesh::cube(1.0);
        let b = a.translate(Vec3::new(0.5, 0.5, 0.5));
        let mesh = Mesh::combine(&[&a, &b]).unwrap();
        let j = super::json(&mesh).unwrap();
        let faces = j["crossing_faces"].as_u64().unwrap();
        assert!(faces >= 6, "{j}");
        assert_eq!(j["crossing_faces_shown"], faces);
        // Quads: two triangles of nine numbers each.
        assert_eq!(j["crossings"].as_array().unwrap().len() as u64, faces * 2 * 9);
        assert!(j["boundaries"].as_array().unwrap().is_empty() && j["handles"].as_array().unwrap().is_empty());
    }
}
