//! Script values ↔ kernel types, and the error helpers of the binding edge.
//!
//! Every binding turns kernel errors into script errors here: the message names the function,
//! the offending argument and why; Rhai adds the script position.

use std::fmt::Display;

use blocksmith_kernel::Vec3;
use rhai::{Array, Dynamic, EvalAltResult, FnPtr, Map, INT};

/// The result type of every fallible binding.
pub type ScriptResult<T> = Result<T, Box<EvalAltResult>>;

/// An argument that takes an integer or a float (`number` in signatures); read it with [`number`].
pub type Number = Dynamic;
/// An argument that must be an integer but is checked by the binding, which names it in its
/// error (`int` in signatures).
pub type Integer = Dynamic;
/// An argument that takes a `Vec3` or an array of three numbers (`Vec3` in signatures); read it
/// with [`vec3`].
pub type Vector = Dynamic;
/// An argument that takes a number or a vector (`number|Vec3` in signatures), e.g. a scale
/// factor; read it with [`factor3`].
pub type NumberOrVector = Dynamic;
/// A CSG operand: a `Mesh` or a `BlockModel` (`Mesh|BlockModel` in signatures).
pub type Solid = Dynamic;
/// A colour argument: `[r, g, b]`, `[r, g, b, a]` (0–1) or a hex string `"#rrggbb"`
/// (`[r, g, b, a]|string` in signatures); read it with `api::color::color_value`.
pub type Color = Dynamic;
/// A colour `[r, g, b, a]`, or `()` for none (`[r, g, b, a]|()` in signatures).
pub type ColorOrUnit = Dynamic;

/// A script error `"{func}: {message}"`.
pub fn fail<T>(func: &str, message: impl Display) -> ScriptResult<T> {
    Err(error(func, message))
}

/// The error value behind [`fail`].
#[must_use]
pub fn error(func: &str, message: impl Display) -> Box<EvalAltResult> {
    // Kernel messages quote files' bytes (names, comments): escaped here, at the edge, so a
    // caught error holds no terminal control sequence either.
    crate::printable::printable(&format!("{func}: {message}")).into_owned().into()
}

/// Maps a kernel error into a script error naming the function.
pub fn kernel<T, E: Display>(func: &str, r: Result<T, E>) -> ScriptResult<T> {
    r.map_err(|e| error(func, e))
}

/// What a closure called back from Rust (`key`, e.g. "the closure `radius`") failed with, for
/// a kernel error's message: a stop (the operation or time limit, an interrupt) as its reason
/// alone, a thrown value as itself with its place, other errors as Rhai words them.
#[must_use]
pub fn closure_error(key: &str, e: &EvalAltResult) -> String {
    match e {
        EvalAltResult::ErrorTerminated(reason, _) => reason.to_string(),
        EvalAltResult::ErrorInFunctionCall(_, _, inner, _) => closure_error(key, inner),
        EvalAltResult::ErrorRuntime(value, pos) if pos.is_none() => format!("{key} raised: {value}"),
        EvalAltResult::ErrorRuntime(value, pos) => format!("{key} raised: {value} ({pos})"),
        other => format!("{key} raised: {other}"),
    }
}

/// A short name for a script value's type, for messages.
#[must_use]
pub fn type_name(v: &Dynamic) -> String {
    if v.is_array() {
        let n = v.clone().into_array().map(|a| a.len()).unwrap_or(0);
        return format!("an array of {n}");
    }
    let t = v.type_name();
    match t {
        "i64" => "an integer".into(),
        "f64" => "a float".into(),
        "string" | "ImmutableString" => "a string".into(),
        "bool" => "a bool".into(),
        "()" => "nothing (unit)".into(),
        "map" => "an object map".into(),
        other => {
            let short = other.rsplit("::").next().unwrap_or(other);
            format!("a {short}")
        }
    }
}

