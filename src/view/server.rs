//! The HTTP side of the viewer, on `tiny_http`: the page, the event stream, render requests
//! and the current image.
//!
//! | request | answer |
//! |---|---|
//! | `GET /` | the page (compiled into the binary) |
//! | `GET /state` | JSON: the running render's settings and the built-in scenes |
//! | `GET /events` | server-sent events: `start`, then a `tile` per finished tile, a `pass` per pass, `done` |
//! | `POST /render?flag=value…` | cancels the running render and starts this one (body: a pasted TOML scene, optional); 202 |
//! | `GET /image.pfm`, `/image.png` | the image after the latest finished pass; header `X-Raypool-Spp` says how many samples |
//! | `GET /scene.toml` | the running render's scene, camera included |
//!
//! Every request is answered on its own short thread (an event stream lives as long as its
//! page); rendering never runs on them, only on the session's pool. A bad request gets a 4xx
//! status and a one-line reason, and the server goes on serving.

use std::io::{Read, Write};
use std::sync::Arc;
use std::time::Duration;

use crossbeam_channel::RecvTimeoutError;
use serde_json::json;
use tiny_http::{Header, Method, Request, Response};

use crate::files::output::{Format, encode};
use crate::scenes::builtin::BUILTINS;
use crate::view::request::{MAX_PASTED_SCENE, parse};
use crate::view::session::Session;

/// The page, compiled in: no CDN, works offline.
const PAGE: &str = include_str!("page.html");

/// A page's event stream sends a comment this often when idle, so a gone page is noticed.
const KEEP_ALIVE: Duration = Duration::from_secs(10);

/// Answers `request`.
pub fn handle(session: &Arc<Session>, mut request: Request) {
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let answer = match (request.method(), path) {
        (Method::Get, "/") => ok("text/html; charset=utf-8", PAGE.as_bytes().to_vec()),
        (Method::Get, "/state") => ok("application/json", state(session).into_bytes()),
        (Method::Get, "/events") => return stream_events(session, request),
        (Method::Post, "/render") => render(session, query, &mut request),
        (Method::Get, "/image.pfm") => image(session, Format::Pfm),
        (Method::Get, "/image.png") => image(session, Format::Png),
        (Method::Get, "/scene.toml") => {
            ok("text/plain; charset=utf-8", session.current().1.scene.to_toml().into_bytes())
        }
        (_, "/" | "/state" | "/events" | "/render" | "/image.pfm" | "/image.png" | "/scene.toml") => {
            Err((405, format!("{} is not allowed on {path}", request.method())))
        }
        _ => Err((404, format!("no such page: {path}"))),
    };
    let response = match answer {
        Ok(response) => response,
        Err((status, reason)) => text_response(status, &reason),
    };
    let _ = request.respond(response); // a client that left is not an error
}

type Answer = Result<Response<std::io::Cursor<Vec<u8>>>, (u16, String)>;

fn ok(content_type: &str, body: Vec<u8>) -> Answer {
    Ok(Response::from_data(body).with_header(header("Content-Type", content_type)))
}

fn text_response(status: u16, reason: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_data(format!("{reason}\n").into_bytes())
        .with_status_code(status)
        .with_header(header("Content-Type", "text/plain; charset=utf-8"))
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
}

/// `GET /state`: what the page's controls start from.
fn state(session: &Session) -> String {
    let (generation, config) = session.current();
    let settings = &config.job.settings;
    json!({
        "gen": generation, "scene": config.name, "scenes": BUILTINS.iter().map(|b| b.name).collect::<Vec<_>>(),
        "mode": config.mode.name(), "threads": config.threads, "tile": config.tile,
        "rng": if config.shared_rng { "shared" } else { "per-sample" }, "sampler": settings.sampler.name(),
        "width": settings.width, "height": settings.height, "spp": settings.spp,
    })
    .to_string()
}

/// `POST /render`: checks the request, then restarts the render with it.
fn render(session: &Arc<Session>, query: &str, request: &mut Request) -> Answer {
    if request.body_length().is_some_and(|n| n > MAX_PASTED_SCENE) {
        return Err((413, format!("the pasted scene is larger than {} MiB", MAX_PASTED_SCENE >> 20)));
    }
    let mut body = Vec::new();
    request
        .as_reader()
        .take(MAX_PASTED_SCENE as u64 + 1)
        .read_to_end(&mut body)
        .map_err(|e| (400, format!("cannot read the request body: {e}")))?;
    if body.len() > MAX_PASTED_SCENE {
        return Err((413, format!("the pasted scene is larger than {} MiB", MAX_PASTED_SCENE >> 20)));
    }
    let body =
        String::from_utf8(body).map_err(|_| (400, "the pasted scene is not UTF-8 text".to_string()))?;
    let config = parse(query, &body).map_err(|e| (400, e.to_string()))?;
    let generation = session.restart(config);
    Ok(Response::from_data(json!({ "gen": generation }).to_string().into_bytes())
        .with_status_code(202)
        .with_header(header("Content-Type", "application/json")))
}

/// `GET /image.*`: the latest finished pass.
fn image(session: &Session, format: Format) -> Answer {
    let snapshot =
        session.latest().ok_or((409, "no pass has finished yet: ask again in a moment".to_string()))?;
    let mut bytes = Vec::new();
    encode(&snapshot.image, format, &mut bytes).map_err(|e| (500, e))?;
    let content_type = if format == Format::Png { "image/png" } else { "application/octet-stream" };
    Ok(Response::from_data(bytes)
        .with_header(header("Content-Type", content_type))
        .with_header(header("X-Raypool-Spp", &snapshot.spp.to_string()))
        .with_header(header("X-Raypool-Gen", &snapshot.generation.to_string())))
}

/// `GET /events`: server-sent events until the page goes or the server stops.
fn stream_events(session: &Session, request: Request) {
    let events = session.subscribe();
    let mut out = request.into_writer();
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-cache\r\nConnection: close\r\n\r\n";
    if out.write_all(head.as_bytes()).and_then(|()| out.flush()).is_err() {
        return;
    }
    loop {
        let sent = match events.recv_timeout(KEEP_ALIVE) {
            Ok(event) => write!(out, "data: {event}\n\n"),
            Err(RecvTimeoutError::Timeout) => out.write_all(b": still here\n\n"),
            Err(RecvTimeoutError::Disconnected) => return,
        };
        if sent.and_then(|()| out.flush()).is_err() {
            return; // the page has gone; dropping `events` unsubscribes it
        }
    }
}
