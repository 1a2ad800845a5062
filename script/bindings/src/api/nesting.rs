//! Comparing and printing nested arrays and maps, with their nesting limited.
//!
//! Rhai compares (`==`, `!=`) and converts (`to_string`, `to_debug`) arrays and maps by calling
//! itself once per level, a few kilobytes of stack each: data nested a few thousand deep (made
//! by a loop, `a = [a]`) overflowed the stack and aborted the process. These versions measure
//! the nesting first — without recursing past [`MAX_NESTING`] — and refuse deeper data with a
//! catchable error naming the limit; so do `print`, `debug` and a map's `to_json`. (Rhai's
//! string interpolation, `${x}`, cannot be refused: it falls back to Rhai's own text of a value
//! whose `to_string` fails, which recurses on the command's large stack.)

use std::cell::Cell;
use std::fmt::Write;

use rhai::plugin::*;
use rhai::{Array, Map};

use crate::convert::{fail, ScriptResult};

/// The deepest nesting of arrays and maps that can be compared or printed.
pub const MAX_NESTING: usize = 500;

thread_local! {
    /// Set while an outer comparison or print, whose nesting was measured, handles the inner
    /// levels: they need not measure again.
    static MEASURED: Cell<bool> = const { Cell::new(false) };
}

/// Whether `v` nests arrays and maps more than `limit` deep (recursing at most `limit` levels).
fn deeper_than(v: &Dynamic, limit: usize) -> bool {
    if let Some(a) = v.read_lock::<Array>() {
        array_deeper(&a, limit)
    } else if let Some(m) = v.read_lock::<Map>() {
        map_deeper(&m, limit)
    } else {
        false
    }
}

fn array_deeper(a: &Array, limit: usize) -> bool {
    limit == 0 || a.iter().any(|x| deeper_than(x, limit - 1))
}

fn map_deeper(m: &Map, limit: usize) -> bool {
    limit == 0 || m.values().any(|x| deeper_than(x, limit - 1))
}

/// Clears [`MEASURED`] when the outermost call ends.
struct Measured;

impl Drop for Measured {
    fn drop(&mut self) {
        MEASURED.set(false);
    }
}

/// Checks, unless an outer call already did, that the values nest at most [`MAX_NESTING`]
/// deep (`too_deep` says whether they do not); the inner levels skip the check while the
/// returned guard lives.
fn measure(func: &str, too_deep: impl FnOnce() -> bool) -> ScriptResult<Option<Measured>> {
    if MEASURED.get() {
        return Ok(None);
    }
    if too_deep() {
        return fail(
            func,
            format!("the value nests arrays and maps more than {MAX_NESTING} deep, too deep to compare or print"),
        );
    }
    MEASURED.set(true);
    Ok(Some(Measured))
}

/// The element or value comparison of Rhai's `==` of arrays and maps: `==` of the pair, false
/// for values of different types without a `==`.
fn elements_equal(ctx: &NativeCallContext, a: &mut Dynamic, b: &mut Dynamic) -> ScriptResult<bool> {
    let same_type = a.type_id() == b.type_id();
    let r = ctx.call_native_fn_raw("==", true, &mut [&mut *a, &mut *b]).or_else(|err| match *err {
        EvalAltResult::ErrorFunctionNotFound(ref sig, ..) if sig.starts_with("==") && !same_type => Ok(Dynamic::FALSE),
        _ => Err(err),
    })?;
    Ok(r.as_bool().unwrap_or(false))
}

fn arrays_equal(ctx: &NativeCallContext, a: &mut Array, mut b: Array) -> ScriptResult<bool> {
    if a.len() != b.len() {
        return Ok(false);
    }
    for (x, y) in a.iter_mut().zip(b.iter_mut()) {
        if !elements_equal(ctx, x, y)? {
            return Ok(false);
        }
    }
    Ok(true)
}

fn maps_equal(ctx: &NativeCallContext, a: &mut Map, mut b: Map) -> ScriptResult<bool> {
    if a.len() != b.len() {
        return Ok(false);
    }
    for (k, x) in a.iter_mut() {
        let Some(y) = b.get_mut(k) else { return Ok(false) };
        if !elements_equal(ctx, x, y)? {
            return Ok(false);
        }
    }
    Ok(true)
}

/// One element as Rhai prints it inside an array or map: its `to_debug`.
fn element_text(ctx: &NativeCallContext, v: &mut Dynamic) -> String {
    match ctx.call_native_fn_raw("to_debug", true, &mut [&mut *v]) {
        Ok(r) if r.is_string() => r.into_immutable_string().map(|s| s.to_string()).unwrap_or_default(),
        Ok(r) => ctx.engine().map_type_name(r.type_name()).to_string(),
        Err(_) => ctx.engine().map_type_name(&format!("{v:?}")).to_string(),
    }
}

/// `array_text` of `a` after refusing nesting over [`MAX_NESTING`] (`func` names the caller).
fn checked_array_text(func: &str, ctx: &NativeCallContext, a: &mut Array) -> ScriptResult<String> {
    let _measured = measure(func, || array_deeper(a, MAX_NESTING))?;
    Ok(array_text(ctx, a))
}

/// `map_text` of `m` after refusing nesting over [`MAX_NESTING`] (`func` names the caller).
fn checked_map_text(func: &str, ctx: &NativeCallContext, m: &mut Map) -> ScriptResult<String> {
    let _measured = measure(func, || map_deeper(m, MAX_NESTING))?;
    Ok(map_text(ctx, m))
}

