//! Recipe parameters, in one place: `param(name, default, #{min, max, step, choices, doc})`
//! declared and its `--set` text parsed and checked ([`declare`]), the declaration as a run
//! records it ([`spec`]), and the listing `blocksmith params` prints ([`listing`]).
//!
//! Like OpenSCAD's customizer, the default gives the type; the options give a control (range,
//! step, choices, description) and the checks a value must pass.

pub mod declare;
pub mod listing;
pub mod spec;

pub use declare::Declared;
pub use listing::ListFormat;
pub use spec::{parse_param, to_json, ParamKind, ParamSpec};
