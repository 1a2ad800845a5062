//! What one run of a recipe declared and read: its parameters (every `param` call, in
//! declaration order) and its inputs (the script, each imported module file, each `load`ed
//! file). `blocksmith params` lists the first, manifests hash the second, and a watcher re-runs
//! when any input changes.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use crate::params::ParamSpec;

/// What one run declared and read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunRecord {
    /// Every parameter, once, in the order of the first `param` call naming it.
    pub params: Vec<ParamSpec>,
    /// Every file read, as an absolute path, once, in the order first read: the script, then
    /// imported module files and `load`ed files. Recorded before the file is parsed, so a run
    /// that failed on a file still names it.
    pub inputs: Vec<PathBuf>,
    /// Standard-library modules imported (embedded in the binary, so no file), by name.
    pub stdlib: Vec<String>,
    /// Every `param_check` the run reached, in order: its message and whether it held.
    pub checks: Vec<ParamCheck>,
}

/// One `param_check(condition, message)` a run reached.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamCheck {
    /// The recipe's message.
    pub message: String,
    /// Whether the condition held.
    pub passed: bool,
    /// The script line of the call (1-based; 0 when unknown).
    pub line: usize,
}

impl RunRecord {
    /// The parameter called `name`, if the run declared it.
    #[must_use]
    pub fn param(&self, name: &str) -> Option<&ParamSpec> {
        self.params.iter().find(|p| p.name == name)
    }
}

/// The shared, growing record of a running script, carried in its [`crate::RunContext`].
/// Cloning shares it.
#[derive(Clone, Debug, Default)]
pub struct Recorder(Rc<RefCell<RunRecord>>);

impl Recorder {
    /// Records a parameter unless one of that name was recorded already (the first `param`
    /// call of a name declares it). Returns whether it was new.
    pub fn param(&self, spec: ParamSpec) -> bool {
        let mut r = self.0.borrow_mut();
        if r.param(&spec.name).is_some() {
            return false;
        }
        r.params.push(spec);
        true
    }

    /// Records that the run read the file at `path` (made absolute; symbolic links resolved
    /// when the file exists).
    pub fn input(&self, path: &Path) {
        let p = path.canonicalize().or_else(|_| std::path::absolute(path)).unwrap_or_else(|_| path.to_path_buf());
        let mut r = self.0.borrow_mut();
        if !r.inputs.contains(&p) {
            r.inputs.push(p);
        }
    }

    /// Records an import of the standard-library module `name`.
    pub fn stdlib(&self, name: &str) {
        let mut r = self.0.borrow_mut();
        if !r.stdlib.iter().any(|n| n == name) {
            r.stdlib.push(name.to_string());
        }
    }

    /// Records a `param_check` the run reached.
    pub fn check(&self, check: ParamCheck) {
        self.0.borrow_mut().checks.push(check);
    }

    /// A copy of the record so far.
    #[must_use]
    pub fn snapshot(&self) -> RunRecord {
        self.0.borrow().clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamKind;
    use serde_json::json;

    #[test]
    fn the_first_declaration_of_a_name_wins_and_inputs_are_kept_once() {
        // plant_growth.rhai reads `delay` twice: one parameter, declared where first read.
        let r = Recorder::default();
        let spec = |d: i64| ParamSpec {
            name: "delay".into(),
            kind: ParamKind::Int,
            default: json!(d),
            value: json!(d),
            set: false,
            min: None,
            max: None,
            step: None,
            choices: vec![],
            doc: None,
        };
        assert!(r.param(spec(1)));
        assert!(!r.param(spec(2)));
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("a.rhai");
        std::fs::write(&f, "1").unwrap();
        r.input(&f);
        r.input(&dir.path().join(".").join("a.rhai"));
        let rec = r.snapshot();
        assert_eq!(rec.params.len(), 1);
        assert_eq!(rec.params[0].default, json!(1));
        assert_eq!(rec.inputs, vec![f.canonicalize().unwrap()]);
    }
}
