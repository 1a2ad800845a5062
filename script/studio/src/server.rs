//! The studio's HTTP server, bound to 127.0.0.1 only, on the standard library's sockets with
//! the bounded reading of [`super::http`] (why not a server crate: see there). It serves the
//! embedded page ([`super::assets`]), the models on show from memory, and a WebSocket per page
//! ([`super::socket`]) over which the session pushes its updates. It reads no file from disk,
//! so no path — `/../`, absolute, percent-encoded — reaches anything outside what it shows.
//! Who may ask for what is [`super::guard`]'s: Host, token, Origin, non-simple requests.
//!
//! | request | token | answer |
//! |---|---|---|
//! | `GET /`, `GET /app.js`, `GET /vendor/three/...` | — | the page's files |
//! | `GET /ws?token=T&name=value...` | query | the page's WebSocket, its parameters those of the query: JSON messages `model`, `error`, `running`, `params` out, a `model` followed by binary messages, each layer's `.glb` then each control mesh's edges; `{"type": "params", "values": {...}}` in |
//! | `GET /api/state?name=value...` | header or query | the state of the variant with those parameters (over the defaults) as JSON: model (layers, facts, warnings), error, parameters, running |
//! | `POST /api/params` (`Content-Type: application/json`, `{"name": "value", ...}`) | header | asks for the variant with those parameters, run if new; 202 and the parameters in force |
//! | `GET /model/V/I.glb` | header or query | layer `I` of model version `V` (404 once it is no longer shown) |
//! | `GET /model/V/I.control` | header or query | its control mesh's edges: little-endian `f32` x, y, z of each end |
//! | `GET /model/V/I.provenance` | header or query | for a boolean result, the layer as `.glb` coloured by operand (one colour per source mesh), the page's debugging view |
//! | `GET /model/V/I.faces?line=L&column=C&file=F` | header or query | the triangles of the faces of layer `I` made by the call written at `F:L:C` (any column when `C` is 0 or missing, any file when `F` is missing): little-endian `f32` x, y, z of each corner |
//! | `GET /model/V/I.faces?component=K` | header or query | the same, of the faces of component `K` of layer `I` (numbered as `.defects` lists them) |
//! | `GET /model/V/I.defects` | header or query | what is wrong with layer `I` as geometry to draw, JSON ([`super::defects::json`]): boundaries and handle loops as segments, crossing faces as triangles, the components |
//! | `POST /api/pick` (`Content-Type: application/json`, `{"version": V, "layer": I, "point": [x, y, z], "editor": true}`) | header | the face of layer `I` nearest the point (kernel axes), its triangles and the chain of calls that made it, first call first: `{face, triangles: [x, y, z of each corner], steps: [{call, file, line, column}], editor}`; an editor following the studio (`blocksmith lsp`) is shown the first call's line unless `"editor": false` (the page's measure tool) (`editor`: whether one was told) |
//! | `GET /download/V/I.glb`, `.obj`, `.stl` | header or query | layer `I` of model `V` as a file |
//!
//! At most [`MAX_CONNECTIONS`] connections (sockets included) are served at once; more are
//! answered 503 and closed. Every connection has its own thread, which ends with it.

use std::io::BufReader;
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use blocksmith_kernel::io::{obj::write_obj, stl::write_stl};

use super::assets;
use super::guard;
use super::http::{read_request, Refused, Request, Response, HEAD_TIME};
use super::recipe_lines;
use super::session::{Params, Session};
use super::socket;

/// The most connections served at once.
pub const MAX_CONNECTIONS: usize = 128;
/// The most requests on one kept-alive connection.
const MAX_REQUESTS: usize = 1000;
/// How long accepting may keep failing for a reason that does not pass by itself (not a
/// want of descriptors or memory, which pages give back) before the server gives up and says
/// so.
const GIVE_UP: Duration = Duration::from_secs(60);

/// A running server.
pub struct Studio {
    listener: TcpListener,
    pub addr: SocketAddr,
    token: String,
}

/// Counts an open connection while it lives.
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

