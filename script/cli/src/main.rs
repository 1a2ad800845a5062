//! `blocksmith`: the command line of blocksmith — run recipes, list their parameters, a REPL,
//! the test runner, the studio (`watch`, `view`), CPU rendering and the API reference.
//!
//! It owns what a terminal needs: the argument types ([`args`], clap), one file per subcommand
//! ([`commands`]), the REPL ([`repl`], rustyline), progress bars ([`progress_bars`], indicatif),
//! manifests ([`manifest`], sha2) and the process's allocator. It depends on the studio, the
//! bindings and the kernel; nothing depends on it.

mod args;
mod commands;
mod manifest;
mod output;
mod progress_bars;
mod repl;
mod stats;

use std::process::ExitCode;

use blocksmith_kernel::limits;
use clap::Parser;

use args::{Cli, Command};
use commands::run::RunCommand;

/// mimalloc rather than the system allocator: the boolean engine allocates and frees many
/// mid-sized arrays per operation, which glibc returns to the system and faults back in.
/// Counted, so that a script whose data grows over the memory budget stops with an error.
#[global_allocator]
static ALLOCATOR: limits::CountingAllocator<mimalloc::MiMalloc> = limits::CountingAllocator(mimalloc::MiMalloc);

/// The stack of the thread the command runs on: deep data (an array nested a million deep, made
/// by a loop) is copied and freed by recursion, more than the main thread's 8 MiB allow. Only
/// the pages used are ever committed.
const STACK_BYTES: usize = 1 << 30;

fn main() -> ExitCode {
    match std::thread::Builder::new().name("blocksmith".into()).stack_size(STACK_BYTES).spawn(command) {
        Ok(thread) => thread.join().unwrap_or(ExitCode::FAILURE),
        // A system refusing so large a stack: run with the main thread's.
        Err(_) => command(),
    }
}

fn command() -> ExitCode {
    match Cli::parse().command {
        Command::Run { file, set, params: Some(format), .. } => commands::params::execute(&file, &set, &format),
        Command::Run { file, output, set, limits, stats, manifest, params: None } => {
            let l = limits.apply();
            commands::run::run(&RunCommand {
                file,
                output,
                params: set,
                max_operations: l.max_operations,
                timeout: l.timeout,
                stats: stats.is_some(),
                manifest,
                progress: l.progress,
            })
        }
        Command::Params { file, format, set } => commands::params::execute(&file, &set, &format),
        Command::Repl { limits } => commands::repl::execute(&limits),
        Command::Test { paths, out, limits } => commands::test::execute(paths, &out, &limits),
        Command::Render { file, output, size, view, set } => commands::render::execute(&file, &output, size, view, set),
        Command::Watch { file, set, port, open } => {
            commands::watch::execute(&file, set.into_iter().collect(), port, open)
        }
        Command::View { file, port, open } => commands::watch::execute(&file, Default::default(), port, open),
        Command::Doc { name, format } => commands::doc::execute(name.as_deref(), &format),
    }
}
