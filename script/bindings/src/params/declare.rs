//! `param(name, default, #{min, max, step, choices, doc})`: one recipe parameter declared, its
//! `--set` text parsed by the default's type and checked against the range and the choices.

use blocksmith_kernel::Vec3;
use rhai::{Array, Dynamic, Map, INT};

use super::spec::{parse_param, to_json, ParamKind, ParamSpec};
use crate::convert::{error, type_name, Options, ScriptResult};

const FUNC: &str = "param";
const OPTIONS: [&str; 5] = ["choices", "doc", "max", "min", "step"];

/// A declared parameter: its spec (without a value yet) and the default as a script value.
pub struct Declared {
    spec: ParamSpec,
    default: Dynamic,
    /// The element kind of an array parameter (from its first element).
    element: ParamKind,
    choices: Array,
}

impl Declared {
    /// Checks the declaration: known option keys, numeric `min ≤ max`, `step > 0`, `choices`
    /// a non-empty array of values of the default's type, `doc` a string, and the default
    /// itself within the range and among the choices.
    ///
    /// # Errors
    /// A script error naming `param`, the parameter and the bad option.
    pub fn new(name: &str, default: Dynamic, options: Map) -> ScriptResult<Declared> {
        let opts = Options::new(FUNC, options, &OPTIONS).map_err(|e| prefix(name, &e))?;
        let bad = |msg: String| error(FUNC, format!("`{name}`: {msg}"));
        let mut kind = ParamKind::of(&default);
        let element = match default.read_lock::<Array>() {
            Some(a) => a.first().map_or(ParamKind::Other, ParamKind::of),
            None => ParamKind::Other,
        };
        let numeric = matches!(kind, ParamKind::Int | ParamKind::Float | ParamKind::Vec3)
            || (kind == ParamKind::Array && matches!(element, ParamKind::Int | ParamKind::Float));
        let bound = |key: &str| -> ScriptResult<Option<f64>> {
            if !opts.has(key) {
                return Ok(None);
            }
            if !numeric {
                return Err(bad(format!("option `{key}` needs a numeric default, got {}", type_name(&default))));
            }
            opts.number(key, 0.0).map(Some).map_err(|e| prefix(name, &e))
        };
        let (min, max, step) = (bound("min")?, bound("max")?, bound("step")?);
        if let (Some(lo), Some(hi)) = (min, max) {
            if lo > hi {
                return Err(bad(format!("option `min` ({lo}) must not exceed `max` ({hi})")));
            }
        }
        if let Some(s) = step.filter(|s| *s <= 0.0) {
            return Err(bad(format!("option `step` must be > 0, got {s}")));
        }
        let choices = match opts.raw("choices") {
            None => Array::new(),
            Some(c) => {
                let Some(list) = c.read_lock::<Array>().map(|a| a.clone()) else {
                    return Err(bad(format!("option `choices` must be an array, got {}", type_name(c))));
                };
                if list.is_empty() {
                    return Err(bad("option `choices` must not be empty".into()));
                }
                if let Some(x) = list.iter().find(|x| !same_kind(kind, x)) {
                    return Err(bad(format!(
                        "option `choices` must hold values of the default's type ({}), got {}",
                        kind.name(),
                        type_name(x)
                    )));
                }
                list
            }
        };
        let doc = if opts.has("doc") { Some(opts.string("doc", "").map_err(|e| prefix(name, &e))?) } else { None };
        if !choices.is_empty() {
            kind = ParamKind::Choice;
        }
        let spec = ParamSpec {
            name: name.to_string(),
            kind,
            default: to_json(&default),
            value: to_json(&default),
            set: false,
            min,
            max,
            step,
            choices: choices.iter().map(to_json).collect(),
            doc,
        };
        let declared = Declared { spec, default, element, choices };
        if let Err(why) = declared.check(&declared.default) {
            return Err(bad(format!("the default {} {why}", declared.spec.default)));
        }
        Ok(declared)
    }

    /// The value to use: `text` (from `--set`) parsed by the default's type and checked, else
    /// the default. Returns the value and its spec.
    ///
    /// # Errors
    /// A script error naming the parameter, what it must be, its default and the text given.
    pub fn resolve(mut self, text: Option<&str>) -> ScriptResult<(Dynamic, ParamSpec)> {
        let Some(text) = text else {
            return Ok((self.default, self.spec));
        };
        let value = self.parse(text).and_then(|v| self.check(&v).map(|()| v)).map_err(|_| {
            error(
                FUNC,
                format!(
                    "`{}` must be {} (default {}), got `{text}`",
                    self.spec.name,
                    self.expected(),
                    self.spec.default
                ),
            )
        })?;
        self.spec.value = to_json(&value);
        self.spec.set = true;
        Ok((value, self.spec))
    }

