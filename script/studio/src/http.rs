//! Just enough HTTP/1.1 for the studio, every size bounded: a request's head (request line and
//! headers) is read a line at a time up to [`MAX_HEAD`] bytes and [`MAX_HEADERS`] headers, and
//! refused (431) past them before more is read, so a 64 MiB header line costs the server
//! 16 KiB; a body up to [`MAX_BODY`] bytes, with a `Content-Length` (413 past it, 411 without
//! one, no chunked bodies); the whole head within [`HEAD_TIME`].
//!
//! Why not tiny_http (which the studio used before): it reads a header line into a growing
//! buffer with no limit (a 64 MiB line grew the server by 140–204 MiB) and runs each connection
//! on a pool that grows without bound, with no way to set either. The maintained servers that
//! can (hyper and the frameworks on it) bring an async runtime, far more than a page for one
//! person on 127.0.0.1 needs. The head is parsed by `httparse` (already here through
//! tungstenite's handshake), the reading around it is these few bounded lines.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

/// The most bytes of a request's head (its request line and headers).
pub const MAX_HEAD: usize = 16 * 1024;
/// The most headers of a request.
pub const MAX_HEADERS: usize = 64;
/// The most bytes of a request's body (a JSON of parameters).
pub const MAX_BODY: usize = 64 * 1024;
/// The longest a request's head may take to arrive, and the longest a kept-alive connection
/// waits for the next request.
pub const HEAD_TIME: Duration = Duration::from_secs(10);

/// A request as read: method, target (path and query), lower-case header names.
#[derive(Debug, Clone)]
pub struct Request {
    pub method: String,
    pub path: String,
    pub query: String,
    pub headers: BTreeMap<String, String>,
    pub body: Vec<u8>,
    /// HTTP/1.0, or `Connection: close`.
    pub close: bool,
}

impl Request {
    /// The value of header `name` (lower case).
    #[must_use]
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.get(name).map(String::as_str)
    }

    /// The query's pairs, decoded.
    #[must_use]
    pub fn query_pairs(&self) -> BTreeMap<String, String> {
        parse_form(&self.query)
    }
}

/// Why a request could not be read: the status to answer with (0: none, the peer went or
/// was silent too long).
#[derive(Debug, PartialEq, Eq)]
pub struct Refused(pub u16);

/// Reads one request from `reader` within the bounds above. `Err(Refused(0))`: the connection
/// closed or timed out between requests (answer nothing).
///
/// # Errors
/// The status to refuse the request with (400, 411, 413, 431, 501), or 0.
pub fn read_request(reader: &mut BufReader<TcpStream>) -> Result<Request, Refused> {
    let start = Instant::now();
    let mut head = Vec::new();
    loop {
        let room = (MAX_HEAD + 1).saturating_sub(head.len());
        let before = head.len();
        let n = reader.by_ref().take(room as u64).read_until(b'\n', &mut head).map_err(|_| Refused(0))?;
        if n == 0 {
            return Err(Refused(if head.is_empty() { 0 } else { 400 }));
        }
        if head.len() > MAX_HEAD {
            return Err(Refused(431));
        }
        if start.elapsed() > HEAD_TIME {
            return Err(Refused(0));
        }
        let line = &head[before..];
        if line == b"\r\n" || line == b"\n" {
            if before == 0 {
                head.clear(); // a stray empty line between requests (RFC 9112 §2.2)
                continue;
            }
            break;
        }
    }
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut parsed = httparse::Request::new(&mut headers);
    match parsed.parse(&head) {
        Ok(httparse::Status::Complete(_)) => {}
        Err(httparse::Error::TooManyHeaders) => return Err(Refused(431)),
        _ => return Err(Refused(400)),
    }
    let (Some(method), Some(target), Some(version)) = (parsed.method, parsed.path, parsed.version) else {
        return Err(Refused(400));
    };
    let mut map = BTreeMap::new();
    for h in parsed.headers.iter() {
        let value = std::str::from_utf8(h.value).map_err(|_| Refused(400))?.trim().to_string();
        let name = h.name.to_ascii_lowercase();
        // A repeated header that matters (Host, Origin, the token) is refused, not merged.
        let matters = ["host", "origin", super::guard::TOKEN_HEADER].contains(&name.as_str());
        if map.insert(name, value).is_some() && matters {
            return Err(Refused(400));
        }
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let connection = map.get("connection").map(|c| c.to_ascii_lowercase()).unwrap_or_default();
    let mut request = Request {
        method: method.to_string(),
        path: path.to_string(),
        query: query.to_string(),
        close: version == 0 || connection.split(',').any(|t| t.trim() == "close"),
        headers: map,
        body: Vec::new(),
    };
    if request.headers.contains_key("transfer-encoding") {
        return Err(Refused(501));
    }
    match request.header("content-length").map(str::parse::<usize>) {
        None if request.method == "POST" => return Err(Refused(411)),
        None => {}
        Some(Err(_)) => return Err(Refused(400)),
        Some(Ok(n)) if n > MAX_BODY => return Err(Refused(413)),
        Some(Ok(n)) => {
            request.body = vec![0; n];
            reader.read_exact(&mut request.body).map_err(|_| Refused(0))?;
        }
    }
    Ok(request)
}

/// The reason phrase of `status`.
#[must_use]
pub fn reason(status: u16) -> &'static str {
    match status {
        101 => "Switching Protocols",
        200 => "OK",
        202 => "Accepted",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        411 => "Length Required",
        413 => "Content Too Large",
        415 => "Unsupported Media Type",
        421 => "Misdirected Request",
        431 => "Request Header Fields Too Large",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        _ => "",
    }
}

