//! `raypool view`, over HTTP: the page, the event stream with tiles from several workers, the
//! image equal to the command line's byte for byte (before and after a camera move), bad
//! requests answered with 4xx while the server goes on, cancelled renders that leave no thread
//! behind, and Ctrl-C.

mod common;
mod deadline;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::process::Command;
use std::time::{Duration, Instant};

use common::viewer::{Viewer, until_done};
use deadline::output_within;
use serde_json::Value;

const MINUTE: Duration = Duration::from_secs(60);

/// `raypool render` of the server's current scene with these flags, as PFM bytes.
fn cli_render(viewer: &Viewer, flags: &[&str]) -> Vec<u8> {
    viewer.cli_render(flags, "cli.pfm")
}

/// The server's image once render `generation` is done (a new event stream replays the
/// finished render's `done`, so this cannot miss it).
fn served_image(viewer: &Viewer, generation: u64) -> Vec<u8> {
    until_done(&mut viewer.events(), generation);
    let (status, image) = viewer.get("/image.pfm");
    assert_eq!(status, 200);
    assert!(image.starts_with(b"PF\n"));
    image
}

#[test]
fn the_page_the_events_and_the_image_of_the_command_line() {
    let viewer =
        Viewer::start(&["--scene", "final", "--width", "96", "--spp", "8", "--threads", "3", "--tile", "8"]);
    let (status, page) = viewer.get("/");
    assert_eq!(status, 200);
    let page = String::from_utf8(page).unwrap();
    assert!(page.contains("<canvas id=\"image\"") && page.contains("new EventSource(\"/events\")"));
    assert!(!page.contains("http://") && !page.contains("https://"), "no CDN: the page works offline");
    let (_, state) = viewer.get("/state");
    let state: Value = serde_json::from_slice(&state).unwrap();
    assert_eq!(
        (state["width"].as_u64(), state["threads"].as_u64(), state["mode"].as_str()),
        (Some(96), Some(3), Some("steal"))
    );

    // Render 2, asked for while listening, so every tile of it is seen: tiles arrive from
    // several workers, pass by pass.
    let mut events = viewer.events();
    let (status, body) = viewer.post("/render?scene=final&width=96&spp=8&threads=3&tile=8", b"");
    assert_eq!((status, serde_json::from_str::<Value>(&body).unwrap()["gen"].as_u64()), (202, Some(2)));
    let render = until_done(&mut events, 2);
    let tiles: Vec<&Value> = render.iter().filter(|e| e["type"] == "tile").collect();
    let passes: Vec<u64> =
        render.iter().filter(|e| e["type"] == "pass").map(|e| e["spp"].as_u64().unwrap()).collect();
    assert_eq!(passes, [1, 2, 4, 8], "progressive passes accumulate 1, 2, 4, 8 samples");
    let mut workers: Vec<u64> = tiles.iter().map(|t| t["worker"].as_u64().unwrap()).collect();
    workers.sort_unstable();
    workers.dedup();
    assert!(workers.len() >= 2 && workers.len() <= 3, "tiles from several of the 3 workers: {workers:?}");
    assert_eq!(tiles.len(), 4 * 12 * 8, "every 8-pixel tile of 96 x 64, in each of the 4 passes");
    assert_eq!(tiles[0]["rgb"].as_str().unwrap().len(), 256, "an 8 x 8 tile's 192 RGB bytes, base64");
    let image = served_image(&viewer, 2);
    assert!(
        image == cli_render(&viewer, &["--width", "96", "--spp", "8"]),
        "the viewer's image is the CLI's"
    );

    // Render 3: another mode, thread count and camera; still the CLI's image.
    let (status, body) = viewer.post("/render?mode=static&threads=2&width=80&spp=4&lookfrom=9.5,3,7.25", b"");
    assert_eq!(status, 202, "{body}");
    until_done(&mut events, 3);
    let image = served_image(&viewer, 3);
    let scene = String::from_utf8(viewer.get("/scene.toml").1).unwrap();
    assert!(scene.contains("lookfrom = [9.5, 3.0, 7.25]"), "{scene}");
    assert!(image == cli_render(&viewer, &["--width", "80", "--spp", "4", "--mode", "serial"]));

    // A pasted scene.
    let pasted = "[camera]\nlookfrom = [0, 0, 2]\nlookat = [0, 0, 0]\nvup = [0, 1, 0]\nvfov = 40\nfocus_dist = 2\n\n[background]\nkind = \"gradient\"\nhorizon = [1, 1, 1]\nzenith = [0.5, 0.7, 1]\n\n[[sphere]]\ncenter = [0, 0, 0]\nradius = 0.5\nmaterial = { kind = \"lambertian\", albedo = [0.8, 0.3, 0.3] }\n";
    let (status, body) = viewer.post("/render?width=40&spp=2", pasted.as_bytes());
    assert_eq!(status, 202, "{body}");
    let image = served_image(&viewer, 4);
    assert!(image == cli_render(&viewer, &["--width", "40", "--spp", "2"]));
}

