//! `cargo bench --bench view_hostile`: the viewer under hostile traffic for 60 s (`-- --quick`: 15 s; loopback only),
//! then the worst cancels, then 256 slow image readers of a 2048 × 2048 image. Writes
//! `results/view-hostile.md`: requests sent by kind, answers by status, the `/state` probes,
//! peak threads and memory, each cancel's `POST` → 202 time, and the slow readers' memory.
//! `tests/view.rs` runs the same traffic for 20 s and asserts on it.

#[path = "../tests/common/mod.rs"]
mod common;

use std::fmt::Write as _;
use std::time::Duration;

use common::hostile;
use common::viewer::Viewer;
use raypool::measure::machine::{Machine, results_dir};

fn main() {
    // `--quick` (for `benches/all.sh --quick`): 15 s of traffic.
    let quick = std::env::args().any(|a| a == "--quick");
    let seconds = if quick { 15 } else { 60 };
    let viewer = Viewer::start(&["--scene", "final", "--width", "400", "--spp", "100000", "--threads", "2"]);
    let report = hostile::run(&viewer, Duration::from_secs(seconds), 7);
    let mut md = String::new();
    let _ = writeln!(md, "# The viewer under hostile traffic\n");
    let _ = writeln!(
        md,
        "Command: `cargo bench --bench view_hostile{}` · {} · `raypool view --scene final --width 400 --spp 100000 --threads 2` · traffic for {:.1} s, loopback only (`tests/common/hostile.rs`)\n",
        if quick { " -- --quick" } else { "" },
        Machine::current().describe(),
        report.ran.as_secs_f64()
    );
    let _ = writeln!(md, "## Requests sent, and the answers\n");
    let _ = writeln!(md, "| kind | sent | answers (status × count) |\n|---|---:|---|");
    for (kind, sent) in &report.sent {
        let answers: Vec<String> = report
            .answers
            .iter()
            .filter(|((k, _), _)| k == kind)
            .map(|((_, status), n)| format!("{status} × {n}"))
            .collect();
        let _ = writeln!(md, "| {kind} | {sent} | {} |", answers.join(", "));
    }
    let _ = writeln!(
        md,
        "\n`closed`: the server closed the connection without an answer (the client had already left, or sent nothing it could answer). \
         25 event-stream clients read throughout: {} of {} received tiles.\n",
        report.streams_with_tiles, report.streams
    );
    let _ = writeln!(md, "## The server meanwhile\n");
    let _ = writeln!(
        md,
        "| `GET /state` probes | failed | slowest | peak threads | peak resident memory |\n|---:|---:|---:|---:|---:|\n| {} | {} | {:.1} ms | {} | {} MiB |\n",
        report.probes,
        report.failed_probes,
        report.slowest_probe.as_secs_f64() * 1e3,
        report.peak_threads,
        report.peak_rss_kib >> 10
    );
    let _ = writeln!(md, "## The worst cancels\n");
    let _ = writeln!(
        md,
        "Each request restarts the render with the largest one the viewer accepts (2048 × 2048, 10⁶ spp, 4 threads per core, 64-pixel tiles), 300 ms after the one before; \
         the time is from sending the `POST` to its 202, which the server sends once the running render's jobs have stopped and its thread has been joined.\n"
    );
    let _ = writeln!(md, "| request | POST → 202 |\n|---|---:|");
    for (query, took) in &report.cancels {
        let _ = writeln!(md, "| `{query}` | {:.1} ms |", took.as_secs_f64() * 1e3);
    }
    let slowest = report.cancels.iter().map(|(_, t)| *t).max().unwrap_or_default();
    let _ = writeln!(md, "\nSlowest cancel: **{:.1} ms**.", slowest.as_secs_f64() * 1e3);
    drop(viewer);
    let _ = writeln!(md, "\n## 256 slow image readers at 2048 × 2048\n");
    let large =
        Viewer::start(&["--scene", "three-spheres", "--width", "2048", "--height", "2048", "--spp", "1"]);
    common::viewer::until_done(&mut large.events(), 1);
    let seen = hostile::slow_image_readers(&large, 256, Duration::from_secs(8));
    let answers: Vec<String> = seen.answers.iter().map(|(status, n)| format!("{status} × {n}")).collect();
    let _ = writeln!(
        md,
        "`raypool view --scene three-spheres --width 2048 --height 2048 --spp 1`, its first pass done; 256 connections \
         each ask for `/image.pfm` (48 MiB) and read nothing for 8 s. Each pass is encoded once and shared; at most 32 \
         image answers are written at once, the rest get 503 (`results/view-slow-readers.md` has the viewer before that: \
         3,310 MiB).\n\n| resident before | peak resident | answers |\n|---:|---:|---|\n| {} MiB | {} MiB | {} |",
        seen.before_kib >> 10,
        seen.peak_kib >> 10,
        answers.join(", ")
    );
    std::fs::write(results_dir().join("view-hostile.md"), &md).expect("the output directory is writable");
    println!("{md}");
}
