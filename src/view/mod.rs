//! **The viewer**: `raypool view`, a local web server whose page shows the image refining
//! live, each tile drawn the moment a worker finishes it and outlined in that worker's colour,
//! with a timeline of one lane per worker; the page's controls and camera restart the render.
//!
//! This is the top layer: it uses [`crate::cli`] (a request is checked by the command line's
//! own flag definitions), [`crate::schedule`] (the passes run on our schedulers and pools, never
//! on the server's threads), [`crate::files`] and [`crate::scenes`]. Nothing uses it but
//! `main.rs`. [`session`] owns the one render at a time, [`request`] turns a request into a
//! checked render, [`server`] answers HTTP, and `page.html` is the page.

pub mod session;
pub mod request;
pub mod server;

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::cli::ViewArgs;
use crate::error::Error;
use crate::view::session::Session;

/// Runs `raypool view` until Ctrl-C (or SIGTERM): prints the address as the first line of
/// stdout, renders the command line's scene, and serves the page.
pub fn run(args: ViewArgs) -> Result<(), Error> {
    let config = request::config(&args, None, None)?;
    let ip = args.bind.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    let server = tiny_http::Server::http((ip, args.port))
        .map_err(|e| Error::new(format!("cannot serve on {ip} port {}: {e}", args.port)))?;
    let address = server.server_addr().to_ip().ok_or_else(|| Error::new("the server has no TCP address"))?;
    if args.bind.is_some() {
        eprintln!(
            "raypool: warning: serving on {address}: anyone who can reach it can use this viewer and its CPUs"
        );
    }
    println!("http://{address}/");
    let _ = std::io::stdout().flush();

    let stop = Arc::new(AtomicBool::new(false));
    let on_signal = Arc::clone(&stop);
    ctrlc::set_handler(move || on_signal.store(true, Ordering::SeqCst))
        .map_err(|e| Error::new(format!("cannot catch Ctrl-C: {e}")))?;
    let session = Session::start(config);
    while !stop.load(Ordering::SeqCst) {
        // A short wait, so Ctrl-C is noticed within a tenth of a second.
        if let Ok(Some(request)) = server.recv_timeout(Duration::from_millis(100)) {
            let session = Arc::clone(&session);
            std::thread::spawn(move || server::handle(&session, request));
        }
    }
    session.stop();
    eprintln!("raypool: viewer stopped");
    Ok(())
}
