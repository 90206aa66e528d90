//! The HTTP side of the viewer, on [`http`](crate::view::http): the page, the event stream,
//! render requests and the current image, to the page's own origin only.
//!
//! | request | answer |
//! |---|---|
//! | `GET /` | the page (compiled into the binary) |
//! | `GET /state` | JSON: the running render's settings and the built-in scenes |
//! | `GET /events` | server-sent events: `start`, then a `tile` per finished tile, a `pass` per pass, `done` |
//! | `POST /render?flag=value…` | cancels the running render and starts this one (body: a pasted TOML scene, optional); 202 |
//! | `GET /image.pfm`, `/image.png` | the image after the latest finished pass, encoded once per pass for every reader (at most 32 at once, then 503); header `X-Raypool-Spp` says how many samples |
//! | `GET /preview.rgba` | the latest navigation frame (a `POST /render` with `preview=1` makes one; it stays while the next render runs): 8-bit RGBA, its size in `X-Raypool-Width` and `X-Raypool-Height`, its render in `X-Raypool-Gen` (counted among the 32 image answers) |
//! | `GET /scene.toml` | the running render's scene, camera included |
//!
//! Every connection is answered on its own short thread (an event stream lives as long as its
//! page); rendering never runs on them, only on the session's pool. A bad request gets a 4xx
//! status and a one-line reason, and the server goes on serving.
//!
//! **Same origin only**, as Jupyter's server does. A request whose `Host` is not an address
//! this server answers on (`127.0.0.1:PORT`, `localhost:PORT`, `[::1]:PORT`, or the `--bind`
//! address) gets 403: a DNS-rebinding page, whose requests carry its own host name, can read
//! nothing. A `POST` whose `Origin` is present and is not `http://` + one of those gets 403: a
//! page on another site cannot start renders on this machine.

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, TcpStream};
use std::sync::Arc;
use std::time::Duration;

use crossbeam_channel::RecvTimeoutError;
use serde_json::json;

use crate::files::output::Format;
use crate::scenes::builtin::BUILTINS;
use crate::schedule::modes::Schedule;
use crate::schedule::random::RngChoice;
use crate::view::http::{Request, Response, WRITE_TIME, read_request};
use crate::view::request::{MAX_PASTED_SCENE, parse};
use crate::view::session::{MAX_IMAGE_READERS, Session};

/// The page, compiled in: no CDN, works offline.
const PAGE: &str = include_str!("page.html");

/// A page's event stream sends a comment this often when idle, so a gone page is noticed.
const KEEP_ALIVE: Duration = Duration::from_secs(10);

/// The `Host` values this server answers to.
#[derive(Clone, Debug)]
pub struct Origins {
    hosts: Vec<String>,
}

impl Origins {
    /// Those of a server listening on `address` (its port, and its IP if not loopback).
    pub fn of(address: SocketAddr) -> Origins {
        let port = address.port();
        let mut hosts: Vec<String> =
            ["127.0.0.1", "localhost", "[::1]"].iter().map(|h| format!("{h}:{port}")).collect();
        let ip = address.ip();
        if !ip.is_loopback() && !ip.is_unspecified() {
            hosts.push(SocketAddr::new(ip, port).to_string());
        }
        if ip == IpAddr::V4(Ipv4Addr::UNSPECIFIED) || ip == IpAddr::V6(Ipv6Addr::UNSPECIFIED) {
            // Bound to every interface: the machine's own names are not known here, so any
            // IP literal with this port is accepted (a rebinding page uses a name, not an IP).
            hosts.push(format!("*:{port}"));
        }
        Origins { hosts }
    }

    fn host_allowed(&self, host: &str) -> bool {
        let host = host.trim().to_ascii_lowercase();
        self.hosts.iter().any(|allowed| match allowed.strip_prefix("*:") {
            Some(port) => host.rsplit_once(':').is_some_and(|(ip, p)| {
                p == port && ip.trim_start_matches('[').trim_end_matches(']').parse::<IpAddr>().is_ok()
            }),
            None => *allowed == host,
        })
    }

    /// `Err((403, reason))` for a request from outside the page's own origin.
    fn check(&self, request: &Request) -> Result<(), (u16, String)> {
        let host = request.header("host").unwrap_or("");
        if !self.host_allowed(host) {
            return Err((403, format!("Host '{host}' is not this viewer's address")));
        }
        if let Some(origin) = request.header("origin").filter(|_| request.method != "GET") {
            let own = origin.strip_prefix("http://").is_some_and(|h| self.host_allowed(h));
            if !own {
                return Err((403, format!("requests from the page of '{origin}' are refused")));
            }
        }
        Ok(())
    }
}

