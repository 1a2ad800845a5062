//! `blocksmith repl`: the interactive session ([`crate::repl`]).

use std::process::ExitCode;

use crate::args::LimitArgs;
use crate::output::fail;

/// Runs the REPL, each entry under `limits`.
pub fn execute(limits: &LimitArgs) -> ExitCode {
    let options = limits.apply();
    match crate::repl::run(options.max_operations, options.timeout) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    }
}
