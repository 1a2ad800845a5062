//! `blocksmith run --stats [text|json]`: the written model's facts and where it is broken, for
//! people and pipelines.

use std::path::Path;
use std::time::Duration;

use blocksmith_kernel::io;
use serde_json::{json, Value};

use blocksmith_script::diagnosis::{short, Diagnosis};
use blocksmith_script::facts::Facts;

use blocksmith_script::run::RunError;

/// The stats of a written model: its facts and diagnosis as JSON, and the diagnosis as lines.
#[derive(Debug, Clone)]
pub struct Stats {
    /// What `--stats json` prints.
    pub json: Value,
    /// The diagnosis as lines ([`Diagnosis::text`]).
    pub diagnosis: Vec<String>,
}

/// The facts of the model written to `out`, read back from the file (so they are those of
/// what was written; [`Facts`], as the studio lists them), its path, the run time in seconds,
/// what reading it back repaired (`repairs`, lines; a file of sheets that touch is split as
/// `load` splits it) and its `diagnosis` ([`Diagnosis::json`]).
///
/// # Errors
/// The file cannot be read back, or the diagnosis is stopped (Ctrl-C, `--timeout`).
pub fn of_file(out: &Path, run_time: Duration) -> Result<Stats, RunError> {
    let (mesh, repairs) = io::load_report(out, &io::LoadOptions::DEFAULT)
        .map_err(|e| RunError(format!("error: --stats: cannot read back the model: {e}")))?;
    let diagnosis =
        Diagnosis::of(&mesh).map_err(|e| RunError(format!("error: --stats: cannot diagnose the model: {e}")))?;
    let mut facts = Facts::of(&mesh).json();
    facts["file"] = json!(out.display().to_string());
    facts["run_time_s"] = json!(run_time.as_secs_f64());
    facts["repairs"] = json!(repairs.summary());
    facts["diagnosis"] = diagnosis.json();
    Ok(Stats { json: facts, diagnosis: diagnosis.text() })
}

/// The stats of [`of_file`] as lines for a person: the counts and measures, then the
/// diagnosis (each kind's count and where), ending with a newline.
#[must_use]
pub fn text(all: &Stats) -> String {
    let stats = &all.json;
    let n = |k: &str| stats[k].as_u64().unwrap_or(0);
    let x = |v: &Value| v.as_f64().map_or_else(|| "?".to_string(), short);
    let yes = |k: &str| if stats[k].as_bool() == Some(true) { "yes" } else { "no" };
    let point = |v: &Value| format!("({}, {}, {})", x(&v[0]), x(&v[1]), x(&v[2]));
    let mut out = vec![
        format!("file: {}", stats["file"].as_str().unwrap_or_default()),
        format!(
            "vertices {}, edges {}, faces {} ({} triangles)",
            n("vertices"),
            n("edges"),
            n("faces"),
            n("triangles")
        ),
        format!("closed: {}, manifold: {}, genus: {}", yes("closed"), yes("manifold"), stats["genus"]),
        format!("volume {}, area {}", x(&stats["volume"]), x(&stats["area"])),
        format!("bounds {} … {}", point(&stats["bounds"]["min"]), point(&stats["bounds"]["max"])),
    ];
    if let Some(pose) = stats["pose"].as_str() {
        out.insert(1, format!("pose: {pose}"));
    }
    for r in stats["repairs"].as_array().into_iter().flatten() {
        out.push(format!("repaired on reading back: {}", r.as_str().unwrap_or_default()));
    }
    out.extend(all.diagnosis.iter().cloned());
    out.push(format!("run time: {} s", x(&stats["run_time_s"])));
    out.join("\n") + "\n"
}
