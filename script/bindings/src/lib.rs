//! blocksmith-script: the Rhai bindings of blocksmith, the crate a program embeds to run
//! recipes. [`new_engine`] makes an engine with the whole script API; [`run::run_recipe`] is the
//! one way a recipe is run (the command line, the studio and the tests all go through it).
//!
//! What it holds, one concept per module:
//! - [`engine`]: [`new_engine`] and the limits of a run; [`context`]: what a running script
//!   knows of its surroundings; [`access`]: what a run may read and write; [`progress`]: how long kernel work reports progress to the host.
//! - [`api`]: the script API, one `register` per file, mirroring the kernel's areas;
//!   [`convert`]: script values to kernel types and kernel errors to script errors.
//! - [`run`]: the runner; [`record`]: what a run declared and read; [`params`]: recipe
//!   parameters (declared, parsed, checked, listed); [`resolver`]: imports and the standard library.
//! - [`lint`]: warnings found before a run (dropped results); [`diagnostics`]: errors and
//!   warnings formatted at their line, [`printable`] escaped; [`explain`]: lookup failures explained from the
//!   [`catalogue`] of what exists, and raised explained by [`lookup_failure`]; [`spelling`]: near names for did-you-mean.
//! - [`doc`]: the API reference, generated from the engine's metadata; [`editing_rules`]: how
//!   each kind of value changes, stated once.
//! - [`facts`]: a mesh's measures as JSON; [`gltf_buffers`]: the files a `.gltf` refers to.
//!
//! It depends on the kernel, rhai and serde_json only (`tests/dependencies.rs` checks it): no
//! terminal, web, watcher or image crate. It never prints; a host shows progress through
//! [`progress::Progress`] and prints what the runner returns.

pub mod access;
pub mod api;
pub mod catalogue;
pub mod context;
pub mod convert;
pub mod data_race;
pub mod diagnosis;
pub mod diagnostics;
pub mod doc;
pub mod editing_rules;
pub mod engine;
pub mod explain;
pub mod facts;
pub mod gltf_buffers;
pub mod lint;
pub mod lookup_failure;
pub mod origins;
pub mod params;
pub mod printable;
pub mod progress;
pub mod record;
pub mod resolver;
pub mod run;
pub mod spelling;

pub use context::RunContext;
pub use engine::{limit_data_sizes, new_engine, set_limits, EngineOptions, INTERRUPTED, OPERATION_LIMIT, TIME_LIMIT};
