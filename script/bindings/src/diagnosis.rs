//! A mesh's diagnosis, where each thing wrong with it is: its components with their genus, open
//! boundaries, faces that cross, vertices and edges where sheets touched, degenerate faces and
//! a loop around each handle (the kernel's [`diagnose::defects`]). What `run --stats` prints
//! after the facts and what the studio draws over a model — computed one way for both.

use blocksmith_kernel::diagnose::{self, Defect, DefectKind};
use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::mesh::MeshError;
use blocksmith_kernel::{Mesh, Vec3};
use serde_json::{json, Value};

/// How many places of each kind the text and the JSON list (the counts are always whole).
pub const LISTED: usize = 20;

/// How many crossing faces, boundary and handle corners the studio's overlay draws at most.
pub const DRAWN: usize = 200_000;

/// One connected component.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    pub faces: usize,
    pub genus: i64,
    /// Its open boundary loops.
    pub boundary_loops: usize,
    /// The centre of its vertices.
    pub at: Vec3,
}

/// A loop of vertices (an open boundary, or a loop around a handle).
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// Its corners in order (closed: the last joins the first).
    pub points: Vec<Vec3>,
    /// Its length.
    pub length: f64,
    /// The centre of its corners.
    pub at: Vec3,
    /// Its component.
    pub component: usize,
}

/// What is wrong with a mesh and where.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Diagnosis {
    /// Every component, in the order of their first faces.
    pub components: Vec<Component>,
    pub boundaries: Vec<Loop>,
    /// Pairs of faces that cross or touch, with a point of each crossing.
    pub crossings: Vec<([u32; 2], Vec3)>,
    /// The corners of each crossing face (for drawing), face by face.
    pub crossing_faces: Vec<Vec<Vec3>>,
    /// Places where vertices at one position are not one vertex (sheets touching).
    pub touching_vertices: Vec<Vec3>,
    /// Edges at one position that are not one edge (faces beyond two met there): their ends.
    pub touching_edges: Vec<[Vec3; 2]>,
    /// Faces of zero area: their centres.
    pub degenerate_faces: Vec<Vec3>,
    pub handles: Vec<Loop>,
}

