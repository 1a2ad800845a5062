//! `blocksmith`: the command line of blocksmith — run recipes, list their parameters, a REPL,
//! the test runner, the studio (`watch`, `view`), CPU rendering and the API reference.
//!
//! It owns what a terminal needs: the argument types ([`args`], clap), one file per subcommand
//! ([`commands`]), the REPL ([`repl`], rustyline), progress bars ([`progress_bars`], indicatif),
//! manifests ([`manifest`], sha2) and the process's allocator. It depends on the studio, the
//! bindings and the kernel; nothing depends on it.

mod allocator;
mod args;
mod commands;
mod interrupt;
mod manifest;
mod output;
mod progress_bars;
mod project;
mod repl;
mod stats;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use blocksmith_kernel::limits;
use blocksmith_script::access::Saves;
use clap::Parser;

use args::{Cli, Command};
use commands::run::{RunCommand, StatsFormat};

/// mimalloc for small blocks, the C library's malloc for large ones (see [`allocator`]).
/// Counted, so that a script whose data grows over the memory budget stops with an error.
#[global_allocator]
static ALLOCATOR: limits::CountingAllocator<allocator::SplitAllocator> =
    limits::CountingAllocator(allocator::SplitAllocator);

/// The stack of the thread the command runs on: deep data (an array nested a million deep, made
/// by a loop) is copied and freed by recursion, more than the main thread's 8 MiB allow. Only
/// the pages used are ever committed.
const STACK_BYTES: usize = 1 << 30;

fn main() -> ExitCode {
    allocator::configure();
    allocator::release_when_idle();
    match std::thread::Builder::new().name("blocksmith".into()).stack_size(STACK_BYTES).spawn(command) {
        Ok(thread) => thread.join().unwrap_or(ExitCode::FAILURE),
        // A system refusing so large a stack: run with the main thread's.
        Err(_) => command(),
    }
}

fn command() -> ExitCode {
    let command = Cli::parse().command;
    if let Err(e) = confine(&command) {
        return output::fail(e);
    }
    if !matches!(command, Command::Repl { .. }) {
        interrupt::install();
    }
    match command {
        Command::Run { file, set, params: Some(format), .. } => commands::params::execute(&file, &set, &format),
        Command::Run { file, output, set, limits, stats, time, manifest, params: None, access: _ } => {
            let l = limits.apply();
            commands::run::run(&RunCommand {
                file,
                output,
                params: set,
                max_operations: l.max_operations,
                timeout: l.timeout,
                stats: stats.map(|f| if f == "json" { StatsFormat::Json } else { StatsFormat::Text }),
                manifest,
                progress: l.progress,
                time,
            })
        }
        Command::Params { file, format, set, .. } => commands::params::execute(&file, &set, &format),
        Command::Repl { limits, .. } => commands::repl::execute(&limits),
        Command::Test { paths, out, limits, .. } => commands::test::execute(paths, &out, &limits),
        Command::Render { file, output, size, view, time, set, .. } => {
            commands::render::execute(&file, &output, size, view, set, time)
        }
        Command::Watch { file, set, port, open, .. } => {
            commands::watch::execute(&file, set.into_iter().collect(), port, open)
        }
        Command::View { file, port, open } => commands::watch::execute(&file, Default::default(), port, open),
        Command::Doc { name, format } => commands::doc::execute(name.as_deref(), &format),
        Command::Lsp => commands::lsp::execute(),
    }
}

/// Makes what the command's runs may read and write the process's policy
/// ([`project::AccessArgs::apply`]): each run is confined to its recipe's project and the paths
/// the command line names; `params`, `render` and `watch` write nothing.
fn confine(command: &Command) -> Result<(), String> {
    let here = Path::new(".");
    match command {
        Command::Run { file, output, manifest, access, params, .. } => {
            let named: Vec<&Path> = output.iter().chain(manifest).map(PathBuf::as_path).collect();
            let saves = if params.is_some() { Saves::Report } else { Saves::Write };
            access.apply(file, &named, saves)
        }
        Command::Params { file, access, .. } => access.apply(file, &[], Saves::Report),
        Command::Repl { access, .. } => access.apply(here, &[], Saves::Write),
        // Tests are the user's own, run from their project: each may use that project (where
        // `blocksmith.toml` is read) besides its own, and `--out`.
        Command::Test { out, access, .. } => {
            let project = blocksmith_script::access::project_of(here);
            access.apply(here, &[out.as_path(), project.as_path()], Saves::Write)
        }
        Command::Render { file, access, .. } => access.apply(file, &[], Saves::Report),
        Command::Watch { file, access, .. } => access.apply(file, &[], Saves::Report),
        Command::View { .. } | Command::Doc { .. } | Command::Lsp => Ok(()),
    }
}
