//! The editor and the studio, both ways, end to end: `blocksmith lsp` driven over its standard
//! input and output by a small JSON-RPC client here, its studio's page in a real browser
//! (Debian's `chromium`, headless; skipped when it is missing, except under CI=true). A click
//! on a pip's bite in the page lists the pip sphere's line and makes the server ask the editor
//! to show it (`window/showDocument`); the editor's cursor on a call (document highlight, hover)
//! lights up in the page the faces that call made. The page's new endpoints keep the studio's
//! rules: Host, token, Origin, JSON, bounded bodies.

#[path = "support/browser.rs"]
mod browser;
#[path = "support/child.rs"]
mod child;
#[path = "support/http.rs"]
mod http;
mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use browser::Browser;
use http::raw;
use serde_json::{json, Value};

/// The die in small: a cube with three sphere pips cut from it, the pip made on line 3.
const DIE: &str = "let body = cube(2);\n\
                   let size = 0.3;\n\
                   let pip = uv_sphere(size, 16, 8);\n\
                   let die = body - pip.translate([0, 0, 1]);\n\
                   for c in [[0.5, 0.5, -1], [-0.5, -0.5, -1]] { die = die - pip.translate(c); }\n\
                   die\n";

/// `blocksmith lsp` and what it says, message by message.
struct Lsp {
    child: Child,
    input: ChildStdin,
    said: Receiver<Value>,
    next: u64,
}

impl Drop for Lsp {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Lsp {
    fn start() -> Lsp {
        let mut child = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let input = child.stdin.take().unwrap();
        let mut out = BufReader::new(child.stdout.take().unwrap());
        let (tx, said) = mpsc::channel();
        std::thread::spawn(move || loop {
            let mut length = 0;
            loop {
                let mut line = String::new();
                if out.read_line(&mut line).unwrap_or(0) == 0 {
                    return;
                }
                if let Some(n) = line.strip_prefix("Content-Length: ") {
                    length = n.trim().parse().unwrap();
                }
                if line == "\r\n" {
                    break;
                }
            }
            let mut body = vec![0; length];
            if out.read_exact(&mut body).is_err() || tx.send(serde_json::from_slice(&body).unwrap()).is_err() {
                return;
            }
        });
        Lsp { child, input, said, next: 0 }
    }