#[test]
fn bad_requests_get_4xx_and_one_line_and_the_server_goes_on() {
    let viewer = Viewer::start(&["--width", "48", "--spp", "2"]);
    let huge = vec![b'#'; (1 << 20) + 1];
    let cases: Vec<(&str, &str, &[u8], u16, &str)> = vec![
        ("POST", "/render?width=0", b"", 400, "0 is not in 1..=16384"),
        ("POST", "/render?width=16385", b"", 400, "16385 is not in 1..=16384"),
        ("POST", "/render?threads=4097", b"", 400, "4097 is not in 1..=4096"),
        ("POST", "/render?spp=0", b"", 400, "--spp"),
        ("POST", "/render?mode=fastest", b"", 400, "invalid value 'fastest' for '--mode"),
        ("POST", "/render?rng=global", b"", 400, "invalid value 'global' for '--rng"),
        ("POST", "/render?scene=nowhere", b"", 400, "nowhere"),
        ("POST", "/render?colour=red", b"", 400, "unexpected argument '--colour'"),
        ("POST", "/render?scene-file=/etc/passwd", b"", 400, "cannot read files on the server"),
        ("POST", "/render?bind=0.0.0.0", b"", 400, "cannot be set by a request"),
        ("POST", "/render?target-error=0.1", b"", 400, "not adaptive sampling"),
        ("POST", "/render?lookfrom=1,2", b"", 400, "lookfrom must be three finite numbers"),
        ("POST", "/render?lookfrom=nan,1,2", b"", 400, "lookfrom must be three finite numbers"),
        ("POST", "/render?lookfrom=0,0,0", b"", 400, "is the camera's look-at point"),
        ("POST", "/render?roulette=maybe", b"", 400, "roulette must be true or false"),
        ("POST", "/render", b"[camera\nnot toml", 400, "pasted scene:1:"),
        ("POST", "/render", b"\xff\xfe", 400, "not UTF-8"),
        ("POST", "/render", &huge, 413, "larger than 1 MiB"),
        ("GET", "/render", b"", 405, "GET is not allowed on /render"),
        ("POST", "/state", b"", 405, "POST is not allowed on /state"),
        ("GET", "/etc/passwd", b"", 404, "no such page: /etc/passwd"),
    ];
    for (method, path, body, status, reason) in cases {
        let (got, text) = match method {
            "GET" => {
                let (s, b) = viewer.get(path);
                (s, String::from_utf8(b).unwrap())
            }
            _ => viewer.post(path, body),
        };
        assert_eq!(got, status, "{method} {path}: {text}");
        assert!(text.contains(reason), "{method} {path}: expected '{reason}' in {text:?}");
        assert_eq!(text.trim_end().lines().count(), 1, "{method} {path}: one line: {text:?}");
        assert_eq!(viewer.get("/state").0, 200, "still serving after {method} {path}");
    }

    // A client that sends half a request, and one that leaves an event stream mid-way.
    let address = viewer.url.trim_start_matches("http://").trim_end_matches('/').to_string();
    let mut half = TcpStream::connect(&address).unwrap();
    half.write_all(b"POST /render?width=40 HTTP/1.1\r\nContent-Length: 100\r\n\r\nabc").unwrap();
    drop(half);
    let mut stream = TcpStream::connect(&address).unwrap();
    stream.set_read_timeout(Some(MINUTE)).unwrap(); // an answer that never comes fails, not hangs
    stream.write_all(format!("GET /events HTTP/1.1\r\nHost: {address}\r\n\r\n").as_bytes()).unwrap();
    let mut first = String::new();
    BufReader::new(&stream).read_line(&mut first).expect("the event stream's status line within a minute");
    assert!(first.starts_with("HTTP/1.1 200"), "{first}");
    drop(stream);
    assert_eq!(viewer.post("/render?width=40&spp=2", b"").0, 202);
    served_image(&viewer, 2);
}

