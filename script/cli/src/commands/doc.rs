//! `blocksmith doc [NAME] [--format text|markdown|html|json]`: the API reference, generated
//! from the engine's own metadata ([`blocksmith_script::doc`]).

use std::process::ExitCode;

use blocksmith_script::{doc, new_engine, EngineOptions};

use crate::output::{fail, print_out};

/// Prints the reference of `name` (or of everything) as `format`.
pub fn execute(name: Option<&str>, format: &str) -> ExitCode {
    let engine = new_engine(EngineOptions::default());
    let format = format.parse::<doc::Format>().unwrap_or(doc::Format::Text);
    match doc::render_as(&engine, name, format) {
        Ok(text) => {
            print_out(&text);
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}
