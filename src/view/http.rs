//! The viewer's HTTP/1.1, on `std::net` and `httparse` (the request parser hyper uses): one
//! request per connection, read under caps and a deadline whatever the client claims.
//!
//! Why not an HTTP server crate: `tiny_http` 0.12 (its latest release), which the viewer
//! used, allocates a buffer the size of the claimed `Content-Length` when it drops a request
//! whose body was not read (`Content-Length: 1000000000000` aborted the process), and reads
//! that body on the thread that drops it; the well-kept servers (hyper, axum) need an async
//! runtime and would turn the event stream into a future. What is left to write by hand is
//! small and is exactly the part that must be bounded, so it is here:
//!
//! | bound | value | when it is hit |
//! |---|---|---|
//! | request head (request line and headers) | [`MAX_HEAD`] bytes | 431, connection closed |
//! | body | the caller's cap ([`read_request`]) | 413 before a byte of it is read |
//! | whole request | [`REQUEST_TIME`] from the first byte | 408: a slow or stalled client costs one thread for at most this long |
//! | answer | [`WRITE_TIME`] per write | the client is dropped |
//!
//! A `Content-Length` that is not a single non-negative decimal number is a 400; a body in
//! `Transfer-Encoding: chunked` is a 411 (the page never sends one). Every answer closes the
//! connection, so nothing of a request can be left unread for the next one; what a client
//! still sends after the answer is read and dropped for at most 2 s and 4 MiB, so that it sees
//! the answer instead of a reset.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Largest request head, bytes.
pub const MAX_HEAD: usize = 16 * 1024;
/// Longest time from a connection's first byte to the end of its request.
pub const REQUEST_TIME: Duration = Duration::from_secs(10);
/// Longest time one write of an answer may block (a page that stopped reading is dropped).
pub const WRITE_TIME: Duration = Duration::from_secs(10);

/// A request, read whole.
#[derive(Debug)]
pub struct Request {
    /// `GET`, `POST`, …
    pub method: String,
    /// The path, without the query.
    pub path: String,
    /// What follows `?` in the target, or "".
    pub query: String,
    /// Header names (lower case) and values, in order.
    pub headers: Vec<(String, String)>,
    /// The body: at most the cap given to [`read_request`].
    pub body: Vec<u8>,
}

impl Request {
    /// The first header called `name` (lower case), if any.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }
}

/// Why a request could not be read: an HTTP status and a one-line reason, or `None` for a
/// client that left (nothing to answer).
pub type ReadError = Option<(u16, String)>;

/// Reads one request from `stream`: its head (at most [`MAX_HEAD`] bytes), then a body of at
/// most `max_body` bytes, all within [`REQUEST_TIME`].
pub fn read_request(stream: &mut TcpStream, max_body: usize) -> Result<Request, ReadError> {
    let deadline = Instant::now() + REQUEST_TIME;
    let mut buffer = Vec::with_capacity(1024);
    let (head_len, mut request) = loop {
        if let Some(parsed) = parse_head(&buffer)? {
            break parsed;
        }
        if buffer.len() >= MAX_HEAD {
            return Err(Some((431, format!("the request head is larger than {}", size(MAX_HEAD)))));
        }
        let room = MAX_HEAD - buffer.len();
        if read_some(stream, &mut buffer, room.min(4096), deadline)? == 0 {
            return Err(None);
        }
    };
    let length = body_length(&request)?;
    if length > max_body {
        return Err(Some((413, format!("the body is larger than {}", size(max_body)))));
    }
    let mut body = buffer.split_off(head_len.min(buffer.len()));
    body.truncate(length);
    body.reserve_exact(length - body.len());
    while body.len() < length {
        let missing = length - body.len();
        if read_some(stream, &mut body, missing, deadline)? == 0 {
            return Err(Some((400, format!("the body ended after {} of {length} bytes", body.len()))));
        }
    }
    request.body = body;
    Ok(request)
}

/// `bytes` as "N MiB" or "N KiB" or "N bytes".
fn size(bytes: usize) -> String {
    match bytes {
        b if b >= 1 << 20 && b % (1 << 20) == 0 => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 && b % (1 << 10) == 0 => format!("{} KiB", b >> 10),
        b => format!("{b} bytes"),
    }
}

/// The head in `buffer`, parsed, with its length; `None` if more bytes are needed.
fn parse_head(buffer: &[u8]) -> Result<Option<(usize, Request)>, ReadError> {
    let mut headers = [httparse::EMPTY_HEADER; 64];
    let mut parsed = httparse::Request::new(&mut headers);
    let head_len = match parsed.parse(buffer) {
        Ok(httparse::Status::Complete(n)) => n,
        Ok(httparse::Status::Partial) => return Ok(None),
        Err(httparse::Error::TooManyHeaders) => return Err(Some((431, "more than 64 headers".into()))),
        Err(e) => return Err(Some((400, format!("not an HTTP request: {e}")))),
    };
    let target = parsed.path.unwrap_or("/");
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let headers = parsed
        .headers
        .iter()
        .map(|h| (h.name.to_ascii_lowercase(), String::from_utf8_lossy(h.value).into_owned()))
        .collect();
    let method = parsed.method.unwrap_or("").to_string();
    let request = Request { method, path: path.into(), query: query.into(), headers, body: Vec::new() };
    Ok(Some((head_len, request)))
}