    /// `text` parsed as a value of the parameter's type.
    fn parse(&self, text: &str) -> Result<Dynamic, String> {
        let kind = if self.spec.kind == ParamKind::Choice { ParamKind::of(&self.default) } else { self.spec.kind };
        match kind {
            ParamKind::Array => {
                let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
                if inner.trim().is_empty() {
                    return Ok(Dynamic::from(Array::new()));
                }
                let items: Result<Array, String> = inner.split(',').map(|s| scalar(self.element, s.trim())).collect();
                items.map(Dynamic::from)
            }
            ParamKind::Vec3 => {
                let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
                let c: Vec<f64> = inner
                    .split(',')
                    .map(|s| s.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| e.to_string())?;
                match c[..] {
                    [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                        Ok(Dynamic::from(Vec3::new(x, y, z)))
                    }
                    _ => Err("three finite numbers".into()),
                }
            }
            k => scalar(k, text),
        }
    }

    /// Whether `v` (of the parameter's type) is within the range and among the choices; what
    /// it must be when not.
    fn check(&self, v: &Dynamic) -> Result<(), String> {
        if !self.choices.is_empty() && !self.choices.iter().any(|c| equal(c, v)) {
            return Err(format!("must be one of {}", self.choice_list()));
        }
        let xs = numbers(v);
        let each = if xs.len() > 1 || v.is_array() { "each " } else { "" };
        if xs.iter().any(|&x| self.spec.min.is_some_and(|lo| x < lo) || self.spec.max.is_some_and(|hi| x > hi)) {
            return Err(format!("must be {each}{}", self.range()));
        }
        if let Some(step) = self.spec.step {
            let base = self.spec.min.unwrap_or(0.0);
            if xs.iter().any(|&x| !on_step(x, base, step)) {
                return Err(format!("must be {each}{}", self.steps().trim_start_matches(", ")));
            }
        }
        Ok(())
    }

    /// The steps a value must be on, in words (`, in steps of 0.5 from 1`), or nothing.
    fn steps(&self) -> String {
        self.spec.step.map_or_else(String::new, |s| format!(", in steps of {s} from {}", self.spec.min.unwrap_or(0.0)))
    }

    /// What a `--set` value must be, in words: "an integer from 1 to 12", "one of a, b".
    fn expected(&self) -> String {
        let what = match self.spec.kind {
            ParamKind::Choice => return format!("one of {}", self.choice_list()),
            ParamKind::Int => "an integer".to_string(),
            ParamKind::Float => "a number".to_string(),
            ParamKind::Bool => "true or false".to_string(),
            ParamKind::String => "text".to_string(),
            ParamKind::Vec3 => "three numbers x,y,z".to_string(),
            ParamKind::Array => format!("a comma-separated list of {}", plural(self.element)),
            ParamKind::Other => "a value".to_string(),
        };
        let range = self.range();
        let steps = self.steps();
        if range.is_empty() && steps.is_empty() {
            what
        } else if matches!(self.spec.kind, ParamKind::Vec3 | ParamKind::Array) {
            format!("{what}, each {range}{steps}").replace("each , ", "each ")
        } else if range.is_empty() {
            format!("{what}{steps}")
        } else {
            format!("{what} {range}{steps}")
        }
    }

    fn range(&self) -> String {
        match (self.spec.min, self.spec.max) {
            (Some(lo), Some(hi)) => format!("from {lo} to {hi}"),
            (Some(lo), None) => format!("at least {lo}"),
            (None, Some(hi)) => format!("at most {hi}"),
            (None, None) => String::new(),
        }
    }

