//! No test may hang. Whatever a test waits for (a render on several threads, a `raypool`
//! process) it waits for under a deadline, and when the deadline passes the test fails with
//! "waited N s for WHAT: it never happened", naming what never happened, instead of stalling
//! `cargo test` until a CI limit kills it with no word of where.
//!
//! The helper is the workspace's one, `pool::deadline`: [`within`] (re-exported here) runs a
//! test body on a thread of its own, and [`deadline`] is its limit (120 s, or
//! `RAYPOOL_TEST_DEADLINE` seconds). What stays here is the root crate's own: [`output_within`]
//! runs a child process to completion (it replaces `Command::output`), and [`skipped`].
#![allow(dead_code, unused_imports)] // each test file uses a part of these

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

pub use pool::deadline::{limit as deadline, within, within_for};

/// `command.output()`, waiting at most [`deadline`]: runs the child with stdin closed and
/// stdout and stderr captured, each pipe read on a thread of its own (so a child that fills
/// one pipe while nobody reads it cannot block). If the child has not exited by the deadline
/// it is killed and the test fails with "waited N s for `what`: it never happened" and the
/// command line (so `what` reads "`raypool render` to exit"). The same if it exits but its
/// output stays open past the deadline (a process it started still holds the pipes).
pub fn output_within(command: &mut Command, what: impl AsRef<str>) -> Output {
    let (limit, start, line) = (deadline(), Instant::now(), format!("{command:?}"));
    let never = |how: &str| -> String {
        let missed = pool::deadline::Missed { what: what.as_ref().to_string(), limit };
        format!("{missed} ({how}: {line})")
    };
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{line} does not start: {e}"));
    let stdout = drain(child.stdout.take().expect("stdout is piped"));
    let stderr = drain(child.stderr.take().expect("stderr is piped"));
    let mut pause = Duration::from_millis(1);
    let status = loop {
        if let Some(status) = child.try_wait().expect("the child's status can be read") {
            break status;
        }
        if start.elapsed() >= limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{}", never("killed"));
        }
        std::thread::sleep(pause.min(limit.saturating_sub(start.elapsed())));
        pause = (pause * 2).min(Duration::from_millis(50));
    };
    let read = |bytes: mpsc::Receiver<Vec<u8>>| {
        bytes.recv_timeout(limit.saturating_sub(start.elapsed())).unwrap_or_else(|_| {
            panic!("{}", never("it exited, but a process it started still holds its output open"))
        })
    };
    Output { status, stdout: read(stdout), stderr: read(stderr) }
}

/// Runs `raypool args` in `dir` to completion under the deadline ([`output_within`]).
pub fn raypool(args: &[&str], dir: &Path) -> Output {
    let what = format!("`raypool {}` to exit", args.first().unwrap_or(&""));
    output_within(Command::new(env!("CARGO_BIN_EXE_raypool")).args(args).current_dir(dir), what)
}

/// A fresh, empty scratch folder for test `name` of this test file and process.
pub fn scratch(name: &str) -> PathBuf {
    let file = env!("CARGO_CRATE_NAME");
    let dir = std::env::temp_dir().join(format!("raypool-{file}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `out`, after checking that its command succeeded (else its stderr is the failure).
pub fn ok(out: Output) -> Output {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    out
}

/// Reads `pipe` to its end on a thread of its own; the bytes arrive on the returned channel.
fn drain(mut pipe: impl Read + Send + 'static) -> mpsc::Receiver<Vec<u8>> {
    let (sent, bytes) = mpsc::channel();
    std::thread::spawn(move || {
        let mut all = Vec::new();
        let _ = pipe.read_to_end(&mut all);
        let _ = sent.send(all);
    });
    bytes
}

/// Says that test `name` skipped, and why, where `cargo test` shows it without `--nocapture`:
/// straight to the process's stderr, which the harness does not capture (it captures only
/// `eprintln!`), so the line stands beside the test's `ok`.
pub fn skipped(name: &str, why: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED {name}: {why}");
}
