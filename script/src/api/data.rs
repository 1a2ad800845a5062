//! Rhai's functions that grow a string, array or BLOB by a requested amount in one call
//! (`pad`, `blob`, `replace`), checked against the memory budget before they allocate.
//!
//! Scripts' data is held to the budget by counting the heap in use (every script step checks
//! it, see `set_limits`), which costs the same for any size of data — Rhai's own size limits
//! walk the whole of an array after every call that may change it, making `a.push(x)` in a loop
//! quadratic. A single step at most doubles its data (`a += a`) except for these functions,
//! which take the size to grow by as an argument: they are replaced here by versions that
//! estimate the growth first and refuse, naming the estimate and the budget.

use blocksmith_kernel::limits;
use rhai::plugin::*;
use rhai::{Array, Blob, ImmutableString, INT};

use crate::convert::{error, ScriptResult};

/// Bytes a value holds: 16 for its slot, plus the elements of arrays and maps and the bytes of
/// strings inside it, down to [`MAX_NESTING`](super::nesting::MAX_NESTING) levels.
#[must_use]
pub fn value_bytes(v: &Dynamic) -> f64 {
    bytes_within(v, super::nesting::MAX_NESTING)
}

fn bytes_within(v: &Dynamic, levels: usize) -> f64 {
    let inner = |x: &Dynamic| if levels == 0 { 16.0 } else { bytes_within(x, levels - 1) };
    16.0 + if let Some(a) = v.read_lock::<Array>() {
        a.iter().map(inner).sum()
    } else if let Some(m) = v.read_lock::<rhai::Map>() {
        m.iter().map(|(k, x)| 32.0 + k.len() as f64 + inner(x)).sum()
    } else if let Some(s) = v.read_lock::<ImmutableString>() {
        s.len() as f64
    } else if let Some(b) = v.read_lock::<Blob>() {
        b.len() as f64
    } else {
        0.0
    }
}

fn check(func: &str, what: impl FnOnce() -> String, bytes: f64) -> ScriptResult<()> {
    limits::check_growth(what, bytes).map_err(|e| error(func, e))
}

#[export_module]
pub mod data_api {
    use super::*;

    /// Pads the array with copies of `item` up to `len` elements (nothing when it is already as
    /// long). The padding is refused, before anything is allocated, when it would put the
    /// memory in use over the budget (`--memory-limit`).
    ///
    /// ```rhai
    /// let a = [1, 2];
    /// a.pad(4, 0);
    /// assert_eq(a, [1, 2, 0, 0]);
    /// ```
    #[rhai_fn(name = "pad", return_raw)]
    pub fn pad_array(array: &mut Array, len: INT, item: Dynamic) -> ScriptResult<()> {
        let len = usize::try_from(len).unwrap_or(0);
        if len <= array.len() {
            return Ok(());
        }
        let extra = (len - array.len()) as f64;
        check("pad", || format!("padding an array to {len} elements"), extra * value_bytes(&item))?;
        array.resize(len, item);
        Ok(())
    }

    /// Pads the BLOB with bytes `value` (its lower 8 bits) up to `len` bytes, refused before
    /// allocating when over the memory budget.
    ///
    /// ```rhai
    /// let b = blob(2, 1);
    /// b.pad(4, 7);
    /// assert_eq(b.len(), 4);
    /// ```
    #[rhai_fn(name = "pad", return_raw)]
    pub fn pad_blob(blob: &mut Blob, len: INT, value: INT) -> ScriptResult<()> {
        let len = usize::try_from(len).unwrap_or(0);
        if len <= blob.len() {
            return Ok(());
        }
        check("pad", || format!("padding a BLOB to {len} bytes"), (len - blob.len()) as f64)?;
        blob.resize(len, (value & 0xff) as u8);
        Ok(())
    }

    /// A new BLOB of `len` zero bytes (empty when `len` ≤ 0), refused before allocating when
    /// over the memory budget.
    ///
    /// ```rhai
    /// assert_eq(blob(3).len(), 3);
    /// ```
    #[rhai_fn(name = "blob", return_raw)]
    pub fn blob_zeroed(len: INT) -> ScriptResult<Blob> {
        blob_filled(len, 0)
    }