    fn choice_list(&self) -> String {
        self.spec
            .choices
            .iter()
            .map(|c| c.as_str().map_or_else(|| c.to_string(), str::to_string))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Prefixes an option error of [`Options`] (`param: option ...`) with the parameter's name.
fn prefix(name: &str, e: &rhai::EvalAltResult) -> Box<rhai::EvalAltResult> {
    let msg = crate::diagnostics::message(e);
    let rest = msg.strip_prefix("param: ").unwrap_or(&msg);
    error(FUNC, format!("`{name}`: {rest}"))
}

/// `text` as a value of the scalar kind `kind` (an `Other` kind: integer, float, bool, else
/// string).
fn scalar(kind: ParamKind, text: &str) -> Result<Dynamic, String> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    match kind {
        ParamKind::Int => text.trim().parse::<INT>().map(Dynamic::from).map_err(|x| e(&x)),
        ParamKind::Float => match text.trim().parse::<f64>() {
            Ok(f) if f.is_finite() => Ok(Dynamic::from(f)),
            Ok(f) => Err(format!("{f} is not finite")),
            Err(x) => Err(e(&x)),
        },
        ParamKind::Bool => text.trim().parse::<bool>().map(Dynamic::from).map_err(|x| e(&x)),
        ParamKind::String => Ok(Dynamic::from(text.to_string())),
        _ => Ok(parse_param(text)),
    }
}

fn plural(kind: ParamKind) -> &'static str {
    match kind {
        ParamKind::Int => "integers",
        ParamKind::Float => "numbers",
        ParamKind::Bool => "bools",
        ParamKind::String => "strings",
        _ => "values",
    }
}

/// Whether `x` is a value of a parameter of kind `kind` (an integer counts as a float).
fn same_kind(kind: ParamKind, x: &Dynamic) -> bool {
    match kind {
        ParamKind::Float => x.is_float() || x.is_int(),
        k => ParamKind::of(x) == k,
    }
}

/// Equality of two parameter values (an integer equals the float of the same value).
fn equal(a: &Dynamic, b: &Dynamic) -> bool {
    let (ja, jb) = (to_json(a), to_json(b));
    match (ja.as_f64(), jb.as_f64()) {
        (Some(x), Some(y)) => x == y,
        _ => ja == jb,
    }
}

/// How far, in steps, a value may be from a step (`base + k × step`): floating-point
/// arithmetic leaves 0.1 + 0.2 a hair away from the third step of 0.1.
const STEP_TOLERANCE: f64 = 1e-6;

/// Whether `x` is `base + k × step` for a whole `k`, within [`STEP_TOLERANCE`] of a step.
fn on_step(x: f64, base: f64, step: f64) -> bool {
    let k = (x - base) / step;
    (k - k.round()).abs() <= STEP_TOLERANCE
}

