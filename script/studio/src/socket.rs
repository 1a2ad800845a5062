//! A page's WebSocket: the session's messages go out (a model's followed by its files, see
//! [`super::server`]), and the page's parameters come in (`{"type": "params", "values":
//! {...}}`, as its controls change; the first ones come in the socket's address).
//!
//! Two threads per page, both gone (and the socket closed) as soon as the page is: a reader,
//! which is the one that notices the page leaving (a close frame, the connection dropped, or
//! no answer to the pings sent every [`PING`] within [`SILENCE`]), and a writer, which sends
//! what the session and the reader tell it. Frames from a page are at most [`MAX_MESSAGE`]
//! bytes; sends give up after [`SEND_TIME`].

use std::io::{BufReader, Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::mpsc::{self, Sender};
use std::time::{Duration, Instant};

use tungstenite::protocol::{Role, WebSocketConfig};
use tungstenite::{Message, WebSocket};

use super::http::{Request, Response};
use super::session::{Params, Session};

/// The largest message a page may send (its parameters).
pub const MAX_MESSAGE: usize = 64 * 1024;
/// How often a quiet socket is pinged.
pub const PING: Duration = Duration::from_secs(20);
/// How long a page may say nothing (not even a pong) before it counts as gone.
pub const SILENCE: Duration = Duration::from_secs(60);
/// The longest one send may take before the page counts as gone.
pub const SEND_TIME: Duration = Duration::from_secs(30);

/// What a page's writer hears.
enum Event {
    /// A message of the session.
    Update(String),
    /// The page's controls changed.
    Params(Params),
    /// The page is gone.
    Gone,
}

/// Only reads: the reader's half of the socket. What tungstenite would write on its own (the
/// answer to a close or a ping) is dropped; the writer sends its own close.
struct ReadHalf(TcpStream);

impl Read for ReadHalf {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0.read(buf)
    }
}

impl Write for ReadHalf {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn config() -> WebSocketConfig {
    WebSocketConfig::default().max_message_size(Some(MAX_MESSAGE)).max_frame_size(Some(MAX_MESSAGE))
}

/// Whether `request` asks for a WebSocket (its key, if so).
#[must_use]
pub fn key(request: &Request) -> Option<&str> {
    let upgrade = request.header("upgrade").is_some_and(|u| u.eq_ignore_ascii_case("websocket"));
    let version = request.header("sec-websocket-version") == Some("13");
    (upgrade && version).then(|| request.header("sec-websocket-key")).flatten()
}

/// Upgrades the connection to a WebSocket (the request already checked) and serves the page
/// on it until it goes; `given` are the parameters of the socket's address.
pub fn serve(reader: BufReader<TcpStream>, request: &Request, session: &Session, given: &Params) {
    let Some(key) = key(request) else {
        let mut stream = reader.into_inner();
        let _ = Response::empty(400).write(&mut stream, true);
        return;
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let buffered = reader.buffer().to_vec();
    let mut stream = reader.into_inner();
    let upgrade = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: {accept}\r\n\r\n"
    );
    if stream.write_all(upgrade.as_bytes()).is_err() {
        return;
    }
    let (Ok(()), Ok(()), Ok(read_half)) =
        (stream.set_read_timeout(Some(SILENCE)), stream.set_write_timeout(Some(SEND_TIME)), stream.try_clone())
    else {
        return;
    };
    let (tell, events) = mpsc::channel::<Event>();
    let reader = {
        let tell = tell.clone();
        let mut socket = WebSocket::from_partially_read(ReadHalf(read_half), buffered, Role::Server, Some(config()));
        std::thread::spawn(move || read_page(&mut socket, &tell))
    };
    let page = {
        let tell = tell.clone();
        session.join(given, move |m| tell.send(Event::Update(m.to_string())).is_ok())
    };
    drop(tell);
    let mut socket = WebSocket::from_raw_socket(stream, Role::Server, Some(config()));
    let mut ping = Instant::now() + PING;
    loop {
        let event = events.recv_timeout(ping.saturating_duration_since(Instant::now()));
        if Instant::now() >= ping {
            // Every PING, busy or not: the page's pong is what keeps the reader waiting.
            ping = Instant::now() + PING;
            if socket.send(Message::Ping(Default::default())).is_err() {
                break;
            }
        }
        let event = match event {
            Ok(e) => e,
            Err(mpsc::RecvTimeoutError::Timeout) => continue,
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        };
        match event {
            Event::Update(message) => {
                if send_update(&mut socket, session, message).is_err() {
                    break;
                }
            }
            Event::Params(p) => session.move_page(page, &p),
            Event::Gone => {
                let _ = socket.close(None);
                let _ = socket.flush();
                break;
            }
        }
    }
    session.leave(page);
    // Wakes the reader if it is still waiting (the writer failed first), then waits for it:
    // the socket's descriptors are both closed when this returns.
    let _ = socket.get_ref().shutdown(Shutdown::Both);
    drop(socket);
    let _ = reader.join();
}

/// Reads the page's messages until it goes; tells the writer its parameters, and that it went.
fn read_page(socket: &mut WebSocket<ReadHalf>, tell: &Sender<Event>) {
    loop {
        match socket.read() {
            Ok(Message::Text(text)) => {
                let Ok(v) = serde_json::from_str::<serde_json::Value>(text.as_str()) else { continue };
                if v["type"] != "params" {
                    continue;
                }
                let Some(values) = v["values"].as_object() else { continue };
                let params: Params = values
                    .iter()
                    .map(|(k, v)| (k.clone(), v.as_str().map_or_else(|| v.to_string(), str::to_string)))
                    .collect();
                if tell.send(Event::Params(params)).is_err() {
                    return;
                }
            }
            Ok(Message::Close(_)) | Err(_) => {
                let _ = tell.send(Event::Gone);
                return;
            }
            Ok(_) => {}
        }
    }
}

/// Sends one of the session's messages; a model's is followed by its files, and one already
/// replaced by a newer model is skipped (the newer one's message follows).
fn send_update(socket: &mut WebSocket<TcpStream>, session: &Session, message: String) -> tungstenite::Result<()> {
    let mut files = Vec::new();
    if let Some(version) = model_version(&message) {
        let Some(model) = session.model_numbered(version) else { return Ok(()) };
        files.extend(model.layers.iter().map(|l| l.glb.clone()));
        let ends = model.layers.iter().filter_map(|l| l.control.as_ref());
        files.extend(ends.map(|e| e.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>()));
    }
    socket.write(Message::text(message))?;
    for f in files {
        socket.write(Message::binary(f))?;
    }
    socket.flush()
}

/// The version of the model a `model` message announces; `None` for other messages.
fn model_version(message: &str) -> Option<u64> {
    let v: serde_json::Value = serde_json::from_str(message).ok()?;
    (v["type"] == "model").then(|| v["version"].as_u64()).flatten()
}