#[test]
fn a_new_request_cancels_the_render_and_leaves_no_thread_behind() {
    // A render long enough to be cancelled many times over: 2 threads, 4096 spp.
    let viewer = Viewer::start(&["--width", "160", "--spp", "4096", "--threads", "2"]);
    let mut events = viewer.events();
    let mut generation = 1;
    for round in 0..20 {
        let mode = ["steal", "pool", "static", "interleaved", "pool-rows"][round % 5];
        let (status, body) = viewer.post(&format!("/render?width=160&spp=4096&threads=2&mode={mode}"), b"");
        assert_eq!(status, 202, "{body}");
        generation += 1;
        std::thread::sleep(Duration::from_millis(30));
    }
    // After the last restart's `start`, no event of an older render may arrive: each restart
    // waits for the cancelled render's jobs, which skip their tiles once cancelled.
    let mut started = false;
    let start = Instant::now();
    let mut newest_tiles = 0;
    for event in events.by_ref() {
        let g = event["gen"].as_u64().unwrap();
        if g == generation && event["type"] == "start" {
            started = true;
        } else if started {
            assert_eq!(g, generation, "an event of render {g} after render {generation} started: {event}");
            newest_tiles += 1;
            if newest_tiles == 20 {
                break;
            }
        }
        assert!(start.elapsed() < MINUTE, "the newest render did not start");
    }
    drop(events);
    // One render thread and one pool's workers at most; a cancelled render's are gone. (A
    // thread just spawned carries its parent's name until it sets its own, and a request
    // that changes the mode or threads starts a pool, so one snapshot may catch a worker
    // under the render thread's name: a leak shows in every snapshot, so look for one clean
    // snapshot within two seconds.)
    let clean = |names: &[String]| {
        let render_threads = names.iter().filter(|n| n.starts_with("raypool-view")).count();
        let workers = names.iter().filter(|n| n.starts_with("pool-worker")).count();
        render_threads <= 1 && workers <= 2
    };
    let start = Instant::now();
    let mut names = viewer.thread_names();
    while !clean(&names) && start.elapsed() < Duration::from_secs(2) {
        std::thread::sleep(Duration::from_millis(20));
        names = viewer.thread_names();
    }
    assert!(clean(&names), "threads after 20 restarts: {names:?}");
    assert_eq!(viewer.post("/render?width=8&spp=1", b"").0, 202);
    served_image(&viewer, generation + 1);
    std::thread::sleep(Duration::from_millis(200));
    let names = viewer.thread_names();
    let workers = names.iter().filter(|n| n.starts_with("pool-worker")).count();
    assert!(
        !names.iter().any(|n| n.starts_with("raypool-view")) && workers <= 2,
        "a finished render leaves no render thread, and only the session's one pool (2 workers, \
         asleep until the next render): {names:?}"
    );
}