/// The numbers in a value a range applies to: a number, a vector's coordinates, an array's
/// numeric elements.
fn numbers(v: &Dynamic) -> Vec<f64> {
    if let Ok(i) = v.as_int() {
        vec![i as f64]
    } else if let Ok(f) = v.as_float() {
        vec![f]
    } else if let Some(p) = v.read_lock::<Vec3>() {
        vec![p.x, p.y, p.z]
    } else if let Some(a) = v.read_lock::<Array>() {
        a.iter().flat_map(numbers).collect()
    } else {
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn map(pairs: &[(&str, Dynamic)]) -> Map {
        pairs.iter().map(|(k, v)| ((*k).into(), v.clone())).collect()
    }

    fn msg(r: ScriptResult<impl Sized>) -> String {
        match r {
            Ok(_) => panic!("expected an error"),
            Err(e) => crate::diagnostics::message(&e),
        }
    }

    #[test]
    fn a_value_must_be_on_its_step_counted_from_min_or_zero() {
        let opts = map(&[("min", Dynamic::from(0.5)), ("max", Dynamic::from(4.0)), ("step", Dynamic::from(0.5))]);
        let size = || Declared::new("size", Dynamic::from(1.0), opts.clone()).unwrap();
        assert_eq!(size().resolve(Some("2.5")).unwrap().0.as_float().unwrap(), 2.5);
        assert_eq!(
            msg(size().resolve(Some("1.2"))),
            "param: `size` must be a number from 0.5 to 4, in steps of 0.5 from 0.5 (default 1.0), got `1.2`"
        );
        // Tenths add up with rounding errors and still count as on the step.
        let tenth = map(&[("step", Dynamic::from(0.1))]);
        let t = Declared::new("t", Dynamic::from(0.3), tenth.clone()).unwrap();
        assert!(t.resolve(Some("0.7")).is_ok());
        let t = Declared::new("t", Dynamic::from(0.3), tenth.clone()).unwrap();
        assert!(msg(t.resolve(Some("0.75"))).contains("in steps of 0.1 from 0"));
        // A default off its own step is a declaration error; vectors are checked per coordinate.
        let e = msg(Declared::new("t", Dynamic::from(0.25), tenth));
        assert_eq!(e, "param: `t`: the default 0.25 must be in steps of 0.1 from 0");
        let v = Declared::new("at", Dynamic::from(Vec3::ZERO), map(&[("step", Dynamic::from(2_i64))])).unwrap();
        assert!(msg(v.resolve(Some("2,4,5"))).contains("each in steps of 2 from 0"));
    }

    #[test]
    fn set_text_is_parsed_by_the_defaults_type() {
        let int = Declared::new("n", Dynamic::from(8_i64), Map::new()).unwrap();
        assert_eq!(int.resolve(Some("12")).unwrap().0.as_int().unwrap(), 12);
        // An integer given for a float default becomes a float, as before.
        let float = Declared::new("r", Dynamic::from(1.0), Map::new()).unwrap();
        assert_eq!(float.resolve(Some("2")).unwrap().0.as_float().unwrap(), 2.0);
        // A string parameter takes any text as is, numbers included.
        let s = Declared::new("s", Dynamic::from("oak"), Map::new()).unwrap();
        assert_eq!(s.resolve(Some("12")).unwrap().0.into_string().unwrap(), "12");
        let v = Declared::new("at", Dynamic::from(Vec3::ZERO), Map::new()).unwrap();
        let (value, spec) = v.resolve(Some("1, 2,3.5")).unwrap();
        assert_eq!(value.cast::<Vec3>(), Vec3::new(1.0, 2.0, 3.5));
        assert_eq!(spec.value, json!([1.0, 2.0, 3.5]));
        assert!(spec.set);
        let a = Declared::new("xs", Dynamic::from(vec![Dynamic::from(1_i64)]), Map::new()).unwrap();
        assert_eq!(to_json(&a.resolve(Some("[4,5]")).unwrap().0), json!([4, 5]));
    }

    #[test]
    fn a_bad_value_names_the_parameter_what_it_must_be_and_its_default() {
        let steps = Declared::new("steps", Dynamic::from(8_i64), Map::new()).unwrap();
        assert_eq!(msg(steps.resolve(Some("2.5"))), "param: `steps` must be an integer (default 8), got `2.5`");
        let opts = map(&[("min", Dynamic::from(1_i64)), ("max", Dynamic::from(12_i64))]);
        let steps = Declared::new("steps", Dynamic::from(8_i64), opts).unwrap();
        assert_eq!(
            msg(steps.resolve(Some("13"))),
            "param: `steps` must be an integer from 1 to 12 (default 8), got `13`"
        );
        let b = Declared::new("pips", Dynamic::from(true), Map::new()).unwrap();
        assert_eq!(msg(b.resolve(Some("yes"))), "param: `pips` must be true or false (default true), got `yes`");
        let choices: Array = vec!["oak".into(), "pine".into()];
        let wood = Declared::new("wood", Dynamic::from("oak"), map(&[("choices", Dynamic::from(choices))])).unwrap();
        assert_eq!(
            msg(wood.resolve(Some("elm"))),
            "param: `wood` must be one of oak, pine (default \"oak\"), got `elm`"
        );
        let v = Declared::new("at", Dynamic::from(Vec3::ZERO), map(&[("min", Dynamic::from(-1.0))])).unwrap();
        assert_eq!(
            msg(v.resolve(Some("0,0,-2"))),
            "param: `at` must be three numbers x,y,z, each at least -1 (default [0.0,0.0,0.0]), got `0,0,-2`"
        );
    }

    #[test]
    fn a_bad_declaration_is_refused_naming_the_option() {
        let e = msg(Declared::new("n", Dynamic::from(5_i64), map(&[("max", Dynamic::from(3_i64))])));
        assert_eq!(e, "param: `n`: the default 5 must be at most 3");
        let e = msg(Declared::new("n", Dynamic::from(5_i64), map(&[("mx", Dynamic::from(3_i64))])));
        assert_eq!(e, "param: `n`: unknown option `mx`; valid options are: choices, doc, max, min, step");
        let e = msg(Declared::new("s", Dynamic::from("a"), map(&[("min", Dynamic::from(3_i64))])));
        assert_eq!(e, "param: `s`: option `min` needs a numeric default, got a string");
        let lohi = map(&[("min", Dynamic::from(3_i64)), ("max", Dynamic::from(1_i64))]);
        assert_eq!(
            msg(Declared::new("n", Dynamic::from(2_i64), lohi)),
            "param: `n`: option `min` (3) must not exceed `max` (1)"
        );
        let mixed: Array = vec![Dynamic::from(1_i64), "two".into()];
        let e = msg(Declared::new("n", Dynamic::from(1_i64), map(&[("choices", Dynamic::from(mixed))])));
        assert_eq!(e, "param: `n`: option `choices` must hold values of the default's type (int), got a string");
    }
}
