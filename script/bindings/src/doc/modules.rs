//! The standard library's modules (`stdlib/*.rhai`) as the reference shows them: each module's
//! header comment and its public functions with their doc comments, read from the compiled
//! modules themselves.

use rhai::{Engine, FnAccess};

use crate::resolver::Resolver;

/// One standard-library module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Module {
    /// The name scripts import it by (`import "check" as check;`).
    pub name: String,
    /// The module's header: its leading `//` comment, without the markers.
    pub doc: String,
    /// Its public functions, sorted by name then number of parameters.
    pub functions: Vec<ModuleFn>,
}

/// One public function of a standard-library module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleFn {
    /// The module's name.
    pub module: String,
    /// The function's name inside the module.
    pub name: String,
    /// Its parameters' names (script functions take any value).
    pub params: Vec<String>,
    /// Its doc comment, without the `///` markers.
    pub doc: String,
}

impl ModuleFn {
    /// `check::solid` — how a script that imported the module as its own name calls it.
    #[must_use]
    pub fn path(&self) -> String {
        format!("{}::{}", self.module, self.name)
    }

    /// `check::solid(m, genus)`.
    #[must_use]
    pub fn signature(&self) -> String {
        format!("{}({})", self.path(), self.params.join(", "))
    }
}

/// Every standard-library module, sorted by name. A module that does not compile is listed
/// with its error as its text (the test suite compiles each, so this does not happen in a
/// release).
#[must_use]
pub fn stdlib(engine: &Engine) -> Vec<Module> {
    let mut names = Resolver::stdlib_names();
    names.sort_unstable();
    names.into_iter().filter_map(|name| Some(module(engine, name, Resolver::stdlib_source(name)?))).collect()
}

/// The module `name` whose source is `source`.
fn module(engine: &Engine, name: &str, source: &str) -> Module {
    let ast = match engine.compile(source) {
        Ok(ast) => ast,
        Err(e) => return Module { name: name.into(), doc: format!("(does not compile: {e})"), functions: Vec::new() },
    };
    let mut functions: Vec<ModuleFn> = ast
        .iter_functions()
        .filter(|f| f.access != FnAccess::Private)
        .map(|f| ModuleFn {
            module: name.to_string(),
            name: f.name.to_string(),
            params: f.params.iter().map(|p| (*p).to_string()).collect(),
            doc: crate::catalogue::clean_comments(&f.comments),
        })
        .collect();
    functions.sort_by(|a, b| (&a.name, a.params.len()).cmp(&(&b.name, b.params.len())));
    Module { name: name.to_string(), doc: header(source), functions }
}

/// The leading `//` comment of a module's source (not its functions' `///` doc comments).
fn header(source: &str) -> String {
    let lines: Vec<&str> = source
        .lines()
        .take_while(|l| l.trim_start().starts_with("//") && !l.trim_start().starts_with("///"))
        .map(|l| {
            let l = l.trim_start().trim_start_matches("//");
            l.strip_prefix(' ').unwrap_or(l)
        })
        .collect();
    lines.join("\n").trim().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modules_list_their_public_functions_with_docs() {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let modules = stdlib(&engine);
        let names: Vec<&str> = modules.iter().map(|m| m.name.as_str()).collect();
        assert!(names.contains(&"check") && names.contains(&"plants"), "{names:?}");
        let check = modules.iter().find(|m| m.name == "check").unwrap();
        assert!(check.doc.starts_with("check.rhai"), "{}", check.doc);
        assert!(check.doc.lines().all(|l| !l.trim_start().starts_with("//")), "{}", check.doc);
        let solid = check.functions.iter().find(|f| f.name == "solid").unwrap();
        assert_eq!(solid.signature(), "check::solid(m, genus)");
        assert!(solid.doc.starts_with("Asserts that `m` is a watertight solid"), "{}", solid.doc);
        for m in &modules {
            assert!(!m.doc.is_empty(), "module {} has no header comment", m.name);
            for f in &m.functions {
                assert!(!f.doc.is_empty(), "{} has no doc comment", f.path());
            }
        }
    }

    #[test]
    fn header_stops_at_the_first_code_or_doc_comment() {
        assert_eq!(header("// a\n//   b\n\n/// f\nfn f() {}"), "a\n  b");
        assert_eq!(header("fn f() {}"), "");
    }
}
