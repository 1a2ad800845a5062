//! Script errors for people: `file:line:col: error: message`, the source line and a caret.

use rhai::{Engine, EvalAltResult, ParseError, Position};

use crate::context::Warning;

/// The message of an error without Rhai's trailing `(line L, position P)`.
#[must_use]
pub fn message(err: &EvalAltResult) -> String {
    let text = match err {
        // Raised inside a script function: what was raised there.
        EvalAltResult::ErrorInFunctionCall(_, _, inner, _) => return message(inner),
        EvalAltResult::ErrorTerminated(token, _) => format!("script stopped: {token}"),
        EvalAltResult::ErrorRuntime(value, _) => value.to_string(),
        _ => err.to_string(),
    };
    strip_position(&text).to_string()
}

/// [`message`], with a function or property not found explained from what `engine` (the
/// engine that gave the error) has ([`crate::explain`]).
#[must_use]
pub fn explained_message(engine: &Engine, err: &EvalAltResult) -> String {
    crate::explain::explain(engine, &message(err))
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

/// At most this many calls of script functions are shown under an error raised inside them
/// (a deep recursion would otherwise list every level); the rest are counted.
const CALLS_SHOWN: usize = 8;

/// Formats `err` raised in `engine` by the script `name` whose text is `source`:
///
/// ```text
/// recipe.rhai:3:9: error: translate: argument `offset` must be a Vec3 ...
///     3 | let m = cube(2).translate([1, 2]);
///       |         ^
/// ```
///
/// An error raised inside one of the script's functions is shown at its own line, followed by
/// a note at each call that led there, innermost first (`note: in the call of `f` here`). An
/// error inside an imported module (a syntax error, or its top-level code or one of its
/// functions failing) points into the module's file, followed by a note at the `import` or
/// the call.
#[must_use]
pub fn format_error(engine: &Engine, name: &str, source: &str, err: &EvalAltResult) -> String {
    let mut file = (name.to_string(), source.to_string());
    let mut calls: Vec<String> = Vec::new();
    let mut err = err;
    while let EvalAltResult::ErrorInFunctionCall(function, defined_in, inner, call) = err {
        calls.push(format_kind(&file.0, &file.1, *call, "note", &format!("in the call of `{function}` here")));
        if !defined_in.is_empty() && *defined_in != file.0 {
            let Some(text) = module_source(defined_in) else { break };
            file = (defined_in.clone(), text);
        }
        err = inner;
    }
    let mut out = format_raised(engine, &file.0, &file.1, err);
    // A recursion's calls from one place: one note, counted.
    let mut repeated: Vec<(String, usize)> = Vec::new();
    for note in calls.into_iter().rev() {
        match repeated.last_mut() {
            Some((last, n)) if *last == note => *n += 1,
            _ => repeated.push((note, 1)),
        }
    }
    let hidden: usize = repeated.iter().skip(CALLS_SHOWN).map(|(_, n)| n).sum();
    for (note, n) in repeated.iter().take(CALLS_SHOWN) {
        out.push('\n');
        match note.split_once('\n') {
            Some((first, rest)) if *n > 1 => out.push_str(&format!("{first} ({n} times)\n{rest}")),
            _ => out.push_str(note),
        }
    }
    if hidden > 0 {
        out.push_str(&format!("\n… and {hidden} earlier call(s)"));
    }
    out
}

/// [`format_error`] of an error raised where it is reported (not inside a script function).
fn format_raised(engine: &Engine, name: &str, source: &str, err: &EvalAltResult) -> String {
    if let EvalAltResult::ErrorInModule(path, inner, pos) = err {
        if let Some(module_source) = module_source(path) {
            let inner_text = match &**inner {
                EvalAltResult::ErrorParsing(kind, at) => {
                    let e = ParseError(Box::new(kind.clone()), *at);
                    format_parse_error(path, &module_source, &e)
                }
                other => format_error(engine, path, &module_source, other),
            };
            return format!("{inner_text}\n{}", format_kind(name, source, *pos, "note", "imported here"));
        }
    }
    let pos = err.position();
    let text = explained_message(engine, err);
    // A data race carries no position: find the call whose closure causes it.
    if pos.is_none() {
        if let Some(race) = crate::data_race::function_of(&text).and_then(|f| crate::data_race::locate(source, f)) {
            return format_at(name, source, race.position, &race.message);
        }
    }
    format_at(name, source, pos, &text)
}

/// The text of the module file at `path` (a file, or a standard-library module written
/// `stdlib/NAME.rhai`).
fn module_source(path: &str) -> Option<String> {
    if let Some(name) = path.strip_prefix("stdlib/").and_then(|p| p.strip_suffix(".rhai")) {
        if let Some(src) = crate::resolver::Resolver::stdlib_source(name) {
            return Some(src.to_string());
        }
    }
    std::fs::read_to_string(path).ok()
}

/// Formats a parse error like [`format_error`]. Input that ends while a bracket is still open
/// is reported at that bracket ("missing `}`"), not at the end of the file.
#[must_use]
pub fn format_parse_error(name: &str, source: &str, err: &ParseError) -> String {
    let at_end = err.position().line().is_none_or(|l| l >= source.lines().count());
    if let (true, Some((open, line, col))) = (at_end, unclosed_bracket(source)) {
        let close = match open {
            '(' => ')',
            '[' => ']',
            _ => '}',
        };
        let message = format!("missing `{close}`: the `{open}` here is never closed");
        return format_at(name, source, Position::new(line as u16, col as u16), &message);
    }
    format_at(name, source, err.position(), strip_position(&err.to_string()))
}

/// The innermost bracket still open at the end of `text` (strings and comments skipped):
/// the bracket, its line and column (from 1).
#[must_use]
pub fn unclosed_bracket(text: &str) -> Option<(char, usize, usize)> {
    let mut open: Vec<(char, usize, usize)> = Vec::new();
    let (mut line, mut col) = (1usize, 0usize);
    let mut chars = text.chars().peekable();
    let mut quote: Option<char> = None;
    let mut comment = false;
    while let Some(c) = chars.next() {
        if c == '\n' {
            line += 1;
            col = 0;
            comment = false;
            continue;
        }
        col += 1;
        if comment {
            continue;
        }
        if let Some(q) = quote {
            if c == '\\' {
                chars.next();
                col += 1;
            } else if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '"' | '`' | '\'' => quote = Some(c),
            '/' if chars.peek() == Some(&'/') => comment = true,
            '(' | '[' | '{' => open.push((c, line, col)),
            ')' | ']' | '}' => {
                open.pop();
            }
            _ => {}
        }
    }
    open.pop()
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
    crate::printable::printable(&format_raw(name, source, pos, kind, message)).into_owned()
}

fn format_raw(name: &str, source: &str, pos: Position, kind: &str, message: &str) -> String {
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

/// The warnings a run gave as it went (`warnings`, taken from its
/// [`crate::context::Warnings`]), formatted as the lint's are (`file:line:col: warning: ...`,
/// the source line and a caret): the script's own as `name` with its `source`, a module's with
/// its file.
#[must_use]
pub fn format_run_warnings(warnings: &[Warning], name: &str, source: &str) -> Vec<String> {
    warnings
        .iter()
        .map(|w| match &w.source {
            Some(module) if module != name => {
                let text = std::fs::read_to_string(module).unwrap_or_default();
                format_warning(module, &text, w.position, &w.message)
            }
            _ => format_warning(name, source, w.position, &w.message),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_from_files_and_scripts_never_reach_the_terminal() {
        // A file's bytes (an STL solid name, a PLY comment, a file name) and a script's own
        // strings reach messages; an ESC among them could clear the screen or hide a line. Each
        // way in — a kernel error at the binding edge (also as a caught error), a thrown string,
        // the source line shown — comes out escaped.
        let d = tempfile::tempdir().unwrap();
        let evil = d.path().join("\u{1b}[2Jclear\u{9b}31m.stl");
        std::fs::write(&evil, "solid \u{1b}]0;title\u{7}\nfacet normal 0 0 1\nendfacet\nendsolid\n").unwrap();
        let engine = crate::new_engine(crate::EngineOptions::default());
        // Rhai's escapes: `\x1b` is ESC, `\u009b` the one-character CSI.
        let path = evil.display().to_string().replace('\u{1b}', "\\x1b").replace('\u{9b}', "\\u009b");
        let script = format!(
            "let caught = \"\";\ntry {{ load(\"{path}\"); }} catch (e) {{ caught = e; }}\n\
             if caught.contains(\"\\x1b\") {{ throw \"raw\"; }}\nthrow \"\\x1b[31mred\\r \" + caught;\n"
        );
        let err = engine.eval::<rhai::Dynamic>(&script).unwrap_err();
        let text = format_error(&engine, "t.rhai", &script, &err);
        assert!(!text.chars().any(|c| c.is_control() && c != '\n'), "{text:?}");
        assert!(text.contains("\\x1b[31mred\\x0d load: ") && text.contains("\\x1b[2Jclear\\u{9b}31m.stl"), "{text}");
        assert_eq!(crate::printable::printable("two\nlines\tand a tab"), "two\nlines\tand a tab");
    }

    #[test]
    fn a_missing_brace_is_reported_at_the_brace_left_open() {
        let src = "let m = cube(1);\nif true {\n  m = m.scale(2);\n\nm\n";
        let err = rhai::Engine::new().compile(src).unwrap_err();
        let text = format_parse_error("x.rhai", src, &err);
        assert!(text.starts_with("x.rhai:2:9: error: missing `}`: the `{` here is never closed"), "{text}");
        assert_eq!(unclosed_bracket("let s = \"{\"; // (\nf([1, 2]"), Some(('(', 2, 2)));
        assert_eq!(unclosed_bracket("fn f() { 1 }"), None);
    }

    #[test]
    fn error_shows_file_line_col_source_and_caret() {
        let engine = rhai::Engine::new();
        let src = "let a = 1;\nlet b = a + undefined_thing;";
        let err = engine.eval::<rhai::Dynamic>(src).unwrap_err();
        let text = format_error(&engine, "x.rhai", src, &err);
        assert!(text.starts_with("x.rhai:2:13: error: Variable not found: undefined_thing"), "{text}");
        assert!(text.contains("2 | let b = a + undefined_thing;"), "{text}");
        assert!(text.lines().last().unwrap().ends_with("            ^"), "{text}");
    }
}