impl Studio {
    /// Binds 127.0.0.1:`port` (0: any free port) and makes the session's token.
    ///
    /// # Errors
    /// The port cannot be bound (in use, or not allowed), or there is no randomness.
    pub fn bind(port: u16) -> Result<Studio, String> {
        let listener = TcpListener::bind(("127.0.0.1", port))
            .map_err(|e| format!("error: cannot listen on 127.0.0.1:{port}: {e}"))?;
        let addr = listener.local_addr().map_err(|e| format!("error: the server has no address: {e}"))?;
        Ok(Studio { listener, addr, token: guard::session_token()? })
    }

    /// The page's address, with the token.
    #[must_use]
    pub fn url(&self) -> String {
        format!("http://{}/?token={}", self.addr, self.token)
    }

    /// Answers requests for `session`, each connection on its own thread, for as long as it
    /// can: it returns only when accepting connections has failed for [`GIVE_UP`] for a reason
    /// other than running short of descriptors or memory (which it waits out, saying so once).
    ///
    /// # Errors
    /// Why the server stopped.
    pub fn serve(&self, session: &Arc<Session>) -> Result<(), String> {
        let open = Arc::new(AtomicUsize::new(0));
        // Since when accepting has failed without a break (a failure within a second of the
        // last one), for errors other than running short of descriptors or memory.
        let mut failing: Option<(Instant, Instant)> = None;
        let mut warned = false;
        loop {
            let stream = match self.listener.accept() {
                Ok((stream, _)) => stream,
                Err(e) => {
                    if !warned {
                        eprintln!("warning: the studio cannot take a connection now ({e}); it keeps trying");
                        warned = true;
                    }
                    let now = Instant::now();
                    let since = match failing {
                        Some((since, last)) if now - last < Duration::from_secs(1) => since,
                        _ => now,
                    };
                    failing = Some((since, now));
                    if !is_transient(&e) && now - since > GIVE_UP {
                        return Err(format!(
                            "error: the studio stopped: no connection could be taken for {} s: {e}",
                            GIVE_UP.as_secs()
                        ));
                    }
                    // Out of descriptors: the pages that close give them back.
                    std::thread::sleep(Duration::from_millis(50));
                    continue;
                }
            };
            (failing, warned) = (None, false);
            if open.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
                let _ = stream.set_write_timeout(Some(Duration::from_secs(1)));
                let _ = Response::empty(503).write(&mut &stream, true);
                continue;
            }
            open.fetch_add(1, Ordering::SeqCst);
            let slot = Slot(Arc::clone(&open));
            let (session, token, port) = (Arc::clone(session), self.token.clone(), self.addr.port());
            // A thread that cannot be made drops the connection (and its slot) with the closure.
            let _ = std::thread::Builder::new().name("studio connection".into()).spawn(move || {
                let _slot = slot;
                connection(stream, &session, &token, port);
            });
        }
    }
}

/// Whether accepting failed for want of something that comes back by itself: descriptors,
/// memory, buffers, or a connection that went before it was taken.
fn is_transient(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::{ConnectionAborted, ConnectionReset, Interrupted, OutOfMemory, WouldBlock};
    // EMFILE, ENFILE, ENOBUFS, ENOMEM on Linux and the BSDs (24, 23, 105/55, 12).
    matches!(e.kind(), ConnectionAborted | ConnectionReset | Interrupted | WouldBlock | OutOfMemory)
        || matches!(e.raw_os_error(), Some(23 | 24 | 12 | 55 | 105))
}

/// Serves the requests of one connection until it closes, is idle for [`HEAD_TIME`], or
/// becomes a page's socket.
fn connection(stream: TcpStream, session: &Session, token: &str, port: u16) {
    if stream.set_read_timeout(Some(HEAD_TIME)).is_err() || stream.set_write_timeout(Some(HEAD_TIME * 3)).is_err() {
        return;
    }
    let mut reader = BufReader::with_capacity(8 * 1024, stream);
    for _ in 0..MAX_REQUESTS {
        let request = match read_request(&mut reader) {
            Ok(r) => r,
            Err(Refused(0)) => return,
            Err(Refused(status)) => {
                let _ = Response::empty(status).write(reader.get_mut(), true);
                return;
            }
        };
        if !request.header("host").is_some_and(|h| guard::is_own_host(h, port)) {
            let _ = Response::empty(421).write(reader.get_mut(), true);
            return;
        }
        if request.path == "/ws" && request.method == "GET" {
            if !guard::has_token(&request, token, true) || !guard::is_own_origin(&request) {
                let _ = Response::empty(403).write(reader.get_mut(), true);
                return;
            }
            let given = page_params(&request);
            return socket::serve(reader, &request, session, &given);
        }
        let response = route(&request, session, token);
        if response.write(reader.get_mut(), request.close).is_err() || request.close {
            return;
        }
    }
}

