//! The protocol: rust-analyzer's `lsp-server` over standard input and output, one thread,
//! full-text sync. Each open or changed document is diagnosed at once and its diagnostics
//! published; requests are answered from the document's current text.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use lsp_server::{Connection, ExtractError, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument, Notification as _,
    PublishDiagnostics,
};
use lsp_types::request::{
    CodeLensRequest, Completion, DocumentHighlightRequest, DocumentSymbolRequest, ExecuteCommand, GotoDefinition,
    HoverRequest, InlayHintRequest, Request as _, SignatureHelpRequest,
};
use lsp_types::{
    CodeLensOptions, CompletionOptions, CompletionResponse, DocumentSymbolResponse, ExecuteCommandOptions,
    GotoDefinitionResponse, HoverProviderCapability, OneOf, PublishDiagnosticsParams, ServerCapabilities, ServerInfo,
    SignatureHelpOptions, TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};

use crate::lens::Outcome;
use crate::navigate::path_of;
use crate::studio_link::{Outbox, Studios};
use crate::text::Lines;
use crate::Analyzer;

/// What the server says it can do.
#[must_use]
pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some([".", ":", "\"", "{", ",", "/"].map(String::from).to_vec()),
            ..CompletionOptions::default()
        }),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        signature_help_provider: Some(SignatureHelpOptions {
            trigger_characters: Some(vec!["(".into(), ",".into()]),
            ..SignatureHelpOptions::default()
        }),
        definition_provider: Some(OneOf::Left(true)),
        document_highlight_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        inlay_hint_provider: Some(OneOf::Left(true)),
        code_lens_provider: Some(CodeLensOptions { resolve_provider: Some(false) }),
        execute_command_provider: Some(ExecuteCommandOptions {
            commands: vec![crate::lens::RUN.into(), crate::studio_link::STUDIO.into()],
            ..ExecuteCommandOptions::default()
        }),
        ..ServerCapabilities::default()
    }
}

/// `blocksmith lsp`: serves the editor on standard input and output until it says `exit`.
///
/// # Errors
/// The connection failed (the editor went away mid-message).
pub fn serve_stdio() -> Result<(), String> {
    let (connection, io_threads) = Connection::stdio();
    let init = serde_json::json!({
        "capabilities": capabilities(),
        "serverInfo": ServerInfo { name: "blocksmith".into(), version: Some(env!("CARGO_PKG_VERSION").into()) },
    });
    let (id, params) = connection.initialize_start().map_err(|e| format!("lsp: {e}"))?;
    connection.initialize_finish(id, init).map_err(|e| format!("lsp: {e}"))?;
    let mut server = Server::new();
    server.refresh_lenses = params["capabilities"]["workspace"]["codeLens"]["refreshSupport"] == true;
    server.show_document = params["capabilities"]["window"]["showDocument"]["support"] == true;
    // Studios' threads hold the outbox past `exit`: they reach the sender through a weak
    // handle, so that once the loop ends the writer thread sees its last sender gone and stops.
    let sender = Arc::new(connection.sender.clone());
    let weak = Arc::downgrade(&sender);
    server.outbox = Some(Arc::new(move |m| {
        if let Some(sender) = weak.upgrade() {
            let _ = sender.send(m);
        }
    }));
    let served = server.main_loop(&connection);
    drop(sender);
    drop(server);
    drop(connection);
    served?;
    io_threads.join().map_err(|e| format!("lsp: {e}"))
}

/// The server's state: open documents and each one's last run.
pub struct Server {
    pub analyzer: Analyzer,
    pub documents: HashMap<String, String>,
    outcomes: HashMap<String, Outcome>,
    /// The editor fetches lenses again when asked (`workspace/codeLens/refresh`).
    refresh_lenses: bool,
    /// Requests sent to the editor so far (their ids).
    sent: u64,
    /// The studios started from the editor, one per recipe.
    pub studios: Studios,
    /// Where messages to the editor go from other threads (a face picked in a studio page).
    outbox: Option<Outbox>,
    /// The editor opens documents when asked (`window/showDocument`).
    show_document: bool,
}

impl Server {
    /// A server with no documents open.
    #[must_use]
    pub fn new() -> Server {
        Server {
            analyzer: Analyzer::new(),
            documents: HashMap::new(),
            outcomes: HashMap::new(),
            refresh_lenses: false,
            sent: 0,
            studios: Studios::default(),
            outbox: None,
            show_document: false,
        }
    }

