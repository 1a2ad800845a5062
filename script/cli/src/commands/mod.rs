//! One file per subcommand of `blocksmith`; each takes its parsed arguments ([`crate::args`])
//! and returns the exit status.

pub mod doc;
pub mod lsp;
pub mod params;
pub mod render;
pub mod repl;
pub mod run;
pub mod test;
pub mod watch;

use blocksmith_script::access::Access;
use blocksmith_script::{EngineOptions, RunContext};

/// The options of a run with `--set` parameters, its progress shown on the terminal.
#[must_use]
pub fn with_params(set: Vec<(String, String)>) -> EngineOptions {
    EngineOptions {
        context: RunContext { params: set.into_iter().collect(), ..RunContext::default() },
        progress: crate::progress_bars::on_terminal(),
        interrupt: Some(crate::interrupt::flag()),
        ..EngineOptions::default()
    }
}

/// Says on standard error which saves a run of `command` (`params`, `render`: commands that
/// never write) asked for and did not get.
pub fn report_unwritten(command: &str, access: &Access) {
    for path in access.reported() {
        eprintln!("note: not written: {} (`blocksmith {command}` never writes files)", path.display());
    }
}
