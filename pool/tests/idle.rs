//! An idle pool sleeps: its workers burn (almost) no CPU. (Own test binary: it reads the
//! CPU time of every thread of the process.)
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

/// CPU time of the whole process so far, from each thread's `/proc` schedstat (nanoseconds
/// on CPU), precise where `getrusage`'s tick-based numbers are not.
#[cfg(target_os = "linux")]
fn process_cpu() -> std::time::Duration {
    let ns: u64 = std::fs::read_dir("/proc/self/task")
        .unwrap()
        .filter_map(|task| std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    std::time::Duration::from_nanos(ns)
}

#[cfg(target_os = "linux")]
#[test]
fn an_idle_pool_of_four_uses_under_20_ms_of_cpu_per_second() {
    for discipline in pool::Discipline::ALL {
        common::within(format!("{discipline:?}: the idle pool's batch and drop to return"), move || {
            let pool = pool::ThreadPool::new(4, discipline).unwrap();
            pool.batch((0..100).map(|i| move || i)); // wake everyone once, then go idle
            let before = process_cpu();
            std::thread::sleep(std::time::Duration::from_secs(1));
            let used = process_cpu() - before;
            assert!(used.as_millis() < 20, "{discipline:?}: idle pool used {used:?} of CPU in 1 s");
            drop(pool);
        });
    }
}
