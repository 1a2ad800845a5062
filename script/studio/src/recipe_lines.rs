//! From the model to the recipe and back: the face under a clicked point and the chain of calls
//! that made it (`uv_sphere` at 58 → `translate` at 60 → `-` at 61), and the faces one call made
//! (what a page lights up when an editor's cursor rests on that call). The chains are the face
//! parts' origins, which every run records ([`blocksmith_script::origins`]).

use std::path::{Path, PathBuf};

use blocksmith_kernel::math::closest_on_triangle;
use blocksmith_kernel::mesh::Origin;
use blocksmith_kernel::{Mesh, Vec3};
use serde_json::json;

/// A place in a recipe: the file as the run named it (`None`: no file), 1-based line and column.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Site {
    pub file: Option<String>,
    pub line: u32,
    pub column: u32,
}

impl Site {
    /// Whether `file` (as a run named it: the path given, or `stdlib/NAME.rhai`) is `path`,
    /// comparing the files themselves when both exist.
    #[must_use]
    pub fn same_file(file: Option<&str>, path: Option<&Path>) -> bool {
        match (file, path) {
            (None, None) => true,
            (Some(f), Some(p)) => {
                let canon = |q: &Path| q.canonicalize().unwrap_or_else(|_| q.to_path_buf());
                Path::new(f) == p || canon(Path::new(f)) == canon(p)
            }
            _ => false,
        }
    }

    /// The file as an absolute path, if it is one on disk.
    #[must_use]
    pub fn path(&self) -> Option<PathBuf> {
        self.file.as_deref().map(Path::new).filter(|p| p.is_file()).and_then(|p| p.canonicalize().ok())
    }
}

/// One step of a face's chain: the call and where it is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    pub call: String,
    pub site: Site,
}

impl Step {
    fn of(o: &Origin) -> Step {
        Step {
            call: o.call.to_string(),
            site: Site { file: o.span.file.as_deref().map(str::to_string), line: o.span.line, column: o.span.column },
        }
    }

    /// `{call, file, line, column}`.
    #[must_use]
    pub fn json(&self) -> serde_json::Value {
        json!({ "call": self.call, "file": self.site.file, "line": self.site.line, "column": self.site.column })
    }
}

/// The chain of calls that made face `f`, the first call (what made the geometry) first; empty
/// when the face has no recorded origin.
#[must_use]
pub fn chain(mesh: &Mesh, f: u32) -> Vec<Step> {
    let origin = mesh.face_part(f).and_then(|p| p.origin.as_deref());
    let mut steps: Vec<Step> = origin.into_iter().flat_map(Origin::chain).map(Step::of).collect();
    steps.reverse();
    steps
}

/// The face of `mesh` nearest to `point` (a point the page found on the drawn surface), if
/// the mesh has faces. Linear in the faces: one click, one pass.
#[must_use]
pub fn face_at(mesh: &Mesh, point: Vec3) -> Option<u32> {
    let mut best: Option<(f64, u32)> = None;
    for f in 0..mesh.face_count() as u32 {
        for [a, b, c] in triangles_of_face(mesh, f) {
            let d = (closest_on_triangle(point, a, b, c) - point).length();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, f));
            }
        }
    }
    best.map(|(_, f)| f)
}

/// The faces whose chain has a step written at `site`: at `site.line`, in any column when
/// `site.column` is 0, in any file when `site.file` is `None`.
#[must_use]
pub fn faces_made_at(mesh: &Mesh, site: &Site) -> Vec<u32> {
    let Some(ids) = mesh.face_part_ids() else { return Vec::new() };
    let wanted = site.file.as_deref().map(Path::new);
    // Each recorded file name compared once.
    let mut same: std::collections::HashMap<Option<&str>, bool> = std::collections::HashMap::new();
    let made: Vec<bool> = mesh
        .parts()
        .iter()
        .map(|p| {
            p.origin.as_deref().into_iter().flat_map(Origin::chain).any(|o| {
                o.span.line == site.line
                    && (site.column == 0 || o.span.column == site.column)
                    && (wanted.is_none()
                        || *same
                            .entry(o.span.file.as_deref())
                            .or_insert_with(|| Site::same_file(o.span.file.as_deref(), wanted)))
            })
        })
        .collect();
    (0..ids.len() as u32).filter(|&f| made[ids[f as usize] as usize]).collect()
}

/// The triangles of `faces` as x, y, z of each corner (kernel axes, as the page draws).
#[must_use]
pub fn triangles(mesh: &Mesh, faces: &[u32]) -> Vec<f32> {
    let mut out = Vec::new();
    for &f in faces {
        for t in triangles_of_face(mesh, f) {
            out.extend(t.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]));
        }
    }
    out
}

/// The triangles of face `f` as x, y, z of each corner, at full precision (what the page's
/// measure tool sums for the face's area and normal).
#[must_use]
pub fn corners(mesh: &Mesh, f: u32) -> Vec<f64> {
    triangles_of_face(mesh, f).iter().flatten().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// The triangles of face `f` (its fan when it cannot be cut between its corners).
fn triangles_of_face(mesh: &Mesh, f: u32) -> Vec<[Vec3; 3]> {
    let corners = |t: [u32; 3]| t.map(|v| mesh.position(v));
    match mesh.triangulate_face(f) {
        Ok(tris) => tris.into_iter().map(corners).collect(),
        Err(_) => {
            let ids: Vec<u32> = mesh.face_vertices(f).collect();
            (1..ids.len().saturating_sub(1)).map(|i| corners([ids[0], ids[i], ids[i + 1]])).collect()
        }
    }
}

#[cfg(test)]
#[path = "tests_recipe_lines.rs"]
mod tests;
