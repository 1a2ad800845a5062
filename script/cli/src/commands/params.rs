//! `blocksmith params FILE.rhai` (and `run --params`): a recipe's parameters as a text table
//! or as JSON ([`blocksmith_script::params::listing`]).

use std::path::Path;
use std::process::ExitCode;

use blocksmith_script::params::{listing, ListFormat};
use blocksmith_script::run::{run_recipe, RunError};

use crate::output::{fail, print_out};

/// Prints the parameters of the recipe at `file`, run with the `--set` pairs `set`, as
/// `format` (`text` or `json`).
pub fn execute(file: &Path, set: &[(String, String)], format: &str) -> ExitCode {
    let format = if format == "json" { ListFormat::Json } else { ListFormat::Text };
    match list(file, set, format) {
        Ok(text) => {
            print_out(&text);
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}

/// The listing: the recipe is run (with the `--set` pairs `set`) since its parameters are
/// known only by running it — a default may depend on another parameter.
///
/// # Errors
/// Any error of the run, formatted.
pub fn list(file: &Path, set: &[(String, String)], format: ListFormat) -> Result<String, RunError> {
    let options = super::with_params(set.to_vec());
    let access = options.context.access.clone();
    let run = run_recipe(file, options)?;
    super::report_unwritten("params", &access);
    Ok(match format {
        ListFormat::Text if run.record.params.is_empty() => format!("{} declares no parameters\n", file.display()),
        ListFormat::Text => listing::to_text(&run.record.params),
        ListFormat::Json => format!("{:#}\n", listing::to_json(&run.record.params)),
    })
}
