//! The conformance check for queue disciplines: what a queue written outside this crate (a
//! course assignment's) must pass before it is measured.
//!
//! [`check`] builds pools on the queue and runs, each under a deadline, the contract every
//! built-in discipline keeps (`pool/tests/contract.rs` checks them at greater length):
//! - a batch returns every result, in submission order, on 1 to 4 workers, and each job ran
//!   exactly once;
//! - jobs spawned from several threads all run;
//! - batches nested inside jobs return, even on one worker (the waiting rule of `batch.rs`
//!   needs `try_pop` to hand a waiting worker the queued jobs);
//! - dropping a pool runs every job still queued;
//! - idle workers sleep: a pool with nothing to do uses (almost) no CPU time, and is not even
//!   scheduled (a spinning worker on a machine busy with other work gets little CPU time, but
//!   is switched in and out every few milliseconds: load can hide one sign, not both).
//!
//! A deadline missed is reported as an error naming what never happened ([`crate::deadline`]). The stuck threads
//! cannot be stopped from outside and are left behind: a failed check is the end of a run.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::deadline::run_within;
use crate::pool::ThreadPool;
use crate::queue::MakeQueue;

/// How long each part of the check may take (they take milliseconds when they pass).
pub const DEADLINE: Duration = Duration::from_secs(30);

/// Checks that pools built on `make`'s queues keep the pool's contract; the error says
/// which rule broke.
///
/// ```
/// for discipline in pool::Discipline::ALL {
///     pool::conformance::check(discipline.queue()).unwrap();
/// }
/// ```
pub fn check(make: MakeQueue) -> Result<(), String> {
    check_within(make, DEADLINE)
}

/// [`check`] with another deadline for each part (a test of a queue that is meant to fail
/// need not wait 30 s).
///
/// ```
/// use std::time::Duration;
/// pool::conformance::check_within(pool::Discipline::Locked.queue(), Duration::from_secs(60)).unwrap();
/// ```
pub fn check_within(make: MakeQueue, deadline: Duration) -> Result<(), String> {
    let within = |what: String, part| within(what, deadline, part);
    for workers in 1..=4 {
        within(
            format!(
                "a batch of 2,000 jobs on {workers} worker{} to return",
                if workers == 1 { "" } else { "s" }
            ),
            Box::new(move || batches_return_in_order(make, workers)),
        )?;
    }
    within(
        "20,000 jobs spawned from 4 threads to run".into(),
        Box::new(move || spawned_jobs_all_run(make, deadline)),
    )?;
    for workers in [1, 2] {
        within(
            format!("batches nested in jobs on {workers} worker(s) to return"),
            Box::new(move || nested_batches_return(make, workers)),
        )?;
    }
    within(
        "a dropped pool to run its 1,000 queued jobs and join".into(),
        Box::new(move || drop_runs_queued(make)),
    )?;
    within(
        "4 jobs that wait for each other to run on 4 workers at once (every idle worker must be able \
         to take a queued job), then the idle pool's CPU time to be read"
            .into(),
        Box::new(move || idle_workers_sleep(make)),
    )?;
    Ok(())
}

/// One part of the check.
type Part = Box<dyn FnOnce() -> Result<(), String> + Send>;

/// Runs `part` on its own thread (the workspace's deadline helper, [`crate::deadline`]) and
/// waits at most `deadline` for it; a panic in it is an error, not a panic of the check.
fn within(what: String, deadline: Duration, part: Part) -> Result<(), String> {
    let outcome = run_within(deadline, &what, move || {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(part))
            .unwrap_or_else(|_| Err("it panicked (see the message above)".into()))
    });
    match outcome {
        Ok(outcome) => outcome.map_err(|e| format!("{what}: {e}")),
        Err(missed) => Err(missed.to_string()),
    }
}

fn pool(make: MakeQueue, workers: usize) -> ThreadPool {
    ThreadPool::builder().workers(workers).queue(make).build().expect("the pool's threads start")
}

fn batches_return_in_order(make: MakeQueue, workers: usize) -> Result<(), String> {
    let pool = pool(make, workers);
    let runs: Arc<Vec<AtomicUsize>> = Arc::new((0..2_000).map(|_| AtomicUsize::new(0)).collect());
    let out = pool.batch((0..2_000).map(|i| {
        let runs = Arc::clone(&runs);
        move || {
            runs[i].fetch_add(1, Relaxed);
            i
        }
    }));
    if let Some(i) = (0..2_000).find(|&i| out.get(i) != Some(&i)) {
        return Err(format!("result {i} is {:?}: results must come back in submission order", out.get(i)));
    }
    match (0..2_000).find(|&i| runs[i].load(Relaxed) != 1) {
        Some(i) => Err(format!("job {i} ran {} times instead of once", runs[i].load(Relaxed))),
        None => Ok(()),
    }
}

