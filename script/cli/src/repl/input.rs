//! Whether a REPL entry is finished: brackets still open, a string or block comment not yet
//! closed. An unfinished entry reads another line (with the continuation prompt on a terminal).

/// What the scan of an entry found at its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Scan {
    /// Brackets opened and not closed (negative when more were closed than opened).
    depth: i64,
    /// Ends inside a string that goes on to the next line (a backtick string, or a `"` string
    /// whose line ends in `\`), or inside a block comment.
    open_text: bool,
}

fn scan(text: &str) -> Scan {
    let mut depth = 0i64;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' | '`' | '\'' => {
                let mut closed = false;
                let mut last_escape = false;
                while let Some(d) = chars.next() {
                    if d == '\\' {
                        last_escape = chars.next().is_none();
                        if last_escape {
                            break;
                        }
                    } else if d == c {
                        closed = true;
                        break;
                    }
                }
                if !closed {
                    // A backtick string spans lines; a "..." string does when the line ends in `\`.
                    return Scan { depth, open_text: c == '`' || (c == '"' && last_escape) };
                }
            }
            '/' if chars.peek() == Some(&'/') => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        break;
                    }
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                let mut prev = ' ';
                let mut closed = false;
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        closed = true;
                        break;
                    }
                    prev = d;
                }
                if !closed {
                    return Scan { depth, open_text: true };
                }
            }
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            _ => {}
        }
    }
    Scan { depth, open_text: false }
}

/// The number of brackets still open in `text`, ignoring strings and comments.
#[must_use]
pub fn open_brackets(text: &str) -> i64 {
    scan(text).depth
}

/// Whether `text` needs more lines: a bracket still open, or a string or block comment that
/// goes on. (An entry with too many closing brackets is finished: its error is shown.)
#[must_use]
pub fn unfinished(text: &str) -> bool {
    let s = scan(text);
    s.depth > 0 || s.open_text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brackets_in_strings_and_comments_do_not_count() {
        assert_eq!(open_brackets("fn f() {"), 1);
        assert_eq!(open_brackets("let s = \"{(\"; // [[["), 0);
        assert_eq!(open_brackets("[1, [2]"), 1);
        assert_eq!(open_brackets("/* { */ }"), -1);
    }

    #[test]
    fn unfinished_entries_wait_for_more() {
        for text in ["fn f(x) {", "let a = [1,\n2,", "let s = `one\ntwo", "let s = \"a\\", "/* note", "f(#{ a: 1"] {
            assert!(unfinished(text), "{text:?} is unfinished");
        }
        for text in ["fn f(x) { x }", "let s = `a{b`;", "let s = \"oops", "x }", "let c = '{';", "1 /* } */"] {
            assert!(!unfinished(text), "{text:?} is finished");
        }
    }
}
