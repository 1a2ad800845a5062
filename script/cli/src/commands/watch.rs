//! `blocksmith watch FILE.rhai` and `blocksmith view FILE`: the studio page, the recipe run
//! again (or the mesh file read again) on every save ([`blocksmith_studio::serve`]).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::ExitCode;

use crate::output::fail;

/// Serves the page for `file` with `--set` values `params` until the process is stopped.
pub fn execute(file: &Path, params: BTreeMap<String, String>, port: u16, open: bool) -> ExitCode {
    match blocksmith_studio::serve(file, params, port, open) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    }
}
