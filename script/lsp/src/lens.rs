//! The run lens: "▶ run" above the recipe's first line runs it (saved, as `blocksmith watch`
//! runs it: the recipe's saves reported, not done, its prints kept off the protocol) and then
//! shows the final value's facts beside the line that made it — closed, manifold, genus,
//! volume for a mesh, else the value's description — or the error.

use std::path::Path;
use std::time::Duration;

use blocksmith_script::context::{PrintTo, RunContext};
use blocksmith_script::EngineOptions;
use lsp_types::{CodeLens, Command, Position, Range, Uri};

/// The command a lens runs.
pub const RUN: &str = "blocksmith.run";

/// How long a run from the editor may take.
pub const TIMEOUT: Duration = Duration::from_secs(120);

/// The outcome of the last run of a document: the line its lens goes on and the text.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub line: u32,
    pub text: String,
}

/// The lenses of a document: run, the studio (its address once it runs, `studio`), and the
/// last run's outcome.
#[must_use]
pub fn lenses(uri: &Uri, outcome: Option<&Outcome>, studio: Option<&str>) -> Vec<CodeLens> {
    let at_top = |title: String, command: &str| CodeLens {
        range: Range::new(Position::new(0, 0), Position::new(0, 0)),
        command: Some(Command {
            title,
            command: command.into(),
            arguments: Some(vec![serde_json::Value::String(uri.as_str().to_string())]),
        }),
        data: None,
    };
    let studio_title = studio.map_or_else(|| "◉ studio".to_string(), |url| format!("◉ studio {url}"));
    let mut out = vec![at_top("▶ run".into(), RUN), at_top(studio_title, crate::studio_link::STUDIO)];
    if let Some(o) = outcome {
        out.push(CodeLens {
            range: Range::new(Position::new(o.line, 0), Position::new(o.line, 0)),
            command: Some(Command { title: o.text.clone(), command: String::new(), arguments: None }),
            data: None,
        });
    }
    out
}

/// Runs the recipe at `path` and says what it made, on one line.
#[must_use]
pub fn run(path: &Path, text: &str) -> Outcome {
    let options = EngineOptions {
        context: RunContext {
            access: blocksmith_script::access::Access::default().reporting(),
            print_to: PrintTo::Stderr,
            ..RunContext::default()
        },
        timeout: Some(TIMEOUT),
        ..EngineOptions::default()
    };
    let line = last_code_line(text);
    match blocksmith_script::run::run_recipe(path, options) {
        Ok(run) => {
            let seconds = run.elapsed.as_secs_f64();
            let text = match run.value.clone().try_cast::<blocksmith_script::api::mesh::SharedMesh>() {
                Some(m) => {
                    let f = blocksmith_script::facts::Facts::of(&m.0);
                    format!(
                        "{} · {} · genus {} · volume {:.6} · {} triangles · {seconds:.2} s",
                        if f.closed { "closed" } else { "open" },
                        if f.manifold { "manifold" } else { "not manifold" },
                        f.genus,
                        f.volume,
                        f.triangles
                    )
                }
                None => format!("{} · {seconds:.2} s", blocksmith_script::run::describe(&run.engine, &run.value)),
            };
            Outcome { line, text }
        }
        Err(failure) => {
            let first = failure.error.0.lines().find(|l| l.contains("error")).unwrap_or("error").to_string();
            Outcome { line, text: first }
        }
    }
}

/// The last line holding code (the final value's, in a recipe).
fn last_code_line(text: &str) -> u32 {
    let code = crate::text::blank_strings_and_comments(text);
    code.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()).map(|(i, _)| i as u32).last().unwrap_or(0)
}
