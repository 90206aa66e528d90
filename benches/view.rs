//! The viewer's responsiveness, measured in a real browser (`cargo bench --bench view`):
//! on `final` at 400 × 267 with 2 threads, how long from a camera move until the first whole
//! 1-spp frame is on screen, and how many updates a second the page receives while rendering.
//! Both are measured inside the page (`performance.now()`: the request sent → the frame
//! painted, at the next animation frame; events arrived in the last second). Writes
//! `results/view.md` and the screenshot `results/view.png`; viewer flags after `--` are added
//! (`cargo bench --bench view -- --sampler independent`).

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use common::browser::{Browser, chromium};
use common::viewer::Viewer;
use raypool::measure::machine::{Machine, results_dir};

const MOVES: usize = 25;

fn main() {
    let binary = chromium().expect("the view benchmark needs Chromium: apt-get install -y chromium");
    // Extra viewer flags may follow `--` (e.g. `-- --sampler independent`); cargo's own
    // `--bench` flag is not one of them.
    let extra: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let mut flags = vec!["--scene", "final", "--width", "400", "--spp", "1024", "--threads", "2"];
    flags.extend(extra.iter().map(String::as_str));
    let viewer = Viewer::start(&flags);
    let mut page = Browser::open(&binary, &viewer.url, (1280, 860));
    page.wait_for("document.body.dataset.spp >= 1", Duration::from_secs(60));

    // Updates a second while rendering: sample the page's one-second count for 5 s.
    page.eval("const s = document.getElementById('spp'); s.value = 1024; s.dispatchEvent(new Event('change')); true");
    std::thread::sleep(Duration::from_millis(500));
    let mut rates: Vec<f64> = (0..50)
        .map(|_| {
            std::thread::sleep(Duration::from_millis(100));
            page.eval("+document.body.dataset.rate").as_f64().unwrap()
        })
        .collect();
    rates.sort_by(f64::total_cmp);

    // Camera moves: the same call a drag makes, one at a time, each after the last one's
    // first frame is on screen and a moment of rendering.
    for k in 0..MOVES {
        page.eval(&format!("orbit({}, 0.01, 1); true", if k % 2 == 0 { 0.05 } else { -0.04 }));
        page.wait_for(&format!("window.raypoolLatencies.length >= {}", k + 1), Duration::from_secs(30));
        std::thread::sleep(Duration::from_millis(150));
    }
    let mut latencies: Vec<f64> = serde_json::from_value(page.eval("window.raypoolLatencies")).unwrap();
    latencies.sort_by(f64::total_cmp);

    // The screenshot: a fresh render a few passes in, outlines and timeline showing.
    page.eval("orbit(0.3, 0.05, 0.9); true");
    page.wait_for("+document.body.dataset.spp >= 32", Duration::from_secs(60));
    std::fs::write(results_dir().join("view.png"), page.screenshot()).expect("write view.png");

    let quantile = |v: &[f64], q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    let machine = Machine::current();
    let report = format!(
        "# The viewer's responsiveness\n\n\
         Command: `cargo bench --bench view` · {} · headless Chromium ({})\n\n\
         Server: `raypool view {}`; the page measures itself (`performance.now()` in `src/view/page.html`).\n\n\
         | measure | target | median | 10th percentile | 90th percentile | worst |\n|---|---:|---:|---:|---:|---:|\n\
         | camera move → first whole 1-spp frame on screen ({MOVES} moves) | ≤ 33 ms (#38; goal 16) | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms |\n\
         | updates a second received while rendering (50 samples over 5 s) | ≥ 20 | {:.0} | {:.0} | {:.0} | {:.0} |\n\n\
         A move is the call a mouse drag makes (`orbit`): it sends `POST /render` with the new camera; the server \
         cancels the running render (its jobs skip their tiles once the flag is set), starts the new one, and streams \
         each 16 × 16 tile of its first pass (1 sample per pixel, 425 tiles) as it is finished; the latency ends at the \
         animation frame after the pass's last tile was drawn. An update is one server-sent event (a tile, a pass or \
         the end of a render). `results/view.png` is the page a few passes into a render after a move.\n",
        machine.describe(),
        chromium_version(&binary),
        flags.join(" "),
        quantile(&latencies, 0.5),
        quantile(&latencies, 0.1),
        quantile(&latencies, 0.9),
        latencies[latencies.len() - 1],
        quantile(&rates, 0.5),
        quantile(&rates, 0.1),
        quantile(&rates, 0.9),
        rates[0],
    );
    std::fs::write(results_dir().join("view.md"), &report).expect("write view.md");
    print!("{report}");
}

fn chromium_version(binary: &std::path::Path) -> String {
    std::process::Command::new(binary)
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|_| "unknown version".into())
}
