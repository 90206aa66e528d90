//! Hostile traffic against a running viewer, on loopback only, bounded in time and count: the
//! test (`tests/view.rs`) asserts on its report, the benchmark (`cargo bench --bench
//! view_hostile`) writes it to `results/view-hostile.md`.
//!
//! For `duration`, eight client threads each send, in turn, one of the [`KINDS`] of bad
//! request (random and oversized headers; huge, negative and non-numeric `Content-Length`;
//! truncated requests; foreign `Origin` and `Host`; event streams dropped mid-way), while four
//! slow clients hold half-sent requests open, 25 event-stream clients read all along, and a
//! prober asks `GET /state` every 50 ms and times it. Then the worst cancels: restarts with the
//! largest render the viewer accepts, timed from the `POST` to its 202.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::common::viewer::Viewer;

/// The kinds of bad request, by name.
pub const KINDS: [&str; 12] = [
    "random header bytes",
    "oversized header (20 KiB)",
    "Content-Length 10^12 (POST)",
    "Content-Length 10^12 (GET)",
    "negative Content-Length",
    "non-numeric Content-Length",
    "truncated head",
    "truncated body",
    "foreign Origin (POST)",
    "foreign Host",
    "event stream dropped mid-way",
    "runaway render (16384² × 10^6 spp, 4096 threads)",
];

/// What a run saw.
#[derive(Debug, Default)]
pub struct Report {
    /// Requests sent, by kind.
    pub sent: BTreeMap<String, u64>,
    /// Answers, by kind and status ("closed" when the server closed without an answer).
    pub answers: BTreeMap<(String, String), u64>,
    /// `GET /state` probes: how many, how many failed, the slowest.
    pub probes: u64,
    pub failed_probes: u64,
    pub slowest_probe: Duration,
    /// Event streams read all along, and how many of them saw a `tile` event.
    pub streams: usize,
    pub streams_with_tiles: usize,
    /// The server's peak threads and resident memory (`/proc/PID/status`), sampled.
    pub peak_threads: u64,
    pub peak_rss_kib: u64,
    /// The restarts with the largest accepted render: settings and `POST` → 202 time.
    pub cancels: Vec<(String, Duration)>,
    /// How long the traffic ran.
    pub ran: Duration,
}

/// A tiny deterministic generator (xorshift), so a run is reproducible from its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// `host:port` of the viewer.
fn address(viewer: &Viewer) -> String {
    viewer.url.trim_start_matches("http://").trim_end_matches('/').to_string()
}

/// Sends `bytes` on a new connection (then closes the sending side if `half_close`) and returns
/// the answer's status, or "closed".
fn exchange(address: &str, bytes: &[u8], half_close: bool) -> String {
    let Ok(mut stream) = TcpStream::connect(address) else { return "refused".into() };
    let _ = stream.set_read_timeout(Some(Duration::from_secs(15)));
    let _ = stream.write_all(bytes);
    if half_close {
        let _ = stream.shutdown(std::net::Shutdown::Write);
    }
    let mut first = String::new();
    let _ = BufReader::new(&stream).read_line(&mut first);
    first.split_whitespace().nth(1).map_or("closed".into(), str::to_string)
}

