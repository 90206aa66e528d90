//! No test may hang. Whatever a test waits for (a render on several threads, a `raypool`
//! process) it waits for under a deadline, and when the deadline passes the test fails with
//! "waited N s for WHAT: it never happened", naming what never happened, instead of stalling
//! `cargo test` until a CI limit kills it with no word of where. [`within`] runs a test body on
//! a thread of its own; [`output_within`] runs a child process to completion (it replaces
//! `Command::output`). The pool's tests have the same helper (`pool/tests/common/mod.rs`).
#![allow(dead_code)] // each test file uses a part of these

use std::io::Read;
use std::panic::resume_unwind;
use std::process::{Command, Output, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long any one wait of a test may take before the test fails: 120 s, or
/// `RAYPOOL_TEST_DEADLINE` seconds. Far above what the slowest test needs in the README's
/// `cargo test --release` (a few seconds of rendering on a loaded 2-core machine), far below a
/// CI time limit.
pub fn deadline() -> Duration {
    let seconds = std::env::var("RAYPOOL_TEST_DEADLINE").ok().and_then(|s| s.parse().ok());
    Duration::from_secs(seconds.unwrap_or(120))
}

/// Runs `body` on a thread of its own and waits for it at most [`deadline`]. If it has not
/// finished by then, the test fails with "waited N s for `what`: it never happened" (so
/// `what` reads "the render to finish"): a scheduler that never returns (a lost wake-up, a
/// worker waiting on a tile nobody renders) is a failure one can read, not a hang. The stuck
/// thread is left behind; the test binary exits regardless.
///
/// A panic in `body` (a failed assertion) is re-raised here unchanged.
pub fn within<T: Send + 'static>(what: impl AsRef<str>, body: impl FnOnce() -> T + Send + 'static) -> T {
    let limit = deadline();
    let (done, finished) = mpsc::channel();
    let thread = std::thread::Builder::new()
        .name("test-body".into())
        .spawn(move || {
            let _ = done.send(body());
        })
        .expect("a test thread starts");
    match finished.recv_timeout(limit) {
        Ok(value) => value,
        Err(mpsc::RecvTimeoutError::Disconnected) => match thread.join() {
            Err(panic) => resume_unwind(panic),
            Ok(()) => unreachable!("the body sends before it returns"),
        },
        Err(mpsc::RecvTimeoutError::Timeout) => {
            panic!("waited {} s for {}: it never happened", limit.as_secs(), what.as_ref())
        }
    }
}

/// `command.output()`, waiting at most [`deadline`]: runs the child with stdin closed and
/// stdout and stderr captured, each pipe read on a thread of its own (so a child that fills
/// one pipe while nobody reads it cannot block). If the child has not exited by the deadline
/// it is killed and the test fails with "waited N s for `what`: it never happened" and the
/// command line (so `what` reads "`raypool render` to exit"). The same if it exits but its
/// output stays open past the deadline (a process it started still holds the pipes).
pub fn output_within(command: &mut Command, what: impl AsRef<str>) -> Output {
    let (limit, start, line) = (deadline(), Instant::now(), format!("{command:?}"));
    let never = |how: &str| -> String {
        format!("waited {} s for {}: it never happened ({how}: {line})", limit.as_secs(), what.as_ref())
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
