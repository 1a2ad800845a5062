//! blocksmith-lsp: `blocksmith lsp`, a language server for recipes over stdio
//! ([`server::serve_stdio`], on rust-analyzer's synchronous `lsp-server` and `lsp-types`).
//! Everything it says comes from the bindings, written once there: the catalogue of functions
//! (completion, signature help, type inference), `blocksmith doc` (hover), the lint and the
//! error explanations (diagnostics), the parameter checks and the standard library.
//!
//! One concept per module: [`text`] (positions and scans), [`infer`] (types known without a
//! run), [`diagnose`], [`complete`], [`describe`] (hover and signature help), [`navigate`]
//! (definitions and document symbols), [`inlay`] (each `param`'s type and range), [`lens`] (the
//! run lens and its facts), [`server`] (the protocol).

pub mod complete;
pub mod describe;
pub mod diagnose;
pub mod infer;
pub mod inlay;
pub mod lens;
pub mod navigate;
pub mod options;
pub mod server;
pub mod studio_link;
pub mod text;

use std::cell::OnceCell;
use std::collections::HashMap;
use std::rc::Rc;

use blocksmith_script::catalogue::Overload;
use blocksmith_script::doc::modules::Module;

/// What the features read: an engine with the whole script API (never run by analysis), its
/// catalogue and the standard library's modules, made once per server.
pub struct Analyzer {
    /// The engine recipes are compiled with (as `blocksmith run` makes it).
    pub engine: rhai::Engine,
    /// Every function scripts can call, with signatures and docs.
    pub catalogue: Rc<[Overload]>,
    /// The standard library's modules with their public functions.
    pub stdlib: Vec<Module>,
    /// The option-map keys of each function, asked once when first needed ([`options::probe`]).
    keys: OnceCell<HashMap<String, Vec<String>>>,
}

impl Analyzer {
    /// Reads the catalogue and the standard library once.
    #[must_use]
    pub fn new() -> Analyzer {
        let mut engine = blocksmith_script::new_engine(blocksmith_script::EngineOptions::default());
        // Literals stay as written (a constant map keeps its keys' positions).
        engine.set_optimization_level(rhai::OptimizationLevel::None);
        let catalogue = blocksmith_script::catalogue::of(&engine);
        let stdlib = blocksmith_script::doc::modules::stdlib(&engine);
        Analyzer { engine, catalogue, stdlib, keys: OnceCell::new() }
    }

    /// The option-map keys of each function that takes a map.
    #[must_use]
    pub fn option_keys(&self) -> &HashMap<String, Vec<String>> {
        self.keys.get_or_init(|| options::probe(&self.catalogue))
    }

    /// The standard-library module `name`.
    #[must_use]
    pub fn module(&self, name: &str) -> Option<&Module> {
        self.stdlib.iter().find(|m| m.name == name)
    }
}

impl Default for Analyzer {
    fn default() -> Analyzer {
        Analyzer::new()
    }
}

#[cfg(test)]
mod tests_features;
#[cfg(test)]
mod tests_fuzz;
