//! The viewer's responsiveness, measured in a real browser (`cargo bench --bench view`): on
//! `final`, `cornell` and `next-week` at 400 pixels wide with 2 threads, how long from a
//! camera move until its first frame is on screen, how many frames the page paints a second
//! while the mouse drags the camera, how long after the camera rests the full-size image
//! reaches 16 samples per pixel, and how many updates a second the page receives while
//! rendering. Everything is measured inside the page (`performance.now()`). Writes
//! `results/view.md`, the screenshot `results/view.png` and a strip of a drag,
//! `results/view-drag.png`; viewer flags after `--` are added (`-- --sampler independent`).

#[path = "../tests/common/mod.rs"]
mod common;

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use common::browser::{Browser, chromium};
use common::viewer::Viewer;
use raypool::measure::machine::{Machine, results_dir};

const MOVES: usize = 25;
const DRAGS: usize = 3;
const DRAG_TIME: Duration = Duration::from_secs(2);
const MINUTE: Duration = Duration::from_secs(60);

/// One scene's figures.
struct Figures {
    scene: &'static str,
    latencies: Vec<f64>,
    frames_per_second: Vec<f64>,
    moves_per_second: Vec<f64>,
    rest_to_16: Vec<f64>,
    rates: Vec<f64>,
    /// The start resolution's divisor of each side at the end.
    divisor: String,
    /// The navigation frames' time on the server, and the denoiser's share of it, ms.
    frame_ms: Vec<f64>,
    denoise_ms: Vec<f64>,
}

fn main() {
    let binary = chromium().expect("the view benchmark needs Chromium: apt-get install -y chromium");
    // Extra viewer flags may follow `--`; cargo's own `--bench` flag is not one of them.
    let extra: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let mut figures = Vec::new();
    for scene in ["final", "cornell", "next-week"] {
        let mut flags = vec!["--scene", scene, "--width", "400", "--spp", "1024", "--threads", "2"];
        flags.extend(extra.iter().map(String::as_str));
        let viewer = Viewer::start(&flags);
        let mut page = Browser::open(&binary, &viewer.url, (1280, 860));
        page.wait_for("document.body.dataset.spp >= 1", MINUTE);
        figures.push(measure(&mut page, scene));
        if scene == "final" {
            // The same without the denoiser (the page's checkbox), then with it again.
            page.eval("document.getElementById('denoise').checked = false; true");
            figures.push(measure(&mut page, "final, denoise off"));
            page.eval("document.getElementById('denoise').checked = true; true");
            drag_strip(&mut page);
            page.eval("orbit(0.3, 0.05, 0.9); true");
            page.wait_for("+document.body.dataset.spp >= 32", MINUTE);
            std::fs::write(results_dir().join("view.png"), page.screenshot()).expect("write view.png");
        }
    }
    let report = report(&figures, &binary, &extra);
    std::fs::write(results_dir().join("view.md"), &report).expect("write view.md");
    print!("{report}");
}