/// One bad request of kind `k`; returns the status seen.
fn bad_request(address: &str, k: usize, rng: &mut Rng) -> String {
    let host = format!("Host: {address}\r\n");
    match k {
        0 => {
            let junk: Vec<u8> = (0..200 + rng.next() % 2000).map(|_| (rng.next() % 256) as u8).collect();
            let mut bytes = format!("GET /state HTTP/1.1\r\n{host}").into_bytes();
            bytes.extend(junk);
            bytes.extend(b"\r\n\r\n");
            exchange(address, &bytes, false)
        }
        1 => exchange(
            address,
            format!("GET /state HTTP/1.1\r\n{host}X-Big: {}\r\n\r\n", "a".repeat(20 << 10)).as_bytes(),
            false,
        ),
        2 => exchange(
            address,
            format!("POST /render HTTP/1.1\r\n{host}Content-Length: 1000000000000\r\n\r\nabc").as_bytes(),
            false,
        ),
        3 => exchange(
            address,
            format!("GET /state HTTP/1.1\r\n{host}Content-Length: 1000000000000\r\n\r\n").as_bytes(),
            false,
        ),
        4 => exchange(address, format!("POST /render HTTP/1.1\r\n{host}Content-Length: -7\r\n\r\n").as_bytes(), false),
        5 => exchange(address, format!("POST /render HTTP/1.1\r\n{host}Content-Length: 12ab\r\n\r\n").as_bytes(), false),
        6 => exchange(address, format!("GET /state HTTP/1.1\r\n{host}X-Cut: ").as_bytes(), true),
        7 => exchange(
            address,
            format!("POST /render HTTP/1.1\r\n{host}Content-Length: 5000\r\n\r\n[camera]").as_bytes(),
            true,
        ),
        8 => exchange(
            address,
            format!("POST /render?width=32 HTTP/1.1\r\n{host}Origin: https://evil.example\r\nContent-Length: 0\r\n\r\n")
                .as_bytes(),
            false,
        ),
        9 => exchange(address, b"GET /state HTTP/1.1\r\nHost: evil.example\r\n\r\n", false),
        10 => {
            let Ok(mut stream) = TcpStream::connect(address) else { return "refused".into() };
            let _ = stream.set_read_timeout(Some(Duration::from_secs(15)));
            let _ = stream.write_all(format!("GET /events HTTP/1.1\r\n{host}\r\n").as_bytes());
            let mut first = String::new();
            let _ = BufReader::new(&stream).read_line(&mut first);
            first.split_whitespace().nth(1).map_or("closed".into(), str::to_string) // dropped here
        }
        _ => exchange(
            address,
            format!(
                "POST /render?width=16384&height=16384&spp=1000000&threads=4096 HTTP/1.1\r\n{host}Content-Length: 0\r\n\r\n"
            )
            .as_bytes(),
            false,
        ),
    }
}

/// A `/proc/PID/status` field, as a number (kB for memory).
fn status_field(pid: u32, name: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(name)?.trim_start_matches(':').split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

/// Runs the traffic against `viewer` for `duration`, then the worst cancels.
pub fn run(viewer: &Viewer, duration: Duration, seed: u64) -> Report {
    let address = address(viewer);
    let pid = viewer.child.id();
    let report = Arc::new(Mutex::new(Report::default()));
    let stop = Arc::new(AtomicBool::new(false));
    let start = Instant::now();
    let mut threads = Vec::new();
    // 25 event streams, read all along.
    let streams: Vec<_> = (0..25)
        .map(|_| {
            let (address, stop) = (address.clone(), Arc::clone(&stop));
            std::thread::spawn(move || {
                let Ok(mut stream) = TcpStream::connect(&address) else { return false };
                let _ = stream.set_read_timeout(Some(Duration::from_millis(500)));
                let _ =
                    stream.write_all(format!("GET /events HTTP/1.1\r\nHost: {address}\r\n\r\n").as_bytes());
                let (mut tail, mut buffer, mut saw_tile) = (Vec::new(), vec![0u8; 1 << 16], false);
                while !stop.load(Ordering::SeqCst) {
                    match stream.read(&mut buffer) {
                        Ok(0) => break,
                        Ok(n) => {
                            tail.extend_from_slice(&buffer[..n]);
                            saw_tile |= String::from_utf8_lossy(&tail).contains("\"type\":\"tile\"");
                            tail.drain(..tail.len().saturating_sub(16)); // a marker may straddle reads
                        }
                        Err(_) => {} // a read timeout: look at the stop flag again
                    }
                }
                saw_tile
            })
        })
        .collect();
    // Four slow clients: half a request each, held past the server's request deadline.
    for _ in 0..4 {
        let (address, report) = (address.clone(), Arc::clone(&report));
        threads.push(std::thread::spawn(move || {
            let status = exchange_slowly(&address);
            let mut report = report.lock().unwrap();
            *report.sent.entry("slow client (head never finished)".into()).or_default() += 1;
            *report.answers.entry(("slow client (head never finished)".into(), status)).or_default() += 1;
        }));
    }
    // Eight senders of bad requests.
    for t in 0..8u64 {
        let (address, report, stop) = (address.clone(), Arc::clone(&report), Arc::clone(&stop));
        threads.push(std::thread::spawn(move || {
            let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (t + 1));
            while !stop.load(Ordering::SeqCst) {
                let k = (rng.next() % KINDS.len() as u64) as usize;
                let status = bad_request(&address, k, &mut rng);
                let mut report = report.lock().unwrap();
                *report.sent.entry(KINDS[k].into()).or_default() += 1;
                *report.answers.entry((KINDS[k].into(), status)).or_default() += 1;
            }
        }));
    }
    // The prober and the sampler of threads and memory.
    while start.elapsed() < duration {
        let asked = Instant::now();
        let status =
            exchange(&address, format!("GET /state HTTP/1.1\r\nHost: {address}\r\n\r\n").as_bytes(), false);
        let took = asked.elapsed();
        let mut r = report.lock().unwrap();
        r.probes += 1;
        r.failed_probes += u64::from(status != "200");
        r.slowest_probe = r.slowest_probe.max(took);
        r.peak_threads = r.peak_threads.max(status_field(pid, "Threads"));
        r.peak_rss_kib = r.peak_rss_kib.max(status_field(pid, "VmHWM"));
        drop(r);
        std::thread::sleep(Duration::from_millis(50));
    }
    stop.store(true, Ordering::SeqCst);
    threads.into_iter().for_each(|t| t.join().unwrap());
    let with_tiles = streams.into_iter().map(|s| s.join().unwrap()).filter(|&t| t).count();
    let mut report = Arc::try_unwrap(report).unwrap().into_inner().unwrap();
    (report.streams, report.streams_with_tiles, report.ran) = (25, with_tiles, start.elapsed());
    report.cancels = worst_cancels(viewer);
    report.peak_threads = report.peak_threads.max(status_field(pid, "Threads"));
    report.peak_rss_kib = report.peak_rss_kib.max(status_field(pid, "VmHWM"));
    report
}

