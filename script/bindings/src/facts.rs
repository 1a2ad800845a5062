//! A mesh's facts: what the studio page lists beside a model and what `run --stats json` prints
//! for pipelines — one set, computed one way (the kernel's [`Mesh::measures`]), so the page and
//! the command line never disagree.

use blocksmith_kernel::Mesh;
use serde_json::{json, Value};

/// The facts of a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Facts {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub triangles: usize,
    pub components: usize,
    pub boundary_loops: usize,
    pub closed: bool,
    pub manifold: bool,
    pub genus: i64,
    pub volume: f64,
    pub area: f64,
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Facts {
    /// The facts of `mesh`.
    #[must_use]
    pub fn of(mesh: &Mesh) -> Facts {
        let m = mesh.measures();
        Facts {
            vertices: m.vertices,
            edges: m.edges,
            faces: m.faces,
            triangles: mesh.triangle_count(),
            components: m.components,
            boundary_loops: m.boundary_loops,
            closed: mesh.is_closed(),
            manifold: mesh.is_manifold(),
            genus: m.genus,
            volume: m.volume,
            area: m.area,
            min: m.bounds.min.to_array(),
            max: m.bounds.max.to_array(),
        }
    }

    /// The facts as a JSON object: counts (`vertices`, `edges`, `faces`, `triangles`,
    /// `components`, `boundary_loops`), `closed`, `manifold`, `genus`, `volume`, `area` and
    /// `bounds` (`min`, `max`).
    #[must_use]
    pub fn json(&self) -> Value {
        json!({
            "vertices": self.vertices,
            "edges": self.edges,
            "faces": self.faces,
            "triangles": self.triangles,
            "components": self.components,
            "boundary_loops": self.boundary_loops,
            "closed": self.closed,
            "manifold": self.manifold,
            "genus": self.genus,
            "volume": self.volume,
            "area": self.area,
            "bounds": { "min": self.min, "max": self.max },
        })
    }
}

#[cfg(test)]
mod tests {
    use blocksmith_kernel::Vec3;

    use super::*;

    #[test]
    fn a_cube_has_the_facts_of_a_cube() {
        let f = Facts::of(&Mesh::cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)));
        assert_eq!((f.vertices, f.edges, f.faces, f.triangles, f.components, f.boundary_loops), (8, 12, 6, 12, 1, 0));
        assert_eq!((f.closed, f.manifold, f.genus), (true, true, 0));
        assert!((f.volume - 6.0).abs() < 1e-12 && (f.area - 22.0).abs() < 1e-12, "{f:?}");
        assert_eq!(f.json()["bounds"]["max"], json!([1.0, 2.0, 3.0]));
    }
}
