//! A document's text as the protocol addresses it: lines and UTF-16 columns (the protocol's
//! default encoding) to and from byte offsets and Rhai's positions (1-based line, 1-based
//! character column), and the small scans the features need (the word under the cursor, the
//! call the cursor is in).

use lsp_types::{Position, Range};

/// The starts of the lines of one text, for converting between offsets and positions.
#[derive(Debug, Clone)]
pub struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    /// Indexes `text`.
    #[must_use]
    pub fn new(text: &'a str) -> Lines<'a> {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        Lines { text, starts }
    }

    /// Line `line` (0-based) without its line break; empty past the end.
    #[must_use]
    pub fn line(&self, line: usize) -> &'a str {
        let Some(&start) = self.starts.get(line) else { return "" };
        let end = self.starts.get(line + 1).map_or(self.text.len(), |e| e - 1);
        self.text[start..end.max(start)].trim_end_matches('\r')
    }

    /// The byte offset of a protocol position (clamped to the text).
    #[must_use]
    pub fn offset(&self, p: Position) -> usize {
        let line = p.line as usize;
        let Some(&start) = self.starts.get(line) else { return self.text.len() };
        let text = self.line(line);
        let mut units = 0u32;
        for (i, c) in text.char_indices() {
            if units >= p.character {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        start + text.len()
    }

    /// The protocol position of a byte offset.
    #[must_use]
    pub fn position(&self, offset: usize) -> Position {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let col: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position::new(line as u32, col as u32)
    }

    /// The protocol position of a Rhai position (1-based line and character column); the
    /// start of the text for none.
    #[must_use]
    pub fn from_rhai(&self, p: rhai::Position) -> Position {
        let (Some(line), col) = (p.line(), p.position().unwrap_or(1)) else { return Position::new(0, 0) };
        let text = self.line(line - 1);
        let units: usize = text.chars().take(col.saturating_sub(1)).map(char::len_utf16).sum();
        Position::new((line - 1) as u32, units as u32)
    }

    /// The range of the word (identifier, or `alias::name`) starting at a Rhai position, at
    /// least one character wide.
    #[must_use]
    pub fn word_range(&self, p: rhai::Position) -> Range {
        let start = self.from_rhai(p);
        let from = self.offset(start);
        let len = word_len(&self.text[from..]).max(self.text[from..].chars().next().map_or(0, char::len_utf8));
        Range::new(start, self.position(from + len))
    }

    /// The text.
    #[must_use]
    pub fn text(&self) -> &'a str {
        self.text
    }
}

/// Whether `c` may be part of an identifier.
#[must_use]
pub fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Where the identifier `s` ends with starts (a byte index, `s.len()` when `s` ends with none):
/// after the last character that is not part of one, whatever its length in bytes.
#[must_use]
pub fn ident_start(s: &str) -> usize {
    s.char_indices().rev().find(|&(_, c)| !is_ident(c)).map_or(0, |(i, c)| i + c.len_utf8())
}

/// The length in bytes of the identifier at the start of `s`.
#[must_use]
pub fn word_len(s: &str) -> usize {
    s.char_indices().find(|(_, c)| !is_ident(*c)).map_or(s.len(), |(i, _)| i)
}

/// The word at byte `offset` of `text` (identifiers joined by `::`, so `check::solid` is one
/// word) and where it starts.
#[must_use]
pub fn word_at(text: &str, offset: usize) -> Option<(usize, &str)> {
    let offset = offset.min(text.len());
    let is_word = |c: char| is_ident(c) || c == ':';
    let start = text[..offset].char_indices().rev().find(|(_, c)| !is_word(*c)).map_or(0, |(i, c)| i + c.len_utf8());
    let end = text[offset..].char_indices().find(|(_, c)| !is_word(*c)).map_or(text.len(), |(i, _)| offset + i);
    let w = text[start..end].trim_matches(':');
    let lead = text[start..end].len() - text[start..end].trim_start_matches(':').len();
    (!w.is_empty()).then_some((start + lead, w))
}

/// Where the innermost call whose argument list holds `offset` opens: the callee's name, the
/// offset of its `(`, and the index of the argument the cursor is in. Strings and comments are
/// skipped.
#[must_use]
pub fn enclosing_call(text: &str, offset: usize) -> Option<(String, usize, usize)> {
    let code = blank_strings_and_comments(&text[..offset.min(text.len())]);
    let mut depth = 0i64;
    let mut commas = 0usize;
    for (i, c) in code.char_indices().rev() {
        match c {
            ')' | ']' | '}' => depth += 1,
            '[' | '{' if depth > 0 => depth -= 1,
            '[' | '{' => commas = 0,
            '(' if depth > 0 => depth -= 1,
            '(' => {
                let before = code[..i].trim_end();
                let start =
                    before.char_indices().rev().find(|(_, c)| !is_ident(*c)).map_or(0, |(j, c)| j + c.len_utf8());
                let name = &before[start..];
                if name.is_empty() {
                    return None;
                }
                return Some((name.to_string(), i, commas));
            }
            ',' if depth == 0 => commas += 1,
            ';' if depth == 0 => return None,
            _ => {}
        }
    }
    None
}

/// `text` with the contents of string literals and comments replaced by spaces (same
/// length, line breaks kept), so scans for brackets and keywords see code only.
#[must_use]
pub fn blank_strings_and_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let blank = |out: &mut String, c: char| {
        if c == '\n' {
            out.push('\n');
        } else {
            out.extend(std::iter::repeat_n(' ', c.len_utf8()));
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '"' | '`' => {
                out.push(c);
                let mut escaped = false;
                for d in chars.by_ref() {
                    if !escaped && d == c {
                        out.push(d);
                        break;
                    }
                    escaped = !escaped && d == '\\';
                    blank(&mut out, d);
                }
            }
            '/' if chars.peek() == Some(&'/') => {
                blank(&mut out, c);
                for d in chars.by_ref() {
                    if d == '\n' {
                        out.push('\n');
                        break;
                    }
                    blank(&mut out, d);
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                blank(&mut out, c);
                let mut prev = ' ';
                for d in chars.by_ref() {
                    blank(&mut out, d);
                    if prev == '*' && d == '/' {
                        break;
                    }
                    prev = d;
                }
            }
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_utf16_units_and_rhai_columns_count_characters() {
        let t = "let é = 1;\nlet 𝑥 = cube(2);\n";
        let l = Lines::new(t);
        // `𝑥` is two UTF-16 units: `cube` starts at unit 9 of line 1.
        let cube = t.find("cube").unwrap();
        assert_eq!(l.position(cube), Position::new(1, 9));
        assert_eq!(l.offset(Position::new(1, 9)), cube);
        // Rhai counts characters: `cube` is at column 9 (1-based) of line 2.
        assert_eq!(l.from_rhai(rhai::Position::new(2, 9)), Position::new(1, 9));
        assert_eq!(l.word_range(rhai::Position::new(2, 9)).end, Position::new(1, 13));
    }

    #[test]
    fn the_enclosing_call_and_argument_are_found_past_nested_brackets_and_strings() {
        let t = "let m = cylinder(1, f(2, 3), \"a,(b\", ";
        assert_eq!(enclosing_call(t, t.len()), Some(("cylinder".into(), 16, 3)));
        assert_eq!(enclosing_call("x.translate([1, 2", 17), Some(("translate".into(), 11, 0)));
        assert_eq!(enclosing_call("cube(1); x", 10), None);
        assert_eq!(word_at("check::solid(m)", 3), Some((0, "check::solid")));
    }
}
