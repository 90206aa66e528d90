//! An idle pool sleeps: its workers burn (almost) no CPU. (Own test binary: it reads the
//! CPU time of every thread of the process.)
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

/// CPU time so far of each thread of the process, by thread id, from its `/proc` schedstat
/// (nanoseconds on CPU), precise where `getrusage`'s tick-based numbers are not.
#[cfg(target_os = "linux")]
fn thread_cpu() -> std::collections::HashMap<String, u64> {
    std::fs::read_dir("/proc/self/task")
        .unwrap()
        .filter_map(|task| {
            let task = task.ok()?;
            let stat = std::fs::read_to_string(task.path().join("schedstat")).ok()?;
            Some((
                task.file_name().to_string_lossy().into_owned(),
                stat.split_whitespace().next()?.parse().ok()?,
            ))
        })
        .collect()
}

/// CPU time the process's threads used since `before` (a [`thread_cpu`] reading). Threads
/// that ended in between are left out, not subtracted: a finished helper thread (the last
/// round's deadline thread) must not make the sum go down.
#[cfg(target_os = "linux")]
fn cpu_since(before: &std::collections::HashMap<String, u64>) -> std::time::Duration {
    let now = thread_cpu();
    let ns = now.iter().map(|(tid, &ns)| ns.saturating_sub(before.get(tid).copied().unwrap_or(0))).sum();
    std::time::Duration::from_nanos(ns)
}

#[cfg(target_os = "linux")]
#[test]
fn an_idle_pool_of_four_uses_under_20_ms_of_cpu_per_second() {
    for discipline in pool::Discipline::ALL {
        common::within(format!("{discipline:?}: the idle pool's batch and drop to return"), move || {
            let pool = pool::ThreadPool::new(4, discipline).unwrap();
            pool.batch((0..100).map(|i| move || i)); // wake everyone once, then go idle
            let before = thread_cpu();
            std::thread::sleep(std::time::Duration::from_secs(1));
            let used = cpu_since(&before);
            assert!(used.as_millis() < 20, "{discipline:?}: idle pool used {used:?} of CPU in 1 s");
            drop(pool);
        });
    }
}
