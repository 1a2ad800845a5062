//! Script errors for people: `file:line:col: error: message`, the source line and a caret.

use rhai::{EvalAltResult, ParseError, Position};

/// The message of an error without Rhai's trailing `(line L, position P)`; a function or
/// property not found is explained from what exists ([`crate::explain`]).
#[must_use]
pub fn message(err: &EvalAltResult) -> String {
    let text = match err {
        EvalAltResult::ErrorTerminated(token, _) => format!("script stopped: {token}"),
        EvalAltResult::ErrorRuntime(value, _) => value.to_string(),
        _ => err.to_string(),
    };
    crate::explain::explain(strip_position(&text))
}

fn strip_position(text: &str) -> &str {
    let trimmed = text.trim_end();
    if trimmed.ends_with(')') {
        if let Some(i) = trimmed.rfind(" (line ") {
            return &trimmed[..i];
        }
    }
    trimmed
}

/// The innermost position that lies in the script itself (an error raised inside a called
/// script function carries the call's position outside and the failing line inside).
fn innermost_position(err: &EvalAltResult) -> Position {
    match err {
        EvalAltResult::ErrorInFunctionCall(_, src, inner, pos) if src.is_empty() => {
            let p = innermost_position(inner);
            if p.is_none() {
                *pos
            } else {
                p
            }
        }
        _ => err.position(),
    }
}

/// Formats `err` raised by the script `name` whose text is `source`:
///
/// ```text
/// recipe.rhai:3:9: error: translate: argument `offset` must be a Vec3 ...
///     3 | let m = cube(2).translate([1, 2]);
///       |         ^
/// ```
#[must_use]
pub fn format_error(name: &str, source: &str, err: &EvalAltResult) -> String {
    let pos = innermost_position(err);
    format_at(name, source, pos, &message(err))
}

/// Formats a parse error like [`format_error`].
#[must_use]
pub fn format_parse_error(name: &str, source: &str, err: &ParseError) -> String {
    format_at(name, source, err.position(), strip_position(&err.to_string()))
}

/// Formats a warning at `pos` like [`format_error`] (`file:line:col: warning: ...`).
#[must_use]
pub fn format_warning(name: &str, source: &str, pos: Position, message: &str) -> String {
    format_kind(name, source, pos, "warning", message)
}

fn format_at(name: &str, source: &str, pos: Position, message: &str) -> String {
    format_kind(name, source, pos, "error", message)
}

fn format_kind(name: &str, source: &str, pos: Position, kind: &str, message: &str) -> String {
    let (Some(line), col) = (pos.line(), pos.position().unwrap_or(1)) else {
        return format!("{name}: {kind}: {message}");
    };
    // A message's first line goes before the source line, its other lines after the caret.
    let (first, more) = message.split_once('\n').map_or((message, None), |(a, b)| (a, Some(b)));
    let mut out = format!("{name}:{line}:{col}: {kind}: {first}");
    if let Some(text) = source.lines().nth(line - 1) {
        let gutter = line.to_string().len() + 4;
        out.push_str(&format!(
            "\n{line:>w$} | {text}\n{:>w$} | {}^",
            "",
            " ".repeat(col.saturating_sub(1)),
            w = gutter
        ));
    }
    if let Some(more) = more {
        out.push('\n');
        out.push_str(more);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_shows_file_line_col_source_and_caret() {
        let engine = rhai::Engine::new();
        let src = "let a = 1;\nlet b = a + undefined_thing;";
        let err = engine.eval::<rhai::Dynamic>(src).unwrap_err();
        let text = format_error("x.rhai", src, &err);
        assert!(text.starts_with("x.rhai:2:13: error: Variable not found: undefined_thing"), "{text}");
        assert!(text.contains("2 | let b = a + undefined_thing;"), "{text}");
        assert!(text.lines().last().unwrap().ends_with("            ^"), "{text}");
    }
}