    fn main_loop(&mut self, connection: &Connection) -> Result<(), String> {
        for message in &connection.receiver {
            match message {
                Message::Request(req) => {
                    if connection.handle_shutdown(&req).map_err(|e| format!("lsp: {e}"))? {
                        return Ok(());
                    }
                    let run = req.method == ExecuteCommand::METHOD;
                    let opens = self.opens_studio(&req);
                    let response = self.request(req);
                    let url =
                        response.response_result.as_ref().ok().and_then(|r| r["url"].as_str()).map(str::to_string);
                    connection.sender.send(Message::Response(response)).map_err(|e| format!("lsp: {e}"))?;
                    if let (true, Some(url)) = (opens && self.show_document, url) {
                        // The studio's page, opened by the editor in the browser.
                        self.sent += 1;
                        let id = RequestId::from(format!("blocksmith-{}", self.sent));
                        let params = serde_json::json!({ "uri": url, "external": true });
                        let _ = connection.sender.send(Message::Request(Request::new(
                            id,
                            "window/showDocument".into(),
                            params,
                        )));
                    }
                    if run && self.refresh_lenses {
                        // The lenses changed: ask the editor to fetch them again.
                        self.sent += 1;
                        let id = RequestId::from(format!("blocksmith-{}", self.sent));
                        let refresh = Request::new(id, "workspace/codeLens/refresh".into(), serde_json::Value::Null);
                        let _ = connection.sender.send(Message::Request(refresh));
                    }
                }
                Message::Notification(n) => {
                    for out in self.notification(n) {
                        connection.sender.send(Message::Notification(out)).map_err(|e| format!("lsp: {e}"))?;
                    }
                }
                Message::Response(_) => {}
            }
        }
        Ok(())
    }

    /// Whether `req` starts a studio (the editor is then asked to open its page).
    fn opens_studio(&self, req: &Request) -> bool {
        req.method == ExecuteCommand::METHOD && req.params["command"] == crate::studio_link::STUDIO
    }