#[test]
fn ctrl_c_stops_the_server_cleanly_and_bind_warns() {
    let mut viewer = Viewer::start(&["--width", "64", "--spp", "100000", "--bind", "127.0.0.1"]);
    std::thread::sleep(Duration::from_millis(300)); // mid-render
    let pid = viewer.child.id().to_string();
    assert!(output_within(Command::new("kill").args(["-INT", &pid]), "`kill -INT` to exit").status.success());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = viewer.child.try_wait().unwrap() {
            break status;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "still running after Ctrl-C");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status:?}");
    let stderr = viewer.stderr();
    assert!(stderr.contains("warning: serving on 127.0.0.1:"), "{stderr}");
    assert!(stderr.contains("viewer stopped"), "{stderr}");
}

#[test]
fn bad_command_lines_exit_2() {
    for (args, expected) in [
        (vec!["view", "--width", "0"], "0 is not in 1..=16384"),
        (vec!["view", "--threads", "0"], "0 is not in 1..=4096"),
        (vec!["view", "--bind", "not-an-address"], "--bind"),
        (vec!["view", "--target-error", "0.1"], "not adaptive sampling"),
    ] {
        let out =
            output_within(Command::new(env!("CARGO_BIN_EXE_raypool")).args(&args), "`raypool view` to exit");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected) && stderr.lines().count() == 1, "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "no address printed: {args:?}");
    }
}

#[test]
fn foreign_pages_and_hosts_get_403_and_the_page_own_origin_works() {
    let viewer = Viewer::start(&["--width", "32", "--spp", "2"]);
    let address = viewer.url.trim_start_matches("http://").trim_end_matches('/').to_string();
    let port = address.rsplit_once(':').unwrap().1.to_string();
    let ask = |request: String| {
        let mut stream = TcpStream::connect(&address).unwrap();
        stream.set_read_timeout(Some(MINUTE)).unwrap();
        stream.write_all(request.as_bytes()).unwrap();
        let mut answer = String::new();
        let _ = std::io::Read::read_to_string(&mut stream, &mut answer);
        answer
    };
    let post = |origin: &str| {
        ask(format!(
            "POST /render?width=16 HTTP/1.1\r\nHost: {address}\r\nOrigin: {origin}\r\nContent-Length: 0\r\n\r\n"
        ))
    };
    for host in ["evil.example", &format!("evil.example:{port}"), "127.0.0.1:1", ""] {
        let answer = ask(format!("GET /state HTTP/1.1\r\nHost: {host}\r\n\r\n"));
        assert!(answer.starts_with("HTTP/1.1 403"), "Host {host:?}: {answer}");
        assert!(answer.contains("is not this viewer's address"), "{answer}");
    }
    for origin in
        ["https://evil.example", "http://127.0.0.1.evil.example", "null", &format!("http://localhost:{}", 1)]
    {
        let answer = post(origin);
        assert!(answer.starts_with("HTTP/1.1 403"), "Origin {origin:?}: {answer}");
    }
    for host in [format!("127.0.0.1:{port}"), format!("localhost:{port}"), format!("[::1]:{port}")] {
        let answer = ask(format!("GET /state HTTP/1.1\r\nHost: {host}\r\n\r\n"));
        assert!(answer.starts_with("HTTP/1.1 200"), "Host {host}: {answer}");
        let answer = post(&format!("http://{host}"));
        assert!(answer.starts_with("HTTP/1.1 202"), "Origin http://{host}: {answer}");
    }
}