fn measure(page: &mut Browser, scene: &'static str) -> Figures {
    // Updates a second while rendering: sample the page's one-second count for 5 s.
    page.eval("(() => { const s = document.getElementById('spp'); s.value = 1024; s.dispatchEvent(new Event('change')); return true; })()");
    std::thread::sleep(Duration::from_millis(500));
    let rates = (0..50)
        .map(|_| {
            std::thread::sleep(Duration::from_millis(100));
            page.eval("+document.body.dataset.rate").as_f64().unwrap()
        })
        .collect();

    // Camera moves: the call a drag makes (`orbit`), one at a time, each after the last
    // one's first frame is on screen and a moment of rendering.
    let before = page.eval("window.raypoolLatencies.length").as_u64().unwrap() as usize;
    let previews_before = page.eval("window.raypoolPreviews.length").as_u64().unwrap() as usize;
    for k in 0..MOVES {
        page.eval(&format!("orbit({}, 0.01, 1); true", if k % 2 == 0 { 0.05 } else { -0.04 }));
        page.wait_for(&format!("window.raypoolLatencies.length >= {}", before + k + 1), MINUTE);
        std::thread::sleep(Duration::from_millis(150));
    }
    let latencies: Vec<f64> = serde_json::from_value(page.eval("window.raypoolLatencies")).unwrap();

    // Drags: the mouse held and moved 2 pixels at a time for 2 s, then released.
    let (mut frames_per_second, mut rest_to_16, mut moves_per_second) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..DRAGS {
        let (from, to, released, moves) = drag(page, DRAG_TIME, |_, _| {});
        moves_per_second.push(moves);
        let frames = page.eval(&format!("window.raypoolFrames.filter(t => t >= {from} && t <= {to}).length"));
        frames_per_second.push(frames.as_f64().unwrap() / ((to - from) / 1000.0));
        let rested =
            "!nav.busy && window.raypoolPasses.some(p => p[0] === +document.body.dataset.gen && p[1] >= 16)";
        page.wait_for(rested, MINUTE);
        let at16 =
            page.eval("window.raypoolPasses.find(p => p[0] === +document.body.dataset.gen && p[1] >= 16)[2]");
        rest_to_16.push(at16.as_f64().unwrap() - released);
        std::thread::sleep(Duration::from_millis(300));
    }
    let divisor = page.eval("document.body.dataset.divisor").as_str().unwrap_or("?").to_string();
    let latencies = latencies[before..].to_vec();
    let previews: Vec<(f64, Option<f64>)> =
        serde_json::from_value(page.eval("window.raypoolPreviews")).unwrap();
    let previews = &previews[previews_before..];
    let frame_ms = previews.iter().map(|p| p.0 * 1e3).collect();
    let denoise_ms = previews.iter().filter_map(|p| p.1).map(|d| d * 1e3).collect();
    Figures {
        scene,
        latencies,
        frames_per_second,
        moves_per_second,
        rest_to_16,
        rates,
        divisor,
        frame_ms,
        denoise_ms,
    }
}

