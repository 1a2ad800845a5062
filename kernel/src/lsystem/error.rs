//! Errors of L-systems: bad grammars, failed derivations, refused or runaway growth.

use thiserror::Error;

use crate::polar::PolarError;

/// Why building, deriving or growing an L-system failed. Every variant but
/// [`LsystemError::Internal`] is bad input; [`LsystemError::Internal`] is a bug in blocksmith.
/// Nothing is half-built on error: [`Lsystem`](super::Lsystem) values never change, and
/// [`grow`](super::grow) returns no mesh.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum LsystemError {
    /// A character that starts no symbol.
    #[error("{place}: unknown symbol `{found}` at character {at} (symbols are a letter with optional digits, the turtle symbols + - & ^ \\ / | ! and the brackets [ ] [L [R)")]
    UnknownSymbol { place: String, found: char, at: usize },
    /// A malformed parameter list, expression or rule key.
    #[error("{place}: {reason} at character {at}")]
    Syntax { place: String, reason: String, at: usize },
    /// A `]` without its `[`, or a `[` never closed.
    #[error("{place}: unbalanced brackets: {reason}")]
    UnbalancedBrackets { place: String, reason: String },
    /// An empty axiom.
    #[error("the axiom is empty")]
    EmptyAxiom,
    /// A name in a successor's parameter expression that is not a formal parameter of its rule.
    #[error("{place}: `{name}` is not a parameter of the rule (its parameters: {formals})")]
    UnknownParameter { place: String, name: String, formals: String },
    /// A rule with no choices.
    #[error("{place}: a rule needs at least one successor")]
    NoChoices { place: String },
    /// A probability that is negative, above 1 or not finite.
    #[error("{place}: probability {p} of choice {choice} is not a number between 0 and 1")]
    BadProbability { place: String, choice: usize, p: f64 },
    /// Choice probabilities that do not add up to 1 (a consistent grammar, §11).
    #[error("{place}: the choices' probabilities sum to {sum}, not 1 (a stochastic rule must be consistent, §11)")]
    ProbabilitySum { place: String, sum: f64 },
    /// A probability callback (a script closure) failed.
    #[error("{place}: the probability of choice {choice} failed: {message}")]
    Callback { place: String, choice: usize, message: String },
    /// A size callback (a script closure giving a length or a radius) failed.
    #[error("{place}: {message}")]
    SizeCallback { place: String, message: String },
    /// A parameter expression gave a non-finite value.
    #[error("{place}: parameter {index} of `{symbol}` evaluates to {value}")]
    NonFiniteParameter { place: String, symbol: String, index: usize, value: f64 },
    /// The derived string grew past its cap.
    #[error("runaway derivation: the string reached {count} modules at step {step}, over the cap max_modules = {cap}")]
    TooManyModules { count: usize, step: u32, cap: usize },
    /// Growth reached its cap on vertices or features.
    #[error("runaway growth: {what} reached {count} at module {module} (`{symbol}`), over the cap {cap_name} = {cap}")]
    GrowthCap { what: &'static str, count: usize, cap_name: &'static str, cap: usize, module: usize, symbol: String },
    /// Nothing to grow.
    #[error("the string draws no segment (no F, L, L0, P, [L or [R): nothing to grow")]
    NothingDrawn,
    /// A segment drawn in a branch that a `P` already closed.
    #[error("module {module} (`{symbol}`) draws after `P` ended its branch at module {ended}")]
    DrawAfterPole { module: usize, symbol: String, ended: usize },
    /// No run of free loop vertices left for another branch; `works` is the smallest trunk
    /// valence found that grows the string (searched when growth refuses, and itself grown).
    #[error("module {module} (`{symbol}`): the loop of {valence} vertices has no run of 3 free vertices left for another branch; {}", room_advice(*works))]
    NoRoomForBranch { module: usize, symbol: String, valence: usize, works: Option<u32> },
    /// A bad growth option.
    #[error("{0}")]
    InvalidOption(String),
    /// A polar operation refused: a bug in the growth (the operations are chosen to be valid).
    #[error("internal error (please file an issue): polar operation failed at module {module}: {source}")]
    Polar { module: usize, source: PolarError },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}

/// What to do about [`LsystemError::NoRoomForBranch`]: the valence that grows the string, or
/// fewer branches per loop when none does.
fn room_advice(works: Option<u32>) -> String {
    match works {
        Some(v) => format!(
            "each branch takes 3 or more vertices of its loop and its own loops get fewer than its parent's, \
             so deep branching needs a larger trunk valence: `valence: {v}` grows this string"
        ),
        None => "no trunk valence up to 100000 grows this string within the caps: put fewer branches on one \
                 loop (split a `[..][..][..]` group across two segments) or nest them less deeply"
            .to_string(),
    }
}