/// The body's length as the headers give it: 0 without `Content-Length`.
fn body_length(request: &Request) -> Result<usize, ReadError> {
    if request.header("transfer-encoding").is_some() {
        return Err(Some((411, "send the body with a Content-Length, not Transfer-Encoding".into())));
    }
    let lengths: Vec<&str> =
        request.headers.iter().filter(|(n, _)| n == "content-length").map(|(_, v)| v.trim()).collect();
    match lengths[..] {
        [] => Ok(0),
        [text] if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) => {
            // A number too large for usize is larger than any cap.
            Ok(text.parse().unwrap_or(usize::MAX))
        }
        [text] => Err(Some((400, format!("Content-Length must be a non-negative number, not '{text}'")))),
        _ => Err(Some((400, "more than one Content-Length".into()))),
    }
}

/// Reads at most `most` more bytes into `into`, waiting no later than `deadline`; 0 at the
/// end of the stream.
fn read_some(
    stream: &mut TcpStream,
    into: &mut Vec<u8>,
    most: usize,
    deadline: Instant,
) -> Result<usize, ReadError> {
    let too_slow = || Some((408, format!("the request took longer than {} s", REQUEST_TIME.as_secs())));
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(too_slow());
        }
        stream.set_read_timeout(Some(left)).map_err(|_| None)?;
        let start = into.len();
        into.resize(start + most, 0);
        let read = stream.read(&mut into[start..]);
        into.truncate(start + read.as_ref().map_or(0, |n| *n));
        match read {
            Ok(n) => return Ok(n),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                return Err(too_slow());
            }
            Err(_) => return Err(None),
        }
    }
}

/// An answer: status, headers, body.
#[derive(Debug)]
pub struct Response {
    /// HTTP status.
    pub status: u16,
    /// Header names and values (`Content-Length` and `Connection` are added).
    pub headers: Vec<(&'static str, String)>,
    /// The body (shared: the same encoded image goes to every reader of a pass).
    pub body: Arc<[u8]>,
}

impl Response {
    /// A 200 with `content_type`.
    pub fn ok(content_type: &str, body: impl Into<Arc<[u8]>>) -> Response {
        Response { status: 200, headers: vec![("Content-Type", content_type.into())], body: body.into() }
    }

    /// `status` with a one-line plain-text reason.
    pub fn text(status: u16, reason: &str) -> Response {
        Response {
            status,
            headers: vec![("Content-Type", "text/plain; charset=utf-8".into())],
            body: format!("{reason}\n").into_bytes().into(),
        }
    }

    /// The same, with one more header.
    pub fn with(mut self, name: &'static str, value: impl ToString) -> Response {
        self.headers.push((name, value.to_string()));
        self
    }

    /// Writes the answer and closes the connection; a client that left is not an error.
    pub fn send(self, stream: &mut TcpStream) {
        let mut head = format!("HTTP/1.1 {} {}\r\n", self.status, reason_phrase(self.status));
        for (name, value) in &self.headers {
            head.push_str(&format!("{name}: {value}\r\n"));
        }
        head.push_str(&format!("Content-Length: {}\r\nConnection: close\r\n\r\n", self.body.len()));
        let _ = stream.set_write_timeout(Some(WRITE_TIME));
        let _ = stream.write_all(head.as_bytes()).and_then(|()| stream.write_all(&self.body));
        let _ = stream.flush();
        linger(stream);
    }
}

/// Closes the connection gracefully: our side first, then whatever the client still sends is
/// read and dropped until it closes too, for at most [`LINGER`] and [`LINGER_BYTES`]. A client
/// still sending a body the server refused (a 413) would otherwise get a reset before it reads
/// the answer.
fn linger(stream: &mut TcpStream) {
    let _ = stream.shutdown(std::net::Shutdown::Write);
    let give_up = Instant::now() + LINGER;
    let (mut drained, mut sink) = (0, [0u8; 16 * 1024]);
    while drained < LINGER_BYTES {
        let left = give_up.saturating_duration_since(Instant::now());
        if left.is_zero() || stream.set_read_timeout(Some(left)).is_err() {
            break;
        }
        match stream.read(&mut sink) {
            Ok(0) | Err(_) => break,
            Ok(n) => drained += n,
        }
    }
}

/// How long, and how much, [`linger`] reads after an answer.
const LINGER: Duration = Duration::from_secs(2);
const LINGER_BYTES: usize = 4 << 20;

/// The standard reason phrase of the statuses the viewer sends.
fn reason_phrase(status: u16) -> &'static str {
    match status {
        200 => "OK",
        202 => "Accepted",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        500 => "Internal Server Error",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    }
}
