//! **The viewer**: `raypool view`, a local web server whose page shows the image refining
//! live, each tile drawn the moment a worker finishes it and outlined in that worker's colour,
//! with a timeline of one lane per worker; the page's controls and camera restart the render.
//!
//! This is the top layer: of the command line it uses only the flags and what they resolve
//! to ([`crate::cli::args`], [`crate::cli::settings`]: a request is checked by the command
//! line's own flag definitions and rules), never a command; it also uses [`crate::schedule`]
//! (the passes run on our schedulers and pools, never on the server's threads),
//! [`crate::measure::machine`] (the CPUs, for its thread limit), [`crate::files`] and
//! [`crate::scenes`]. Nothing uses it but `main.rs`. [`session`] owns the one render at a
//! time and renders its passes (`passes.rs` holds what they share), [`preview`] its navigation frames while the camera moves, [`events`] what the pages
//! are told, [`request`] turns a request into a checked render, [`http`] reads requests under caps
//! and deadlines, [`server`] answers them to the page's own origin only, and `page.html` is
//! the page.

pub mod events;
pub mod http;
mod passes;
pub mod preview;
pub mod request;
pub mod server;
pub mod session;

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use crate::cli::args::ViewArgs;
use crate::error::Error;
use crate::view::http::Response;
use crate::view::server::Origins;
use crate::view::session::Session;

/// Connections served at once (event streams included); more are answered 503 and closed.
/// Each costs one thread, for at most `http::REQUEST_TIME` unless it is an event stream.
pub const MAX_CONNECTIONS: usize = 256;

/// Runs `raypool view` until Ctrl-C (or SIGTERM): prints the address as the first line of
/// stdout, renders the command line's scene, and serves the page.
pub fn run(args: ViewArgs) -> Result<(), Error> {
    let config = request::config(&args, None, None, None)?;
    let ip = args.bind.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    let listener = TcpListener::bind((ip, args.port))
        .map_err(|e| Error::new(format!("cannot serve on {ip} port {}: {e}", args.port)))?;
    let address = listener.local_addr().map_err(|e| Error::new(format!("the server has no address: {e}")))?;
    if args.bind.is_some() {
        eprintln!(
            "raypool: warning: serving on {address}: anyone who can reach it can use this viewer and its CPUs"
        );
    }
    println!("http://{address}/");
    let _ = std::io::stdout().flush();

    let stop = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, Arc::clone(&stop))
            .map_err(|e| Error::new(format!("cannot catch Ctrl-C: {e}")))?;
    }
    let session = Session::start(config);
    let origins = Origins::of(address);
    {
        let session = Arc::clone(&session);
        std::thread::Builder::new()
            .name("raypool-http-accept".into())
            .spawn(move || accept(&listener, &session, &origins))
            .map_err(|e| Error::new(format!("cannot start the server's thread: {e}")))?;
    }
    while !stop.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(50)); // Ctrl-C is noticed within 50 ms
    }
    session.stop();
    eprintln!("raypool: viewer stopped");
    Ok(())
}

/// Accepts connections forever, each answered on a thread of its own, at most
/// [`MAX_CONNECTIONS`] at once.
fn accept(listener: &TcpListener, session: &Arc<Session>, origins: &Origins) {
    let live = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue }; // a connection reset before it was accepted
        if live.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            live.fetch_sub(1, Ordering::SeqCst);
            refuse(stream);
            continue;
        }
        let (session, origins, done) = (Arc::clone(session), origins.clone(), Arc::clone(&live));
        let spawned = std::thread::Builder::new().name("raypool-http".into()).spawn(move || {
            server::handle(&session, &origins, stream);
            done.fetch_sub(1, Ordering::SeqCst);
        });
        if spawned.is_err() {
            live.fetch_sub(1, Ordering::SeqCst); // the stream was dropped with the closure: closed
        }
    }
}

/// Answers 503 without blocking the accepting thread: the answer fits the socket's buffer.
fn refuse(mut stream: TcpStream) {
    if stream.set_nonblocking(true).is_ok() {
        let busy = format!("the viewer is serving {MAX_CONNECTIONS} connections: try again");
        Response::text(503, &busy).send(&mut stream);
    }
}
