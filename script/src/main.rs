//! The `blocksmith` command: run recipes, a REPL, the test runner and the API reference.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use blocksmith_kernel::limits;

use blocksmith::params_list::{self, ListFormat};
use blocksmith::run::{execute_with_outcome, RunCommand, RunError};
use blocksmith::{doc, new_engine, repl, studio, test_runner, EngineOptions, RunContext};
use clap::{Parser, Subcommand};

/// mimalloc rather than the system allocator: the boolean engine allocates and frees many
/// mid-sized arrays per operation, which glibc returns to the system and faults back in.
/// Counted, so that a script whose data grows over the memory budget stops with an error.
#[global_allocator]
static ALLOCATOR: limits::CountingAllocator<mimalloc::MiMalloc> = limits::CountingAllocator(mimalloc::MiMalloc);

#[derive(Parser)]
#[command(name = "blocksmith", version, about = "Scriptable 3D modeling: blocks, polar meshes, subdivision, voxels.")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a recipe; write its last value to OUT (by extension: .glb .gltf .obj .stl .ply .3mf).
    Run {
        /// The recipe (.rhai).
        file: PathBuf,
        /// Where to write the script's last value.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// A parameter read by `param(name, default)`; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
        #[command(flatten)]
        limits: LimitArgs,
        /// Print the written model's facts (counts, closed, manifold, genus, volume, area,
        /// bounds, run time) to standard output as JSON; needs -o.
        #[arg(long, value_parser = ["json"], requires = "output")]
        stats: Option<String>,
        /// Write a manifest (hashes of the recipe, its inputs and the output; the parameters;
        /// the tool version) to this JSON file.
        #[arg(long, value_name = "FILE.json")]
        manifest: Option<PathBuf>,
        /// List the recipe's parameters instead of writing a model, as `blocksmith params`
        /// does: `--params` (a table) or `--params json`.
        #[arg(long, value_name = "FORMAT", num_args = 0..=1, default_missing_value = "text",
              value_parser = ["text", "json"], conflicts_with_all = ["output", "stats", "manifest", "max_operations"])]
        params: Option<String>,
    },
    /// List a recipe's parameters (found by running it): name, type, default, range, doc.
    Params {
        /// The recipe (.rhai).
        file: PathBuf,
        /// `text` (a table) or `json`.
        #[arg(long, value_parser = ["text", "json"], default_value = "text")]
        format: String,
        /// A parameter value to list with (a default may depend on another parameter).
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
    },
    /// Interactive session (also reads piped standard input).
    Repl {
        #[command(flatten)]
        limits: LimitArgs,
    },
    /// Run .rhai test scripts (default: tests/), each in a fresh engine. A warning fails the
    /// test (a dropped result, blocks that touch without connecting) unless the script takes
    /// it with `take_warnings()`.
    Test {
        /// Test files or directories.
        paths: Vec<PathBuf>,
        /// Where relative `save` paths of the tests go.
        #[arg(long, default_value = "target/test-output")]
        out: PathBuf,
        #[command(flatten)]
        limits: LimitArgs,
    },
    /// Draw a recipe's value (or a mesh file) to a PNG on the CPU: no GPU, no browser.
    Render {
        /// The recipe (.rhai) or mesh file (.glb .gltf .obj .stl .ply .3mf).
        file: PathBuf,
        /// The PNG to write.
        #[arg(short, long)]
        output: PathBuf,
        /// The picture's size.
        #[arg(long, default_value = "800x600", value_parser = parse_size)]
        size: (u32, u32),
        /// Where the camera looks from: iso, front, back, left, right, top, bottom.
        #[arg(long, default_value = "iso")]
        view: blocksmith::studio::render::View,
        /// A parameter read by `param(name, default)`; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
    },
    /// Show a recipe in the browser and run it again on every save (page on 127.0.0.1).
    Watch {
        /// The recipe (.rhai).
        file: PathBuf,
        /// A parameter read by `param(name, default)`; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
        /// The port (default: any free one).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Open the page in the default browser.
        #[arg(long)]
        open: bool,
    },
    /// Show a mesh file (.glb .gltf .obj .stl .ply .3mf) in the browser, read again on every save.
    View {
        /// The mesh file.
        file: PathBuf,
        /// The port (default: any free one).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Open the page in the default browser.
        #[arg(long)]
        open: bool,
    },
    /// Print the API reference: of one function, operator, type or standard-library module,
    /// or of everything.
    Doc {
        /// A function (`cube`), operator (`+`), type (`Mesh`), module (`check`) or module
        /// function (`check::solid`).
        name: Option<String>,
        /// `text`, `markdown` (docs/reference.md), `html` (docs/reference.html) or `json`
        /// (for editors: every function with all its signatures).
        #[arg(long, default_value = "text", value_parser = ["text", "markdown", "html", "json"])]
        format: String,
    },
}

/// The limits of a run (for the REPL: of each entry; for tests: of each script).
#[derive(clap::Args)]
struct LimitArgs {
    /// Stop after this many operations: script steps, also inside closures, and the elements
    /// kernel work processes.
    #[arg(long)]
    max_operations: Option<u64>,
    /// Stop after this many seconds (the kernel work in progress included).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    timeout: Option<Duration>,
    /// The memory budget: a request whose result is estimated over it is refused before
    /// allocating. Bytes, or with a unit: 512M, 8G, 1T. Default: half the physical memory.
    #[arg(long, value_name = "SIZE", value_parser = parse_memory)]
    memory_limit: Option<u64>,
}