fn spawned_jobs_all_run(make: MakeQueue, deadline: Duration) -> Result<(), String> {
    let ran = Arc::new(AtomicUsize::new(0));
    let (tell, told) = mpsc::channel();
    let pool = pool(make, 3);
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| {
                for _ in 0..5_000 {
                    let (ran, tell) = (Arc::clone(&ran), tell.clone());
                    pool.spawn(move || {
                        ran.fetch_add(1, Relaxed);
                        let _ = tell.send(());
                    });
                }
            });
        }
    });
    for _ in 0..20_000 {
        told.recv_timeout(deadline / 2).map_err(|_| {
            format!("only {} of 20,000 spawned jobs ran: is a pushed job lost?", ran.load(Relaxed))
        })?;
    }
    Ok(())
}

fn nested_batches_return(make: MakeQueue, workers: usize) -> Result<(), String> {
    let pool = Arc::new(pool(make, workers));
    let inner = Arc::clone(&pool);
    let sums = pool.batch((0..8u64).map(|i| {
        let pool = Arc::clone(&inner);
        move || pool.batch((0..8u64).map(move |j| move || i * 8 + j)).into_iter().sum::<u64>()
    }));
    let total: u64 = sums.iter().sum();
    if total == (0..64).sum::<u64>() { Ok(()) } else { Err(format!("the nested sums add up to {total}")) }
}

fn drop_runs_queued(make: MakeQueue) -> Result<(), String> {
    let ran = Arc::new(AtomicUsize::new(0));
    {
        let pool = pool(make, 2);
        for _ in 0..1_000 {
            let ran = Arc::clone(&ran);
            pool.spawn(move || {
                std::thread::sleep(Duration::from_micros(10));
                ran.fetch_add(1, Relaxed);
            });
        }
    }
    match ran.load(Relaxed) {
        1_000 => Ok(()),
        n => Err(format!("only {n} of 1,000 queued jobs ran before drop returned")),
    }
}

/// Four idle workers for 200 ms use (almost) no CPU time and are (almost) never switched in
/// and out: measured per worker thread, from `/proc`, so that other threads of the process do
/// not count. On Linux a `/proc` that cannot
/// be read fails the check (a check that cannot look must not pass); on other systems this
/// part is skipped, and says so on stderr.
fn idle_workers_sleep(make: MakeQueue) -> Result<(), String> {
    let pool = pool(make, 4);
    // Four jobs that wait for each other: each worker runs exactly one, and says who it is.
    let all_four = Arc::new(std::sync::Barrier::new(4));
    let tids = pool.batch((0..4).map(|_| {
        let all_four = Arc::clone(&all_four);
        move || {
            all_four.wait();
            thread_id_in_proc()
        }
    }));
    let unreadable = |what: &str| {
        if cfg!(target_os = "linux") {
            Err(format!("cannot read {what} from /proc, so cannot tell whether idle workers sleep"))
        } else {
            eprintln!("pool::conformance: idle workers' CPU time not checked: no /proc on this system");
            Ok(())
        }
    };
    let Some(tids) = tids.into_iter().collect::<Option<Vec<u64>>>() else {
        return unreadable("the workers' thread ids (/proc/thread-self/stat)");
    };
    let cpu = || tids.iter().map(|&tid| thread_cpu_time(tid)).sum::<Option<Duration>>();
    let switches = || tids.iter().map(|&tid| thread_switches(tid)).sum::<Option<u64>>();
    let (before, switched_before, wall) = (cpu(), switches(), Instant::now());
    std::thread::sleep(Duration::from_millis(200));
    let (after, switched_after, wall) = (cpu(), switches(), wall.elapsed());
    let (Some(before), Some(after)) = (before, after) else {
        return unreadable("the workers' CPU times (/proc/self/task/TID/stat)");
    };
    let (Some(switched_before), Some(switched_after)) = (switched_before, switched_after) else {
        return unreadable("the workers' context switches (/proc/self/task/TID/status)");
    };
    let used = after.saturating_sub(before);
    let switched = switched_after.saturating_sub(switched_before);
    // A sleeping worker is not scheduled at all; one still on its way to sleep as the window
    // opens is switched out once. A spinner shares the cores with whatever else runs and is
    // switched out every few milliseconds: dozens of times in 200 ms.
    if switched > MAX_IDLE_SWITCHES {
        return Err(format!(
            "4 idle workers were switched in and out {switched} times in {} ms (using {} ms of CPU): \
             a worker with nothing to do must sleep (wait on a condition variable or a channel), not spin",
            wall.as_millis(),
            used.as_millis()
        ));
    }
    // Four spinning workers would use up to 4 × 200 ms, and still over 100 ms when other
    // processes leave them a fraction of a loaded 2-core machine; sleeping ones use nothing
    // (the kernel counts in 10 ms ticks, so at most a tick or two by rounding).
    if used > wall / 4 {
        return Err(format!(
            "4 idle workers used {} ms of CPU in {} ms: a worker with nothing to do must sleep \
             (wait on a condition variable or a channel), not spin",
            used.as_millis(),
            wall.as_millis()
        ));
    }
    Ok(())
}

