//! `blocksmith run --stats json`: the written model's facts for pipelines.

use std::path::Path;
use std::time::Duration;

use blocksmith_kernel::io;
use serde_json::{json, Value};

use blocksmith_script::facts::Facts;

use blocksmith_script::run::RunError;

/// The facts of the model written to `out`, read back from the file (so they are those of
/// what was written; [`Facts`], as the studio lists them), its path and the run time in seconds.
///
/// # Errors
/// The file cannot be read back.
pub fn of_file(out: &Path, run_time: Duration) -> Result<Value, RunError> {
    let mesh = io::load(out).map_err(|e| RunError(format!("error: --stats: cannot read back the model: {e}")))?;
    let mut facts = Facts::of(&mesh).json();
    facts["file"] = json!(out.display().to_string());
    facts["run_time_s"] = json!(run_time.as_secs_f64());
    Ok(facts)
}
