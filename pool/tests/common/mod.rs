//! Helpers shared by the pool's test files.
#![allow(dead_code)] // each test file uses a subset of these

use pool::Discipline;

pub const ALL: [Discipline; 3] = [Discipline::Shared, Discipline::Locked, Discipline::Stealing];

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

/// Busy-waits about `micros` microseconds (a job of known length that really uses the CPU).
pub fn spin(micros: u64) {
    let start = std::time::Instant::now();
    while start.elapsed().as_micros() < micros as u128 {
        std::hint::spin_loop();
    }
}
