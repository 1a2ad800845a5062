//! The editor and the studio, both ways: `blocksmith.studio` (a lens above the recipe) starts a
//! studio for the recipe in this process — the page `blocksmith watch` serves, behind the same
//! guard (loopback Host, checked Origin, session token, bounded requests), run again on save.
//! A face clicked in its page comes back here as the chain of calls that made it, and the
//! editor is asked to show the first call's line (`window/showDocument`; an editor without it
//! is told in a message, and the page lists the chain either way). The other way, when the
//! editor asks for the highlights or the hover of a place in the recipe, the page lights up the
//! faces the call written there made (any call on that line when the cursor is not on one).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use blocksmith_studio::recipe_lines::{Site, Step};
use blocksmith_studio::server::Studio;
use blocksmith_studio::session::{Params, Session, Source};
use lsp_server::{Message, Notification, Request, RequestId};
use lsp_types::{Range, Uri};

use crate::text::{word_at, Lines};

/// The command that starts (or shows again) the studio of a recipe.
pub const STUDIO: &str = "blocksmith.studio";

/// Sends a message to the editor from any thread (the connection's sender).
pub type Outbox = Arc<dyn Fn(Message) + Send + Sync>;

/// The studios this server started, one per recipe file.
#[derive(Default)]
pub struct Studios {
    running: HashMap<PathBuf, Linked>,
}

struct Linked {
    session: Arc<Session>,
    url: String,
}

impl Studios {
    /// The studio of the recipe at `path`, started when there is none: its page's address.
    /// `outbox`: where a face picked in the page is sent as `window/showDocument` (when
    /// `show_document`, else as `window/showMessage`); `None`: nowhere (tests of the server alone).
    ///
    /// # Errors
    /// No port to listen on, or a recipe folder that cannot be watched.
    pub fn start(&mut self, path: &Path, outbox: Option<Outbox>, show_document: bool) -> Result<String, String> {
        if let Some(l) = self.running.get(path) {
            return Ok(l.url.clone());
        }
        let studio = Studio::bind(0)?;
        let session = Session::start(Source::Recipe(path.to_path_buf()), Params::new());
        blocksmith_studio::watch::watch(&session)?;
        if let Some(outbox) = outbox {
            let sent = AtomicU64::new(0);
            session.on_pick(move |steps| {
                if let Some(message) = show(steps, show_document, sent.fetch_add(1, Ordering::SeqCst)) {
                    outbox(message);
                }
            });
        }
        let url = studio.url();
        let serving = Arc::clone(&session);
        std::thread::Builder::new()
            .name("studio".into())
            .spawn(move || {
                if let Err(e) = studio.serve(&serving) {
                    eprintln!("{e}");
                }
            })
            .map_err(|e| format!("error: cannot start the studio: {e}"))?;
        eprintln!("showing {} at {url}", path.display());
        self.running.insert(path.to_path_buf(), Linked { session, url: url.clone() });
        Ok(url)
    }

    /// The address of the studio of `path`, if one is running.
    #[must_use]
    pub fn url(&self, path: &Path) -> Option<&str> {
        self.running.get(path).map(|l| l.url.as_str())
    }

    /// The cursor rests at `offset` of `text`, the recipe at `path`: the studio of that recipe,
    /// if any, lights up the faces made there. Returns the site lit.
    pub fn cursor(&self, path: &Path, text: &str, offset: usize) -> Option<Site> {
        let linked = self.running.get(path)?;
        let site = call_site(path, text, offset);
        linked.session.highlight(&site);
        Some(site)
    }
}

/// The call at `offset` as a run records its place: the name under the cursor when a `(`
/// follows it, or an operator character (`a - b`), at its 1-based line and character column;
/// elsewhere the line alone (column 0: every call on it).
#[must_use]
pub fn call_site(path: &Path, text: &str, offset: usize) -> Site {
    let code = crate::text::blank_strings_and_comments(text);
    let rhai_place = |at: usize| {
        let before = &text[..at.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (u32::try_from(line).unwrap_or(u32::MAX), u32::try_from(column).unwrap_or(u32::MAX))
    };
    let file = Some(path.display().to_string());
    let called = word_at(&code, offset)
        .filter(|(start, word)| code[start + word.len()..].trim_start().starts_with('(') && !word.is_empty());
    if let Some((start, word)) = called {
        // A module's function (`check::solid`) is recorded at its name, after the `::`.
        let name_at = start + word.rfind("::").map_or(0, |i| i + 2);
        let (line, column) = rhai_place(name_at);
        return Site { file, line, column };
    }
    let operator = code[offset.min(code.len())..].chars().next().filter(|c| "+-*/%&|^".contains(*c));
    let (line, column) = rhai_place(offset);
    Site { file, line, column: if operator.is_some() { column } else { 0 } }
}

/// The message that shows the editor where the picked face was made: its first call's line.
fn show(steps: &[Step], show_document: bool, n: u64) -> Option<Message> {
    let first = steps.first()?;
    let path = first.site.path()?;
    let uri: Uri = format!("file://{}", path.display()).parse().ok()?;
    // The call's name, its columns in UTF-16 units (the run counts characters).
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let at = rhai::Position::new(
        u16::try_from(first.site.line).unwrap_or(u16::MAX),
        u16::try_from(first.site.column).unwrap_or(u16::MAX),
    );
    let range: Range = Lines::new(&text).word_range(at);
    if show_document {
        let params = lsp_types::ShowDocumentParams {
            uri,
            external: Some(false),
            take_focus: Some(true),
            selection: Some(range),
        };
        let id = RequestId::from(format!("blocksmith-show-{n}"));
        Some(Message::Request(Request::new(id, "window/showDocument".into(), params)))
    } else {
        let chain: Vec<String> = steps.iter().map(|s| format!("{} at {}", s.call, s.site.line)).collect();
        let params = lsp_types::ShowMessageParams {
            typ: lsp_types::MessageType::INFO,
            message: format!("{}:{}: {}", path.display(), first.site.line, chain.join(" → ")),
        };
        Some(Message::Notification(Notification::new("window/showMessage".into(), params)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_site_under_the_cursor_is_the_call_the_run_records() {
        let path = Path::new("/r/die.rhai");
        let text = "let body = cube(2);\n// cube(9)\nlet d = body - check::solid(x);\nlet é = body;\n";
        let at = |needle: &str, plus: usize| text.find(needle).unwrap() + plus;
        let site = |o| call_site(path, text, o);
        assert_eq!(site(at("cube", 2)), Site { file: Some("/r/die.rhai".into()), line: 1, column: 12 });
        assert_eq!(site(at("- check", 0)).column, 14, "an operator");
        assert_eq!(site(at("solid", 1)).column, 23, "a module's function: at its name");
        assert_eq!(site(at("check::", 1)).column, 23);
        assert_eq!(site(at("body;", 1)), Site { file: Some("/r/die.rhai".into()), line: 4, column: 0 }, "no call");
        assert_eq!(site(at("cube(9)", 1)).column, 0, "a comment makes no call");
    }
}
