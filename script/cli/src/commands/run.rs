//! `blocksmith run FILE.rhai [-o OUT]`: evaluates a recipe through the runner
//! ([`blocksmith_script::run::run_recipe`]) and writes its last value to a model file; with
//! `--stats [text|json]` also prints the written model's facts and diagnosis (alone on standard
//! output: the recipe's `print` and `debug` then go to standard error), with `--manifest`
//! writes a manifest.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use blocksmith_script::api::anim::pose_of_value;
use blocksmith_script::context::PrintTo;
use blocksmith_script::progress::Progress;
use blocksmith_script::run::{describe, run_recipe, save_value, RecipeRun, RunError};
use blocksmith_script::{EngineOptions, RunContext};

use crate::output::{print_out, report};

/// Runs `cmd`, printing its warnings and summary on standard error and its stats (if asked)
/// on standard output.
pub fn run(cmd: &RunCommand) -> ExitCode {
    report(execute_with_outcome(cmd).map(|o| {
        for w in &o.warnings {
            eprintln!("{w}");
        }
        match (o.stats, cmd.stats) {
            (Some(stats), Some(StatsFormat::Text)) => print_out(&crate::stats::text(&stats)),
            (Some(stats), _) => print_out(&format!("{:#}\n", stats.json)),
            _ => {}
        }
        o.summary
    }))
}

/// Options of `blocksmith run`.
#[derive(Debug, Clone, Default)]
pub struct RunCommand {
    pub file: PathBuf,
    pub output: Option<PathBuf>,
    pub params: Vec<(String, String)>,
    pub max_operations: Option<u64>,
    /// `--timeout SECONDS`: stop the run (kernel work included) after this long.
    pub timeout: Option<Duration>,
    /// `--stats [text|json]`: the written model's facts and diagnosis
    /// ([`crate::stats::of_file`]); needs `output`.
    pub stats: Option<StatsFormat>,
    /// `--manifest FILE.json`: where to write the run's manifest ([`crate::manifest`]).
    pub manifest: Option<PathBuf>,
    /// Where long kernel work shows its progress (bars on a terminal).
    pub progress: Progress,
    /// `--time T`: write the pose at T of the Animation the recipe ends with, not the animation.
    pub time: Option<f64>,
}

/// How `--stats` prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatsFormat {
    /// Lines of text ([`crate::stats::text`]).
    Text,
    /// One JSON object.
    Json,
}

/// What `blocksmith run` reports: a one-line summary (for standard error) and, with
/// `--stats`, the facts (for standard output).
#[derive(Debug, Clone)]
pub struct RunOutcome {
    pub summary: String,
    /// The recipe's warnings (dropped results), for standard error before the summary.
    pub warnings: Vec<String>,
    pub stats: Option<crate::stats::Stats>,
}

/// Runs `blocksmith run`: evaluates the recipe and writes its last value to the output file,
/// and writes the manifest and computes the stats `cmd` asks for.
///
/// # Errors
/// Any error of the run, the write, the stats or the manifest, formatted.
pub fn execute_with_outcome(cmd: &RunCommand) -> Result<RunOutcome, RunError> {
    if cmd.stats.is_some() && cmd.output.is_none() {
        return Err(RunError("error: --stats needs -o OUT: the facts are those of the written model".into()));
    }
    // With the stats on standard output, the recipe's `print` and `debug` go to standard error:
    // `run --stats json | jq` reads the stats alone.
    let print_to = if cmd.stats.is_some() { PrintTo::Stderr } else { PrintTo::Stdout };
    let context = RunContext { params: cmd.params.iter().cloned().collect(), print_to, ..RunContext::default() };
    let options = EngineOptions {
        context,
        max_operations: cmd.max_operations,
        timeout: cmd.timeout,
        interrupt: Some(crate::interrupt::flag()),
        progress: cmd.progress.clone(),
    };
    let RecipeRun { engine, value, ast, record, elapsed, warnings } = run_recipe(&cmd.file, options)?;
    let mut summary = describe(&engine, &value);
    // An animation's pose: the still at `--time`, or (for --stats) the rest mesh the animated
    // file skins.
    let animated = engine.map_type_name(value.type_name()) == "Animation";
    let (value, pose) = match cmd.time {
        Some(t) => match pose_of_value(&engine, &ast, &value, Some(t)) {
            Ok(Some((mesh, t))) => {
                summary = format!("{summary} posed at t = {t}");
                (rhai::Dynamic::from(mesh), format!("t = {t}: the animation's pose at that time"))
            }
            Ok(None) => {
                return Err(RunError(format!(
                    "error: --time {t}: the recipe's value is {}, not an Animation: only an animation has poses",
                    blocksmith_script::catalogue::a(engine.map_type_name(value.type_name()))
                )))
            }
            Err(e) => return Err(RunError(format!("error: --time {t}: {e}"))),
        },
        None => (value, "rest: the mesh the animated file skins, as modelled (--time T measures the pose at T)".into()),
    };
    let summary = match &cmd.output {
        Some(out) => {
            // `-o out/model.glb` on a fresh checkout: the output's folder is made.
            if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
                std::fs::create_dir_all(dir)
                    .map_err(|e| RunError(format!("error: cannot make the folder {}: {e}", dir.display())))?;
            }
            save_value(&engine, &ast, value, out)?;
            format!("wrote {} ({summary})", out.display())
        }
        None => summary,
    };
    let stats = match &cmd.output {
        Some(out) if cmd.stats.is_some() => {
            let mut stats = crate::stats::of_file(out, elapsed)?;
            if animated {
                stats.json["pose"] = serde_json::json!(pose);
            }
            Some(stats)
        }
        _ => None,
    };
    if let Some(path) = &cmd.manifest {
        // Never over the recipe or a module it imports (`--manifest r.rhai`), nor a read-only file.
        let sources: Vec<PathBuf> =
            record.inputs.iter().filter(|p| p.extension().is_some_and(|e| e == "rhai")).cloned().collect();
        blocksmith_script::access::check_host_write(path, &sources)
            .map_err(|e| RunError(format!("error: --manifest: {e}")))?;
        let manifest = crate::manifest::build(&cmd.file, &record, cmd.output.as_deref())?;
        crate::manifest::write(&manifest, path)?;
    }
    Ok(RunOutcome { summary, warnings, stats })
}