/// Sends half a request head, a byte at a time, for 12 s (past the server's 10 s deadline).
fn exchange_slowly(address: &str) -> String {
    let Ok(mut stream) = TcpStream::connect(address) else { return "refused".into() };
    let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
    let head = format!("GET /state HTTP/1.1\r\nHost: {address}\r\nX-Slow: ");
    let start = Instant::now();
    for byte in head.bytes().chain(std::iter::repeat(b'z')) {
        if start.elapsed() > Duration::from_secs(12) || stream.write_all(&[byte]).is_err() {
            break;
        }
        let mut first = String::new();
        if BufReader::new(&stream).read_line(&mut first).is_ok() && !first.is_empty() {
            return first.split_whitespace().nth(1).map_or("closed".into(), str::to_string);
        }
    }
    "closed".into()
}

/// Restarts with the largest render the viewer accepts, in every mode, each after the one
/// before has run for 300 ms; returns each restart's `POST` → 202 time.
fn worst_cancels(viewer: &Viewer) -> Vec<(String, Duration)> {
    let threads = raypool::view::request::max_threads();
    let mut cancels = Vec::new();
    for mode in ["steal", "pool", "static", "interleaved", "pool-rows", "serial"] {
        for scene in ["final", "paper3"] {
            let query = format!(
                "/render?scene={scene}&width=2048&height=2048&spp=1000000&threads={threads}&tile=64&mode={mode}"
            );
            std::thread::sleep(Duration::from_millis(300));
            let asked = Instant::now();
            let (status, body) = viewer.post(&query, b"");
            assert_eq!(status, 202, "{query}: {body}");
            cancels.push((query, asked.elapsed()));
        }
    }
    cancels
}

/// What [`slow_image_readers`] saw.
#[derive(Debug, Default)]
pub struct SlowReaders {
    /// The viewer's resident memory before the readers came, KiB.
    pub before_kib: u64,
    /// Its peak resident memory while they held their answers (`VmHWM`), KiB.
    pub peak_kib: u64,
    /// The first line's status each reader got ("none" if nothing came within a second).
    pub answers: BTreeMap<String, usize>,
}

/// `readers` connections that each ask for `/image.pfm` and then read nothing for `hold`,
/// against a viewer whose first pass has finished; then each reads its status line.
pub fn slow_image_readers(viewer: &Viewer, readers: usize, hold: Duration) -> SlowReaders {
    let (address, pid) = (address(viewer), viewer.child.id());
    let before_kib = status_field(pid, "VmRSS");
    let request = format!("GET /image.pfm HTTP/1.1\r\nHost: {address}\r\n\r\n");
    let streams: Vec<TcpStream> = (0..readers)
        .filter_map(|_| {
            let mut stream = TcpStream::connect(&address).ok()?;
            stream.write_all(request.as_bytes()).ok()?;
            Some(stream)
        })
        .collect();
    std::thread::sleep(hold);
    let peak_kib = status_field(pid, "VmHWM");
    let mut answers = BTreeMap::new();
    for mut stream in streams {
        let _ = stream.set_read_timeout(Some(Duration::from_secs(1)));
        let mut head = [0u8; 12];
        let status = match stream.read_exact(&mut head) {
            Ok(()) => String::from_utf8_lossy(&head[9..]).into_owned(),
            Err(_) => "none".into(),
        };
        *answers.entry(status).or_default() += 1;
    }
    SlowReaders { before_kib, peak_kib, answers }
}