/// Reads and answers one connection.
pub fn handle(session: &Arc<Session>, origins: &Origins, mut stream: TcpStream) {
    let request = match read_request(&mut stream, MAX_PASTED_SCENE) {
        Ok(request) => request,
        Err(Some((status, reason))) => return Response::text(status, &reason).send(&mut stream),
        Err(None) => return, // the client left
    };
    if let Err((status, reason)) = origins.check(&request) {
        return Response::text(status, &reason).send(&mut stream);
    }
    let path = request.path.as_str();
    let answer = match (request.method.as_str(), path) {
        ("GET", "/") => Ok(Response::ok("text/html; charset=utf-8", PAGE.as_bytes().to_vec())),
        ("GET", "/state") => Ok(Response::ok("application/json", state(session).into_bytes())),
        ("GET", "/events") => return stream_events(session, stream),
        ("POST", "/render") => render(session, &request),
        ("GET", "/image.pfm") => return image(session, Format::Pfm, &mut stream),
        ("GET", "/image.png") => return image(session, Format::Png, &mut stream),
        ("GET", "/preview.rgba") => return preview(session, &mut stream),
        ("GET", "/scene.toml") => {
            Ok(Response::ok("text/plain; charset=utf-8", session.current().1.scene.to_toml().into_bytes()))
        }
        (
            method,
            "/" | "/state" | "/events" | "/render" | "/image.pfm" | "/image.png" | "/preview.rgba"
            | "/scene.toml",
        ) => Err((405, format!("{method} is not allowed on {path}"))),
        _ => Err((404, format!("no such page: {path}"))),
    };
    answer.unwrap_or_else(|(status, reason)| Response::text(status, &reason)).send(&mut stream);
}

type Answer = Result<Response, (u16, String)>;

/// `GET /state`: what the page's controls start from, and the scenes and modes they offer
/// (from the code's own lists, so a new `--mode` needs no edit here or in the page).
fn state(session: &Session) -> String {
    let (generation, config) = session.current();
    let settings = &config.job.settings;
    json!({
        "gen": generation, "scene": config.name, "scenes": BUILTINS.iter().map(|b| b.name).collect::<Vec<_>>(),
        "mode": config.mode.name(), "modes": Schedule::ALL.map(Schedule::name), "threads": config.threads, "tile": config.tile,
        "rng": if config.rng == RngChoice::Shared { "shared" } else { "per-sample" }, "sampler": settings.sampler.name(),
        "light-sampling": settings.light_sampling.name(), "guiding": if settings.guiding.is_some() { "on" } else { "off" },
        "width": settings.width, "height": settings.height, "spp": settings.spp, "denoise": config.denoise,
    })
    .to_string()
}

/// `POST /render`: checks the request, then restarts the render with it.
fn render(session: &Arc<Session>, request: &Request) -> Answer {
    let body = std::str::from_utf8(&request.body)
        .map_err(|_| (400, "the pasted scene is not UTF-8 text".to_string()))?;
    let config = parse(&request.query, body, &session.current().1).map_err(|e| (400, e.to_string()))?;
    let generation = session.restart(config);
    Ok(Response {
        status: 202,
        ..Response::ok("application/json", json!({ "gen": generation }).to_string().into_bytes())
    })
}

/// Writes an image answer, `answer()`, if one of the [`MAX_IMAGE_READERS`] places is free;
/// 503 if not.
fn send_image(session: &Session, stream: &mut TcpStream, answer: impl FnOnce() -> Response) {
    let Some(_slot) = session.image_slot() else {
        let busy = format!("{MAX_IMAGE_READERS} images are being sent: try again in a moment");
        return Response::text(503, &busy).send(stream);
    };
    answer().send(stream);
}

/// `GET /image.*`: the latest finished pass, encoded once per pass and shared.
fn image(session: &Session, format: Format, stream: &mut TcpStream) {
    send_image(session, stream, || match session.encoded(format) {
        Ok(Some(image)) => {
            let content_type = if format == Format::Png { "image/png" } else { "application/octet-stream" };
            Response::ok(content_type, image.bytes)
                .with("X-Raypool-Spp", image.spp)
                .with("X-Raypool-Gen", image.generation)
        }
        Ok(None) => Response::text(409, "no pass has finished yet: ask again in a moment"),
        Err(e) => Response::text(500, &e),
    });
}

/// `GET /preview.rgba`: the latest navigation frame, shared bytes; 409 before the first.
fn preview(session: &Session, stream: &mut TcpStream) {
    send_image(session, stream, || match session.preview() {
        Some(p) => Response::ok("application/octet-stream", Arc::clone(&p.rgba))
            .with("X-Raypool-Width", p.width)
            .with("X-Raypool-Height", p.height)
            .with("X-Raypool-Gen", p.generation),
        None => Response::text(409, "no navigation frame yet: a POST /render with preview=1 makes one"),
    });
}

/// `GET /events`: server-sent events until the page goes or the server stops. A page that
/// stops reading is dropped after one write has blocked for [`WRITE_TIME`].
fn stream_events(session: &Session, mut out: TcpStream) {
    let events = session.subscribe();
    let _ = out.set_write_timeout(Some(WRITE_TIME));
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
