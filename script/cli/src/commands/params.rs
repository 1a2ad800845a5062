//! `blocksmith params FILE.rhai` (and `run --params`): a recipe's parameters as a text table
//! or as JSON ([`blocksmith_script::params::listing`]).

use std::path::Path;
use std::process::ExitCode;

use blocksmith_script::context::PrintTo;
use blocksmith_script::params::{listing, ListFormat};
use blocksmith_script::run::{run_recipe, RunError};

use crate::output::{fail, print_out};

/// Prints the parameters of the recipe at `file`, run with the `--set` pairs `set`, as
/// `format` (`text` or `json`). A run that fails (a `param_check` that does not hold, a `--set`
/// value out of range) fails the command with its error on standard error; as JSON, the
/// listing so far is still printed, with the error in `"error"`, so a tool reads why.
pub fn execute(file: &Path, set: &[(String, String)], format: &str) -> ExitCode {
    let format = if format == "json" { ListFormat::Json } else { ListFormat::Text };
    let (listing, error) = list(file, set, format);
    if let Some(text) = listing {
        print_out(&text);
    }
    match error {
        None => ExitCode::SUCCESS,
        Some(e) => fail(e),
    }
}

/// The listing, and the run's error: the recipe is run (with the `--set` pairs `set`) since its
/// parameters are known only by running it — a default may depend on another parameter. A
/// failed run has a listing only as JSON.
pub fn list(file: &Path, set: &[(String, String)], format: ListFormat) -> (Option<String>, Option<RunError>) {
    let mut options = super::with_params(set.to_vec());
    // The listing alone on standard output: what the recipe prints goes to standard error.
    options.context.print_to = PrintTo::Stderr;
    let access = options.context.access.clone();
    let result = run_recipe(file, options);
    super::report_unwritten("params", &access);
    let (record, error) = match result {
        Ok(run) => (run.record, None),
        Err(failure) => (failure.record, Some(failure.error)),
    };
    let listing = match format {
        ListFormat::Text if error.is_some() => None,
        ListFormat::Text if record.params.is_empty() => Some(format!("{} declares no parameters\n", file.display())),
        ListFormat::Text => Some(listing::to_text(&record.params)),
        ListFormat::Json => {
            let mut json = listing::to_json(&record.params, &record.checks);
            if let Some(e) = &error {
                json["error"] = serde_json::Value::String(e.to_string());
            }
            Some(format!("{json:#}\n"))
        }
    };
    (listing, error)
}
