//! Text safe to print on a terminal, for every message that may quote a file or a script.

/// Text safe to print on a terminal: control characters other than line breaks and tabs
/// (an ESC sequence in an STL solid name, a PLY comment, a file name or a string the script
/// throws) written as escapes (`\x1b`, `\u{9b}`), so a file cannot move the cursor, recolour
/// or clear the screen, or retitle the window. Every formatted error and warning goes through
/// it, and so does every error the script API raises ([`crate::convert::error`]).
#[must_use]
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(|c| c.is_control() && c != '\n' && c != '\t') {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\n' | '\t' => out.push(c),
            c if c.is_control() && (c as u32) < 0x80 => out.push_str(&format!("\\x{:02x}", c as u32)),
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    std::borrow::Cow::Owned(out)
}