/// The parameters a request gives in its query (all but the token).
fn page_params(request: &Request) -> Params {
    let mut p = request.query_pairs();
    p.remove("token");
    p
}

fn not_found() -> Response {
    Response::new(404, "text/plain; charset=utf-8", b"not found".to_vec())
}

fn route(request: &Request, session: &Session, token: &str) -> Response {
    let parts: Vec<&str> = request.path.split('/').collect();
    let is_asset = request.method == "GET" && !matches!(parts.get(1), Some(&("api" | "model" | "download")));
    if is_asset {
        return assets::find(&request.path)
            .map_or_else(not_found, |a| Response::new(200, a.media_type, a.bytes.to_vec()));
    }
    if request.method == "POST" {
        // State changes: only from the page's own origin, as JSON, with the token in a header.
        let json = request
            .header("content-type")
            .and_then(|t| t.split(';').next())
            .is_some_and(|t| t.trim().eq_ignore_ascii_case("application/json"));
        if !guard::is_own_origin(request) || !guard::has_token(request, token, false) {
            return Response::empty(403);
        }
        if !json {
            return Response::empty(415);
        }
    } else if request.method != "GET" || !guard::has_token(request, token, true) {
        return if request.method == "GET" { Response::empty(403) } else { Response::empty(405) };
    }
    match (request.method.as_str(), parts.as_slice()) {
        ("GET", ["", "api", "state"]) => {
            let state = session.snapshot(&page_params(request));
            Response::new(200, "application/json", state.to_string().into_bytes())
        }
        ("POST", ["", "api", "params"]) => {
            let Ok(serde_json::Value::Object(values)) = serde_json::from_slice::<serde_json::Value>(&request.body)
            else {
                return Response::new(400, "text/plain; charset=utf-8", b"expected a JSON object".to_vec());
            };
            let given: Params = values
                .into_iter()
                .map(|(k, v)| {
                    let text = v.as_str().map_or_else(|| v.to_string(), str::to_string);
                    (k, text)
                })
                .collect();
            let params = session.ask(&given);
            Response::new(202, "application/json", serde_json::json!({ "params": params }).to_string().into_bytes())
        }
        ("POST", ["", "api", "pick"]) => pick(session, &request.body),
        ("GET", ["", "model", version, file]) if file.ends_with(".faces") => faces(session, request, version, file),
        ("GET", ["", "model", version, file]) if file.ends_with(".defects") => defects(session, version, file),
        ("GET", ["", "model", version, file]) => {
            let found = version.parse().ok().and_then(|v| session.model_numbered(v)).and_then(|m| {
                let (i, ext) = file.split_once('.')?;
                let layer = m.layers.get(i.parse::<usize>().ok()?)?;
                match ext {
                    "glb" => Some(("model/gltf-binary", layer.glb.clone())),
                    "provenance" => Some(("model/gltf-binary", layer.provenance.clone()?)),
                    "control" => {
                        let ends = layer.control.as_ref()?;
                        Some(("application/octet-stream", ends.iter().flat_map(|x| x.to_le_bytes()).collect()))
                    }
                    _ => None,
                }
            });
            found.map_or_else(not_found, |(media, body)| Response::new(200, media, body))
        }
        ("GET", ["", "download", version, file]) => download(session, version, file),
        ("GET", _) => not_found(),
        _ => Response::empty(405),
    }
}