/// The most context switches four idle workers may have in the check's 200 ms: one each on
/// the way to sleep, with room to spare.
const MAX_IDLE_SWITCHES: u64 = 16;

/// The calling thread's id in `/proc` (Linux); `None` elsewhere.
fn thread_id_in_proc() -> Option<u64> {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    stat.split_whitespace().next()?.parse().ok()
}

/// User + system CPU time of thread `tid` of this process, from `/proc` (Linux).
fn thread_cpu_time(tid: u64) -> Option<Duration> {
    cpu_time_in_stat(&std::fs::read_to_string(format!("/proc/self/task/{tid}/stat")).ok()?)
}

/// Voluntary + involuntary context switches of thread `tid` of this process, from `/proc`.
fn thread_switches(tid: u64) -> Option<u64> {
    switches_in_status(&std::fs::read_to_string(format!("/proc/self/task/{tid}/status")).ok()?)
}

/// Voluntary + involuntary context switches in a `/proc/…/status` text.
fn switches_in_status(status: &str) -> Option<u64> {
    let field = |name: &str| -> Option<u64> {
        status.lines().find_map(|line| line.strip_prefix(name)?.strip_prefix(':')?.trim().parse().ok())
    };
    Some(field("voluntary_ctxt_switches")? + field("nonvoluntary_ctxt_switches")?)
}

/// User + system CPU time in one `/proc/…/stat` line.
fn cpu_time_in_stat(stat: &str) -> Option<Duration> {
    // The fields after the command name (which may hold spaces and ')', hence the last ')'):
    // state is the first, utime the 12th and stime the 13th.
    let fields: Vec<&str> = stat[stat.rfind(')')? + 2..].split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    // The kernel's USER_HZ is 100 on every Linux this runs on.
    Some(Duration::from_millis(ticks * 10))
}

#[cfg(all(test, not(loom)))]
mod tests {
    use std::time::Duration;

    use super::{cpu_time_in_stat, switches_in_status};

    /// A `/proc/self/task/TID/stat` line, its 52 fields in the order proc(5) gives them, with a
    /// command name that holds a space and a ')' (as a thread may name itself): utime 731
    /// ticks, stime 29, and the fields around them (majflt 3, cmajflt 5, cutime 11) different,
    /// so that reading the fields shifted either way, or subtracting, gives another answer.
    const STAT: &str = "41532 (pool) worker 0) S 41520 41520 3297 34816 41520 4194368 \
                        209 0 3 5 731 29 11 0 20 0 6 0 2893151 309051392 1052 \
                        18446744073709551615 1 1 0 0 0 0 0 4096 17922 0 0 0 -1 1 0 0 0 0 0 0 0 0 0 0 0 0 0";

    #[test]
    fn cpu_time_is_utime_plus_stime_in_ticks_of_10_ms() {
        assert_eq!(cpu_time_in_stat(STAT), Some(Duration::from_millis((731 + 29) * 10)));
    }

    #[test]
    fn a_line_cut_short_or_without_a_command_name_reads_as_none() {
        assert_eq!(cpu_time_in_stat(&STAT[..60]), None);
        assert_eq!(cpu_time_in_stat("41532 pool-worker-0 S 1 2 3"), None);
    }

    /// The end of a `/proc/self/task/TID/status`, with the two counts different (and a field
    /// whose name ends like theirs) so that a swapped, doubled or missed field shows.
    const STATUS: &str = "Name:\tpool-worker-0\nState:\tS (sleeping)\nSpeculation_Store_Bypass:\tthread vulnerable\n\
                          voluntary_ctxt_switches:\t1234\nnonvoluntary_ctxt_switches:\t56\n";

    #[test]
    fn switches_are_voluntary_plus_involuntary() {
        assert_eq!(switches_in_status(STATUS), Some(1234 + 56));
        assert_eq!(switches_in_status("voluntary_ctxt_switches:\t3\n"), None);
        assert_eq!(
            switches_in_status("voluntary_ctxt_switches:\tmany\nnonvoluntary_ctxt_switches:\t1\n"),
            None
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn this_threads_cpu_time_can_be_read() {
        let tid = super::thread_id_in_proc().expect("/proc/thread-self/stat can be read");
        assert!(super::thread_cpu_time(tid).is_some());
        assert!(super::thread_switches(tid).is_some());
    }
}
