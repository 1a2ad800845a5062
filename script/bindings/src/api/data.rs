//! Rhai's functions that grow a string, array or BLOB — by a requested amount (`pad`, `blob`,
//! `replace`) or by joining (`+`, `+=`, `append`, `push`) — checked against the memory budget
//! before they allocate.
//!
//! Scripts' data is held to the budget by counting the heap in use (every script step checks
//! it, see `set_limits`), which costs the same for any size of data — Rhai's own size limits
//! walk the whole of an array after every call that may change it, making `a.push(x)` in a loop
//! quadratic. A step checked only afterwards could still pass the budget several times over in
//! one allocation (`a += a` doubles an array, and a `Vec` growing past its capacity allocates
//! twice as much while the old buffer is still held), so these functions are replaced here by
//! versions that estimate the new allocation first (in O(1), from lengths and capacities; `+`
//! of arrays and `pad` also count the copies of the elements they make) and refuse, naming the
//! estimate and the budget. Rhai's fast operators are turned off (`new_engine`) so that `+` and
//! `+=` of strings, arrays and BLOBs reach these versions instead of Rhai's built-in ones.

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

/// The bytes of a value's slot in an array.
const SLOT: f64 = std::mem::size_of::<Dynamic>() as f64;

/// The new buffer, in elements, of a `Vec` of capacity `cap` grown to hold `len` (Rust's
/// growth: at least double); 0 when it need not grow.
fn grown(cap: usize, len: usize) -> f64 {
    if len <= cap {
        0.0
    } else {
        len.max(cap.saturating_mul(2)) as f64
    }
}

/// Refuses to grow `array` to `len` elements when the new buffer would put the heap over the
/// budget (the old buffer is still held while the elements move).
fn check_array_growth(func: &str, array: &Array, len: usize) -> ScriptResult<()> {
    let buffer = grown(array.capacity(), len) * SLOT;
    if buffer == 0.0 {
        return Ok(());
    }
    check(func, || format!("an array of {len} elements"), buffer)
}

