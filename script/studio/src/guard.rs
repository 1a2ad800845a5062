//! Who may read and drive the studio: only the person who started it, from the page it
//! printed. As Jupyter does, and Vite and webpack-dev-server since their DNS-rebinding
//! advisories:
//!
//! - **Host**: every request must name this server as a loopback address with its port
//!   (`127.0.0.1:PORT`, `localhost:PORT`, `[::1]:PORT`); any other (a DNS-rebinding page's
//!   `evil.example:PORT`) is answered 421 with nothing in it.
//! - **Token**: a random token, 128 bits from the operating system, made once per server, is
//!   part of the printed address (`/?token=…`; [`TOKEN_VARIABLE`] gives one instead). Every API call, model file, download and socket
//!   must carry it (header [`TOKEN_HEADER`], or `token=` in the query where a header cannot be
//!   set: the socket, a download link); without it, 403. The page itself (HTML, scripts) holds
//!   nothing secret and is served without it, so the address can be opened as printed.
//! - **Origin**: a socket upgrade or a state-changing request that carries an `Origin` must
//!   carry the page's own (`http://` and the request's Host); another site's is refused (403).
//! - **Non-simple requests**: the one state-changing request (`POST /api/params`) must be
//!   `Content-Type: application/json` and carry the token in its header, which a form or a
//!   `text/plain` POST cannot do; a cross-site script would need a CORS preflight, which this
//!   server never grants.

use super::http::Request;

/// The header that carries the token on API calls.
pub const TOKEN_HEADER: &str = "x-blocksmith-token";

/// The environment variable that gives the token instead (as `JUPYTER_TOKEN` does): a page
/// left open then reconnects to a studio started again with the same one.
pub const TOKEN_VARIABLE: &str = "BLOCKSMITH_TOKEN";

/// The session's token: [`TOKEN_VARIABLE`]'s when set (at least 16 letters, digits, `-` or
/// `_`), else a new random one ([`new_token`]).
///
/// # Errors
/// A token in the environment that is too short or has other characters; no randomness.
pub fn session_token() -> Result<String, String> {
    match std::env::var(TOKEN_VARIABLE) {
        Ok(t) if t.len() >= 16 && t.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_') => Ok(t),
        Ok(_) => Err(format!("error: {TOKEN_VARIABLE} must be at least 16 letters, digits, `-` or `_`")),
        Err(_) => new_token(),
    }
}

/// A new random token: 128 bits from the operating system, as 32 hex digits.
///
/// # Errors
/// The operating system has no randomness to give.
pub fn new_token() -> Result<String, String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| format!("error: no random token for the studio: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Whether `host` (a Host header) names this server: a loopback name with `port`.
#[must_use]
pub fn is_own_host(host: &str, port: u16) -> bool {
    let port = port.to_string();
    ["127.0.0.1", "localhost", "[::1]"].iter().any(|name| {
        host.len() == name.len() + 1 + port.len()
            && host[..name.len()].eq_ignore_ascii_case(name)
            && host[name.len()..].strip_prefix(':') == Some(port.as_str())
    })
}

/// Whether the request's `Origin`, if any, is the page's own (`http://` + its Host). Tools
/// send none; browsers send one on every socket upgrade and POST.
#[must_use]
pub fn is_own_origin(request: &Request) -> bool {
    match (request.header("origin"), request.header("host")) {
        (None, _) => true,
        (Some(origin), Some(host)) => origin.strip_prefix("http://").is_some_and(|o| o.eq_ignore_ascii_case(host)),
        (Some(_), None) => false,
    }
}

/// Equal, in a time that does not depend on where they differ.
#[must_use]
pub fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// The token the request carries in its header, if any.
#[must_use]
pub fn header_token(request: &Request) -> Option<&str> {
    request.header(TOKEN_HEADER)
}

/// Whether the request carries `token`, in its header or (`query`) its query.
#[must_use]
pub fn has_token(request: &Request, token: &str, query: bool) -> bool {
    let given = header_token(request)
        .map(str::to_string)
        .or_else(|| query.then(|| request.query_pairs().remove("token")).flatten());
    given.is_some_and(|g| same_secret(&g, token))
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    fn request(headers: &[(&str, &str)], query: &str) -> Request {
        Request {
            method: "GET".into(),
            path: "/".into(),
            query: query.into(),
            headers: headers.iter().map(|(k, v)| ((*k).to_string(), (*v).to_string())).collect::<BTreeMap<_, _>>(),
            body: Vec::new(),
            close: false,
        }
    }

    #[test]
    fn only_loopback_hosts_with_the_port_are_own() {
        for good in ["127.0.0.1:8080", "localhost:8080", "LOCALHOST:8080", "[::1]:8080"] {
            assert!(is_own_host(good, 8080), "{good}");
        }
        for bad in [
            "evil.example:8080",
            "127.0.0.1",
            "localhost",
            "127.0.0.1:8081",
            "127.0.0.1:80800",
            "localhost.evil:8080",
            "127.0.0.2:8080",
            "0.0.0.0:8080",
            "",
            "127.0.0.1:8080.evil",
            "127.0.0.1:8080 ",
            "[::1]",
        ] {
            assert!(!is_own_host(bad, 8080), "{bad}");
        }
    }

    #[test]
    fn the_origin_must_be_the_pages_own_when_given() {
        let host = ("host", "127.0.0.1:9");
        assert!(is_own_origin(&request(&[host], "")));
        assert!(is_own_origin(&request(&[host, ("origin", "http://127.0.0.1:9")], "")));
        for bad in ["http://evil.example", "null", "https://127.0.0.1:9", "http://localhost:9", "http://127.0.0.1:9.x"]
        {
            assert!(!is_own_origin(&request(&[host, ("origin", bad)], "")), "{bad}");
        }
    }

    #[test]
    fn tokens_are_random_and_checked_in_the_header_or_the_query() {
        let (a, b) = (new_token().unwrap(), new_token().unwrap());
        assert_eq!(a.len(), 32);
        assert_ne!(a, b);
        assert!(has_token(&request(&[(TOKEN_HEADER, &a)], ""), &a, false));
        assert!(has_token(&request(&[], &format!("x=1&token={a}")), &a, true));
        assert!(!has_token(&request(&[], &format!("token={a}")), &a, false), "the query only where allowed");
        assert!(!has_token(&request(&[(TOKEN_HEADER, &b)], &format!("token={a}")), &a, true));
        assert!(!has_token(&request(&[], ""), &a, true));
        assert!(!has_token(&request(&[], &format!("token={}", &a[..31])), &a, true));
    }
}
