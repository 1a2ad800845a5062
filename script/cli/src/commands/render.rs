//! `blocksmith render FILE -o OUT.png`: a recipe's value or a mesh file drawn on the CPU
//! ([`blocksmith_studio::render_to_png`]).

use std::path::Path;
use std::process::ExitCode;

use blocksmith_studio::render::View;

use crate::output::report;

/// Draws `file` (run with the `--set` pairs `set`) to the PNG `output`.
pub fn execute(file: &Path, output: &Path, size: (u32, u32), view: View, set: Vec<(String, String)>) -> ExitCode {
    report(blocksmith_studio::render_to_png(file, super::with_params(set), output, size, view))
}
