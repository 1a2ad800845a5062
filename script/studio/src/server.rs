//! The studio's HTTP server (`tiny_http`), bound to 127.0.0.1 only. It serves the embedded
//! page ([`super::assets`]), the model on show from memory, and a WebSocket (`tungstenite`)
//! per page over which the session pushes its updates. It reads no file from disk, so no path
//! — `/../`, absolute, percent-encoded — reaches anything outside what the session shows.
//!
//! | request | answer |
//! |---|---|
//! | `GET /`, `GET /app.js`, `GET /vendor/three/...` | the page's files |
//! | `GET /model/V/I.glb` | layer `I` of model version `V` (404 once a newer model is shown) |
//! | `GET /model/V/I.control` | its control mesh's edges: little-endian `f32` x, y, z of each end |
//! | `GET /download/I.glb`, `.obj`, `.stl` | layer `I` of the model on show, as a file |
//! | `GET /api/state` | the session as JSON: model (layers, facts), error, parameters |
//! | `POST /api/params` (form body `name=value&...`) | sets the parameters; runs again if they changed |
//! | `GET /ws` | the WebSocket: JSON messages `model`, `error`, `running`, `params`; a `model` is followed by binary messages, each layer's `.glb` then each control mesh's edges |
//!
//! A page gets a model's files over its WebSocket, right behind the message, not by asking for
//! them: no request and answer per file between the save and the screen (the `/model/` paths
//! serve the same bytes to tools and tests).

use std::collections::BTreeMap;
use std::io::{Cursor, Read};
use std::net::SocketAddr;
use std::sync::Arc;

use blocksmith_kernel::io::{obj::write_obj, stl::write_stl};
use tiny_http::{Header, Method, Request, Response, Server, StatusCode};

use super::assets;
use super::session::Session;

/// A running server.
pub struct Studio {
    server: Arc<Server>,
    pub addr: SocketAddr,
}

impl Studio {
    /// Binds 127.0.0.1:`port` (0: any free port).
    ///
    /// # Errors
    /// The port cannot be bound (in use, or not allowed).
    pub fn bind(port: u16) -> Result<Studio, String> {
        let server =
            Server::http(("127.0.0.1", port)).map_err(|e| format!("error: cannot listen on 127.0.0.1:{port}: {e}"))?;
        let addr = server.server_addr().to_ip().ok_or("error: the server has no IP address")?;
        Ok(Studio { server: Arc::new(server), addr })
    }

    /// The page's address.
    #[must_use]
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Answers requests for `session`, each on its own thread, until the process ends.
    pub fn serve(&self, session: &Arc<Session>) {
        for request in self.server.incoming_requests() {
            let session = Arc::clone(session);
            std::thread::spawn(move || handle(request, &session));
        }
    }
}

fn header(text: &str) -> Header {
    text.parse().expect("a well-formed header")
}

fn respond(request: Request, status: u16, media_type: &str, body: Vec<u8>) {
    let length = body.len();
    let response = Response::new(
        StatusCode(status),
        vec![header(&format!("Content-Type: {media_type}")), header("Cache-Control: no-store")],
        Cursor::new(body),
        Some(length),
        None,
    );
    // The page may have gone away; nothing to do then.
    let _ = request.respond(response);
}

fn not_found(request: Request) {
    respond(request, 404, "text/plain; charset=utf-8", b"not found".to_vec());
}

fn handle(mut request: Request, session: &Session) {
    let url = request.url().to_string();
    let path = url.split('?').next().unwrap_or("").to_string();
    let parts: Vec<&str> = path.split('/').collect();
    match (request.method(), parts.as_slice()) {
        (Method::Get, ["", "ws"]) => websocket(request, session),
        (Method::Get, ["", "api", "state"]) => {
            respond(request, 200, "application/json", session.snapshot().to_string().into_bytes());
        }
        (Method::Post, ["", "api", "params"]) => {
            let mut body = String::new();
            if request.as_reader().take(1 << 20).read_to_string(&mut body).is_err() {
                return respond(request, 400, "text/plain; charset=utf-8", b"the body is not UTF-8".to_vec());
            }
            session.set_params(parse_form(&body));
            respond(request, 204, "text/plain; charset=utf-8", Vec::new());
        }
        (Method::Get, ["", "model", version, file]) => {
            let found = session.model().filter(|m| version.parse() == Ok(m.version)).and_then(|m| {
                let (i, ext) = file.split_once('.')?;
                let layer = m.layers.get(i.parse::<usize>().ok()?)?;
                match ext {
                    "glb" => Some(("model/gltf-binary", layer.glb.clone())),
                    "control" => {
                        let ends = layer.control.as_ref()?;
                        Some(("application/octet-stream", ends.iter().flat_map(|x| x.to_le_bytes()).collect()))
                    }
                    _ => None,
                }
            });
            match found {
                Some((media, body)) => respond(request, 200, media, body),
                None => not_found(request),
            }
        }
        (Method::Get, ["", "download", file]) => download(request, session, file),
        (Method::Get, _) => match assets::find(&path) {
            Some(a) => respond(request, 200, a.media_type, a.bytes.to_vec()),
            None => not_found(request),
        },
        _ => respond(request, 405, "text/plain; charset=utf-8", b"method not allowed".to_vec()),
    }
}