    /// Handles a notification; returns the notifications to send (published diagnostics).
    pub fn notification(&mut self, n: Notification) -> Vec<Notification> {
        let uri = match n.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Ok(p) = n.extract::<lsp_types::DidOpenTextDocumentParams>(DidOpenTextDocument::METHOD) else {
                    return Vec::new();
                };
                self.documents.insert(p.text_document.uri.as_str().to_string(), p.text_document.text);
                p.text_document.uri
            }
            DidChangeTextDocument::METHOD => {
                let Ok(p) = n.extract::<lsp_types::DidChangeTextDocumentParams>(DidChangeTextDocument::METHOD) else {
                    return Vec::new();
                };
                let key = p.text_document.uri.as_str().to_string();
                for change in p.content_changes {
                    match change.range {
                        None => {
                            self.documents.insert(key.clone(), change.text);
                        }
                        Some(range) => {
                            let doc = self.documents.entry(key.clone()).or_default();
                            let lines = Lines::new(doc);
                            let (a, b) = (lines.offset(range.start), lines.offset(range.end));
                            let (a, b) = (a.min(b), a.max(b));
                            doc.replace_range(a..b, &change.text);
                        }
                    }
                }
                p.text_document.uri
            }
            DidCloseTextDocument::METHOD => {
                let Ok(p) = n.extract::<lsp_types::DidCloseTextDocumentParams>(DidCloseTextDocument::METHOD) else {
                    return Vec::new();
                };
                self.documents.remove(p.text_document.uri.as_str());
                let params = PublishDiagnosticsParams::new(p.text_document.uri, Vec::new(), None);
                return vec![Notification::new(PublishDiagnostics::METHOD.into(), params)];
            }
            DidSaveTextDocument::METHOD => return Vec::new(),
            _ => return Vec::new(),
        };
        let text = self.documents.get(uri.as_str()).cloned().unwrap_or_default();
        let path = path_of(&uri);
        let diagnostics = crate::diagnose::diagnostics(&self.analyzer, &text, path.as_deref());
        let params = PublishDiagnosticsParams::new(uri, diagnostics, None);
        vec![Notification::new(PublishDiagnostics::METHOD.into(), params)]
    }

    /// The document at `uri`: its text and folder.
    fn document(&self, uri: &Uri) -> (String, Option<PathBuf>) {
        let path = path_of(uri);
        let text = self
            .documents
            .get(uri.as_str())
            .cloned()
            .or_else(|| path.as_ref().and_then(|p| std::fs::read_to_string(p).ok()))
            .unwrap_or_default();
        (text, path.and_then(|p| p.parent().map(PathBuf::from)))
    }

    /// Answers a request.
    pub fn request(&mut self, req: Request) -> Response {
        let id = req.id.clone();
        match self.answer(req) {
            Ok(value) => Response::new_ok(id, value),
            Err(message) => Response::new_err(id, lsp_server::ErrorCode::InvalidParams as i32, message),
        }
    }

    fn answer(&mut self, req: Request) -> Result<serde_json::Value, String> {
        fn params<R: lsp_types::request::Request>(req: Request) -> Result<R::Params, String> {
            req.extract::<R::Params>(R::METHOD).map(|(_, p)| p).map_err(|e| match e {
                ExtractError::MethodMismatch(r) => format!("unexpected method {}", r.method),
                ExtractError::JsonError { method, error } => format!("{method}: {error}"),
            })
        }
        let a = &self.analyzer;
        let json = |v: serde_json::Result<serde_json::Value>| v.map_err(|e| e.to_string());
        match req.method.as_str() {
            Completion::METHOD => {
                let p = params::<Completion>(req)?;
                let (text, dir) = self.document(&p.text_document_position.text_document.uri);
                let offset = Lines::new(&text).offset(p.text_document_position.position);
                let items = crate::complete::complete(a, &text, offset, dir.as_deref());
                json(serde_json::to_value(CompletionResponse::Array(items)))
            }
            HoverRequest::METHOD => {
                let p = params::<HoverRequest>(req)?;
                let (text, dir) = self.document(&p.text_document_position_params.text_document.uri);
                let offset = Lines::new(&text).offset(p.text_document_position_params.position);
                if let Some(path) = path_of(&p.text_document_position_params.text_document.uri) {
                    self.studios.cursor(&path, &text, offset);
                }
                json(serde_json::to_value(crate::describe::hover(a, &text, offset, dir.as_deref())))
            }
            SignatureHelpRequest::METHOD => {
                let p = params::<SignatureHelpRequest>(req)?;
                let (text, dir) = self.document(&p.text_document_position_params.text_document.uri);
                let offset = Lines::new(&text).offset(p.text_document_position_params.position);
                json(serde_json::to_value(crate::describe::signature_help(a, &text, offset, dir.as_deref())))
            }
            GotoDefinition::METHOD => {
                let p = params::<GotoDefinition>(req)?;
                let uri = p.text_document_position_params.text_document.uri;
                let (text, dir) = self.document(&uri);
                let offset = Lines::new(&text).offset(p.text_document_position_params.position);
                let found = crate::navigate::definition(&text, offset, &uri, dir.as_deref());
                json(serde_json::to_value(found.map(GotoDefinitionResponse::Scalar)))
            }
            DocumentHighlightRequest::METHOD => {
                // The cursor rests here: a studio of this recipe lights up the faces made here.
                let p = params::<DocumentHighlightRequest>(req)?;
                let uri = p.text_document_position_params.text_document.uri;
                let (text, _) = self.document(&uri);
                let lines = Lines::new(&text);
                let offset = lines.offset(p.text_document_position_params.position);
                let lit = path_of(&uri).and_then(|path| self.studios.cursor(&path, &text, offset));
                let highlights: Vec<lsp_types::DocumentHighlight> = lit
                    .filter(|site| site.column > 0)
                    .map(|site| lsp_types::DocumentHighlight {
                        range: lines.word_range(rhai::Position::new(site.line as u16, site.column as u16)),
                        kind: Some(lsp_types::DocumentHighlightKind::TEXT),
                    })
                    .into_iter()
                    .collect();
                json(serde_json::to_value(highlights))
            }
            DocumentSymbolRequest::METHOD => {
                let p = params::<DocumentSymbolRequest>(req)?;
                let (text, _) = self.document(&p.text_document.uri);
                json(serde_json::to_value(DocumentSymbolResponse::Nested(crate::navigate::symbols(a, &text))))
            }
            InlayHintRequest::METHOD => {
                let p = params::<InlayHintRequest>(req)?;
                let (text, _) = self.document(&p.text_document.uri);
                json(serde_json::to_value(crate::inlay::hints(a, &text, Some(p.range))))
            }
            CodeLensRequest::METHOD => {
                let p = params::<CodeLensRequest>(req)?;
                let outcome = self.outcomes.get(p.text_document.uri.as_str());
                let studio = path_of(&p.text_document.uri).and_then(|path| self.studios.url(&path).map(str::to_string));
                json(serde_json::to_value(crate::lens::lenses(&p.text_document.uri, outcome, studio.as_deref())))
            }
            ExecuteCommand::METHOD => {
                let p = params::<ExecuteCommand>(req)?;
                let known = [crate::lens::RUN, crate::studio_link::STUDIO];
                if !known.contains(&p.command.as_str()) {
                    return Err(format!("unknown command `{}`; the server runs {}", p.command, known.join(", ")));
                }
                let uri: Uri =
                    p.arguments.first().and_then(serde_json::Value::as_str).and_then(|s| s.parse().ok()).ok_or_else(
                        || format!("{}: the argument must be the recipe's file:// address", crate::lens::RUN),
                    )?;
                let path =
                    path_of(&uri).ok_or_else(|| format!("{}: not a file: {}", crate::lens::RUN, uri.as_str()))?;
                if p.command == crate::studio_link::STUDIO {
                    let url = self.studios.start(&path, self.outbox.clone(), self.show_document)?;
                    return Ok(serde_json::json!({ "url": url }));
                }
                let (text, _) = self.document(&uri);
                let outcome = crate::lens::run(&path, &text);
                let shown = serde_json::json!({ "line": outcome.line, "text": outcome.text });
                self.outcomes.insert(uri.as_str().to_string(), outcome);
                Ok(shown)
            }
            other => Err(format!("blocksmith lsp does not answer `{other}`")),
        }
    }
}

impl Default for Server {
    fn default() -> Server {
        Server::new()
    }
}
