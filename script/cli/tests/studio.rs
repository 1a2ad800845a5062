//! `blocksmith watch` end to end: the server answers on 127.0.0.1 only, serves nothing outside
//! what it shows (`/../`, absolute and percent-encoded paths), re-runs on save but not on the
//! recipe's own saves, `view` follows a `.gltf`'s buffer, and the page shows the model (and its
//! control mesh through moves and booleans) in a real browser (Debian's `chromium`, headless
//! on SwiftShader; skipped when it is missing, except under CI=true, where it must be there).

#[path = "support/browser.rs"]
mod browser;
#[path = "support/http.rs"]
mod http;
#[path = "support/repl.rs"]
mod repl;
mod support;
use browser::Browser;
use http::raw;
use repl::repl;
use support::chromium;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A studio server's address (`127.0.0.1:PORT`) and token.
#[derive(Clone, Debug)]
struct Server {
    addr: String,
    token: String,
}

impl Server {
    /// The server of an address line `... http://127.0.0.1:PORT/?token=T ...`.
    fn of(line: &str) -> Server {
        let url = line.split("http://").nth(1).expect("an address").split_whitespace().next().unwrap();
        let (addr, rest) = url.split_once('/').unwrap();
        let token = rest.strip_prefix("?token=").expect("a token in the address").to_string();
        Server { addr: addr.to_string(), token }
    }

    /// The page's address as printed.
    fn url(&self) -> String {
        format!("http://{}/?token={}", self.addr, self.token)
    }

    fn port(&self) -> u16 {
        self.addr.split(':').nth(1).unwrap().parse().unwrap()
    }
}