fn array_text(ctx: &NativeCallContext, a: &mut Array) -> String {
    let items: Vec<String> = a.iter_mut().map(|x| element_text(ctx, x)).collect();
    format!("[{}]", items.join(", "))
}

fn map_text(ctx: &NativeCallContext, m: &mut Map) -> String {
    let mut out = String::from("#{");
    let n = m.len();
    for (i, (k, v)) in m.iter_mut().enumerate() {
        let _ = write!(out, "{k:?}: {}{}", element_text(ctx, v), if i + 1 < n { ", " } else { "" });
    }
    out.push('}');
    out
}

#[export_module]
pub mod nesting_api {
    use super::*;

    /// Whether two arrays have equal elements in the same order (elements compared with their
    /// `==`; values of different types are unequal). Arrays nested more than 500 deep are
    /// refused.
    ///
    /// ```rhai
    /// assert([1, [2, 3]] == [1, [2, 3]]);
    /// ```
    #[rhai_fn(name = "==", return_raw, pure)]
    pub fn array_eq(ctx: NativeCallContext, a: &mut Array, b: Array) -> ScriptResult<bool> {
        let _measured = measure("==", || array_deeper(a, MAX_NESTING) || array_deeper(&b, MAX_NESTING))?;
        arrays_equal(&ctx, a, b)
    }

    /// Whether two arrays differ (the opposite of `==`).
    ///
    /// ```rhai
    /// assert([1, 2] != [2, 1]);
    /// ```
    #[rhai_fn(name = "!=", return_raw, pure)]
    pub fn array_ne(ctx: NativeCallContext, a: &mut Array, b: Array) -> ScriptResult<bool> {
        array_eq(ctx, a, b).map(|e| !e)
    }

    /// Whether two maps have the same keys with equal values (compared with their `==`). Maps
    /// nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// assert(#{ a: [1], b: 2 } == #{ b: 2, a: [1] });
    /// ```
    #[rhai_fn(name = "==", return_raw, pure)]
    pub fn map_eq(ctx: NativeCallContext, a: &mut Map, b: Map) -> ScriptResult<bool> {
        let _measured = measure("==", || map_deeper(a, MAX_NESTING) || map_deeper(&b, MAX_NESTING))?;
        maps_equal(&ctx, a, b)
    }

    /// Whether two maps differ (the opposite of `==`).
    ///
    /// ```rhai
    /// assert(#{ a: 1 } != #{ a: 2 });
    /// ```
    #[rhai_fn(name = "!=", return_raw, pure)]
    pub fn map_ne(ctx: NativeCallContext, a: &mut Map, b: Map) -> ScriptResult<bool> {
        map_eq(ctx, a, b).map(|e| !e)
    }

    /// The array as text, `[1, "a", [2]]` (elements as `debug` shows them), also as `to_debug`.
    /// Arrays nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// assert_eq([1, "a", [2.5]].to_string(), "[1, \"a\", [2.5]]");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", return_raw, pure)]
    pub fn array_to_string(ctx: NativeCallContext, a: &mut Array) -> ScriptResult<String> {
        checked_array_text("to_string", &ctx, a)
    }

    /// Prints the array as `to_string` writes it. Arrays nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// print([1, [2]]);
    /// ```
    #[rhai_fn(name = "print", return_raw, pure)]
    pub fn array_print(ctx: NativeCallContext, a: &mut Array) -> ScriptResult<String> {
        checked_array_text("print", &ctx, a)
    }

    /// Prints the array as `to_debug` writes it. Arrays nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// debug([1, [2]]);
    /// ```
    #[rhai_fn(name = "debug", return_raw, pure)]
    pub fn array_debug(ctx: NativeCallContext, a: &mut Array) -> ScriptResult<String> {
        checked_array_text("debug", &ctx, a)
    }

    /// Prints the map as `to_string` writes it. Maps nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// print(#{ a: [1] });
    /// ```
    #[rhai_fn(name = "print", return_raw, pure)]
    pub fn map_print(ctx: NativeCallContext, m: &mut Map) -> ScriptResult<String> {
        checked_map_text("print", &ctx, m)
    }

    /// Prints the map as `to_debug` writes it. Maps nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// debug(#{ a: [1] });
    /// ```
    #[rhai_fn(name = "debug", return_raw, pure)]
    pub fn map_debug(ctx: NativeCallContext, m: &mut Map) -> ScriptResult<String> {
        checked_map_text("debug", &ctx, m)
    }

    /// The map as JSON text, `{"a":[1]}` (values JSON cannot hold are written as Rhai shows
    /// them). Maps nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// assert_eq(#{ a: [1, 2.5] }.to_json(), "{\"a\":[1,2.5]}");
    /// ```
    #[rhai_fn(name = "to_json", return_raw, pure)]
    pub fn map_to_json(m: &mut Map) -> ScriptResult<String> {
        let _measured = measure("to_json", || map_deeper(m, MAX_NESTING))?;
        Ok(rhai::format_map_as_json(m))
    }

    /// The map as text, `#{"a": 1}` (values as `debug` shows them), also as `to_debug`. Maps
    /// nested more than 500 deep are refused.
    ///
    /// ```rhai
    /// assert_eq(#{ a: [1] }.to_string(), "#{\"a\": [1]}");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", return_raw, pure)]
    pub fn map_to_string(ctx: NativeCallContext, m: &mut Map) -> ScriptResult<String> {
        checked_map_text("to_string", &ctx, m)
    }
}
