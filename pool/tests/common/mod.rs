//! Helpers shared by the pool's test files. Waiting under a deadline is the workspace's one
//! helper, `pool::deadline` (re-exported here); the rest is the pool's tests' own.
#![allow(dead_code, unused_imports)] // each test file uses a subset of these

use std::time::Duration;

pub use pool::deadline::{within, within_for};

/// Stress sizes scale down in debug builds so that `cargo test` stays quick; the README's
/// `cargo test --release` runs them at full size.
pub const fn scaled(n: usize) -> usize {
    if cfg!(debug_assertions) { n / 20 } else { n }
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
