//! blocksmith: scriptable 3D modeling. This crate binds the kernel to Rhai and holds the
//! runner, the test runner, the REPL and the documentation generator behind the `blocksmith`
//! binary.
//!
//! [`new_engine`] makes an engine with the whole script API; [`run`], [`test_runner`],
//! [`repl`] and [`doc`] are the subcommands.

pub mod api;
pub mod catalogue;
pub mod context;
pub mod convert;
pub mod diagnostics;
pub mod doc;
pub mod explain;
pub mod facts;
pub mod gltf_buffers;
pub mod lint;
pub mod manifest;
pub mod param;
pub mod params_list;
pub mod record;
pub mod repl;
pub mod resolver;
pub mod run;
pub mod stats;
pub mod studio;
pub mod test_runner;

use std::cell::Cell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rhai::{Dynamic, Engine};

pub use context::RunContext;

/// How an engine is limited and where its script lives.
#[derive(Clone, Debug, Default)]
pub struct EngineOptions {
    /// The run's surroundings (parameters, script and output directories).
    pub context: RunContext,
    /// Stop after this many operations, counted across closures called back from Rust too.
    pub max_operations: Option<u64>,
    /// Set (e.g. by Ctrl-C) to stop the running evaluation.
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// The message an evaluation stopped by `--max-operations` ends with.
pub const OPERATION_LIMIT: &str = "operation limit reached";
/// The message an evaluation stopped by an interrupt ends with.
pub const INTERRUPTED: &str = "interrupted";

/// An engine with the whole script API, the standard library resolver and the given limits.
///
/// Call levels and expression depths are set explicitly so debug builds behave like release.
#[must_use]
pub fn new_engine(options: EngineOptions) -> Engine {
    let mut engine = Engine::new();
    engine.set_max_call_levels(96);
    engine.set_max_expr_depths(128, 128);
    engine.set_max_string_size(64 << 20);
    engine.set_max_array_size(64 << 20);
    engine.set_max_map_size(1 << 20);
    api::register_all(&mut engine);
    engine.set_module_resolver(
        resolver::Resolver::new(options.context.script_dir.clone()).recording(options.context.record.clone()),
    );
    engine.set_default_tag(options.context.clone().into_tag());
    let limit = options.max_operations;
    let interrupt = options.interrupt;
    let counter = Rc::new(Cell::new(0u64));
    if limit.is_some() || interrupt.is_some() {
        engine.on_progress(move |_| {
            let n = counter.get() + 1;
            counter.set(n);
            if let Some(max) = limit {
                if n > max {
                    return Some(Dynamic::from(format!("{OPERATION_LIMIT} (--max-operations {max})")));
                }
            }
            if let Some(flag) = &interrupt {
                if flag.swap(false, Ordering::SeqCst) {
                    return Some(Dynamic::from(INTERRUPTED.to_string()));
                }
            }
            None
        });
    }
    engine
}
