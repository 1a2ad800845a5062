//! One file per subcommand of `blocksmith`; each takes its parsed arguments ([`crate::args`])
//! and returns the exit status.

pub mod doc;
pub mod params;
pub mod render;
pub mod repl;
pub mod run;
pub mod test;
pub mod watch;

use blocksmith_script::{EngineOptions, RunContext};

/// The options of a run with `--set` parameters, its progress shown on the terminal.
#[must_use]
pub fn with_params(set: Vec<(String, String)>) -> EngineOptions {
    EngineOptions {
        context: RunContext { params: set.into_iter().collect(), ..RunContext::default() },
        progress: crate::progress_bars::on_terminal(),
        ..EngineOptions::default()
    }
}
