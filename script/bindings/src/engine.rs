//! The engine: [`new_engine`] with the whole script API, the standard library resolver and the
//! limits of a run (operations, time, memory, an interrupt), checked at every step and by the
//! kernel work the script starts.

use std::sync::atomic::{AtomicBool, AtomicU64};
use std::sync::Arc;
use std::time::{Duration, Instant};

use blocksmith_kernel::limits::{self, CancelToken, LimitError};
use rhai::{Dynamic, Engine};

use crate::context::RunContext;
use crate::progress::{self, Progress};
use crate::{api, resolver};

/// How an engine is limited and where its script lives.
#[derive(Clone, Debug, Default)]
pub struct EngineOptions {
    /// The run's surroundings (parameters, script and output directories).
    pub context: RunContext,
    /// Stop after this many operations, counted across closures called back from Rust too, and
    /// across the kernel work the script starts (one per element processed).
    pub max_operations: Option<u64>,
    /// Set (e.g. by Ctrl-C) to stop the running evaluation and the kernel work it started.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Stop the evaluation, kernel work included, this long after it starts (`--timeout`).
    pub timeout: Option<Duration>,
    /// Where long kernel work (meshing, booleans) reports how far it has come: none by
    /// default; the `blocksmith` command shows bars on a terminal.
    pub progress: Progress,
}

/// The message an evaluation stopped by `--max-operations` ends with.
pub const OPERATION_LIMIT: &str = "operation limit reached";
/// The message an evaluation stopped by an interrupt ends with.
pub const INTERRUPTED: &str = "interrupted";
/// The message an evaluation stopped by `--timeout` ends with.
pub const TIME_LIMIT: &str = "time limit reached";

/// An engine with the whole script API, the standard library resolver and the given limits.
///
/// Call levels and expression depths are set explicitly so debug builds behave like release.
#[must_use]
pub fn new_engine(options: EngineOptions) -> Engine {
    let mut engine = Engine::new();
    engine.set_max_call_levels(96);
    engine.set_max_expr_depths(128, 128);
    if limits::heap_in_use().is_some() {
        // No size limits of Rhai's: they walk every array after each call that may change it
        // (quadratic pushes). Data is held to the memory budget by the heap check of every step
        // below and by the functions of `api::data`, which grow by a requested size.
        engine.set_max_string_size(0);
        engine.set_max_array_size(0);
        engine.set_max_map_size(0);
    } else {
        limit_data_sizes(&mut engine, limits::memory_limit());
    }
    // `+` and `+=` of strings, arrays and BLOBs go to the budget-checked versions of
    // `api::data` rather than Rhai's built-in ones.
    engine.set_fast_operators(false);
    api::register_all(&mut engine);
    crate::origins::register(&mut engine);
    crate::lookup_failure::install(&mut engine);
    engine.set_module_resolver(
        resolver::Resolver::new(options.context.script_dir.clone())
            .recording(options.context.record.clone())
            .confined_by(options.context.access.clone()),
    );
    if options.context.print_to == crate::context::PrintTo::Stderr {
        // The lines Rhai would print on standard output, on standard error (same text).
        engine.on_print(|s| eprintln!("{s}"));
        engine.on_debug(|s, source, pos| match (source, pos.is_none()) {
            (Some(source), true) => eprintln!("{source} | {s}"),
            (Some(source), false) => eprintln!("{source} @ {pos:?} | {s}"),
            (None, true) => eprintln!("{s}"),
            (None, false) => eprintln!("{pos:?} | {s}"),
        });
    }
    engine.set_default_tag(options.context.clone().into_tag());
    set_limits(&mut engine, &options);
    engine
}

/// Bytes a script value is taken to hold per element of an array or a map, for
/// [`limit_data_sizes`]: the 16-byte `Dynamic` with room for the containers around it.
const BYTES_PER_ELEMENT: u64 = 64;

/// Holds `engine`'s data to `budget` bytes with Rhai's own size limits: strings to `budget`
/// bytes, arrays and maps (nested ones counted whole) to `budget / 64` elements.
///
/// [`new_engine`] uses them when the program embedding it counts no heap (it has not installed
/// [`limits::CountingAllocator`] as its global allocator, so the heap check of every step cannot
/// see the script's data): without them a script doubling an array would grow until an
/// allocation fails and aborts the process. Rhai checks them by walking the data after each call
/// that may change it, so appending in a loop is quadratic there; the `blocksmith` binary counts
/// its heap and needs none of them.
pub fn limit_data_sizes(engine: &mut Engine, budget: u64) {
    let size = |n: u64| usize::try_from(n.max(1)).unwrap_or(usize::MAX);
    engine.set_max_string_size(size(budget));
    engine.set_max_array_size(size(budget / BYTES_PER_ELEMENT));
    engine.set_max_map_size(size(budget / BYTES_PER_ELEMENT));
}

/// (Re)starts the limits of `options` on `engine`: a fresh operation count and deadline.
///
/// Every step checks that the heap in use (when counted, see [`limits::CountingAllocator`]) is
/// within the memory budget, and one cancellation token — the interrupt flag, the deadline and
/// the operation count — and makes it the current token of the thread it runs on, so the kernel
/// work it calls checks the same token in its long loops ([`limits::check`]) and stops with it.
/// Without limits the token never stops anything (and still replaces one left by other work).
/// The options' [`Progress`] becomes the thread's current progress the same way.
pub fn set_limits(engine: &mut Engine, options: &EngineOptions) {
    // The seconds as given (to the microsecond): 1.793 s is held as 1.793000000 s, whose f64
    // reads 1.7930000000000001.
    let deadline = options.timeout.map(|t| (Instant::now() + t, (t.as_secs_f64() * 1e6).round() / 1e6));
    let operations = options.max_operations.map(|max| (Arc::new(AtomicU64::new(0)), max));
    let token = CancelToken::with(options.interrupt.clone(), deadline, operations);
    let shown = options.progress.clone();
    engine.on_progress(move |_| {
        limits::make_current(&token);
        progress::make_current(&shown);
        if let Err(e) = limits::check_heap() {
            return Some(Dynamic::from(e.to_string()));
        }
        match token.charge(1) {
            Ok(()) => None,
            Err(LimitError::Stopped(reason)) => Some(Dynamic::from(reason.to_string())),
            Err(e) => Some(Dynamic::from(e.to_string())),
        }
    });
}