/// Holds the left button on the image and moves it 2 pixels right every 2 ms (plus the time
/// DevTools takes to deliver a move) for `time`, calling `during(page, k)` after move `k`;
/// returns the page's clock at the first move, at the last one, and at the release, and the
/// moves made a second.
fn drag(
    page: &mut Browser,
    time: Duration,
    mut during: impl FnMut(&mut Browser, usize),
) -> (f64, f64, f64, f64) {
    let rect = page.eval("(() => { const r = document.getElementById('image').getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let r: Vec<f64> = serde_json::from_value(rect).unwrap();
    let (x, y) = (r[0] + r[2] * 0.3, r[1] + r[3] / 2.0);
    page.mouse("mousePressed", (x, y), 1);
    let from = page.eval("performance.now()").as_f64().unwrap();
    let start = Instant::now();
    let mut k = 0;
    while start.elapsed() < time {
        k += 1;
        page.mouse("mouseMoved", (x + 2.0 * (k % 100) as f64, y), 1);
        during(page, k);
        std::thread::sleep(Duration::from_millis(2));
    }
    let moves_per_second = k as f64 / start.elapsed().as_secs_f64();
    let to = page.eval("performance.now()").as_f64().unwrap();
    page.mouse("mouseReleased", (x, y), 0);
    (from, to, page.eval("performance.now()").as_f64().unwrap(), moves_per_second)
}

/// Screenshots of the image during a drag and once it has rested, side by side.
fn drag_strip(page: &mut Browser) {
    let rect = page.eval("(() => { const r = document.getElementById('image').getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let clip: [f64; 4] = serde_json::from_value(rect).unwrap();
    let mut shots = Vec::new();
    drag(page, Duration::from_secs(3), |page, k| {
        if k % 30 == 0 && shots.len() < 4 {
            shots.push(page.screenshot_of(clip));
        }
    });
    page.wait_for(
        "!nav.busy && window.raypoolPasses.some(p => p[0] === +document.body.dataset.gen && p[1] >= 16)",
        MINUTE,
    );
    shots.push(page.screenshot_of(clip));
    let shots: Vec<image::RgbaImage> =
        shots.iter().map(|png| image::load_from_memory(png).expect("a PNG screenshot").to_rgba8()).collect();
    let (w, h) = (shots[0].width(), shots[0].height());
    let mut strip = image::RgbaImage::from_pixel(
        w * shots.len() as u32 + 8 * (shots.len() as u32 - 1),
        h,
        image::Rgba([255; 4]),
    );
    for (k, shot) in shots.iter().enumerate() {
        image::imageops::overlay(&mut strip, shot, i64::from(k as u32 * (w + 8)), 0);
    }
    strip.save(results_dir().join("view-drag.png")).expect("write view-drag.png");
}

fn report(figures: &[Figures], binary: &std::path::Path, extra: &[String]) -> String {
    let mut report = format!(
        "# The viewer's responsiveness\n\n\
         Command: `cargo bench --bench view{}` · {} · headless Chromium ({})\n\n\
         Server: `raypool view --scene SCENE --width 400 --spp 1024 --threads 2`; the page measures itself \
         (`performance.now()` in `src/view/page.html`).\n\n\
         | scene | measure | target | median | 10th pct | 90th pct | worst |\n|---|---|---:|---:|---:|---:|---:|\n",
        if extra.is_empty() { String::new() } else { format!(" -- {}", extra.join(" ")) },
        Machine::current().describe(),
        chromium_version(binary),
    );
    for f in figures {
        let rows = [
            (
                format!("camera move → its first frame on screen ({MOVES} moves), ms"),
                "≤ 33 (goal 16)",
                &f.latencies,
                true,
            ),
            (
                format!("frames painted a second while dragging ({DRAGS} drags of 2 s)"),
                "≥ 30 (goal 60)",
                &f.frames_per_second,
                false,
            ),
            ("mouse moves a second the drags made".to_string(), "", &f.moves_per_second, false),
            ("navigation frame on the server (render + denoise), ms".to_string(), "", &f.frame_ms, true),
            ("of which the denoiser, ms".to_string(), "", &f.denoise_ms, true),
            ("camera rests → full size at 16 spp on screen, ms".to_string(), "", &f.rest_to_16, true),
            ("updates a second received while rendering (50 samples)".to_string(), "", &f.rates, false),
        ];
        for (measure, target, values, low_is_good) in rows {
            if values.is_empty() {
                continue; // the denoiser's share, with the denoiser off
            }
            let mut v = values.clone();
            v.sort_by(f64::total_cmp);
            let q = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
            let worst = if low_is_good { v[v.len() - 1] } else { v[0] };
            let _ = writeln!(
                report,
                "| {} | {measure} | {target} | {:.1} | {:.1} | {:.1} | {:.1} |",
                f.scene,
                q(0.5),
                q(0.1),
                q(0.9),
                worst
            );
        }
    }
    let divisors: Vec<String> = figures.iter().map(|f| format!("{} 1/{}", f.scene, f.divisor)).collect();
    let _ = writeln!(report, "\nStart resolution learnt by the end (of each side): {}.", divisors.join(", "));
    report.push_str(
        "\nA move is the call a mouse drag makes (`orbit`): it sends `POST /render` with the new camera and \
         `preview=1`; the server cancels the running render (its jobs skip their tiles once the flag is set), \
         renders a navigation frame at a reduced start resolution (1 sample per pixel, the divisor of each side \
         learnt from the last frame's time, `src/view/preview.rs`), announces it, and the page fetches its pixels \
         as one binary answer, draws them with one `putImageData` and scales them onto the image; the latency ends \
         at the animation frame after that. Navigation frames are denoised (`src/denoise/`, the page's default; \
         its time counts in the frame's, so the start resolution makes room for it); the `final, denoise off` rows \
         are the same page with the checkbox cleared. The full-size render follows once no other move has come for 50 ms, \
         pass after pass, drawn tile by tile. While dragging, the page sends one move at a time and the next as \
         soon as the last one's frame is announced, so the server renders it while the page fetches and draws \
         that frame (moves made meanwhile collapse into the camera as it then is). `results/view-drag.png` is a strip \
         of the image during a drag on `final` (four navigation frames) and after it rested (16 spp); \
         `results/view.png` is the page a few passes into a render after a move.\n",
    );
    report
}

fn chromium_version(binary: &std::path::Path) -> String {
    std::process::Command::new(binary)
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|_| "unknown version".into())
}
