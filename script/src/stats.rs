//! `blocksmith run --stats json`: the written model's facts for pipelines.

use std::path::Path;
use std::time::Duration;

use blocksmith_kernel::io;
use serde_json::{json, Value};

use crate::run::RunError;

/// The facts of the model written to `out`, read back from the file (so they are those of
/// what was written): counts (vertices, edges, faces, triangles, components), closed,
/// manifold, genus, volume, area, bounds (`min`, `max`), and the run time in seconds.
///
/// # Errors
/// The file cannot be read back.
pub fn of_file(out: &Path, run_time: Duration) -> Result<Value, RunError> {
    let mesh = io::load(out).map_err(|e| RunError(format!("error: --stats: cannot read back the model: {e}")))?;
    let m = mesh.measures();
    Ok(json!({
        "file": out.display().to_string(),
        "vertices": m.vertices,
        "edges": m.edges,
        "faces": m.faces,
        "triangles": mesh.triangle_count(),
        "components": m.components,
        "boundary_loops": m.boundary_loops,
        "closed": mesh.is_closed(),
        "manifold": mesh.is_manifold(),
        "genus": m.genus,
        "volume": m.volume,
        "area": m.area,
        "bounds": { "min": m.bounds.min.to_array(), "max": m.bounds.max.to_array() },
        "run_time_s": run_time.as_secs_f64(),
    }))
}