/// A `blocksmith watch` process, stopped when dropped.
struct Watch {
    child: Child,
    server: Server,
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl std::ops::Deref for Watch {
    type Target = Server;
    fn deref(&self) -> &Server {
        &self.server
    }
}

fn watch(recipe: &Path) -> Watch {
    watch_with(recipe, &[])
}

fn watch_with(recipe: &Path, args: &[&str]) -> Watch {
    watch_command("watch", recipe, args)
}

/// `blocksmith COMMAND FILE ARGS...` (`watch` or `view`), once it has printed its address.
fn watch_command(command: &str, file: &Path, args: &[&str]) -> Watch {
    watch_env(command, file, args, &[])
}

/// As [`watch_command`], with environment variables `env`.
fn watch_env(command: &str, file: &Path, args: &[&str], env: &[(&str, &str)]) -> Watch {
    let mut child = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .envs(env.iter().copied())
        .arg(command)
        .arg(file)
        .args(args)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    // The address line (a quick first run may say it was shown before it).
    let first = lines.by_ref().map_while(Result::ok).find(|l| l.contains("http://"));
    let Some(first) = first else {
        let _ = child.kill();
        panic!("no address printed");
    };
    // Keep draining its messages so it never blocks on a full pipe.
    std::thread::spawn(move || lines.for_each(drop));
    Watch { child, server: Server::of(&first) }
}

/// A raw GET of `path` as sent (no normalisation), with the token in its header: status and body.
fn get(server: &Server, path: &str) -> (u16, Vec<u8>) {
    let Server { addr, token } = server;
    raw(
        addr,
        format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\nX-Blocksmith-Token: {token}\r\nConnection: close\r\n\r\n")
            .as_bytes(),
    )
}

/// A POST of JSON `body` to `path` as the page's own script would send it.
fn post_json(server: &Server, path: &str, body: &str) -> u16 {
    let Server { addr, token } = server;
    let request = format!(
        "POST {path} HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nX-Blocksmith-Token: {token}\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    raw(addr, request.as_bytes()).0
}

/// The session's state (of the variant with the parameters of `query`, `name=value&...`) once
/// `ready` holds of it, within `limit`.
fn state_of(
    server: &Server,
    query: &str,
    limit: Duration,
    ready: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let start = Instant::now();
    loop {
        let (status, body) = get(server, &format!("/api/state?{query}"));
        assert_eq!(status, 200);
        let v: serde_json::Value = serde_json::from_slice(&body).unwrap();
        if ready(&v) {
            return v;
        }
        assert!(start.elapsed() < limit, "not ready after {limit:?}: {v}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The state of the page without parameters once `ready` holds of it, within `limit`.
fn state_when(server: &Server, limit: Duration, ready: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
    state_of(server, "", limit, ready)
}

fn triangles(v: &serde_json::Value) -> Option<u64> {
    v["model"]["layers"][0]["facts"]["triangles"].as_u64()
}

#[test]
fn watch_serves_only_what_it_shows_and_runs_again_on_save() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    std::fs::write(&recipe, "cube(1)").unwrap();
    std::fs::write(dir.path().join("secret.txt"), "not for the page").unwrap();
    let w = watch(&recipe);
    assert!(w.addr.starts_with("127.0.0.1:"), "{}", w.addr);
    assert_eq!(w.token.len(), 32, "a 128-bit token in the address");
    // Bound to 127.0.0.1 itself, not to every address: another loopback address of the same
    // port (all of 127/8 reaches this machine) is refused.
    let port = w.addr.split(':').nth(1).unwrap();
    let other = format!("127.0.0.2:{port}").parse().unwrap();
    assert!(TcpStream::connect_timeout(&other, Duration::from_secs(2)).is_err(), "answered on {other}");
    let v = state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    assert_eq!(triangles(&v), Some(12));
    let (status, page) = get(&w, "/");
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&page).contains("importmap"));
    let url = v["model"]["layers"][0]["url"].as_str().unwrap();
    assert_eq!(&get(&w, url).1[..4], b"glTF");
    for (ext, magic) in [("glb", &b"glTF"[..]), ("obj", b"# "), ("stl", b"")] {
        let (status, body) = get(&w, &format!("/download/{}/0.{ext}", version(&v)));
        assert_eq!(status, 200, ".{ext}");
        assert!(body.starts_with(magic), ".{ext}");
    }
    for bad in [
        "/../secret.txt",
        "/secret.txt",
        "/part.rhai",
        "/..%2fsecret.txt",
        "/%2e%2e/%2e%2e/etc/passwd",
        "//etc/passwd",
        "/vendor/three/../../../secret.txt",
        &format!("/{}", dir.path().join("secret.txt").display()),
        "/model/1/../../secret.txt",
        "/download/../secret.txt",
        "/%2e%2e%2fsecret.txt",
        "/..%5csecret.txt",
        &format!("/{}", dir.path().join("secret.txt").display().to_string().replace('/', "%2F")),
        "/model/1/%2e%2e%2f%2e%2e%2fsecret.txt",
    ] {
        let (status, body) = get(&w, bad);
        assert_eq!(status, 404, "{bad}");
        assert!(!String::from_utf8_lossy(&body).contains("not for the page"), "{bad}");
    }
    // A save shows the new model; a syntax error keeps it and says where.
    std::fs::write(&recipe, "icosphere(1, 1)").unwrap();
    state_when(&w, Duration::from_secs(10), |v| triangles(v) == Some(80));
    std::fs::write(&recipe, "let a = ;\nicosphere(1, 1)").unwrap();
    let v = state_when(&w, Duration::from_secs(10), |v| v["error"].is_string());
    assert!(v["error"].as_str().unwrap().contains("part.rhai:1:"), "{v}");
    assert_eq!(triangles(&v), Some(80), "the last good model stays");
    // A parameter from the page's controls runs the recipe with it.
    std::fs::write(&recipe, "cube(param(\"size\", 1, #{ min: 0.1 }))").unwrap();
    state_when(&w, Duration::from_secs(10), |v| v["model"]["params"][0]["name"] == "size");
    assert_eq!(post_json(&w, "/api/params", r#"{"size": "2"}"#), 202);
    let v = state_of(&w, "size=2", Duration::from_secs(10), |v| v["model"]["params"][0]["value"] == 2);
    assert!((v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap() - 8.0).abs() < 1e-6, "{v}");
    assert_eq!(v["model"]["params"][0]["min"], 0.1);
    // ... for that variant only: the page without parameters still shows size 1.
    let v = state_when(&w, Duration::from_secs(1), |_| true);
    assert!((v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap() - 1.0).abs() < 1e-6, "{v}");
}

/// An upgrade to a WebSocket at `path` with `headers`, sent raw: the status of the answer.
fn upgrade(server: &Server, path: &str, headers: &str) -> u16 {
    let addr = &server.addr;
    let request = format!(
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n{headers}\r\n"
    );
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    s.write_all(request.as_bytes()).unwrap();
    let mut head = [0u8; 12];
    s.read_exact(&mut head).map_or(0, |()| std::str::from_utf8(&head[9..12]).unwrap().parse().unwrap())
}

/// A page's socket as a tool opens it: `query` after the token.
fn socket(server: &Server, query: &str) -> tungstenite::Result<tungstenite::WebSocket<TcpStream>> {
    let url = format!("ws://{}/ws?token={}{query}", server.addr, server.token);
    let stream = TcpStream::connect(&server.addr)?;
    stream.set_read_timeout(Some(Duration::from_secs(3)))?;
    tungstenite::client(url.as_str(), stream).map(|(s, _)| s).map_err(|e| match e {
        tungstenite::HandshakeError::Failure(e) => e,
        tungstenite::HandshakeError::Interrupted(_) => tungstenite::Error::ConnectionClosed,
    })
}

#[test]
fn only_the_printed_page_may_read_or_drive_the_studio() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    std::fs::write(&recipe, "cube(param(\"size\", 1))").unwrap();
    let w = watch(&recipe);
    let v = state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let (addr, token, port) = (w.addr.clone(), w.token.clone(), w.port());
    let n = version(&v);
    let paths = [
        "/".to_string(),
        "/app.js".into(),
        "/api/state".into(),
        format!("/model/{n}/0.glb"),
        format!("/model/{n}/0.defects"),
        format!("/download/{n}/0.glb"),
    ];
    // A DNS-rebinding page names its own host: nothing is answered, not even the page.
    for host in
        ["evil.example:PORT", "evil.example", "127.0.0.1", "localhost", "127.0.0.1:1", "127.0.0.1.evil.example:PORT"]
    {
        let host = host.replace("PORT", &port.to_string());
        for path in &paths {
            let request =
                format!("GET {path}?token={token} HTTP/1.1\r\nHost: {host}\r\nX-Blocksmith-Token: {token}\r\n\r\n");
            let (status, body) = raw(&addr, request.as_bytes());
            assert_eq!((status, body.len()), (421, 0), "Host: {host} {path}");
        }
    }
    let no_host = raw(&addr, b"GET / HTTP/1.0\r\n\r\n");
    assert_eq!(no_host, (421, Vec::new()));
    for host in [format!("localhost:{port}"), format!("127.0.0.1:{port}"), format!("[::1]:{port}")] {
        let (status, _) = raw(&addr, format!("GET / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").as_bytes());
        assert_eq!(status, 200, "{host}");
    }
    // The page itself needs no token; everything else does, right or in no form.
    let plain = |path: &str, extra: &str| {
        raw(&addr, format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\n{extra}Connection: close\r\n\r\n").as_bytes())
    };
    assert_eq!(plain("/", "").0, 200);
    // The token with its last digit changed (a fixed digit equals it once in sixteen runs).
    let last = if token.ends_with('0') { '1' } else { '0' };
    let wrong = format!("{}{last}", &token[..31]);
    for path in &paths[2..] {
        assert_eq!(plain(path, ""), (403, Vec::new()), "{path} without a token");
        assert_eq!(plain(&format!("{path}?token={wrong}"), "").0, 403, "{path} with a wrong token");
        assert_eq!(plain(path, &format!("X-Blocksmith-Token: {wrong}\r\n")).0, 403, "{path} with a wrong token");
        assert_eq!(plain(&format!("{path}?token={token}"), "").0, 200, "{path} with the token");
    }
    // A socket needs the token and, from a browser, the page's own origin.
    assert_eq!(upgrade(&w, "/ws", ""), 403, "no token");
    let with_token = format!("/ws?token={token}");
    assert_eq!(upgrade(&w, &with_token, "Origin: http://evil.example\r\n"), 403);
    assert_eq!(upgrade(&w, &with_token, "Origin: null\r\n"), 403);
    assert_eq!(upgrade(&w, &with_token, &format!("Origin: http://{addr}\r\n")), 101);
    let mut page = socket(&w, "").unwrap();
    assert!(page.read().unwrap().to_text().unwrap().contains("\"params\""));
    // No form and no text/plain POST runs the recipe: another site cannot send the token's
    // header without a preflight, which is never granted.
    let before = version(&state_when(&w, Duration::from_secs(1), |_| true));
    let post = |origin: &str, media: &str, token_header: bool, body: &str| {
        let header = if token_header { format!("X-Blocksmith-Token: {token}\r\n") } else { String::new() };
        let request = format!(
            "POST /api/params?token={token} HTTP/1.1\r\nHost: {addr}\r\n{origin}{header}Content-Type: {media}\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        );
        raw(&addr, request.as_bytes())
    };
    let evil = "Origin: http://evil.example\r\n";
    let own = format!("Origin: http://{addr}\r\n");
    for (origin, media, header, body) in [
        (evil, "application/x-www-form-urlencoded", false, "size=2"),
        (evil, "text/plain", false, r#"{"size": "2"}"#),
        (evil, "application/json", true, r#"{"size": "2"}"#),
        (own.as_str(), "application/x-www-form-urlencoded", false, "size=2"),
        (own.as_str(), "text/plain", false, r#"{"size": "2"}"#),
        (own.as_str(), "multipart/form-data; boundary=x", false, "--x\r\n"),
        (own.as_str(), "application/x-www-form-urlencoded", true, "size=2"),
        (own.as_str(), "text/plain", true, r#"{"size": "2"}"#),
    ] {
        let (status, body) = post(origin, media, header, body);
        assert!(matches!(status, 403 | 415) && body.is_empty(), "{origin} {media} {header}: {status}");
    }
    let preflight = raw(&addr, format!("OPTIONS /api/params HTTP/1.1\r\nHost: {addr}\r\n{evil}Access-Control-Request-Method: POST\r\nConnection: close\r\n\r\n").as_bytes());
    assert_eq!(preflight.0, 405);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(version(&state_when(&w, Duration::from_secs(1), |_| true)), before, "a refused POST ran the recipe");
    assert_eq!(state_of(&w, "size=2", Duration::from_secs(1), |_| true)["known"], false, "nor made a variant");
    // The page's own script (its origin, JSON, the token's header) may.
    assert_eq!(post(&own, "application/json", true, r#"{"size": "2"}"#).0, 202);
    state_of(&w, "size=2", Duration::from_secs(10), |v| triangles(v) == Some(12));
    page.close(None).unwrap();
}

/// The number of open file descriptors of process `pid`.
fn descriptors(pid: u32) -> usize {
    std::fs::read_dir(format!("/proc/{pid}/fd")).map_or(0, Iterator::count)
}

/// A field of `/proc/PID/status` in its unit (kB for memory).
fn status_field(pid: u32, field: &str) -> u64 {
    let text = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    text.lines()
        .find_map(|l| l.strip_prefix(field)?.trim_start_matches(':').split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

/// Waits (up to 10 s) until `pid` has at most `limit` descriptors; the count then.
fn descriptors_settle(pid: u32, limit: usize) -> usize {
    let start = Instant::now();
    loop {
        let n = descriptors(pid);
        if n <= limit || start.elapsed() > Duration::from_secs(10) {
            return n;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn the_server_holds_against_floods_of_sockets_and_huge_headers() {
    if !Path::new("/proc/self/fd").exists() {
        eprintln!("no /proc: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    std::fs::write(&recipe, "cube(1)").unwrap();
    // Few descriptors, as in the report of the leak: 110 sockets used to exhaust them.
    let script = format!("ulimit -n 128 && exec {} watch \"$0\"", env!("CARGO_BIN_EXE_blocksmith"));
    let mut child = Command::new("sh").arg("-c").arg(script).arg(&recipe).stderr(Stdio::piped()).spawn().unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines.by_ref().map_while(Result::ok).find(|l| l.contains("http://")).expect("the address");
    std::thread::spawn(move || lines.for_each(drop));
    let pid = child.id();
    let w = Watch { child, server: Server::of(&first) };
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    // Warm up (threads, buffers), then count.
    for _ in 0..3 {
        socket(&w, "").unwrap().close(None).unwrap();
    }
    let base = descriptors_settle(pid, 0);
    let threads = status_field(pid, "Threads");
    // 1,000 sockets opened and closed, half politely (a close frame), half by dropping the
    // connection, each after the page's first message.
    let start = Instant::now();
    for i in 0..1000 {
        let mut s = socket(&w, "").unwrap_or_else(|e| panic!("socket {i}: {e}"));
        s.read().unwrap();
        if i % 2 == 0 {
            s.close(None).unwrap();
            while s.read().is_ok() {}
        }
    }
    let took = start.elapsed();
    let after = descriptors_settle(pid, base + 2);
    eprintln!("1000 sockets in {took:?}: {base} descriptors before, {after} after");
    assert!(after <= base + 2, "descriptors leak: {base} before 1,000 sockets, {after} after");
    // More sockets at once than the limits allow: refused, never fatal, and all given back.
    let many: Vec<_> = (0..150).map(|_| socket(&w, "")).collect();
    let open = many.iter().filter(|s| s.is_ok()).count();
    assert!(open >= 20, "only {open} of 150 sockets opened");
    drop(many);
    let after = descriptors_settle(pid, base + 2);
    assert!(after <= base + 2, "descriptors leak: {base} before 150 sockets at once, {after} after");
    let start = Instant::now();
    while status_field(pid, "Threads") > threads + 2 && start.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(status_field(pid, "Threads") <= threads + 2, "threads leak: {threads} before");
    // A 64 MiB header line is refused after its first 16 KiB, and costs no memory.
    let rss = status_field(pid, "VmRSS");
    let mut s = TcpStream::connect(&w.addr).unwrap();
    s.set_write_timeout(Some(Duration::from_secs(10))).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let _ = write!(s, "GET / HTTP/1.1\r\nHost: {}\r\nX-Long: ", w.addr);
    let chunk = vec![b'a'; 1 << 20];
    let mut sent = 0;
    while sent < 64 && s.write_all(&chunk).is_ok() {
        sent += 1;
    }
    let mut answer = Vec::new();
    let _ = s.read_to_end(&mut answer);
    assert!(sent < 64, "the server read all 64 MiB");
    assert!(answer.is_empty() || answer.starts_with(b"HTTP/1.1 431"), "{}", String::from_utf8_lossy(&answer));
    let grown = status_field(pid, "VmRSS").saturating_sub(rss);
    eprintln!("64 MiB header: refused after {sent} MiB sent, the server grew {grown} kB");
    assert!(grown < 16 * 1024, "the server grew {grown} kB");
    // And it still serves.
    assert_eq!(triangles(&state_when(&w, Duration::from_secs(5), |_| true)), Some(12));
    drop(w);
}

#[test]
fn a_recipe_folder_deleted_and_made_again_is_followed() {
    let dir = tempfile::tempdir().unwrap();
    let home = dir.path().join("part");
    std::fs::create_dir(&home).unwrap();
    let recipe = home.join("part.rhai");
    std::fs::write(&recipe, "cube(1)").unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v) == Some(12));
    // As a `git checkout` of another branch does: the folder goes, and a new one comes.
    std::fs::remove_dir_all(&home).unwrap();
    std::thread::sleep(Duration::from_millis(400));
    std::fs::create_dir(&home).unwrap();
    std::fs::write(&recipe, "icosphere(1, 1)").unwrap();
    state_when(&w, Duration::from_secs(10), |v| triangles(v) == Some(80) && v["error"].is_null());
    // Later saves in the new folder are seen too.
    std::fs::write(&recipe, "cube(2)").unwrap();
    let v = state_when(&w, Duration::from_secs(10), |v| triangles(v) == Some(12));
    assert!((v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap() - 8.0).abs() < 1e-6);
}

fn version(v: &serde_json::Value) -> u64 {
    v["model"]["version"].as_u64().unwrap_or(0)
}

#[test]
fn watch_runs_again_when_an_imported_module_or_a_loaded_file_is_saved() {
    let dir = tempfile::tempdir().unwrap();
    let (home, lib) = (dir.path().join("part"), dir.path().join("lib"));
    std::fs::create_dir_all(home.join("data")).unwrap();
    std::fs::create_dir_all(&lib).unwrap();
    // The project holding part/ and lib/ (a recipe reads only inside its project).
    std::fs::write(dir.path().join("blocksmith.toml"), "").unwrap();
    std::fs::write(lib.join("sizes.rhai"), "fn side() { 1 }").unwrap();
    std::fs::write(lib.join("other.rhai"), "fn unused() { 1 }").unwrap();
    let tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(home.join("data/shape.obj"), tetra).unwrap();
    let recipe = home.join("part.rhai");
    std::fs::write(&recipe, "import \"../lib/sizes\" as s;\n[cube(s::side()), load(\"data/shape.obj\")]").unwrap();
    let w = watch(&recipe);
    let layer = |v: &serde_json::Value, i: usize, fact: &str| v["model"]["layers"][i]["facts"][fact].as_f64();
    let v = state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    assert_eq!((layer(&v, 0, "volume"), layer(&v, 1, "triangles")), (Some(1.0), Some(4.0)), "{v}");
    // The imported module, in another folder, is saved: the recipe runs again with it.
    std::fs::write(lib.join("sizes.rhai"), "fn side() { 2 }").unwrap();
    let v = state_when(&w, Duration::from_secs(30), |v| layer(v, 0, "volume") == Some(8.0));
    let after_module = version(&v);
    // The loaded file, in a folder below, is saved: a square pyramid (a quad and four triangles).
    let pyramid = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nf 1 4 3 2\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";
    std::fs::write(home.join("data/shape.obj"), pyramid).unwrap();
    let v =
        state_when(&w, Duration::from_secs(30), |v| layer(v, 1, "triangles") == Some(6.0) && version(v) > after_module);
    let before = version(&v);
    // A module the recipe does not import, in the imported one's folder, is not an input.
    std::fs::write(lib.join("other.rhai"), "fn unused() { 2 }").unwrap();
    std::thread::sleep(Duration::from_millis(600));
    let v = state_when(&w, Duration::from_secs(1), |_| true);
    assert_eq!(version(&v), before, "saving a file the recipe does not read runs nothing");
}

#[test]
fn a_recipe_that_saves_what_it_loads_runs_once_per_edit_not_forever() {
    let dir = tempfile::tempdir().unwrap();
    let (stl, gltf) = (dir.path().join("copy.stl"), dir.path().join("copy.gltf"));
    let recipe = dir.path().join("part.rhai");
    let text = |size: u32| {
        format!(
            "let c = cube({size});\nc.save({stl:?});\nc.save({gltf:?});\n[load({stl:?}), load({gltf:?})]",
            stl = stl.display().to_string(),
            gltf = gltf.display().to_string()
        )
    };
    let run = |recipe: &Path| {
        let o = Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(recipe).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    // `run` makes the files the recipe loads; `watch` only reports the recipe's saves.
    std::fs::write(&recipe, text(1)).unwrap();
    run(&recipe);
    let written = std::fs::read(&stl).unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| version(v) == 1);
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(version(&state_when(&w, Duration::from_secs(1), |_| true)), 1, "ran itself again");
    // An edit of the recipe runs it once, and its saves are still not done.
    std::fs::write(&recipe, text(2)).unwrap();
    state_when(&w, Duration::from_secs(30), |v| version(v) == 2);
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(version(&state_when(&w, Duration::from_secs(1), |_| true)), 2, "ran itself again");
    assert_eq!(std::fs::read(&stl).unwrap(), written, "watch wrote a file");
    // A file it loads, saved by another program (a recipe elsewhere, written with -o), runs it
    // once: the new cube shows.
    let elsewhere = tempfile::tempdir().unwrap();
    let other = elsewhere.path().join("other.rhai");
    std::fs::write(&other, "cube(3)").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(&other).arg("-o").arg(&stl).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let volume = |v: &serde_json::Value| v["model"]["layers"][0]["facts"]["volume"].as_f64();
    let v = state_when(&w, Duration::from_secs(30), |v| volume(v) == Some(27.0));
    let after = version(&v);
    std::thread::sleep(Duration::from_millis(1000));
    assert_eq!(version(&state_when(&w, Duration::from_secs(1), |_| true)), after, "ran itself again");
}

#[test]
fn view_of_a_gltf_shows_it_again_when_its_bin_is_saved() {
    let dir = tempfile::tempdir().unwrap();
    let (recipe, small, big) = (dir.path().join("r.rhai"), dir.path().join("m.gltf"), dir.path().join("b.gltf"));
    for (size, out) in [(1, &small), (2, &big)] {
        std::fs::write(&recipe, format!("cube({size})")).unwrap();
        let o =
            Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(&recipe).arg("-o").arg(out).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let w = watch_command("view", &small, &[]);
    let volume = |v: &serde_json::Value| v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap_or(0.0);
    let v = state_when(&w, Duration::from_secs(30), |v| version(v) == 1);
    assert!((volume(&v) - 1.0).abs() < 1e-6, "{v}");
    // The buffer alone is saved (the bigger cube's, the same layout): the page shows it. Each
    // .gltf names its buffer by content (`m.HASH.bin`): copy b's buffer over the one m names.
    let buffer_of = |stem: &str| {
        std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok().and_then(|e| e.file_name().into_string().ok()))
            .find(|n| n.starts_with(&format!("{stem}.")) && n.ends_with(".bin"))
            .unwrap_or_else(|| panic!("{stem}'s buffer"))
    };
    std::fs::copy(dir.path().join(buffer_of("b")), dir.path().join(buffer_of("m"))).unwrap();
    let v = state_when(&w, Duration::from_secs(10), |v| version(v) == 2);
    assert!((volume(&v) - 8.0).abs() < 1e-6, "{v}");
}

/// Sends `line` to the REPL and returns the next output line that contains `want`.
fn repl_says(
    stdin: &mut std::process::ChildStdin,
    out: &mut impl Iterator<Item = String>,
    line: &str,
    want: &str,
) -> String {
    writeln!(stdin, "{line}").unwrap();
    stdin.flush().unwrap();
    out.find(|l| l.contains(want)).unwrap_or_else(|| panic!("no line with `{want}` after `{line}`"))
}

#[test]
fn the_repl_shows_values_on_one_studio_page_started_once() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = repl(dir.path(), Stdio::null());
    let mut stdin = child.stdin.take().unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap()).lines().map_while(Result::ok);
    let said = repl_says(&mut stdin, &mut out, ":show", "nothing to show");
    assert!(said.contains(":show cube(1)"), "{said}");
    let said = repl_says(&mut stdin, &mut out, ":show cube(2)", "shown at");
    assert!(said.ends_with("(12 triangles)"), "{said}");
    let server = Server::of(&said);
    let addr = server.addr.clone();
    assert!(addr.starts_with("127.0.0.1:"), "{addr}");
    let v = state_when(&server, Duration::from_secs(5), |v| version(v) == 1);
    assert!((v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap() - 8.0).abs() < 1e-9, "{v}");
    // show() in code updates the same page; the last value stays the entry's own.
    let said = repl_says(&mut stdin, &mut out, "let b = show(icosphere(1, 1)); 5", "shown at");
    assert!(said.contains(&addr) && said.ends_with("(80 triangles)"), "{said}");
    state_when(&server, Duration::from_secs(5), |v| version(v) == 2 && triangles(v) == Some(80));
    // `:show` alone shows the last value; an array is layers; an error shows nothing.
    let said = repl_says(&mut stdin, &mut out, "[b, cube(1)]", "=>");
    assert!(said.contains("=>"), "{said}");
    let said = repl_says(&mut stdin, &mut out, ":show", "shown at");
    assert!(said.ends_with("(2 layers, 92 triangles)"), "{said}");
    let said = repl_says(&mut stdin, &mut out, ":show 5", "cannot be saved");
    assert!(said.contains("cannot show an i64") && !said.contains("blocksmith-studio-"), "no temporary path: {said}");
    let v = state_when(&server, Duration::from_secs(5), |v| version(v) == 3);
    assert_eq!(v["model"]["layers"].as_array().unwrap().len(), 2);
    // A block model is shown as its surface, with its control mesh.
    let said = repl_says(
        &mut stdin,
        &mut out,
        ":show { let m = blocks(); m.add(block([0, 0, 0], [1, 1, 1])); m }",
        "shown at",
    );
    assert!(said.contains(&addr), "{said}");
    let v = state_when(&server, Duration::from_secs(5), |v| version(v) == 4);
    assert_eq!(v["model"]["layers"][0]["control_edges"], 48, "{v}");
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

#[test]
fn show_outside_the_studio_does_nothing_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("r.rhai");
    std::fs::write(&recipe, "let c = show(cube(1)); show(c); c").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .arg("run")
        .arg(&recipe)
        .arg("-o")
        .arg(dir.path().join("r.stl"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(err.matches("show(...)").count(), 1, "said once: {err}");
}

#[test]
fn the_page_shows_the_model_in_a_real_browser() {
    let Some(browser) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("gear.rhai");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/gear.rhai"), &recipe).unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let shot = dir.path().join("page.png");
    // A profile of its own: a browser already running on the default one would take the page.
    let profile = tempfile::tempdir().unwrap();
    let o = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        .args(["--window-size=800,600", "--virtual-time-budget=10000", "--dump-dom", "--no-first-run"])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(w.url())
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&o.stdout);
    assert!(dom.contains("<title>blocksmith: 840 triangles</title>"), "{dom}");
    // The screenshot shows the model, not a blank canvas: in the view (left of the panel),
    // enough pixels far from the background's colour.
    let shot = image::open(&shot).unwrap().to_rgb8();
    let background = shot.get_pixel(2, 2).0;
    let far =
        |p: [u8; 3]| p.iter().zip(background).map(|(&a, b)| i32::from(a).abs_diff(i32::from(b))).sum::<u32>() > 60;
    let view: Vec<[u8; 3]> =
        (0..shot.height()).flat_map(|y| (0..480).map(move |x| (x, y))).map(|(x, y)| shot.get_pixel(x, y).0).collect();
    let share = view.iter().filter(|&&p| far(p)).count() as f64 / view.len() as f64;
    assert!(share > 0.05, "only {:.1} % of the view differs from the background", share * 100.0);
}

#[test]
fn the_page_follows_saves_errors_parameters_and_shows_control_meshes_without_reloading() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    let size = "let s = param(\"size\", 1, #{ min: 0.5, max: 4, step: 0.5 });";
    std::fs::write(&recipe, format!("{size}\ncube(s)")).unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let Some(mut b) = Browser::open(&w.url()) else { return };
    b.wait("window.studio && studio.triangles === 12", Duration::from_secs(20));
    b.eval("window.loadedOnce = 'this page'");
    // An idle page draws nothing: no frame while nothing changes.
    b.wait("studio.shown", Duration::from_secs(5));
    let frames = b.eval("studio.frames()");
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(b.eval("studio.frames()"), frames, "frames drawn while idle");
    // A save shows the new model within 2 s, in the same page.
    let start = Instant::now();
    std::fs::write(&recipe, format!("{size}\nicosphere(s, 1)")).unwrap();
    b.wait("studio.triangles === 80", Duration::from_secs(10));
    let took = start.elapsed();
    assert!(took < Duration::from_secs(2), "the new model took {took:?}");
    assert_eq!(b.eval("window.loadedOnce"), "this page", "the page was not reloaded");
    // A syntax error shows its place and line in the page; the model stays.
    std::fs::write(&recipe, format!("{size}\nlet broken = ;\nicosphere(s, 1)")).unwrap();
    b.wait("studio.error", Duration::from_secs(10));
    let shown = b.eval("document.getElementById('error').textContent").as_str().unwrap().to_string();
    assert!(shown.contains("part.rhai:2:") && shown.contains("let broken = ;") && shown.contains('^'), "{shown}");
    assert_eq!(b.eval("studio.triangles"), 80, "the last model stays");
    assert_eq!(b.eval("document.getElementById('error').hidden"), false);
    // Fixed: the error goes. A parameter control changed in the page runs the recipe with it.
    std::fs::write(&recipe, format!("{size}\ncube(s)")).unwrap();
    b.wait("studio.triangles === 12 && !studio.error", Duration::from_secs(10));
    b.eval(
        "(() => { const i = document.querySelector('#params input[name=size]'); i.value = '2'; \
         i.dispatchEvent(new Event('change')); })()",
    );
    b.wait("document.getElementById('fact-volume')?.textContent === '8'", Duration::from_secs(10));
    assert!(b.eval("location.search").as_str().unwrap().contains("size=2"));
    assert_eq!(b.eval("window.loadedOnce"), "this page");
    // A subdivision surface brings its control mesh; the toggle draws it over the surface.
    std::fs::write(&recipe, format!("{size}\ncube(s).catmull_clark(2)")).unwrap();
    b.wait("studio.triangles === 192", Duration::from_secs(10));
    assert_eq!(b.eval("document.getElementById('control-label').hidden"), false);
    assert_eq!(b.eval("studio.controlEdges"), 0, "off until asked for");
    b.eval("document.getElementById('control').click()");
    assert_eq!(b.eval("studio.controlEdges"), 12, "the cube's edges over the surface");
    assert_eq!(b.eval("document.getElementById('control-note').hidden"), true);
    // Moved, the control mesh moves with the surface; unioned with a plain box, it stays.
    let save = |b: &mut Browser, body: &str| {
        let before = b.eval("studio.version").as_u64().unwrap();
        std::fs::write(&recipe, format!("{size}\n{body}")).unwrap();
        b.wait(&format!("studio.version > {before}"), Duration::from_secs(10));
    };
    save(&mut b, "cube(s).catmull_clark(2).translate([3, 0, 0])");
    assert_eq!(b.eval("studio.controlEdges"), 12);
    assert_eq!(b.eval("studio.controlBounds()[0]").as_f64(), Some(2.0), "the cage's -x side at 3 - 1");
    save(&mut b, "union(cube(s).catmull_clark(2).rotate([0, 0, 1], 90), box([0, 0, 0], [2, 2, 2]))");
    assert_eq!(b.eval("studio.controlEdges"), 12, "the subdivided operand's cage over the union");
    assert_eq!(b.eval("document.getElementById('control-label').hidden"), false);
    // A model with no control mesh: no overlay, and the page says why.
    save(&mut b, "cube(s).translate([1, 0, 0])");
    assert_eq!(b.eval("studio.controlEdges"), 0);
    assert_eq!(b.eval("document.getElementById('control-label').hidden"), true);
    assert_eq!(b.eval("document.getElementById('control-note').hidden"), false);
    assert!(b
        .eval("document.getElementById('control-note').textContent")
        .as_str()
        .unwrap()
        .contains("No control mesh"));
}

#[test]
fn an_animation_plays_in_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("grow.rhai");
    std::fs::write(&recipe, "let a = animation(polar_sphere(0.5, 8, 6));\na.add(growth());\na").unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let Some(mut b) = Browser::open(&w.url()) else { return };
    b.wait("window.studio && studio.version === 1 && studio.time > 0", Duration::from_secs(20));
    assert_eq!(b.eval("document.getElementById('animation').hidden"), false);
    let (t0, box0) = (b.eval("studio.time").as_f64().unwrap(), b.eval("studio.bounds()"));
    b.wait(&format!("studio.time > {t0} + 0.5"), Duration::from_secs(10));
    let box1 = b.eval("studio.bounds()");
    assert_ne!(box0, box1, "the vertices moved between {t0} s and later");
    // Pause stops the clock; scrubbing sets it.
    b.eval("document.getElementById('play').click()");
    let paused = b.eval("studio.time").as_f64().unwrap();
    std::thread::sleep(Duration::from_millis(300));
    assert!((b.eval("studio.time").as_f64().unwrap() - paused).abs() < 1e-9, "paused");
    b.eval("(() => { const t = document.getElementById('timeline'); t.value = '0.25'; t.dispatchEvent(new Event('input')); })()");
    b.wait("Math.abs(studio.time - 0.25) < 1e-6", Duration::from_secs(2));
}

#[test]
fn a_page_left_open_reconnects_after_the_server_restarts() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    std::fs::write(&recipe, "cube(1)").unwrap();
    // The same token both times, as a user keeping the address would set it.
    let token = [("BLOCKSMITH_TOKEN", "restarted-studio-token-1234")];
    let w = watch_env("watch", &recipe, &[], &token);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let Some(mut b) = Browser::open(&w.url()) else { return };
    b.wait("window.studio && studio.triangles === 12", Duration::from_secs(20));
    b.eval("window.loadedOnce = 'this page'");
    let port = w.port().to_string();
    drop(w);
    b.wait("document.getElementById('status').textContent === 'offline'", Duration::from_secs(5));
    // The server comes back on the same port with a changed recipe: its model 1 is news.
    std::fs::write(&recipe, "icosphere(1, 1)").unwrap();
    let w = watch_env("watch", &recipe, &["--port", &port], &token);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    b.wait("studio.triangles === 80 && studio.connections === 2", Duration::from_secs(10));
    assert_eq!(b.eval("window.loadedOnce"), "this page");
    assert_eq!(b.eval("document.getElementById('status').textContent"), "live");
}

/// A headless chromium's screenshot of `url` (800 x 600) once the page has had `budget` ms.
fn screenshot(url: &str, dir: &Path, budget: u32) -> Option<image::RgbImage> {
    let browser = chromium()?;
    let shot = dir.join("shot.png");
    let profile = tempfile::tempdir().unwrap();
    Command::new(browser)
        .args(["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        .args(["--window-size=800,600", "--no-first-run", "--hide-scrollbars"])
        .arg(format!("--virtual-time-budget={budget}"))
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(url)
        .output()
        .unwrap();
    Some(image::open(&shot).unwrap().to_rgb8())
}

/// The share of the model's pixels (in the view, left of the panel, away from the background)
/// whose colour is one of the `k` most common ones, give or take 3 levels a channel.
fn share_of_commonest(shot: &image::RgbImage, k: usize) -> f64 {
    let background = shot.get_pixel(2, 2).0;
    let far = |p: [u8; 3]| p.iter().zip(background).map(|(&a, b)| a.abs_diff(b) as u32).sum::<u32>() > 30;
    let model: Vec<[u8; 3]> = (0..shot.height())
        .flat_map(|y| (0..480).map(move |x| (x, y)))
        .map(|(x, y)| shot.get_pixel(x, y).0)
        .filter(|&p| far(p))
        .collect();
    let mut counts = std::collections::HashMap::new();
    for p in &model {
        *counts.entry(*p).or_insert(0usize) += 1;
    }
    let mut common: Vec<([u8; 3], usize)> = counts.into_iter().collect();
    common.sort_by_key(|c| std::cmp::Reverse(c.1));
    let top: Vec<[u8; 3]> = common.iter().take(k).map(|c| c.0).collect();
    let near = |p: &[u8; 3]| top.iter().any(|t| t.iter().zip(p).all(|(a, b)| a.abs_diff(*b) <= 3));
    model.iter().filter(|p| near(p)).count() as f64 / model.len().max(1) as f64
}

#[test]
fn a_box_is_shaded_flat_a_sphere_round_and_fit_to_view_holds_the_whole_model() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    // A box: three faces in view, each one flat colour (its normals those of its face, not
    // averaged over its corners).
    std::fs::write(&recipe, "cube(1)").unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let Some(shot) = screenshot(&w.url(), dir.path(), 8000) else { return };
    let flat = share_of_commonest(&shot, 3);
    // A sphere: its faces meet at small angles, so its shading is smooth, many colours.
    std::fs::write(&recipe, "icosphere(1, 3)").unwrap();
    state_when(&w, Duration::from_secs(10), |v| triangles(v) == Some(1280));
    let round = share_of_commonest(&screenshot(&w.url(), dir.path(), 8000).unwrap(), 3);
    eprintln!("three commonest colours: {:.0} % of the box, {:.0} % of the sphere", flat * 100.0, round * 100.0);
    assert!(flat > 0.9, "the box's faces are not flat: {:.0} %", flat * 100.0);
    assert!(round < 0.5, "the sphere is not smooth: {:.0} %", round * 100.0);
    // A tall model in a wide view and a wide one: every corner of its box in the frame.
    std::fs::write(&recipe, "box([0, 0, 0], [1, 1, 8])").unwrap();
    state_when(&w, Duration::from_secs(10), |v| triangles(v) == Some(12) && version(v) == 3);
    let Some(mut b) = Browser::open(&w.url()) else { return };
    b.wait("window.studio && studio.version === 3", Duration::from_secs(20));
    assert_eq!(b.eval("studio.inView()"), true, "the tall model is cut off");
    std::fs::write(&recipe, "box([0, 0, 0], [12, 1, 1])").unwrap();
    b.wait("studio.version === 4", Duration::from_secs(10));
    b.eval("document.getElementById('fit').click()");
    assert_eq!(b.eval("studio.inView()"), true, "the wide model is cut off");
}

#[test]
fn each_page_shows_its_own_parameters_with_sliders_choices_checkboxes_and_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("part.rhai");
    std::fs::write(
        &recipe,
        "let s = param(\"size\", 1, #{ min: 0.5, max: 4, step: 0.5 });\n\
         let shape = param(\"shape\", \"cube\", #{ choices: [\"cube\", \"sphere\"] });\n\
         let hollow = param(\"hollow\", false);\n\
         let c = cube(1); c.translate([1, 0, 0]);\n\
         if shape == \"cube\" { cube(s) } else { icosphere(s, 1) }",
    )
    .unwrap();
    let w = watch(&recipe);
    state_when(&w, Duration::from_secs(30), |v| triangles(v).is_some());
    let volume = "document.getElementById('fact-volume')?.textContent";
    let Some(mut a) = Browser::open(&format!("{}&size=2", w.url())) else { return };
    a.wait(&format!("{volume} === '8'"), Duration::from_secs(20));
    // Controls typed from the declarations: a slider with its step beside the box, a select,
    // a checkbox.
    let slider = "document.querySelector('#params input[type=range][data-param=size]')";
    assert_eq!(
        a.eval(&format!("[{slider}.min, {slider}.max, {slider}.step, {slider}.value].join(' ')")),
        "0.5 4 0.5 2"
    );
    assert_eq!(a.eval("document.querySelector('#params input[type=number][name=size]').value"), "2");
    assert_eq!(
        a.eval("[...document.querySelectorAll('#params select[name=shape] option')].map((o) => o.value).join(' ')"),
        "cube sphere"
    );
    assert_eq!(a.eval("document.querySelector('#params input[type=checkbox][name=hollow]').checked"), false);
    // The dropped result is shown as a warning at its line, as the terminal prints it.
    a.wait("!document.getElementById('warnings').hidden", Duration::from_secs(5));
    let warning = a.eval("document.getElementById('warnings').textContent");
    assert!(warning.as_str().unwrap().contains("part.rhai:4:"), "{warning}");
    // A second page without parameters shows the defaults' model, not the first page's.
    let Some(mut b) = Browser::open(&w.url()) else { return };
    b.wait(&format!("{volume} === '1'"), Duration::from_secs(20));
    // The first page's slider runs the recipe again for it alone.
    a.eval(&format!("(() => {{ const s = {slider}; s.value = '3'; s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change')); }})()"));
    a.wait(&format!("{volume} === '27'"), Duration::from_secs(10));
    assert!(a.eval("location.search").as_str().unwrap().contains("size=3"));
    a.eval("(() => { const s = document.querySelector('#params select[name=shape]'); s.value = 'sphere'; s.dispatchEvent(new Event('change')); })()");
    a.wait("studio.triangles === 80", Duration::from_secs(10));
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(b.eval(volume), "1", "the other page changed");
    assert_eq!(b.eval("studio.triangles"), 12);
    assert!(!b.eval("location.search").as_str().unwrap().contains("size=3"));
    let v = state_when(&w, Duration::from_secs(1), |_| true);
    assert!((v["model"]["layers"][0]["facts"]["volume"].as_f64().unwrap() - 1.0).abs() < 1e-9, "{v}");
}