    /// A new BLOB of `len` bytes `value` (its lower 8 bits), refused before allocating when over
    /// the memory budget.
    ///
    /// ```rhai
    /// assert_eq(blob(2, 0x142).to_array(), [0x42, 0x42]);
    /// ```
    #[rhai_fn(name = "blob", return_raw)]
    pub fn blob_filled(len: INT, value: INT) -> ScriptResult<Blob> {
        let len = usize::try_from(len).unwrap_or(0);
        check("blob", || format!("a BLOB of {len} bytes"), len as f64)?;
        Ok(vec![(value & 0xff) as u8; len])
    }

    /// Pads the string with `character` up to `len` characters, refused before allocating when
    /// over the memory budget.
    ///
    /// ```rhai
    /// let s = "ab";
    /// s.pad(4, '!');
    /// assert_eq(s, "ab!!");
    /// ```
    #[rhai_fn(name = "pad", return_raw)]
    pub fn pad_char(string: &mut ImmutableString, len: INT, character: char) -> ScriptResult<()> {
        let len = usize::try_from(len).unwrap_or(0);
        let have = string.chars().count();
        if len <= have {
            return Ok(());
        }
        let extra = (len - have) as f64 * character.len_utf8() as f64;
        check("pad", || format!("padding a string to {len} characters"), extra)?;
        let s = string.make_mut();
        s.extend(std::iter::repeat_n(character, len - have));
        Ok(())
    }

    /// Pads the string with repeats of `padding` (the last one cut short) up to `len`
    /// characters; an empty `padding` pads nothing. Refused before allocating when over the
    /// memory budget.
    ///
    /// ```rhai
    /// let s = "ab";
    /// s.pad(7, "xy");
    /// assert_eq(s, "abxyxyx");
    /// ```
    #[rhai_fn(name = "pad", return_raw)]
    pub fn pad_string(string: &mut ImmutableString, len: INT, padding: &str) -> ScriptResult<()> {
        let len = usize::try_from(len).unwrap_or(0);
        let have = string.chars().count();
        if len <= have || padding.is_empty() {
            return Ok(());
        }
        let extra = (len - have) as f64 * 4.0;
        check("pad", || format!("padding a string to {len} characters"), extra)?;
        let s = string.make_mut();
        s.extend(padding.chars().cycle().take(len - have));
        Ok(())
    }

    /// Replaces every `find` in the string by `substitute`, refused before allocating when the
    /// result would put the memory in use over the budget.
    ///
    /// ```rhai
    /// let s = "a-b-c";
    /// s.replace("-", "--");
    /// assert_eq(s, "a--b--c");
    /// ```
    #[rhai_fn(name = "replace", return_raw)]
    pub fn replace_string(string: &mut ImmutableString, find: &str, substitute: &str) -> ScriptResult<()> {
        let hits = if find.is_empty() { string.chars().count() + 1 } else { string.matches(find).count() };
        let bytes = string.len() as f64 + hits as f64 * substitute.len() as f64;
        check("replace", || format!("the replaced string ({hits} replacements)"), bytes)?;
        *string = string.replace(find, substitute).into();
        Ok(())
    }

    /// Replaces every `find` character in the string by `substitute`, refused before allocating
    /// when the result would put the memory in use over the budget.
    ///
    /// ```rhai
    /// let s = "a-b";
    /// s.replace('-', "+=");
    /// assert_eq(s, "a+=b");
    /// ```
    #[rhai_fn(name = "replace", return_raw)]
    pub fn replace_char_with_string(string: &mut ImmutableString, find: char, substitute: &str) -> ScriptResult<()> {
        let hits = string.matches(find).count();
        let bytes = string.len() as f64 + hits as f64 * substitute.len() as f64;
        check("replace", || format!("the replaced string ({hits} replacements)"), bytes)?;
        *string = string.replace(find, substitute).into();
        Ok(())
    }
}
