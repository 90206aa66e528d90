//! Helpers shared by the pool's test files.
#![allow(dead_code)] // each test file uses a subset of these

use std::io::Write;
use std::panic::resume_unwind;
use std::sync::mpsc;
use std::time::Duration;

/// How long any one blocking step of a test may take before the test fails: 60 s, or
/// `POOL_TEST_DEADLINE` seconds (`pool/break-it/run.sh` sets 15). Far above what the slowest
/// step needs (a million-job batch in a debug build on a loaded 2-core machine takes a few
/// seconds), far below a CI time limit.
pub fn deadline() -> Duration {
    let seconds = std::env::var("POOL_TEST_DEADLINE").ok().and_then(|s| s.parse().ok());
    Duration::from_secs(seconds.unwrap_or(60))
}

/// Stress sizes scale down in debug builds so that `cargo test` stays quick; the README's
/// `cargo test --release` runs them at full size.
pub const fn scaled(n: usize) -> usize {
    if cfg!(debug_assertions) { n / 20 } else { n }
}

/// Runs `body` on a thread of its own and waits for it at most [`deadline`]. If it has not
/// finished by then, the test fails with "waited N s for `what`: it never happened" (so
/// `what` reads "the batch to return"): a pool bug that blocks (a lost wake-up, a worker that
/// waits without helping) is a failure a student can read, not a hang. Then the whole test
/// binary stops (exit code 101, as a failed `cargo test`): the stuck threads cannot be
/// stopped, and the binary's other tests would most likely wait out the same bug one by one.
///
/// A panic in `body` (a failed assertion) is re-raised here unchanged.
pub fn within<T: Send + 'static>(what: impl AsRef<str>, body: impl FnOnce() -> T + Send + 'static) -> T {
    within_for(deadline(), what, body)
}

/// [`within`] with a deadline of the caller's choosing.
pub fn within_for<T: Send + 'static>(
    limit: Duration,
    what: impl AsRef<str>,
    body: impl FnOnce() -> T + Send + 'static,
) -> T {
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
            let test = std::thread::current().name().unwrap_or("a test").to_string();
            // Straight to the process's stderr: the test harness keeps what `eprintln!` writes
            // until the test ends, and this test never will.
            let _ = writeln!(
                std::io::stderr(),
                "\ntest {test} FAILED: waited {} s for {}: it never happened\n\
                 (stopping this test binary: its other tests would wait out the same bug)",
                limit.as_secs(),
                what.as_ref()
            );
            std::process::exit(101)
        }
    }
}

/// Silences the default panic message for the tests' deliberate panics only.
pub fn quiet_deliberate_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info.payload().downcast_ref::<&str>().copied().unwrap_or("");
        if !message.starts_with("deliberate") {
            default(info);
        }
    }));
}

/// Yields until `flag` is set or `limit` has passed; returns the flag. A job that must wait for
/// another job uses it, so that a pool that never runs the other one fails, not hangs.
pub fn wait_until(flag: &std::sync::atomic::AtomicBool, limit: Duration) -> bool {
    let give_up = std::time::Instant::now() + limit;
    while !flag.load(std::sync::atomic::Ordering::SeqCst) && std::time::Instant::now() < give_up {
        std::thread::yield_now();
    }
    flag.load(std::sync::atomic::Ordering::SeqCst)
}

/// Busy-waits about `micros` microseconds (a job of known length that really uses the CPU).
pub fn spin(micros: u64) {
    let start = std::time::Instant::now();
    while start.elapsed().as_micros() < micros as u128 {
        std::hint::spin_loop();
    }
}
