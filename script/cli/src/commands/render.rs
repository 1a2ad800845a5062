//! `blocksmith render FILE -o OUT.png`: a recipe's value or a mesh file drawn on the CPU
//! ([`blocksmith_studio::render_to_png`]).

use std::path::Path;
use std::process::ExitCode;

use blocksmith_studio::render::View;

use crate::output::report;

/// Draws `file` (run with the `--set` pairs `set`) to the PNG `output`; an animation posed at
/// `time` (`--time`), else at its last frame.
pub fn execute(
    file: &Path,
    output: &Path,
    size: (u32, u32),
    view: View,
    set: Vec<(String, String)>,
    time: Option<f64>,
) -> ExitCode {
    // The picture never replaces the recipe (`render r.rhai -o r.rhai`), another recipe or a
    // read-only file.
    let recipe = [file.to_path_buf()];
    if let Err(e) = blocksmith_script::access::check_host_write(output, &recipe) {
        return crate::output::fail(format!("error: -o: {e}"));
    }
    if output.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai")) {
        return crate::output::fail(format!(
            "error: -o: not writing `{}`: a picture is written as .png, not over a recipe",
            output.display()
        ));
    }
    let mut options = super::with_params(set);
    options.context.time = time;
    let access = options.context.access.clone();
    let result = blocksmith_studio::render_to_png(file, options, output, size, view);
    super::report_unwritten("render", &access);
    report(result)
}
