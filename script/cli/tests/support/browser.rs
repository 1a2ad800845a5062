//! A headless chromium driven over the DevTools protocol, for the browser tests that include it
//! (`#[path = "support/browser.rs"] mod browser;`).

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use super::support::chromium;

/// A headless chromium driven over the DevTools protocol: one WebSocket to the browser, the
/// page attached as a flat session, `Runtime.evaluate` for everything. Stopped when dropped.
pub struct Browser {
    child: Child,
    socket: tungstenite::WebSocket<TcpStream>,
    session: String,
    next: u64,
    _profile: tempfile::TempDir,
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Browser {
    /// chromium showing `url`, or None where chromium is missing (see [`chromium`]).
    pub fn open(url: &str) -> Option<Browser> {
        let browser = chromium()?;
        let profile = tempfile::tempdir().unwrap();
        let mut child = Command::new(browser)
            .args(["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
            .args(["--window-size=800,600", "--remote-debugging-port=0", "--no-first-run"])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .arg(url)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines().map_while(Result::ok);
        let ws = lines
            .find_map(|l| l.split_once("DevTools listening on ").map(|(_, u)| u.trim().to_string()))
            .expect("chromium prints its DevTools address");
        std::thread::spawn(move || lines.for_each(drop));
        let host = ws.trim_start_matches("ws://").split('/').next().unwrap().to_string();
        let (socket, _) = tungstenite::client(ws.as_str(), TcpStream::connect(&host).unwrap()).unwrap();
        let mut b = Browser { child, socket, session: String::new(), next: 0, _profile: profile };
        let start = Instant::now();
        let target = loop {
            let targets = b.call("Target.getTargets", serde_json::json!({}));
            let page = targets["targetInfos"].as_array().unwrap().iter().find(|t| t["type"] == "page").cloned();
            if let Some(p) = page {
                break p["targetId"].as_str().unwrap().to_string();
            }
            assert!(start.elapsed() < Duration::from_secs(10), "no page target");
            std::thread::sleep(Duration::from_millis(50));
        };
        let attached = b.call("Target.attachToTarget", serde_json::json!({ "targetId": target, "flatten": true }));
        b.session = attached["sessionId"].as_str().unwrap().to_string();
        Some(b)
    }

    /// Sends a command (to the page once attached) and returns its result.
    pub fn call(&mut self, method: &str, params: serde_json::Value) -> serde_json::Value {
        self.next += 1;
        let mut message = serde_json::json!({ "id": self.next, "method": method, "params": params });
        if !self.session.is_empty() {
            message["sessionId"] = serde_json::json!(self.session);
        }
        self.socket.send(tungstenite::Message::text(message.to_string())).unwrap();
        loop {
            let reply = self.socket.read().unwrap();
            let Ok(text) = reply.to_text() else { continue };
            let v: serde_json::Value = serde_json::from_str(text).unwrap();
            if v["id"] == self.next {
                assert!(v["error"].is_null(), "{method}: {v}");
                return v["result"].clone();
            }
        }
    }

    /// The value of a JavaScript expression in the page (promises awaited).
    pub fn eval(&mut self, expression: &str) -> serde_json::Value {
        let params = serde_json::json!({ "expression": expression, "returnByValue": true, "awaitPromise": true });
        let r = self.call("Runtime.evaluate", params);
        assert!(r["exceptionDetails"].is_null(), "{expression}: {r}");
        r["result"]["value"].clone()
    }

    /// Waits until `expression` is true in the page; returns how long that took.
    pub fn wait(&mut self, expression: &str, limit: Duration) -> Duration {
        let start = Instant::now();
        while self.eval(&format!("!!({expression})")) != serde_json::json!(true) {
            let page = self
                .eval("JSON.stringify({ ...window.studio, status: document.getElementById('status')?.textContent })");
            assert!(start.elapsed() < limit, "not `{expression}` after {limit:?}: {page}");
            std::thread::sleep(Duration::from_millis(10));
        }
        start.elapsed()
    }
}