impl LimitArgs {
    /// Sets the process-wide memory budget and returns the options of the other limits.
    fn apply(&self) -> EngineOptions {
        if let Some(bytes) = self.memory_limit {
            limits::set_memory_limit(bytes);
        }
        EngineOptions { max_operations: self.max_operations, timeout: self.timeout, ..EngineOptions::default() }
    }
}

fn parse_seconds(s: &str) -> Result<Duration, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x > 0.0 && x <= 1e9 => Ok(Duration::from_secs_f64(x)),
        _ => Err(format!("expected a number of seconds between 0 and 1e9, got `{s}`")),
    }
}

/// A size in bytes: a number with an optional unit K, M, G or T (powers of 1024; `B`, `iB`
/// allowed after it).
fn parse_memory(s: &str) -> Result<u64, String> {
    let bad = || format!("expected a size such as 512M, 8G or 1T (at least 1M), got `{s}`");
    let t = s.trim();
    let t = t.strip_suffix("iB").or_else(|| t.strip_suffix('B')).unwrap_or(t);
    let (number, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c.to_ascii_uppercase()),
        _ => (t, ' '),
    };
    let scale = match unit {
        ' ' => 1.0,
        'K' => 1024.0,
        'M' => 1024.0 * 1024.0,
        'G' => 1024.0 * 1024.0 * 1024.0,
        'T' => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        _ => return Err(bad()),
    };
    let x = number.trim().parse::<f64>().map_err(|_| bad())? * scale;
    if x.is_finite() && (1024.0 * 1024.0..1e19).contains(&x) {
        Ok(x as u64)
    } else {
        Err(bad())
    }
}

fn parse_set(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.to_string())),
        _ => Err(format!("expected NAME=VALUE, got `{s}`")),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT (each 1 to 8192), got `{s}`");
    let (w, h) = s.split_once('x').ok_or_else(bad)?;
    let (w, h) = (w.parse::<u32>().map_err(|_| bad())?, h.parse::<u32>().map_err(|_| bad())?);
    if (1..=8192).contains(&w) && (1..=8192).contains(&h) {
        Ok((w, h))
    } else {
        Err(bad())
    }
}

/// The options of a run with `--set` parameters.
fn with_params(set: Vec<(String, String)>) -> EngineOptions {
    EngineOptions {
        context: RunContext { params: set.into_iter().collect(), ..RunContext::default() },
        ..EngineOptions::default()
    }
}

/// Prints a command's result: the summary on success, the error on failure.
fn report(result: Result<String, RunError>) -> ExitCode {
    match result {
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

/// The exit of a server that stopped (it only returns on an error).
/// Writes `text` to standard output. A reader that stops early (`blocksmith doc | head`) closes
/// the pipe: the command then ends quietly, as other command-line tools do, instead of panicking.
fn print_out(text: &str) {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => eprintln!("error: could not write to standard output: {e}"),
        Ok(()) => {}
    }
}

fn served(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

/// `blocksmith params` and `run --params`: the recipe's parameters as `format` (text or json).
fn list_params(file: &std::path::Path, set: &[(String, String)], format: &str) -> ExitCode {
    let format = if format == "json" { ListFormat::Json } else { ListFormat::Text };
    match params_list::execute(file, set, format) {
        Ok(listing) => {
            print_out(&listing);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

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
    let cli = Cli::parse();
    match cli.command {
        Command::Run { file, set, params: Some(format), .. } => list_params(&file, &set, &format),
        Command::Run { file, output, set, limits, stats, manifest, params: None } => {
            let l = limits.apply();
            let cmd = RunCommand {
                file,
                output,
                params: set,
                max_operations: l.max_operations,
                timeout: l.timeout,
                stats: stats.is_some(),
                manifest,
            };
            report(execute_with_outcome(&cmd).map(|o| {
                for w in &o.warnings {
                    eprintln!("{w}");
                }
                if let Some(stats) = o.stats {
                    print_out(&format!("{stats:#}\n"));
                }
                o.summary
            }))
        }
        Command::Params { file, format, set } => list_params(&file, &set, &format),
        Command::Repl { limits } => match repl::run(limits.apply().max_operations, limits.timeout) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        },
        Command::Test { paths, out, limits } => {
            let limits = limits.apply();
            if paths.is_empty() && !std::path::Path::new("tests").is_dir() {
                let here = std::env::current_dir().map(|d| d.display().to_string()).unwrap_or_default();
                eprintln!(
                    "error: no tests directory in {here}: without paths, `blocksmith test` runs the .rhai files \
                     under ./tests (relative to where it is run); give test files or directories"
                );
                return ExitCode::FAILURE;
            }
            let paths = if paths.is_empty() { vec![PathBuf::from("tests")] } else { paths };
            let files = match test_runner::collect(&paths) {
                Ok(f) => f,
                Err(e) => {
                    eprintln!("{e}");
                    return ExitCode::FAILURE;
                }
            };
            let outcomes = test_runner::run_all_limited(&files, &out, limits.max_operations, limits.timeout);
            print_out(&test_runner::report(&outcomes));
            if outcomes.iter().any(|o| o.error.is_some()) {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            }
        }
        Command::Render { file, output, size, view, set } => {
            report(studio::render_to_png(&file, with_params(set), &output, size, view))
        }
        Command::Watch { file, set, port, open } => served(studio::serve(&file, set.into_iter().collect(), port, open)),
        Command::View { file, port, open } => served(studio::serve(&file, Default::default(), port, open)),
        Command::Doc { name, format } => {
            let engine = new_engine(EngineOptions::default());
            let format = format.parse::<doc::Format>().unwrap_or(doc::Format::Text);
            match doc::render_as(&engine, name.as_deref(), format) {
                Ok(text) => {
                    print_out(&text);
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
