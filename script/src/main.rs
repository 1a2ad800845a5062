//! The `blocksmith` command: run recipes, a REPL, the test runner and the API reference.

use std::path::PathBuf;
use std::process::ExitCode;

use blocksmith::run::{execute, RunCommand};
use blocksmith::{doc, new_engine, repl, test_runner, EngineOptions};
use clap::{Parser, Subcommand};

/// mimalloc rather than the system allocator: the boolean engine allocates and frees many
/// mid-sized arrays per operation, which glibc returns to the system and faults back in.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(name = "blocksmith", version, about = "Scriptable 3D modeling: blocks, polar meshes, subdivision, voxels.")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a recipe; write its last value to OUT (by extension: .glb .gltf .obj .stl).
    Run {
        /// The recipe (.rhai).
        file: PathBuf,
        /// Where to write the script's last value.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// A parameter read by `param(name, default)`; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
        /// Stop the script after this many operations (also inside closures).
        #[arg(long)]
        max_operations: Option<u64>,
    },
    /// Interactive session (also reads piped standard input).
    Repl,
    /// Run .rhai test scripts (default: tests/), each in a fresh engine.
    Test {
        /// Test files or directories.
        paths: Vec<PathBuf>,
        /// Where relative `save` paths of the tests go.
        #[arg(long, default_value = "target/test-output")]
        out: PathBuf,
    },
    /// Print the API reference (of one function, or all).
    Doc {
        /// A function name.
        name: Option<String>,
    },
}

fn parse_set(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.to_string())),
        _ => Err(format!("expected NAME=VALUE, got `{s}`")),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run { file, output, set, max_operations } => {
            match execute(&RunCommand { file, output, params: set, max_operations }) {
                Ok(summary) => {
                    eprintln!("{summary}");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("{e}");
                    ExitCode::FAILURE
                }
            }
        }
        Command::Repl => match repl::run() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        },
        Command::Test { paths, out } => {
            let paths = if paths.is_empty() { vec![PathBuf::from("tests")] } else { paths };
            let files = match test_runner::collect(&paths) {
                Ok(f) => f,
                Err(e) => {
                    eprintln!("{e}");
                    return ExitCode::FAILURE;
                }
            };
            let outcomes = test_runner::run_all(&files, &out);
            print!("{}", test_runner::report(&outcomes));
            if outcomes.iter().any(|o| o.error.is_some()) {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            }
        }
        Command::Doc { name } => {
            let engine = new_engine(EngineOptions::default());
            match doc::render(&engine, name.as_deref()) {
                Ok(text) => {
                    print!("{text}");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("{e}");
                    ExitCode::FAILURE
                }
            }
        }
    }
}
