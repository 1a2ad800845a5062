//! A declared parameter as the run records it ([`ParamSpec`], its [`ParamKind`] taken from the
//! default), script values as JSON for listings and manifests, and `--set` text read as a value.

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

/// Parses a `--set` value of a parameter whose default has no simple type (see
/// [`super::declare`]): integer, float, bool, else string.
pub fn parse_param(text: &str) -> Dynamic {
    if let Ok(i) = text.parse::<rhai::INT>() {
        Dynamic::from(i)
    } else if let Ok(f) = text.parse::<f64>() {
        Dynamic::from(f)
    } else if let Ok(b) = text.parse::<bool>() {
        Dynamic::from(b)
    } else {
        Dynamic::from(text.to_string())
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
    fn params_parse_as_int_float_bool_then_string() {
        assert_eq!(parse_param("12").as_int().unwrap(), 12);
        assert_eq!(parse_param("1.5").as_float().unwrap(), 1.5);
        assert!(parse_param("true").as_bool().unwrap());
        assert_eq!(parse_param("oak").into_string().unwrap(), "oak");
    }
}
