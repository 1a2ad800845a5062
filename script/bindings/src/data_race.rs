//! Rhai's "Data race detected on argument #2 of function 'map'" explained, at its line.
//!
//! A closure captures the variables it uses by sharing them. While a method chain such as
//! `pm.outgoing(v).map(|h| pm.ends(h)[1])` runs, Rhai holds the variable the chain starts from
//! (`pm`) as the chain's target; the closure's shared `pm` is then already held when `map`
//! calls it, and Rhai stops with a data race that carries no position. This finds the call in
//! the source — a `.function(` whose arguments hold a closure that uses the chain's first
//! variable — and says what happened and how to write it instead.

use rhai::Position;

/// A data race located in the script.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DataRace {
    /// Where the method is called (its name).
    pub position: Position,
    /// The explanation, with the fix.
    pub message: String,
}

const MARKER: &str = "Data race detected on argument #";

/// The function a data-race message names (`map` in "... of function 'map'"), if `message`
/// is one.
#[must_use]
pub fn function_of(message: &str) -> Option<&str> {
    let rest = &message[message.find(MARKER)?..];
    let start = rest.find("function '")? + "function '".len();
    let end = rest[start..].find('\'')?;
    Some(&rest[start..start + end])
}

/// Finds the call of `function` in `source` whose closure uses the variable its chain starts
/// from, and explains it. `None` when no such call is found (the message is left as Rhai
/// wrote it).
#[must_use]
pub fn locate(source: &str, function: &str) -> Option<DataRace> {
    let needle = format!(".{function}(");
    for (n, line) in source.lines().enumerate() {
        let mut from = 0;
        while let Some(k) = line[from..].find(&needle) {
            let dot = from + k;
            from = dot + 1;
            let Some(start) = chain_start(line, dot) else { continue };
            let root: String = line[start..].chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let open = dot + needle.len() - 1;
            let Some(close) = matching(line, open) else { continue };
            let args = &line[open + 1..close];
            if root.is_empty() || !args.contains('|') || !uses(args, &root) {
                continue;
            }
            let chain = &line[start..dot];
            let col = line[..dot + 1].chars().count() + 1;
            let position = Position::new(u16::try_from(n + 1).ok()?, u16::try_from(col).ok()?);
            let value = if chain == root { format!("{root}_copy") } else { "items".to_string() };
            let message = format!(
                "{function}: the closure passed to `{function}` uses `{root}`, the variable this call chain \
                 starts from (`{chain}.{function}(...)`): Rhai holds `{root}` while the chain runs, so the \
                 closure cannot read it (\"data race\"). Store the chain's value first: \
                 `let {value} = {chain}; {value}.{function}({args})`"
            );
            return Some(DataRace { position, message });
        }
    }
    None
}

/// The byte where the method chain ending at `dot` starts: back over `.name`, `(...)` and
/// `[...]` to the first identifier.
fn chain_start(line: &str, dot: usize) -> Option<usize> {
    let b = line.as_bytes();
    let mut i = dot;
    loop {
        // Before `i` comes a name, possibly followed by calls and indexes.
        while i > 0 && (b[i - 1] == b')' || b[i - 1] == b']') {
            i = opening(line, i - 1)?;
        }
        let end = i;
        while i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_') {
            i -= 1;
        }
        if i == end {
            return None;
        }
        if i > 0 && b[i - 1] == b'.' {
            i -= 1;
            continue;
        }
        return Some(i);
    }
}

/// The byte of the bracket that `close` (a `)` or `]`) closes.
fn opening(line: &str, close: usize) -> Option<usize> {
    let b = line.as_bytes();
    let mut depth = 0i32;
    for i in (0..=close).rev() {
        match b[i] {
            b')' | b']' => depth += 1,
            b'(' | b'[' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// The byte of the bracket closing the `(` at `open`.
fn matching(line: &str, open: usize) -> Option<usize> {
    let mut depth = 0i32;
    for (i, c) in line.char_indices().skip_while(|(i, _)| *i < open) {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// Whether `text` uses the variable `name` (as a whole word, not as a field `.name`).
fn uses(text: &str, name: &str) -> bool {
    let b = text.as_bytes();
    let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    text.match_indices(name).any(|(i, _)| {
        let before = i.checked_sub(1).map(|j| b[j]);
        let after = b.get(i + name.len()).copied();
        !before.is_some_and(|c| word(c) || c == b'.') && !after.is_some_and(word)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_call_whose_closure_uses_the_chain_s_variable_is_found() {
        let src =
            "let pm = polar_octahedron();\nlet v = pm.poles()[0];\nlet e = pm.outgoing(v).map(|h| pm.ends(h)[1]);\n";
        let r = locate(src, "map").unwrap();
        // Line 3, at `map`.
        assert_eq!((r.position.line(), r.position.position()), (Some(3), Some(24)));
        assert!(r.message.contains("uses `pm`"), "{}", r.message);
        assert!(r.message.contains("`let items = pm.outgoing(v); items.map(|h| pm.ends(h)[1])`"), "{}", r.message);
        assert_eq!(function_of("Data race detected on argument #2 of function 'map'"), Some("map"));
        assert_eq!(function_of("Variable not found: x"), None);
    }

    #[test]
    fn a_closure_using_other_variables_or_a_field_of_that_name_is_not_it() {
        assert!(locate("let e = pm.outgoing(v).map(|h| other.ends(h));", "map").is_none());
        assert!(locate("let e = pm.outgoing(v).map(|h| h.pm);", "map").is_none());
        assert!(locate("let e = pm.outgoing(v).map(|h| pmx + h);", "map").is_none());
        // The chain's variable itself as receiver.
        let r = locate("let n = xs.map(|x| xs.len() + x);", "map").unwrap();
        assert!(r.message.contains("`let xs_copy = xs; xs_copy.map(|x| xs.len() + x)`"), "{}", r.message);
    }
}
