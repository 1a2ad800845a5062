//! What one run of a recipe declared and read: its parameters (every `param` call, in
//! declaration order) and its inputs (the script, each imported module file, each `load`ed
//! file). `blocksmith params` lists the first, manifests hash the second, and a watcher re-runs
//! when any input changes.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use blocksmith_kernel::Vec3;
use rhai::Dynamic;
use serde_json::{json, Value};

/// The type of a parameter, taken from its default (`choice` when it has `choices`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// An integer (`param("teeth", 12)`).
    Int,
    /// A number (`param("radius", 1.0)`); an integer given for it becomes a float.
    Float,
    /// `true` or `false`.
    Bool,
    /// Any text.
    String,
    /// A vector: a `Vec3` default, given as `x,y,z`.
    Vec3,
    /// An array, given as comma-separated elements of the default's element type.
    Array,
    /// One of the declared `choices` (of the default's type).
    Choice,
    /// Any other default (a map, a mesh...): a `--set` value is parsed as integer, float, bool,
    /// else string, as `param` always did.
    Other,
}

impl ParamKind {
    /// The kind of a parameter with this default and no choices.
    #[must_use]
    pub fn of(default: &Dynamic) -> ParamKind {
        if default.is_int() {
            ParamKind::Int
        } else if default.is_float() {
            ParamKind::Float
        } else if default.is_bool() {
            ParamKind::Bool
        } else if default.is_string() {
            ParamKind::String
        } else if default.is::<Vec3>() {
            ParamKind::Vec3
        } else if default.is_array() {
            ParamKind::Array
        } else {
            ParamKind::Other
        }
    }

    /// The lower-case name used in listings and JSON: `int`, `float`, `bool`, `string`, `vec3`,
    /// `array`, `choice`, `other`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ParamKind::Int => "int",
            ParamKind::Float => "float",
            ParamKind::Bool => "bool",
            ParamKind::String => "string",
            ParamKind::Vec3 => "vec3",
            ParamKind::Array => "array",
            ParamKind::Choice => "choice",
            ParamKind::Other => "other",
        }
    }
}

/// One parameter as its `param(name, default, #{min, max, step, choices, doc})` call declared
/// it, and the value the run used. Values are JSON (a `Vec3` is `[x, y, z]`) so that the record
/// can leave the script thread and be written out as is.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    /// The name `--set NAME=...` gives.
    pub name: String,
    /// The type a `--set` value is parsed as.
    pub kind: ParamKind,
    /// The default of the `param` call.
    pub default: Value,
    /// The value the run used: the parsed `--set` value, else the default.
    pub value: Value,
    /// Whether `value` came from `--set`.
    pub set: bool,
    /// Inclusive bounds of a number (of each element for a vector or array), if declared.
    pub min: Option<f64>,
    /// See `min`.
    pub max: Option<f64>,
    /// The increment a control uses; a value must be `min` (else 0) plus a whole number of steps.
    pub step: Option<f64>,
    /// The allowed values, when declared (kind [`ParamKind::Choice`]); empty otherwise.
    pub choices: Vec<Value>,
    /// A one-line description, if declared.
    pub doc: Option<String>,
}

impl ParamSpec {
    /// The spec as a JSON object: `name`, `kind`, `default`, `value`, `set`, and `min`, `max`,
    /// `step`, `choices`, `doc` when declared.
    #[must_use]
    pub fn to_json(&self) -> Value {
        let mut o = json!({
            "name": self.name,
            "kind": self.kind.name(),
            "default": self.default,
            "value": self.value,
            "set": self.set,
        });
        let map = o.as_object_mut().expect("a JSON object");
        let numbers = [("min", self.min), ("max", self.max), ("step", self.step)];
        for (key, v) in numbers {
            if let Some(x) = v {
                map.insert(key.into(), json!(x));
            }
        }
        if !self.choices.is_empty() {
            map.insert("choices".into(), Value::Array(self.choices.clone()));
        }
        if let Some(doc) = &self.doc {
            map.insert("doc".into(), json!(doc));
        }
        o
    }
}

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

    /// A copy of the record so far.
    #[must_use]
    pub fn snapshot(&self) -> RunRecord {
        self.0.borrow().clone()
    }
}

/// A script value as JSON: numbers, bools, strings, a `Vec3` as `[x, y, z]`, arrays and maps
/// element by element; a non-finite float as `null`, any other value as its type name.
#[must_use]
pub fn to_json(v: &Dynamic) -> Value {
    if let Ok(i) = v.as_int() {
        json!(i)
    } else if let Ok(f) = v.as_float() {
        serde_json::Number::from_f64(f).map_or(Value::Null, Value::Number)
    } else if let Ok(b) = v.as_bool() {
        json!(b)
    } else if let Some(s) = v.read_lock::<rhai::ImmutableString>() {
        json!(s.as_str())
    } else if let Some(p) = v.read_lock::<Vec3>() {
        json!([p.x, p.y, p.z])
    } else if let Some(a) = v.read_lock::<rhai::Array>() {
        Value::Array(a.iter().map(to_json).collect())
    } else if let Some(m) = v.read_lock::<rhai::Map>() {
        Value::Object(m.iter().map(|(k, x)| (k.to_string(), to_json(x))).collect())
    } else {
        json!(v.type_name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_become_json_with_vectors_as_triples() {
        assert_eq!(to_json(&Dynamic::from(3_i64)), json!(3));
        assert_eq!(to_json(&Dynamic::from(0.5_f64)), json!(0.5));
        assert_eq!(to_json(&Dynamic::from(f64::NAN)), Value::Null);
        assert_eq!(to_json(&Dynamic::from("oak")), json!("oak"));
        assert_eq!(to_json(&Dynamic::from(Vec3::new(1.0, 2.0, 3.0))), json!([1.0, 2.0, 3.0]));
        let a: rhai::Array = vec![Dynamic::from(1_i64), Dynamic::from(true)];
        assert_eq!(to_json(&Dynamic::from(a)), json!([1, true]));
    }

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
