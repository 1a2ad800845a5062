//! The script API's functions as their `#[export_module]` declarations state them, tabulated at
//! build time (`build.rs`): what Rhai's metadata does not carry — whether a method leaves its
//! receiver unchanged (`pure`) and the Rust type it works on. The dropped-result lint
//! ([`crate::lint`]) reads it, so adding or changing a function keeps the lint right without a
//! list to maintain by hand.

/// One registered function under one script name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Declared {
    /// The script name.
    pub name: &'static str,
    /// The Rust type of the receiver when the first parameter is `&mut` (a method that may
    /// change the value it is called on), e.g. `SharedMesh`, `Block`.
    pub receiver: Option<&'static str>,
    /// The number of script arguments, the receiver included.
    pub arity: usize,
    /// Declared `pure`: the receiver is left unchanged.
    pub pure: bool,
    /// Takes the call context, so it may act beyond its arguments (write a file relative to
    /// the output folder, declare a parameter, show a value): dropping its result is not judged.
    pub context: bool,
    /// The Rust type returned (`()` for nothing), e.g. `SharedMesh`.
    pub returns: &'static str,
    /// The Rust type of each script argument, the receiver included (without `&mut`), e.g.
    /// `["BlockModel", "Block"]`.
    pub params: &'static [&'static str],
    /// The api file that registers it (`mesh` for `src/api/mesh.rs`); the reference files a
    /// free function under its file's topic (`crate::doc::topics`).
    pub module: &'static str,
}

impl Declared {
    /// Calling it only for its effect does nothing: a method that leaves its receiver as it
    /// was and returns something, or a function of its arguments alone (no context) that
    /// returns a typed value (`cube(2)`; not `param`, whose value is `Dynamic` and which
    /// declares a parameter).
    #[must_use]
    pub fn returns_new_value(&self) -> bool {
        match self.receiver {
            Some(_) => self.pure && self.returns != "()",
            None => !self.context && self.returns != "()" && self.returns != "Dynamic",
        }
    }

    /// A method that changes its receiver and nothing else: on a value that is then dropped
    /// (a temporary), its change is lost.
    #[must_use]
    pub fn edits_receiver(&self) -> bool {
        self.receiver.is_some() && !self.pure && !self.context
    }

    /// An edit that returns the value it changed, itself (a Block's `subdivide`, see
    /// [`crate::editing_rules::Rule::EditAndSelf`]): the next call of a chain edits the same value.
    #[must_use]
    pub fn returns_receiver(&self) -> bool {
        self.edits_receiver()
            && self.receiver == Some(self.returns)
            && crate::editing_rules::KINDS
                .iter()
                .any(|k| k.rust == self.returns && k.rule == crate::editing_rules::Rule::EditAndSelf)
    }
}

include!(concat!(env!("OUT_DIR"), "/registry.rs"));

/// The declarations named `name` taking `arity` arguments whose receiver, when `receiver` is
/// known, is of that type.
pub fn candidates<'a>(
    name: &'a str,
    arity: usize,
    receiver: Option<&'a str>,
) -> impl Iterator<Item = &'static Declared> + 'a {
    REGISTRY.iter().filter(move |d| {
        d.name == name && d.arity == arity && receiver.is_none_or(|r| d.receiver.is_none_or(|dr| dr == r))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(name: &str, receiver: &str) -> Declared {
        *candidates(name, 1, Some(receiver)).next().unwrap_or_else(|| panic!("{name} on {receiver}"))
    }

    #[test]
    fn the_table_knows_which_methods_keep_their_receiver() {
        // Mesh transforms return a new mesh; Block edits change the block and return it.
        let t = *candidates("translate", 2, Some("SharedMesh")).next().unwrap();
        assert!(t.returns_new_value() && t.returns == "SharedMesh" && !t.returns_receiver(), "{t:?}");
        let b = *candidates("translate", 2, Some("Block")).next().unwrap();
        assert!(!b.pure && b.returns == "Block" && b.returns_receiver(), "{b:?}");
        assert!(candidates("block", 2, Some("BlockModel")).all(|d| !d.returns_receiver()), "a model's block is a copy");
        assert!(!one("crease_all", "SharedMesh").returns_new_value());
        assert!(one("crease_all", "SharedMesh").edits_receiver());
        // Constructors return a new value; `param` and `show` act beyond their arguments.
        assert!(candidates("cube", 1, None).all(|d| d.returns_new_value()));
        assert!(candidates("param", 2, None).all(|d| !d.returns_new_value()));
        assert!(candidates("show", 1, None).all(|d| !d.returns_new_value()));
        // Saving writes a file: not an edit whose loss matters.
        assert!(candidates("save", 2, Some("SharedMesh")).all(|d| !d.edits_receiver() && !d.returns_new_value()));
        assert!(one("volume", "SharedMesh").returns_new_value());
        // Getters are properties, not calls.
        assert_eq!(candidates("vertex_count", 1, None).count(), 0);
        // Several script names on one function; a context parameter is not an argument.
        assert!(candidates("to_debug", 1, Some("SharedMesh")).next().is_some());
        assert_eq!(candidates("grow", 2, Some("LSystem")).next().map(|d| d.returns), Some("PolarMesh"));
        // A multi-line signature.
        assert_eq!(candidates("rotate", 5, Some("PolarMesh")).next().map(|d| d.returns), Some("()"));
    }

    #[test]
    fn every_declared_function_is_registered_with_that_arity() {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let mut registered = std::collections::HashSet::new();
        let meta: serde_json::Value = serde_json::from_str(&engine.gen_fn_metadata_to_json(false).unwrap()).unwrap();
        for f in meta["functions"].as_array().unwrap() {
            registered.insert((f["name"].as_str().unwrap().to_string(), f["numParams"].as_u64().unwrap() as usize));
        }
        for d in REGISTRY {
            assert!(registered.contains(&(d.name.to_string(), d.arity)), "{d:?} is not registered");
        }
        assert!(REGISTRY.len() > 200, "{}", REGISTRY.len());
    }
}