#[test]
fn a_page_opened_late_is_told_what_a_page_open_from_the_start_saw() {
    // 48 × 32 in 8-pixel tiles: 24 tiles a pass, on 2 threads.
    let viewer =
        Viewer::start(&["--width", "48", "--height", "32", "--spp", "4", "--threads", "2", "--tile", "8"]);
    let live = until_done(&mut viewer.events(), 1);
    let late = until_done(&mut viewer.events(), 1);
    let kinds =
        |events: &[Value]| events.iter().map(|e| e["type"].as_str().unwrap().to_string()).collect::<Vec<_>>();
    let late_kinds = kinds(&late);
    assert_eq!(late_kinds.first().map(String::as_str), Some("start"), "{late_kinds:?}");
    assert_eq!(late_kinds[1], "frame", "{late_kinds:?}");
    let tiles = |events: &[Value], pass: u64| -> Vec<(u64, u64, u64)> {
        let mut t: Vec<_> = events
            .iter()
            .filter(|e| e["type"] == "tile" && e["pass"] == pass)
            .map(|e| (e["x"].as_u64().unwrap(), e["y"].as_u64().unwrap(), e["worker"].as_u64().unwrap()))
            .collect();
        t.sort();
        t
    };
    let last_pass =
        live.iter().filter(|e| e["type"] == "pass").map(|e| e["pass"].as_u64().unwrap()).max().unwrap();
    let replayed = tiles(&late, last_pass);
    assert_eq!(replayed.len(), 24, "every tile of the last pass, with its worker: {late_kinds:?}");
    assert_eq!(replayed, tiles(&live, last_pass), "the same tiles, on the same workers' lanes");
    assert_eq!(late.iter().filter(|e| e["type"] == "pass").count(), 1, "the latest pass's figures");
    assert_eq!(late_kinds.last().map(String::as_str), Some("done"));
}

