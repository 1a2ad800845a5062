//! L-systems grown directly as polar-mesh operations (Brazzolotto, seed 004, part III: ch. 10–12).
//!
//! A grammar ([`Lsystem`]: an axiom, deterministic / stochastic / parametric / context-sensitive
//! rules and a seed, §10.2 and §11) is derived to a string of [`Module`]s ([`Lsystem::derive`]),
//! and the string is grown as a sequence of polar operations on one mesh ([`grow`], §11.1): each
//! loop symbol an `add_refinement` and a move, each pole symbol the end of a branch, each branch a
//! feature nested with `add_feature` where the turtle points. The mesh is the string's implicit
//! representation: one skeleton node per drawn module (§7.1).
//!
//! Files, one concept each: `grammar` (modules, expressions, rules), `derive` (rewriting with
//! contexts and seeded choices, drawn from [`SplitMix64`](crate::math::SplitMix64)), `turtle`
//! (the 3D turtle of §10.3), `grow` (the polar interpretation), `symbols` (what each symbol and
//! its parameter mean, tabulated for the reference), `error`.

mod derive;
mod error;
mod grammar;
mod grow;
pub mod symbols;
#[cfg(test)]
pub(crate) mod tests_grow;
#[cfg(test)]
pub(crate) mod tests_selfint;
mod turtle;

pub use derive::ProbabilityFn;
pub use error::LsystemError;
pub use grammar::{
    modules_to_string, parse_modules, ChoiceSpec, Lsystem, Module, Probability, RuleSpec, DEFAULT_MAX_MODULES,
};
pub use grow::{grow, grow_with, sigmoid, GrowOptions, Grown, Size, MAX_SIZE};
pub use turtle::Turtle;
