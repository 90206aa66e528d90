//! No thread outlives its pool. (Its own test binary: it counts the process's threads.)

mod common;

#[cfg(target_os = "linux")]
fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

#[cfg(target_os = "linux")]
#[test]
fn thread_count_returns_to_its_start_after_drop() {
    let before = thread_count();
    for discipline in common::ALL {
        let pool = pool::ThreadPool::new(8, discipline).unwrap();
        assert_eq!(thread_count(), before + 8, "{discipline:?}: eight named workers");
        pool.batch((0..100).map(|i| move || i));
        drop(pool);
        assert_eq!(thread_count(), before, "{discipline:?}: every worker joined");
    }
}
