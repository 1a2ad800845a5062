//! The REPL as a child process, for the tests that include it
//! (`#[path = "support/repl.rs"] mod repl;`).

use std::path::Path;
use std::process::{Child, Command, Stdio};

/// The REPL in `dir` (its history there too), reading piped input and writing to a pipe.
pub fn repl(dir: &Path, stderr: Stdio) -> Child {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .arg("repl")
        .current_dir(dir)
        .env("BLOCKSMITH_HISTORY", dir.join("history"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(stderr)
        .spawn()
        .unwrap()
}
