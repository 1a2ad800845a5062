//! Every argument of the `blocksmith` command, as clap types: the subcommands and their
//! options, the limits shared by several, and the parsers of values (`--set NAME=VALUE`,
//! `--timeout`, `--memory-limit`, `--size`).

use std::path::PathBuf;
use std::time::Duration;

use blocksmith_kernel::limits;
use blocksmith_script::EngineOptions;
use clap::{Parser, Subcommand};

pub use crate::project::AccessArgs;

#[derive(Parser)]
#[command(name = "blocksmith", version, about = "Scriptable 3D modeling: blocks, polar meshes, subdivision, voxels.")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
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
        #[command(flatten)]
        access: AccessArgs,
        /// Print the written model's facts (counts, closed, manifold, genus, volume, area,
        /// bounds, run time) and where it is broken (components with their genus, boundary
        /// loops, handle loops, self-intersecting faces, non-manifold places, degenerate faces)
        /// to standard output: `--stats` or `--stats text` as lines, `--stats json` as JSON;
        /// the recipe's print() and debug() then go to standard error; needs -o.
        #[arg(long, value_name = "FORMAT", num_args = 0..=1, default_missing_value = "text",
              value_parser = ["text", "json"], requires = "output")]
        stats: Option<String>,
        /// When the recipe ends with an Animation: write its pose at this time (a still mesh,
        /// any format) instead of the animated .glb.
        #[arg(long, value_name = "T", requires = "output")]
        time: Option<f64>,
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
        #[command(flatten)]
        access: AccessArgs,
    },
    /// Interactive session (also reads piped standard input).
    Repl {
        #[command(flatten)]
        limits: LimitArgs,
        #[command(flatten)]
        access: AccessArgs,
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
        #[command(flatten)]
        access: AccessArgs,
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
        view: blocksmith_studio::render::View,
        /// When the recipe ends with an Animation: draw its pose at this time (default: its
        /// last frame as `save` writes it).
        #[arg(long, value_name = "T")]
        time: Option<f64>,
        /// A parameter read by `param(name, default)`; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
        set: Vec<(String, String)>,
        #[command(flatten)]
        access: AccessArgs,
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
        #[command(flatten)]
        access: AccessArgs,
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
    /// A language server for editors over standard input and output: diagnostics as you type,
    /// completion, hover, signature help, go-to-definition, symbols, inlay hints, a run lens.
    Lsp,
}

/// The limits of a run (for the REPL: of each entry; for tests: of each script).
#[derive(clap::Args)]
pub struct LimitArgs {
    /// Stop after this many operations: script steps, also inside closures, and the elements
    /// kernel work processes.
    #[arg(long)]
    pub max_operations: Option<u64>,
    /// Stop after this many seconds (the kernel work in progress included).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub timeout: Option<Duration>,
    /// The memory budget: a request whose result is estimated over it is refused before
    /// allocating. Bytes, or with a unit: 512M, 8G, 1T. Default: half the physical memory.
    #[arg(long, value_name = "SIZE", value_parser = parse_memory)]
    pub memory_limit: Option<u64>,
}

impl LimitArgs {
    /// Sets the process-wide memory budget and returns the options of the other limits.
    pub fn apply(&self) -> EngineOptions {
        if let Some(bytes) = self.memory_limit {
            limits::set_memory_limit(bytes);
        }
        EngineOptions {
            max_operations: self.max_operations,
            timeout: self.timeout,
            progress: crate::progress_bars::on_terminal(),
            ..EngineOptions::default()
        }
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