#[test]
fn hostile_traffic_does_not_stop_the_server() {
    let viewer = Viewer::start(&["--scene", "final", "--width", "96", "--spp", "100000", "--threads", "2"]);
    let seconds = std::env::var("RAYPOOL_HOSTILE_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(20);
    let report = common::hostile::run(&viewer, Duration::from_secs(seconds), 7);
    let sent: u64 = report.sent.values().sum();
    assert!(sent > 100, "only {sent} hostile requests in {seconds} s: {report:?}");
    assert_eq!(report.failed_probes, 0, "GET /state failed during the traffic: {report:?}");
    assert!(report.slowest_probe < Duration::from_secs(5), "a probe took {:?}", report.slowest_probe);
    assert_eq!(report.streams_with_tiles, report.streams, "every event stream received tiles: {report:?}");
    let cores = raypool::measure::machine::cpus() as u64;
    // Connections (at most 256), the largest render's workers (4 per core), a few of its own.
    assert!(report.peak_threads <= 256 + 4 * cores + 8, "threads: {report:?}");
    assert!(report.peak_rss_kib < 1 << 20, "peak memory {} MiB", report.peak_rss_kib >> 10);
    let slowest = report.cancels.iter().map(|(_, t)| *t).max().unwrap();
    assert!(slowest < Duration::from_secs(2), "a cancel took {slowest:?}: {:?}", report.cancels);
    for (kind, status) in report.answers.keys() {
        assert!(status != "500", "{kind} got a 500");
    }
    // And a render after it all equals the command line's, byte for byte.
    // The traffic left 2048 high 64-pixel tiles in effect: a request changes only what it
    // names, so this one names the height too.
    let (status, body) = viewer.post("/render?scene=final&width=40&height=auto&spp=2&threads=2", b"");
    assert_eq!(status, 202, "{body}");
    let generation: u64 = serde_json::from_str::<Value>(&body).unwrap()["gen"].as_u64().unwrap();
    let image = served_image(&viewer, generation);
    assert!(image == cli_render(&viewer, &["--width", "40", "--spp", "2"]), "the image after the traffic");
}

#[test]
fn a_second_book_scene_in_the_viewer_is_the_command_lines_image() {
    for scene in ["next-week", "cornell-smoke"] {
        let viewer = Viewer::start(&[
            "--scene",
            scene,
            "--width",
            "40",
            "--spp",
            "4",
            "--threads",
            "2",
            "--tile",
            "8",
        ]);
        let image = served_image(&viewer, 1);
        assert!(
            image == cli_render(&viewer, &["--width", "40", "--spp", "4"]),
            "{scene}: the viewer's image"
        );
    }
}

#[test]
fn a_request_that_names_one_setting_changes_only_that_one() {
    let viewer = Viewer::start(&[
        "--scene",
        "cornell",
        "--width",
        "32",
        "--spp",
        "256",
        "--mode",
        "pool",
        "--threads",
        "2",
        "--tile",
        "8",
    ]);
    let state = |viewer: &Viewer| -> Value { serde_json::from_slice(&viewer.get("/state").1).unwrap() };
    let settings = |s: &Value| {
        (
            s["scene"].as_str().map(str::to_owned),
            s["spp"].as_u64(),
            s["mode"].as_str().map(str::to_owned),
            s["threads"].as_u64(),
            s["tile"].as_u64(),
            s["width"].as_u64(),
        )
    };
    let cornell = |spp, mode: &str, threads| {
        (Some("cornell".to_owned()), Some(spp), Some(mode.to_owned()), Some(threads), Some(8), Some(32))
    };
    assert_eq!(settings(&state(&viewer)), cornell(256, "pool", 2));

    let (status, body) = viewer.post("/render?threads=1", b"");
    assert_eq!(status, 202, "{body}");
    assert_eq!(settings(&state(&viewer)), cornell(256, "pool", 1), "only the threads changed");

    // A camera move, then a mode change: the camera stays where it was moved.
    let (status, body) = viewer.post("/render?lookfrom=300,300,-700", b"");
    assert_eq!(status, 202, "{body}");
    let (status, body) = viewer.post("/render?mode=steal", b"");
    assert_eq!(status, 202, "{body}");
    assert_eq!(settings(&state(&viewer)), cornell(256, "steal", 1));
    let scene = String::from_utf8(viewer.get("/scene.toml").1).unwrap();
    assert!(scene.contains("lookfrom = [300.0, 300.0, -700.0]"), "{scene}");

    // The page's light-sampling control reaches the render, and only it changes.
    assert_eq!(state(&viewer)["light-sampling"].as_str(), Some("mis"));
    assert_eq!(viewer.post("/render?light-sampling=bsdf", b"").0, 202);
    assert_eq!(state(&viewer)["light-sampling"].as_str(), Some("bsdf"));
    assert_eq!(settings(&state(&viewer)), cornell(256, "steal", 1));

    // A height named stays until `height=auto` returns to the scene's aspect (square here).
    assert_eq!(viewer.post("/render?height=20", b"").0, 202);
    assert_eq!(state(&viewer)["height"].as_u64(), Some(20));
    assert_eq!(viewer.post("/render?height=auto", b"").0, 202);
    assert_eq!(state(&viewer)["height"].as_u64(), Some(32));

    // Naming the scene loads it afresh, its own camera included; the other settings stay.
    let (status, body) = viewer.post("/render?scene=cornell", b"");
    assert_eq!(status, 202, "{body}");
    let scene = String::from_utf8(viewer.get("/scene.toml").1).unwrap();
    assert!(!scene.contains("lookfrom = [300.0, 300.0, -700.0]"), "{scene}");
    assert_eq!(settings(&state(&viewer)), cornell(256, "steal", 1));
}

#[test]
fn slow_image_readers_share_one_encoded_image_and_the_surplus_gets_503() {
    // 2048 x 2048: a PFM of 48 MiB, far more than a socket's buffers, so a reader that does
    // not read holds its answer (and its place) until the server's write deadline.
    let viewer =
        Viewer::start(&["--scene", "three-spheres", "--width", "2048", "--height", "2048", "--spp", "1"]);
    until_done(&mut viewer.events(), 1);
    let seen = common::hostile::slow_image_readers(&viewer, 40, Duration::from_secs(2));
    // The first 32 are being answered (and stall); the other 8 were told 503 at once.
    assert_eq!(seen.answers.get("503"), Some(&8), "the readers past the 32 being answered: {seen:?}");
    assert_eq!(seen.answers.get("200"), Some(&32), "{seen:?}");
    // One encoded image (48 MiB) for all 32, not one each (1.5 GiB).
    assert!(seen.peak_kib < seen.before_kib + 160 * 1024, "resident memory: {seen:?}");
    // Once they are gone, images are served again.
    let start = Instant::now();
    while viewer.get("/image.png").0 != 200 {
        assert!(start.elapsed() < MINUTE, "no image answer within a minute after the readers left");
        std::thread::sleep(Duration::from_millis(100));
    }
}