/// `POST /api/pick`: the face nearest a point and the calls that made it.
fn pick(session: &Session, body: &[u8]) -> Response {
    let bad = |why: &str| Response::new(400, "text/plain; charset=utf-8", why.as_bytes().to_vec());
    let Ok(v) = serde_json::from_slice::<serde_json::Value>(body) else { return bad("expected a JSON object") };
    let (Some(version), Some(layer)) = (v["version"].as_u64(), v["layer"].as_u64()) else {
        return bad("expected {\"version\": V, \"layer\": I, \"point\": [x, y, z]}");
    };
    let point: Vec<f64> = v["point"].as_array().into_iter().flatten().filter_map(serde_json::Value::as_f64).collect();
    let [x, y, z] = point[..] else { return bad("point: expected [x, y, z], three numbers") };
    if ![x, y, z].iter().all(|c| c.is_finite()) {
        return bad("point: expected finite numbers");
    }
    let model = session.model_numbered(version);
    let Some(mesh) = model.as_ref().and_then(|m| m.layers.get(usize::try_from(layer).ok()?)).map(|l| &l.mesh) else {
        return not_found();
    };
    let Some(face) = recipe_lines::face_at(mesh, blocksmith_kernel::Vec3::new(x, y, z)) else { return not_found() };
    let steps = recipe_lines::chain(mesh, face);
    let tell = v["editor"].as_bool().unwrap_or(true);
    let editor = tell && !steps.is_empty() && session.picked(&steps);
    let body = serde_json::json!({
        "face": face,
        "triangles": recipe_lines::corners(mesh, face),
        "steps": steps.iter().map(recipe_lines::Step::json).collect::<Vec<_>>(),
        "editor": editor,
    });
    Response::new(200, "application/json", body.to_string().into_bytes())
}

/// `GET /model/V/I.faces?line=L&column=C&file=F`: the triangles of the faces made at a line;
/// `?component=K`: of a component's faces.
fn faces(session: &Session, request: &Request, version: &str, file: &str) -> Response {
    let query = request.query_pairs();
    let number = |k: &str| query.get(k).map_or(Some(0), |v| v.parse::<u32>().ok());
    let (Some(line), Some(column), Some(component)) = (number("line"), number("column"), number("component")) else {
        return Response::new(
            400,
            "text/plain; charset=utf-8",
            b"line, column, component: expected whole numbers".to_vec(),
        );
    };
    let model = version.parse().ok().and_then(|v| session.model_numbered(v));
    let index = file.trim_end_matches(".faces").parse::<usize>().ok();
    let Some(layer) = model.as_ref().and_then(|m| m.layers.get(index?)) else { return not_found() };
    let faces = if query.contains_key("component") {
        super::defects::component_faces(&layer.mesh, component as usize)
    } else {
        recipe_lines::faces_made_at(&layer.mesh, &recipe_lines::Site { file: query.get("file").cloned(), line, column })
    };
    let corners = recipe_lines::triangles(&layer.mesh, &faces);
    Response::new(200, "application/octet-stream", corners.iter().flat_map(|x| x.to_le_bytes()).collect())
}

/// Layer `I` of model `V` as `I.glb` (as shown, animation included), `.obj` or `.stl`.
/// `GET /model/V/I.defects`: what is wrong with a layer, as geometry to draw.
fn defects(session: &Session, version: &str, file: &str) -> Response {
    let model = version.parse().ok().and_then(|v| session.model_numbered(v));
    let index = file.trim_end_matches(".defects").parse::<usize>().ok();
    let Some(layer) = model.as_ref().and_then(|m| m.layers.get(index?)) else { return not_found() };
    match super::defects::json(&layer.mesh) {
        Ok(j) => Response::new(200, "application/json", j.to_string().into_bytes()),
        Err(why) => Response::new(422, "text/plain; charset=utf-8", why.into_bytes()),
    }
}

fn download(session: &Session, version: &str, file: &str) -> Response {
    let model = version.parse().ok().and_then(|v| session.model_numbered(v));
    let Some((index, ext)) = file.split_once('.') else { return not_found() };
    let Some(layer) = model.as_ref().and_then(|m| m.layers.get(index.parse::<usize>().ok()?)) else {
        return not_found();
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
        _ => return not_found(),
    };
    if !ok {
        return Response::new(500, "text/plain; charset=utf-8", format!("cannot write the .{ext}").into_bytes());
    }
    Response::new(200, media, bytes).with("Content-Disposition", &format!("attachment; filename=\"{name}.{ext}\""))
}