/// Layer `I` of the model on show as `I.glb` (as shown, animation included), `.obj` or `.stl`.
fn download(request: Request, session: &Session, file: &str) {
    let model = session.model();
    let Some((index, ext)) = file.split_once('.') else { return not_found(request) };
    let Some(layer) = model.as_ref().and_then(|m| m.layers.get(index.parse::<usize>().ok()?)) else {
        return not_found(request);
    };
    let stem = session.source.path().file_stem().map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let name: String =
        format!("{stem}-{}", layer.name).chars().filter(|c| c.is_alphanumeric() || "-_".contains(*c)).collect();
    let mut bytes = Vec::new();
    let (media, ok) = match ext {
        "glb" => {
            bytes.clone_from(&layer.glb);
            ("model/gltf-binary", true)
        }
        "obj" => ("text/plain; charset=utf-8", write_obj(&layer.mesh, &mut bytes).is_ok()),
        "stl" => ("model/stl", write_stl(&layer.mesh, &mut bytes, std::path::Path::new("download.stl")).is_ok()),
        _ => return not_found(request),
    };
    if !ok {
        return respond(request, 500, "text/plain; charset=utf-8", format!("cannot write the .{ext}").into_bytes());
    }
    let response = Response::from_data(bytes)
        .with_header(header(&format!("Content-Type: {media}")))
        .with_header(header(&format!("Content-Disposition: attachment; filename=\"{name}.{ext}\"")));
    let _ = request.respond(response);
}

/// `name=value&...` with `+` and `%XX` decoded; a pair without `=` or with an empty name is
/// skipped.
#[must_use]
pub fn parse_form(body: &str) -> BTreeMap<String, String> {
    body.split('&')
        .filter_map(|pair| pair.split_once('='))
        .map(|(k, v)| (decode(k), decode(v)))
        .filter(|(k, _)| !k.is_empty())
        .collect()
}

fn decode(text: &str) -> String {
    let hex = |b: u8| char::from(b).to_digit(16).map(|d| d as u8);
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let escaped = match bytes.get(i..i + 3) {
            Some([b'%', hi, lo]) => hex(*hi).zip(hex(*lo)).map(|(h, l)| h * 16 + l),
            _ => None,
        };
        match (escaped, bytes[i]) {
            (Some(b), _) => {
                out.push(b);
                i += 3;
            }
            (None, b'+') => {
                out.push(b' ');
                i += 1;
            }
            (None, b) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The version of the model a `model` message announces; `None` for other messages.
fn model_version(message: &str) -> Option<u64> {
    let v: serde_json::Value = serde_json::from_str(message).ok()?;
    (v["type"] == "model").then(|| v["version"].as_u64()).flatten()
}

/// Upgrades to a WebSocket and sends the session's messages until the page goes away; a
/// model's message is followed by its files (see the module documentation), and one already
/// replaced by a newer model is skipped (the newer one's message follows).
fn websocket(request: Request, session: &Session) {
    let key = request.headers().iter().find(|h| h.field.equiv("Sec-WebSocket-Key")).map(|h| h.value.to_string());
    let Some(key) = key else {
        return respond(request, 400, "text/plain; charset=utf-8", b"expected a WebSocket upgrade".to_vec());
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let response = Response::empty(StatusCode(101)).with_header(header(&format!("Sec-WebSocket-Accept: {accept}")));
    let stream = request.upgrade("websocket", response);
    let mut socket = tungstenite::WebSocket::from_raw_socket(stream, tungstenite::protocol::Role::Server, None);
    let updates = session.follow();
    while let Ok(message) = updates.recv() {
        let mut files = Vec::new();
        if let Some(version) = model_version(&message) {
            let Some(model) = session.model().filter(|m| m.version == version) else { continue };
            files.extend(model.layers.iter().map(|l| l.glb.clone()));
            let ends = model.layers.iter().filter_map(|l| l.control.as_ref());
            files.extend(ends.map(|e| e.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>()));
        }
        let frames = std::iter::once(tungstenite::Message::text(message))
            .chain(files.into_iter().map(tungstenite::Message::binary));
        for frame in frames {
            if socket.send(frame).is_err() {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn form_bodies_decode_plus_and_percent_and_skip_nameless_pairs() {
        let p = parse_form("teeth=16&name=big+gear&sym=%3D%26&bad%zz=1&=5&flag");
        assert_eq!(p.get("teeth").map(String::as_str), Some("16"));
        assert_eq!(p.get("name").map(String::as_str), Some("big gear"));
        assert_eq!(p.get("sym").map(String::as_str), Some("=&"));
        assert_eq!(p.get("bad%zz").map(String::as_str), Some("1"));
        assert_eq!(p.len(), 4);
        assert_eq!(decode("100%"), "100%");
        assert_eq!(decode("%4"), "%4");
    }
}