/// `x` for a person: six decimals at most, trailing zeros dropped (`1e-17` is `0`).
#[must_use]
pub fn short(x: f64) -> String {
    if !x.is_finite() {
        return fmt_num(x);
    }
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn loop_of(mesh: &Mesh, vertices: &[u32], at: Vec3, component: usize) -> Loop {
    let points: Vec<Vec3> = vertices.iter().map(|&v| mesh.position(v)).collect();
    let length = (0..points.len()).map(|i| (points[(i + 1) % points.len()] - points[i]).length()).sum();
    Loop { points, length, at, component }
}

impl Diagnosis {
    /// The diagnosis of `mesh`.
    ///
    /// # Errors
    /// As [`diagnose::defects`]: a stop of the current cancellation token, a face that cannot
    /// be cut into triangles.
    pub fn of(mesh: &Mesh) -> Result<Diagnosis, MeshError> {
        Ok(Diagnosis::from_defects(mesh, diagnose::defects(mesh)?))
    }

    /// The diagnosis of `mesh` from its `defects`.
    #[must_use]
    pub fn from_defects(mesh: &Mesh, defects: Vec<Defect>) -> Diagnosis {
        let mut d = Diagnosis::default();
        let mut crossing_faces = Vec::new();
        for x in defects {
            match x.kind {
                DefectKind::Component => d.components.push(Component {
                    faces: x.elements.len(),
                    genus: x.genus.unwrap_or(0),
                    boundary_loops: 0,
                    at: x.position,
                }),
                DefectKind::Boundary => d.boundaries.push(loop_of(mesh, &x.elements, x.position, x.component)),
                DefectKind::Handle => d.handles.push(loop_of(mesh, &x.elements, x.position, x.component)),
                DefectKind::NonManifoldVertex => d.touching_vertices.push(x.position),
                DefectKind::NonManifoldEdge => {
                    d.touching_edges.push([mesh.position(x.elements[0]), mesh.position(x.elements[1])]);
                }
                DefectKind::DegenerateFace => d.degenerate_faces.push(x.position),
                DefectKind::SelfIntersection => {
                    crossing_faces.extend([x.elements[0], x.elements[1]]);
                    d.crossings.push(([x.elements[0], x.elements[1]], x.position));
                }
            }
        }
        // One closed piece of genus 0 is not listed as a defect: it is still a component.
        if d.components.is_empty() && mesh.face_count() > 0 {
            let n = mesh.vertex_count().max(1) as f64;
            let at = (0..mesh.vertex_count() as u32).map(|v| mesh.position(v)).sum::<Vec3>() / n;
            d.components.push(Component { faces: mesh.face_count(), genus: 0, boundary_loops: 0, at });
        }
        for b in &d.boundaries {
            if let Some(c) = d.components.get_mut(b.component) {
                c.boundary_loops += 1;
            }
        }
        crossing_faces.sort_unstable();
        crossing_faces.dedup();
        let mut corners = 0;
        for f in crossing_faces {
            let face: Vec<Vec3> = mesh.face_vertices(f).map(|v| mesh.position(v)).collect();
            corners += face.len();
            if corners > DRAWN {
                break;
            }
            d.crossing_faces.push(face);
        }
        d
    }

    /// Whether nothing is wrong: one closed component of genus 0 (or none), nothing crossing,
    /// touching or degenerate.
    #[must_use]
    pub fn is_clean(&self) -> bool {
        self.components.len() <= 1
            && self.boundaries.is_empty()
            && self.crossings.is_empty()
            && self.touching_vertices.is_empty()
            && self.touching_edges.is_empty()
            && self.degenerate_faces.is_empty()
            && self.handles.is_empty()
    }

    /// The diagnosis as JSON: `components` (each `faces`, `genus`, `boundary_loops`, `at`),
    /// `component_count`, `boundary_count`, `boundary_edges` (all loops' edges), `handle_count`,
    /// `boundaries` and `handles` (each `vertices`, `length`, `at`, `component`), and for
    /// `self_intersections`, `non_manifold_vertices`, `non_manifold_edges` and
    /// `degenerate_faces` a `count` and the first [`LISTED`] places `at` (a crossing's also
    /// its `faces`). Every list of places stops at [`LISTED`]; counts are whole.
    #[must_use]
    pub fn json(&self) -> Value {
        let p = |v: Vec3| json!([v.x, v.y, v.z]);
        let loops = |l: &[Loop]| {
            l.iter()
                .take(LISTED)
                .map(|l| json!({ "vertices": l.points.len(), "length": l.length, "at": p(l.at), "component": l.component }))
                .collect::<Vec<_>>()
        };
        let places =
            |v: &[Vec3]| json!({ "count": v.len(), "at": v.iter().take(LISTED).map(|&x| p(x)).collect::<Vec<_>>() });
        json!({
            "components": self.components.iter().take(LISTED).map(|c| json!({
                "faces": c.faces, "genus": c.genus, "boundary_loops": c.boundary_loops, "at": p(c.at)
            })).collect::<Vec<_>>(),
            "component_count": self.components.len(),
            "boundaries": loops(&self.boundaries),
            "boundary_count": self.boundaries.len(),
            "boundary_edges": self.boundaries.iter().map(|l| l.points.len()).sum::<usize>(),
            "handles": loops(&self.handles),
            "handle_count": self.handles.len(),
            "self_intersections": {
                "count": self.crossings.len(),
                "at": self.crossings.iter().take(LISTED).map(|(f, at)| json!({ "faces": f, "at": p(*at) })).collect::<Vec<_>>(),
            },
            "non_manifold_vertices": places(&self.touching_vertices),
            "non_manifold_edges": places(&self.touching_edges.iter().map(|[a, b]| (*a + *b) * 0.5).collect::<Vec<_>>()),
            "degenerate_faces": places(&self.degenerate_faces),
        })
    }

    /// The diagnosis as lines of text, one per kind with its count, then the first
    /// [`LISTED`] places of each, indented.
    #[must_use]
    pub fn text(&self) -> Vec<String> {
        let at = |v: Vec3| format!("({}, {}, {})", short(v.x), short(v.y), short(v.z));
        let mut out = Vec::new();
        let more = |out: &mut Vec<String>, n: usize| {
            if n > LISTED {
                out.push(format!("  … and {} more", n - LISTED));
            }
        };
        out.push(format!("components: {}", self.components.len()));
        for (i, c) in self.components.iter().enumerate().take(LISTED) {
            let open = match c.boundary_loops {
                0 => "closed".to_string(),
                1 => "1 boundary loop".to_string(),
                n => format!("{n} boundary loops"),
            };
            out.push(format!("  {i}: {} faces, genus {}, {open}, around {}", c.faces, c.genus, at(c.at)));
        }
        more(&mut out, self.components.len());
        let loops = |out: &mut Vec<String>, name: &str, l: &[Loop]| {
            out.push(format!("{name}: {}", l.len()));
            for (i, l) in l.iter().enumerate().take(LISTED) {
                out.push(format!(
                    "  {i}: {} edges, length {}, around {} (component {})",
                    l.points.len(),
                    short(l.length),
                    at(l.at),
                    l.component
                ));
            }
            more(out, l.len());
        };
        loops(&mut out, "boundary loops", &self.boundaries);
        loops(&mut out, "handle loops", &self.handles);
        out.push(format!("self-intersecting face pairs: {}", self.crossings.len()));
        for ([f, g], p) in self.crossings.iter().take(LISTED) {
            out.push(format!("  faces {f} and {g} at {}", at(*p)));
        }
        more(&mut out, self.crossings.len());
        let places = |out: &mut Vec<String>, name: &str, v: &[Vec3]| {
            out.push(format!("{name}: {}", v.len()));
            for p in v.iter().take(LISTED) {
                out.push(format!("  at {}", at(*p)));
            }
            more(out, v.len());
        };
        places(&mut out, "non-manifold vertices (split on load)", &self.touching_vertices);
        let mids: Vec<Vec3> = self.touching_edges.iter().map(|[a, b]| (*a + *b) * 0.5).collect();
        places(&mut out, "non-manifold edges (separated on load)", &mids);
        places(&mut out, "degenerate faces", &self.degenerate_faces);
        out
    }

    /// What the studio draws over the model: `boundaries` and `handles` as closed polylines
    /// (flat `[x, y, z, …]` each), `crossing_faces` as polygons (flat corners each),
    /// `points` where sheets touch or faces are degenerate, `touching_edges` as segments
    /// (flat, six numbers each), `components` (each its faces' count, genus, centre), and the
    /// counts. At most [`DRAWN`] corners of each kind.
    #[must_use]
    pub fn overlay(&self) -> Value {
        let flat = |pts: &[Vec3]| pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect::<Vec<f64>>();
        let capped = |l: &[Loop]| {
            let mut n = 0;
            l.iter()
                .take_while(|l| {
                    n += l.points.len();
                    n <= DRAWN
                })
                .map(|l| json!(flat(&l.points)))
                .collect::<Vec<_>>()
        };
        let points: Vec<Vec3> =
            self.touching_vertices.iter().chain(&self.degenerate_faces).copied().take(DRAWN).collect();
        json!({
            "boundaries": capped(&self.boundaries),
            "handles": capped(&self.handles),
            "crossing_faces": self.crossing_faces.iter().map(|f| json!(flat(f))).collect::<Vec<_>>(),
            "crossings": self.crossings.len(),
            "points": flat(&points),
            "touching_edges": self.touching_edges.iter().take(DRAWN).flat_map(|[a, b]| [a.x, a.y, a.z, b.x, b.y, b.z]).collect::<Vec<f64>>(),
            "components": self.components.iter().map(|c| json!({ "faces": c.faces, "genus": c.genus, "at": [c.at.x, c.at.y, c.at.z] })).collect::<Vec<_>>(),
            "clean": self.is_clean(),
        })
    }
}

#[cfg(test)]
#[path = "tests_diagnosis.rs"]
mod tests;