/// An answer: status, extra headers, body.
pub struct Response {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Response {
    /// A `status` answer with `body` of `media_type`.
    #[must_use]
    pub fn new(status: u16, media_type: &str, body: Vec<u8>) -> Response {
        Response { status, headers: vec![("Content-Type".into(), media_type.into())], body }
    }

    /// A `status` answer with no content (refusals say nothing).
    #[must_use]
    pub fn empty(status: u16) -> Response {
        Response { status, headers: Vec::new(), body: Vec::new() }
    }

    #[must_use]
    pub fn with(mut self, name: &str, value: &str) -> Response {
        self.headers.push((name.into(), value.into()));
        self
    }

    /// Writes the answer (`close`: and says the connection ends).
    ///
    /// # Errors
    /// The peer went away.
    pub fn write(&self, out: &mut impl Write, close: bool) -> std::io::Result<()> {
        let mut head = format!("HTTP/1.1 {} {}\r\n", self.status, reason(self.status));
        for (k, v) in &self.headers {
            head.push_str(&format!("{k}: {v}\r\n"));
        }
        head.push_str(&format!(
            "Content-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n\
             X-Frame-Options: DENY\r\nReferrer-Policy: no-referrer\r\n",
            self.body.len()
        ));
        if close {
            head.push_str("Connection: close\r\n");
        }
        head.push_str("\r\n");
        let mut bytes = head.into_bytes();
        bytes.extend_from_slice(&self.body);
        out.write_all(&bytes)?;
        out.flush()
    }
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

/// `%XX` and `+` decoded, as HTML forms and query strings write them: `+` is a space, then the
/// escapes go through the kernel's one percent-decoder (a malformed escape stays as it is;
/// bytes that are not UTF-8 are replaced).
#[must_use]
pub fn decode(text: &str) -> String {
    blocksmith_kernel::io::uri::percent_decode(&text.replace('+', " "))
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

#[cfg(test)]
mod tests {
    use std::net::TcpListener;

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

    /// What `read_request` makes of `bytes` sent on a fresh connection.
    fn read(bytes: Vec<u8>) -> Result<Request, Refused> {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let client = std::thread::spawn(move || {
            let mut s = TcpStream::connect(addr).unwrap();
            // The server may stop reading (and close) before all is sent.
            let _ = s.write_all(&bytes);
            let _ = s.shutdown(std::net::Shutdown::Write);
            let _ = s.read_to_end(&mut Vec::new());
        });
        let (stream, _) = listener.accept().unwrap();
        let r = read_request(&mut BufReader::new(stream));
        client.join().unwrap();
        r
    }

    #[test]
    fn requests_are_read_within_their_bounds_and_refused_past_them() {
        let r =
            read(b"POST /api/params?a=1&b=x+y HTTP/1.1\r\nHost: h\r\nContent-Length: 2\r\n\r\n{}".to_vec()).unwrap();
        assert_eq!(
            (r.method.as_str(), r.path.as_str(), r.body.as_slice(), r.close),
            ("POST", "/api/params", &b"{}"[..], false)
        );
        assert_eq!(r.query_pairs().get("b").map(String::as_str), Some("x y"));
        assert_eq!(r.header("host"), Some("h"));
        assert!(read(b"GET / HTTP/1.0\r\n\r\n".to_vec()).unwrap().close);
        let mut long = b"GET / HTTP/1.1\r\nX: ".to_vec();
        long.resize(4 << 20, b'a');
        assert_eq!(read(long).unwrap_err(), Refused(431), "a long header line");
        let many: String = (0..100).map(|i| format!("X-{i}: 1\r\n")).collect();
        assert_eq!(read(format!("GET / HTTP/1.1\r\n{many}\r\n").into_bytes()).unwrap_err(), Refused(431));
        let big = format!("POST / HTTP/1.1\r\nContent-Length: {}\r\n\r\n", MAX_BODY + 1);
        assert_eq!(read(big.into_bytes()).unwrap_err(), Refused(413));
        assert_eq!(read(b"POST / HTTP/1.1\r\n\r\n".to_vec()).unwrap_err(), Refused(411));
        let chunked = b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n".to_vec();
        assert_eq!(read(chunked).unwrap_err(), Refused(501));
        assert_eq!(read(b"GET / HTTP/1.1\r\nHost: a\r\nHost: b\r\n\r\n".to_vec()).unwrap_err(), Refused(400));
        assert_eq!(read(b"nonsense\r\n\r\n".to_vec()).unwrap_err(), Refused(400));
        assert_eq!(read(Vec::new()).unwrap_err(), Refused(0), "closed before a request");
    }
}
