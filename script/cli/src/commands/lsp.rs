//! `blocksmith lsp`: the language server ([`blocksmith_lsp`]) over standard input and output,
//! for any editor with a language-server client (README "Editing recipes").

use std::process::ExitCode;

use crate::output::fail;

/// Serves the editor until it says `exit`.
pub fn execute() -> ExitCode {
    match blocksmith_lsp::server::serve_stdio() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    }
}