/// Refuses a string or BLOB of `len` bytes made from one of `have` bytes (a new buffer, the
/// old one still held).
fn check_bytes_growth(func: &str, what: &str, have: usize, len: usize) -> ScriptResult<()> {
    if len <= have {
        return Ok(());
    }
    check(func, || format!("a {what} of {len} bytes"), len as f64)
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
        // The copies' contents (beyond their slots) and the grown buffer.
        let extra = (len - array.len()) as f64 * (value_bytes(&item) - SLOT);
        let buffer = grown(array.capacity(), len) * SLOT;
        check("pad", || format!("padding an array to {len} elements"), extra + buffer)?;
        array.resize(len, item);
        Ok(())
    }

    /// Adds `item` at the end of the array. Refused, before allocating, when the array's grown
    /// buffer would put the memory in use over the budget (`--memory-limit`).
    ///
    /// ```rhai
    /// let a = [1];
    /// a.push(2);
    /// assert_eq(a, [1, 2]);
    /// ```
    #[rhai_fn(name = "push", return_raw)]
    pub fn push(array: &mut Array, item: Dynamic) -> ScriptResult<()> {
        push_checked("push", array, item)
    }

    /// `a += x`: adds `x` at the end of the array, as `push` does (refused in the same way).
    ///
    /// ```rhai
    /// let a = [1];
    /// a += 2;
    /// assert_eq(a, [1, 2]);
    /// ```
    #[rhai_fn(name = "+=", return_raw)]
    pub fn push_op(array: &mut Array, item: Dynamic) -> ScriptResult<()> {
        push_checked("+=", array, item)
    }

    /// Adds the elements of `other` at the end of the array. Refused, before allocating, when
    /// the array's grown buffer would put the memory in use over the budget.
    ///
    /// ```rhai
    /// let a = [1];
    /// a.append([2, 3]);
    /// assert_eq(a, [1, 2, 3]);
    /// ```
    #[rhai_fn(name = "append", return_raw)]
    pub fn append(array: &mut Array, other: Array) -> ScriptResult<()> {
        append_checked("append", array, other)
    }

    /// `a += b`: adds the elements of `b` at the end of `a`, as `append` does (refused in the
    /// same way: `a += a` doubles the array).
    ///
    /// ```rhai
    /// let a = [1, 2];
    /// a += a;
    /// assert_eq(a, [1, 2, 1, 2]);
    /// ```
    #[rhai_fn(name = "+=", return_raw)]
    pub fn append_op(array: &mut Array, other: Array) -> ScriptResult<()> {
        append_checked("+=", array, other)
    }

    /// `a + b`: a new array of the elements of `a` then those of `b`. Refused, before
    /// allocating, when the new array would put the memory in use over the budget.
    ///
    /// ```rhai
    /// assert_eq([1] + [2, 3], [1, 2, 3]);
    /// ```
    #[rhai_fn(name = "+", return_raw)]
    pub fn concat(a: Array, b: Array) -> ScriptResult<Array> {
        let mut a = a;
        append_checked("+", &mut a, b)?;
        Ok(a)
    }

    /// `s += t`: adds `t` at the end of the string. Refused, before allocating, when the longer
    /// string would put the memory in use over the budget (`s += s` doubles it).
    ///
    /// ```rhai
    /// let s = "ab";
    /// s += s;
    /// assert_eq(s, "abab");
    /// ```
    #[rhai_fn(name = "+=", return_raw)]
    pub fn append_string(string: &mut ImmutableString, other: ImmutableString) -> ScriptResult<()> {
        check_bytes_growth("+=", "string", string.len(), string.len() + other.len())?;
        *string += other;
        Ok(())
    }

    /// `s + t`: the two strings joined. Refused, before allocating, when the joined string
    /// would put the memory in use over the budget.
    ///
    /// ```rhai
    /// assert_eq("ab" + "cd", "abcd");
    /// ```
    #[rhai_fn(name = "+", return_raw)]
    pub fn concat_string(a: ImmutableString, b: ImmutableString) -> ScriptResult<ImmutableString> {
        check_bytes_growth("+", "string", 0, a.len() + b.len())?;
        Ok(a + b)
    }

    /// Adds the bytes of `other` at the end of the BLOB, refused before allocating when over
    /// the memory budget.
    ///
    /// ```rhai
    /// let b = blob(1, 1);
    /// b.append(blob(2, 2));
    /// assert_eq(b.len(), 3);
    /// ```
    #[rhai_fn(name = "append", return_raw)]
    pub fn append_blob(blob: &mut Blob, other: Blob) -> ScriptResult<()> {
        append_blob_checked("append", blob, other)
    }

    /// `b += c`: adds the bytes of `c` at the end of the BLOB, as `append` does.
    ///
    /// ```rhai
    /// let b = blob(1, 1);
    /// b += b;
    /// assert_eq(b.len(), 2);
    /// ```
    #[rhai_fn(name = "+=", return_raw)]
    pub fn append_blob_op(blob: &mut Blob, other: Blob) -> ScriptResult<()> {
        append_blob_checked("+=", blob, other)
    }

    /// `b + c`: a new BLOB of the bytes of `b` then those of `c`, refused before allocating
    /// when over the memory budget.
    ///
    /// ```rhai
    /// assert_eq((blob(1, 1) + blob(2, 2)).len(), 3);
    /// ```
    #[rhai_fn(name = "+", return_raw)]
    pub fn concat_blob(a: Blob, b: Blob) -> ScriptResult<Blob> {
        let mut a = a;
        append_blob_checked("+", &mut a, b)?;
        Ok(a)
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
        check("pad", || format!("padding a BLOB to {len} bytes"), grown(blob.capacity(), len))?;
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
        let bytes = string.len() as f64 + (len - have) as f64 * character.len_utf8() as f64;
        check("pad", || format!("padding a string to {len} characters"), bytes)?;
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
        let bytes = string.len() as f64 + (len - have) as f64 * 4.0;
        check("pad", || format!("padding a string to {len} characters"), bytes)?;
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

/// Pushes `item` onto `array` after checking the grown buffer (`func` names the caller).
fn push_checked(func: &str, array: &mut Array, item: Dynamic) -> ScriptResult<()> {
    check_array_growth(func, array, array.len() + 1)?;
    array.push(item);
    Ok(())
}

/// Appends `other` to `blob` after checking the grown buffer (`func` names the caller).
fn append_blob_checked(func: &str, blob: &mut Blob, other: Blob) -> ScriptResult<()> {
    check_bytes_growth(func, "BLOB", blob.capacity(), blob.len() + other.len())?;
    blob.extend(other);
    Ok(())
}

/// Appends `other` to `array` after checking the grown buffer (`func` names the caller).
fn append_checked(func: &str, array: &mut Array, other: Array) -> ScriptResult<()> {
    if other.is_empty() {
        return Ok(());
    }
    if array.is_empty() {
        *array = other;
        return Ok(());
    }
    check_array_growth(func, array, array.len() + other.len())?;
    array.extend(other);
    Ok(())
}