/// A number from an integer or a float, finite.
pub fn number(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<f64> {
    let (kind, name) = kind_and_name(arg);
    number_named(func, kind, &name, v)
}

/// What `arg` names for messages: an argument by default, or an option when it is written as
/// one (`option `at``, `option `at`[0]`), quoted once: `option `at[0]``.
fn kind_and_name(arg: &str) -> (&'static str, String) {
    match arg.strip_prefix("option ") {
        Some(rest) => ("option", rest.replace('`', "")),
        None => ("argument", arg.to_string()),
    }
}

/// A finite number given as the `kind` (`"argument"` or `"option"`) called `name`.
fn number_named(func: &str, kind: &str, name: &str, v: &Dynamic) -> ScriptResult<f64> {
    let x = if let Some(f) = v.clone().try_cast::<f64>() {
        f
    } else if let Some(i) = v.clone().try_cast::<INT>() {
        i as f64
    } else {
        return fail(func, format!("{kind} `{name}` must be a number, got {}", type_name(v)));
    };
    if !x.is_finite() {
        return fail(func, format!("{kind} `{name}` must be a finite number, got {x}"));
    }
    Ok(x)
}

/// A non-negative integer that fits in `u32`.
pub fn count(func: &str, arg: &str, v: INT, max: INT) -> ScriptResult<u32> {
    if v < 0 || v > max {
        return fail(func, format!("argument `{arg}` must be between 0 and {max}, got {v}"));
    }
    Ok(v as u32)
}

/// A `Vec3` from a `Vec3` or an array of three numbers, finite.
pub fn vec3(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec3> {
    let (kind, name) = kind_and_name(arg);
    vec3_named(func, kind, &name, v)
}

/// A finite vector given as the `kind` (`"argument"` or `"option"`) called `name`.
fn vec3_named(func: &str, kind: &str, name: &str, v: &Dynamic) -> ScriptResult<Vec3> {
    let p = if let Some(p) = v.clone().try_cast::<Vec3>() {
        p
    } else if v.is_array() {
        let a = v.clone().into_array().unwrap_or_default();
        if a.len() != 3 {
            return fail(
                func,
                format!("{kind} `{name}` must be a Vec3 or an array of 3 numbers, got an array of {}", a.len()),
            );
        }
        let mut c = [0.0; 3];
        for (i, x) in a.iter().enumerate() {
            c[i] = number_named(func, kind, &format!("{name}[{i}]"), x)?;
        }
        Vec3::from_array(c)
    } else {
        return fail(func, format!("{kind} `{name}` must be a Vec3 or an array of 3 numbers, got {}", type_name(v)));
    };
    if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
        return fail(func, format!("{kind} `{name}` must have finite coordinates, got ({}, {}, {})", p.x, p.y, p.z));
    }
    Ok(p)
}

/// A `Vec3` scale factor from a number (uniform) or a vector.
pub fn factor3(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec3> {
    if v.is_float() || v.is_int() {
        Ok(Vec3::splat(number(func, arg, v)?))
    } else {
        vec3(func, arg, v)
    }
}

/// An array of element ids (non-negative integers).
pub fn ids(func: &str, arg: &str, v: &Array) -> ScriptResult<Vec<u32>> {
    v.iter()
        .enumerate()
        .map(|(i, x)| match x.as_int() {
            Ok(n) if (0..INT::from(u32::MAX)).contains(&n) => Ok(n as u32),
            Ok(n) => fail(func, format!("argument `{arg}[{i}]` must be a non-negative id, got {n}")),
            Err(_) => fail(func, format!("argument `{arg}[{i}]` must be an integer id, got {}", type_name(x))),
        })
        .collect()
}

/// An array of `[a, b]` vertex-id pairs.
pub fn id_pairs(func: &str, arg: &str, v: &Array) -> ScriptResult<Vec<[u32; 2]>> {
    v.iter()
        .enumerate()
        .map(|(i, x)| {
            let Some(pair) = x.clone().try_cast::<Array>() else {
                return fail(func, format!("argument `{arg}[{i}]` must be an array [a, b], got {}", type_name(x)));
            };
            let p = ids(func, &format!("{arg}[{i}]"), &pair)?;
            match p[..] {
                [a, b] => Ok([a, b]),
                _ => fail(func, format!("argument `{arg}[{i}]` must hold two vertex ids, got {}", p.len())),
            }
        })
        .collect()
}

/// The checked option map of one call: unknown keys are refused up front, naming the key and
/// listing the valid ones; each getter converts and checks one key.
pub struct Options {
    func: &'static str,
    map: Map,
}

impl Options {
    /// Checks `map` against `valid` keys.
    ///
    /// # Errors
    /// A script error naming the first unknown key (in sorted order) and the valid keys.
    pub fn new(func: &'static str, map: Map, valid: &[&str]) -> ScriptResult<Options> {
        if let Some(bad) = map.keys().find(|k| !valid.contains(&k.as_str())) {
            let mut list: Vec<&str> = valid.to_vec();
            list.sort_unstable();
            return fail(func, format!("unknown option `{bad}`; valid options are: {}", list.join(", ")));
        }
        Ok(Options { func, map })
    }

    /// No options: an empty map.
    #[must_use]
    pub fn none(func: &'static str) -> Options {
        Options { func, map: Map::new() }
    }

    /// Whether `key` was given.
    #[must_use]
    pub fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    /// The raw value of `key`.
    #[must_use]
    pub fn raw(&self, key: &str) -> Option<&Dynamic> {
        self.map.get(key)
    }

    /// A number, or `default`.
    pub fn number(&self, key: &str, default: f64) -> ScriptResult<f64> {
        self.map.get(key).map_or(Ok(default), |v| number_named(self.func, "option", key, v))
    }

    /// An integer, or `default`.
    pub fn int(&self, key: &str, default: INT) -> ScriptResult<INT> {
        match self.map.get(key) {
            None => Ok(default),
            Some(v) => v
                .as_int()
                .or_else(|_| fail(self.func, format!("option `{key}` must be an integer, got {}", type_name(v)))),
        }
    }

    /// A bool, or `default`.
    pub fn bool(&self, key: &str, default: bool) -> ScriptResult<bool> {
        match self.map.get(key) {
            None => Ok(default),
            Some(v) => v
                .as_bool()
                .or_else(|_| fail(self.func, format!("option `{key}` must be true or false, got {}", type_name(v)))),
        }
    }

    /// A string, or `default`.
    pub fn string(&self, key: &str, default: &str) -> ScriptResult<String> {
        match self.map.get(key) {
            None => Ok(default.to_string()),
            Some(v) => v
                .clone()
                .into_string()
                .or_else(|_| fail(self.func, format!("option `{key}` must be a string, got {}", type_name(v)))),
        }
    }

    /// One of `choices`, or `default`.
    pub fn choice(&self, key: &str, default: &str, choices: &[&str]) -> ScriptResult<String> {
        let s = self.string(key, default)?;
        if choices.contains(&s.as_str()) {
            Ok(s)
        } else {
            fail(self.func, format!("option `{key}` must be one of {}, got \"{s}\"", choices.map_quoted()))
        }
    }

    /// A vector, or `default`.
    pub fn vec3(&self, key: &str, default: Vec3) -> ScriptResult<Vec3> {
        self.map.get(key).map_or(Ok(default), |v| vec3_named(self.func, "option", key, v))
    }

    /// A closure, if given.
    pub fn fn_ptr(&self, key: &str) -> ScriptResult<Option<FnPtr>> {
        match self.map.get(key) {
            None => Ok(None),
            Some(v) => v
                .clone()
                .try_cast::<FnPtr>()
                .map(Some)
                .ok_or_else(|| error(self.func, format!("option `{key}` must be a closure, got {}", type_name(v)))),
        }
    }
}

trait MapQuoted {
    fn map_quoted(&self) -> String;
}

impl MapQuoted for [&str] {
    fn map_quoted(&self) -> String {
        self.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_option_names_key_and_lists_valid_ones() {
        let mut m = Map::new();
        m.insert("tolerence".into(), Dynamic::from(0.1));
        let e = Options::new("mesh", m, &["tolerance", "max_depth"]).err().unwrap();
        let s = e.to_string();
        assert!(s.contains("mesh: unknown option `tolerence`; valid options are: max_depth, tolerance"), "{s}");
    }

    #[test]
    fn arrays_and_ints_become_vectors() {
        let a: Array = vec![Dynamic::from(1_i64), Dynamic::from(2.5), Dynamic::from(3_i64)];
        assert_eq!(vec3("f", "p", &Dynamic::from(a)).unwrap(), Vec3::new(1.0, 2.5, 3.0));
        let short: Array = vec![Dynamic::from(1_i64)];
        let e = vec3("f", "p", &Dynamic::from(short)).unwrap_err().to_string();
        assert!(e.contains("f: argument `p` must be a Vec3 or an array of 3 numbers, got an array of 1"), "{e}");
        let e = number("f", "x", &Dynamic::from(f64::NAN)).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
    }

    #[test]
    fn bad_option_values_name_the_option_once() {
        let mut m = Map::new();
        m.insert("tolerance".into(), Dynamic::from("fine"));
        m.insert("at".into(), Dynamic::from(vec![Dynamic::from(1_i64), Dynamic::from(f64::NAN), Dynamic::from(0_i64)]));
        let o = Options::new("mesh", m, &["tolerance", "at"]).unwrap();
        let e = o.number("tolerance", 0.1).unwrap_err().to_string();
        assert!(e.contains("mesh: option `tolerance` must be a number, got a string"), "{e}");
        let e = o.vec3("at", Vec3::ZERO).unwrap_err().to_string();
        assert!(e.contains("mesh: option `at[1]` must be a finite number"), "{e}");
        // Callers naming an option as the argument get it quoted once.
        let at = Dynamic::from(vec![Dynamic::from(1_i64), Dynamic::from("x"), Dynamic::from(0_i64)]);
        let e = vec3("sculpt", "option `at`", &at).unwrap_err().to_string();
        assert!(e.contains("sculpt: option `at[1]` must be a number, got a string"), "{e}");
        let e = number("fit", "option `axis`[2]", &Dynamic::from(f64::INFINITY)).unwrap_err().to_string();
        assert!(e.contains("fit: option `axis[2]` must be a finite number"), "{e}");
    }
}
