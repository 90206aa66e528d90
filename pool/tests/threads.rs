//! No thread outlives its pool. (Its own test binary: it counts the process's threads.)
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

use std::time::{Duration, Instant};

#[cfg(target_os = "linux")]
fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

/// The thread count once it settles at `want`, or whatever it is after two seconds.
///
/// Why wait at all: `join` returns when the kernel clears the thread's id word, which happens
/// a moment *before* the kernel removes the thread from `/proc/self/task`. On a loaded
/// machine that moment is visible (CI once saw one extra entry right after `drop`). A thread
/// that really leaked never goes away, so the assertion still catches it.
#[cfg(target_os = "linux")]
fn settled_thread_count(want: usize) -> usize {
    let deadline = Instant::now() + Duration::from_secs(2);
    loop {
        let now = thread_count();
        if now == want || Instant::now() > deadline {
            return now;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[cfg(target_os = "linux")]
#[test]
fn thread_count_returns_to_its_start_after_drop() {
    common::within("eight-worker pools to start, run a batch and be dropped", || {
        let before = thread_count();
        for discipline in pool::Discipline::ALL {
            let pool = pool::ThreadPool::new(8, discipline).unwrap();
            assert_eq!(settled_thread_count(before + 8), before + 8, "{discipline:?}: eight named workers");
            pool.batch((0..100).map(|i| move || i));
            drop(pool);
            assert_eq!(settled_thread_count(before), before, "{discipline:?}: every worker joined");
        }
    });
}