    fn send(&mut self, message: &Value) {
        let body = message.to_string();
        write!(self.input, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        self.input.flush().unwrap();
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// The next message from the server that `wanted` accepts (others are dropped), within 30 s.
    fn expect(&mut self, what: &str, wanted: impl Fn(&Value) -> bool) -> Value {
        let until = Instant::now() + Duration::from_secs(30);
        loop {
            let left = until.saturating_duration_since(Instant::now());
            let m = self.said.recv_timeout(left).unwrap_or_else(|_| panic!("no {what} from the server"));
            if wanted(&m) {
                return m;
            }
        }
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next += 1;
        let id = self.next;
        self.send(&json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        let answer = self.expect(method, |m| m["id"] == id && m.get("method").is_none());
        assert!(answer["error"].is_null(), "{method}: {answer}");
        answer["result"].clone()
    }
}

fn position_of(text: &str, needle: &str, plus: usize) -> Value {
    let at = text.find(needle).unwrap() + plus;
    let line = text[..at].matches('\n').count();
    let character = at - text[..at].rfind('\n').map_or(0, |i| i + 1);
    json!({ "line": line, "character": character })
}

/// A pick as a page would send it, with `headers` (Host and Connection added) and `body`.
fn pick(addr: &str, headers: &str, body: &str) -> (u16, Value) {
    let request = format!(
        "POST /api/pick HTTP/1.1\r\nHost: {addr}\r\n{headers}Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    let (status, body) = raw(addr, request.as_bytes());
    (status, serde_json::from_slice(&body).unwrap_or(Value::Null))
}

#[test]
fn a_click_in_the_studio_shows_the_line_in_the_editor_and_the_cursor_lights_the_faces_in_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("die.rhai");
    std::fs::write(&recipe, DIE).unwrap();
    let recipe = recipe.canonicalize().unwrap();
    let uri = format!("file://{}", recipe.display());
    let mut lsp = Lsp::start();
    lsp.request(
        "initialize",
        json!({ "processId": null, "rootUri": null, "capabilities": { "window": { "showDocument": { "support": true } } } }),
    );
    lsp.notify("initialized", json!({}));
    lsp.notify(
        "textDocument/didOpen",
        json!({ "textDocument": { "uri": uri, "languageId": "rhai", "version": 1, "text": DIE } }),
    );
    // The studio lens starts the studio; the editor is asked to open its page.
    let lenses = lsp.request("textDocument/codeLens", json!({ "textDocument": { "uri": uri } }));
    assert!(lenses.as_array().unwrap().iter().any(|l| l["command"]["command"] == "blocksmith.studio"), "{lenses}");
    let started =
        lsp.request("workspace/executeCommand", json!({ "command": "blocksmith.studio", "arguments": [uri] }));
    let url = started["url"].as_str().unwrap().to_string();
    let open = lsp.expect("a request to open the page", |m| m["method"] == "window/showDocument");
    assert_eq!(open["params"], json!({ "uri": url, "external": true }));
    let lenses = lsp.request("textDocument/codeLens", json!({ "textDocument": { "uri": uri } }));
    assert!(lenses.to_string().contains(&url), "the lens shows the address: {lenses}");

    let addr = url.trim_start_matches("http://").split('/').next().unwrap().to_string();
    let token = url.split("token=").nth(1).unwrap().to_string();
    let own = format!("Origin: http://{addr}\r\nX-Blocksmith-Token: {token}\r\nContent-Type: application/json\r\n");
    // The model is made (the session's first run) once the state says so.
    let until = Instant::now() + Duration::from_secs(60);
    let version = loop {
        let get = format!(
            "GET /api/state HTTP/1.1\r\nHost: {addr}\r\nX-Blocksmith-Token: {token}\r\nConnection: close\r\n\r\n"
        );
        let (_, body) = raw(&addr, get.as_bytes());
        let state: Value = serde_json::from_slice(&body).unwrap_or(Value::Null);
        if let Some(v) = state["model"]["version"].as_u64() {
            break v;
        }
        assert!(Instant::now() < until, "no model: {state}");
        std::thread::sleep(Duration::from_millis(100));
    };

    // The rules: a pick needs the token in a header, the page's own origin, JSON; a bad body is
    // refused by name; the faces of a line need the token too; a huge body is refused unread.
    let body = json!({ "version": version, "layer": 0, "point": [1.0, 0.2, -0.3] }).to_string();
    let without_token = format!("Origin: http://{addr}\r\nContent-Type: application/json\r\n");
    assert_eq!(pick(&addr, &without_token, &body).0, 403);
    let other_origin = own.replace(&format!("http://{addr}"), "http://evil.example");
    assert_eq!(pick(&addr, &other_origin, &body).0, 403);
    assert_eq!(pick(&addr, &own.replace("application/json", "text/plain"), &body).0, 415);
    assert_eq!(pick(&addr, &own, "{\"version\": 1}").0, 400);
    assert_eq!(pick(&addr, &own, &json!({ "version": version, "layer": 0, "point": [1, 2] }).to_string()).0, 400);
    assert_eq!(
        pick(&addr, &own, &json!({ "version": version + 9, "layer": 0, "point": [0, 0, 0] }).to_string()).0,
        404
    );
    let huge = format!("{{\"pad\": \"{}\"}}", "x".repeat(70_000));
    assert_eq!(pick(&addr, &own, &huge).0, 413, "a body past 64 KiB is refused");
    let wrong_host = format!("POST /api/pick HTTP/1.1\r\nHost: evil.example\r\n{own}Content-Length: 2\r\n\r\n{{}}");
    assert_eq!(raw(&addr, wrong_host.as_bytes()).0, 421);
    let faces = |query: &str| {
        let get = format!("GET /model/{version}/0.faces?{query} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n");
        raw(&addr, get.as_bytes())
    };
    assert_eq!(faces("line=3").0, 403, "no token");
    let (status, sphere) = faces(&format!("line=3&token={token}"));
    assert_eq!(status, 200);
    assert_eq!(sphere.len() % 36, 0);
    assert!(!sphere.is_empty());
    assert_eq!(faces(&format!("line=x&token={token}")).0, 400);
    // A side face, picked by a tool as a page would: the cube's line, shown in the editor.
    let (status, side) = pick(&addr, &own, &body);
    assert_eq!(status, 200);
    assert_eq!(side["steps"][0]["call"], "cube");
    assert_eq!(side["steps"][0]["line"], 1);
    assert_eq!(side["editor"], true);
    let shown = lsp.expect("a request to show line 1", |m| m["method"] == "window/showDocument");
    assert_eq!(shown["params"]["uri"], uri);
    assert_eq!(shown["params"]["selection"]["start"], json!({ "line": 0, "character": 11 }));

    let Some(mut b) = Browser::open(&url) else { return };
    b.wait("window.studio && studio.triangles > 0", Duration::from_secs(30));
    // Model → line: a real click on the top pip's bite, on its far wall as the camera sees it
    // (from +x, -y, above): the point of the sphere 0.3 about (0, 0, 1) towards (-1, 1.4, -0.5).
    let xy = b.eval("studio.screenOf([-0.1674, 0.2344, 0.9163])");
    let (x, y) = (xy[0].as_f64().unwrap(), xy[1].as_f64().unwrap());
    for kind in ["mousePressed", "mouseReleased"] {
        b.call(
            "Input.dispatchMouseEvent",
            json!({ "type": kind, "x": x, "y": y, "button": "left", "buttons": 1, "clickCount": 1 }),
        );
    }
    b.wait("studio.picked", Duration::from_secs(20));
    let picked = b.eval("studio.picked");
    let calls: Vec<&str> = picked["steps"].as_array().unwrap().iter().map(|s| s["call"].as_str().unwrap()).collect();
    assert_eq!(calls, ["uv_sphere", "translate", "-", "-", "-"], "{picked}");
    assert_eq!(picked["steps"][0]["line"], 3);
    assert_eq!(picked["steps"][0]["column"], 11);
    let listed = b.eval("document.getElementById('source').textContent").as_str().unwrap().to_string();
    assert!(listed.contains("uv_sphere at die.rhai:3:11") && listed.contains("shown in the editor"), "{listed}");
    let shown = lsp.expect("a request to show the pip's line", |m| m["method"] == "window/showDocument");
    assert_eq!(shown["params"]["uri"], uri);
    let range = &shown["params"]["selection"];
    assert_eq!(
        (range["start"].clone(), range["end"].clone()),
        (position_of(DIE, "uv_sphere", 0), position_of(DIE, "uv_sphere", 9))
    );
    // The click lit the sphere's faces: every lit corner on the pips' spheres.
    b.wait("studio.lit > 0", Duration::from_secs(10));
    let on_a_pip = "studio.litCorners().every((_, i, a) => i % 3 || [[0, 0, 1], [0.5, 0.5, -1], [-0.5, -0.5, -1]]\
                    .some(([x, y, z]) => Math.hypot(a[i] - x, a[i + 1] - y, a[i + 2] - z) <= 0.3 + 1e-4))";
    assert_eq!(b.eval(on_a_pip), true);

    // Line → faces: the editor's cursor on `cube` (a document-highlight request, as editors send
    // when the cursor rests) lights the cube's faces, none on a pip; on `pip.translate` in the
    // loop (hover), the two lower pips' faces only.
    let highlight = lsp.request(
        "textDocument/documentHighlight",
        json!({ "textDocument": { "uri": uri }, "position": position_of(DIE, "cube", 1) }),
    );
    assert_eq!(highlight[0]["range"]["start"], position_of(DIE, "cube", 0));
    b.wait("studio.litSite && studio.litSite.line === 1", Duration::from_secs(10));
    let lit_cube = b.eval("studio.lit").as_u64().unwrap();
    assert!(lit_cube > 0);
    // No lit corner deep inside a pip (the rims of the bites, cut by the 16 × 8 polygonal spheres,
    // are up to 0.3 (1 - cos(π / 16)) = 0.006 inside the round ones).
    let deepest = "(() => { const a = studio.litCorners(); let d = Infinity; \
                   for (let i = 0; i < a.length; i += 3) for (const [x, y, z] of [[0, 0, 1], [0.5, 0.5, -1], [-0.5, -0.5, -1]]) \
                   d = Math.min(d, Math.hypot(a[i] - x, a[i + 1] - y, a[i + 2] - z)); return d; })()";
    let d = b.eval(deepest).as_f64().unwrap();
    assert!(d > 0.3 - 0.01, "a lit corner of the cube {d} from a pip's centre");
    lsp.request(
        "textDocument/hover",
        json!({ "textDocument": { "uri": uri }, "position": position_of(DIE, "translate(c)", 2) }),
    );
    b.wait("studio.litSite && studio.litSite.line === 5", Duration::from_secs(10));
    let lower = "studio.litCorners().every((_, i, a) => i % 3 || [[0.5, 0.5, -1], [-0.5, -0.5, -1]]\
                 .some(([x, y, z]) => Math.hypot(a[i] - x, a[i + 1] - y, a[i + 2] - z) <= 0.3 + 1e-4))";
    assert_eq!(b.eval(lower), true);
    assert!(b.eval("studio.lit").as_u64().unwrap() > 0);
}

/// `exit` ends the server even with a studio running: the studio's threads, which outlive the
/// editor's loop, must not keep the connection (and so the process) open — an editor waits for
/// its server to end, and a test client waits forever.
#[test]
fn exit_ends_the_server_with_a_studio_running() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("die.rhai");
    std::fs::write(&recipe, DIE).unwrap();
    let uri = format!("file://{}", recipe.canonicalize().unwrap().display());
    let mut lsp = Lsp::start();
    lsp.request("initialize", json!({ "processId": null, "rootUri": null, "capabilities": {} }));
    lsp.notify("initialized", json!({}));
    let started =
        lsp.request("workspace/executeCommand", json!({ "command": "blocksmith.studio", "arguments": [uri] }));
    assert!(started["url"].as_str().unwrap().starts_with("http://"), "{started}");
    lsp.request("shutdown", Value::Null);
    lsp.notify("exit", Value::Null);
    let status = child::wait_within(&mut lsp.child, Duration::from_secs(20))
        .unwrap_or_else(|| panic!("the server still runs 20 s after `exit`"));
    assert!(status.success(), "{status}");
}
