//! Stress tests aimed at the pool's race windows, for every discipline. Each one fails, under a
//! deadline and with a message naming what never happened, on a pool that
//!
//! - loses a wake-up: a job pushed in the instant its worker goes to sleep is never run;
//! - wakes too few workers: a batch whose jobs must all run at once never finishes;
//! - lets a waiting worker block instead of helping: nested batches never finish.
//!
//! The loom models (`pool/src/*.rs`, `pool/tests/loom.rs`) prove the protocols on small
//! models; these run the real pool, with real threads, many thousand times.
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{scaled, within};
use pool::{Discipline, ThreadPool};

/// How long one hand-off may take before it counts as lost (a healthy one takes microseconds).
const HAND_OFF_LIMIT: Duration = Duration::from_secs(5);

/// Spins for about `n` short steps: a delay that sweeps the instant of a push across the
/// worker's path from "job done" to "asleep".
fn jitter(n: usize) {
    for _ in 0..n {
        std::hint::spin_loop();
    }
}

/// One worker (and then two) finishes a job and goes back to sleep; the next job is pushed
/// at a slightly different moment each time, from a thread that is not a worker. With a lost
/// wake-up, one of these jobs sits in the queue while every worker sleeps.
#[test]
fn a_job_pushed_as_the_worker_falls_asleep_still_runs() {
    const HAND_OFFS: usize = scaled(20_000);
    for discipline in Discipline::ALL {
        for workers in [1, 2] {
            within(
                format!("{discipline:?}, {workers} workers: {HAND_OFFS} hand-offs to finish"),
                move || {
                    let pool = ThreadPool::new(workers, discipline).unwrap();
                    let (ran, done) = mpsc::channel();
                    for i in 0..HAND_OFFS {
                        jitter(i % 200);
                        if i % 2 == 0 {
                            let ran = ran.clone();
                            pool.spawn(move || ran.send(i).unwrap());
                            let got = done.recv_timeout(HAND_OFF_LIMIT);
                            assert_eq!(
                                got,
                                Ok(i),
                                "{discipline:?}, {workers} workers: job {i}, spawned as the worker went to \
                             sleep, never ran (a lost wake-up)"
                            );
                        } else {
                            let returned = pool.batch([move || i]);
                            assert_eq!(returned, vec![i]);
                        }
                    }
                },
            );
        }
    }
}

/// A batch of `T` jobs on `T` workers, each job waiting until all `T` have started: it can
/// finish only if every worker was woken for it. Each job gives up after a few seconds and
/// reports how many had arrived, so a pool that wakes too few fails instead of hanging.
#[test]
fn a_batch_that_needs_every_worker_at_once_finishes() {
    const ROUNDS: usize = scaled(2_000);
    const PATIENCE: Duration = Duration::from_secs(5);
    for discipline in Discipline::ALL {
        for workers in [2, 4] {
            within(
                format!("{discipline:?}, {workers} workers: {ROUNDS} all-hands batches to return"),
                move || {
                    let pool = ThreadPool::new(workers, discipline).unwrap();
                    for round in 0..ROUNDS {
                        jitter(round % 100); // let the workers fall asleep, or not quite
                        let arrived = Arc::new(AtomicUsize::new(0));
                        let seen = pool.batch((0..workers).map(|_| {
                            let arrived = Arc::clone(&arrived);
                            move || {
                                arrived.fetch_add(1, SeqCst);
                                let give_up = Instant::now() + PATIENCE;
                                while arrived.load(SeqCst) < workers && Instant::now() < give_up {
                                    std::thread::yield_now();
                                }
                                arrived.load(SeqCst)
                            }
                        }));
                        let least = seen.iter().min().copied().unwrap_or(0);
                        assert_eq!(
                            least, workers,
                            "{discipline:?}, round {round}: a job waited {PATIENCE:?} with only {least} of \
                         {workers} jobs started: the pool did not wake a worker for every job"
                        );
                    }
                },
            );
        }
    }
}

/// Batches inside batches inside batches, many times, on pools smaller than the nesting is
/// wide: every outer job's worker must help run the inner jobs while it waits.
#[test]
fn nested_batches_finish_many_times_over() {
    const ROUNDS: usize = scaled(500);
    for discipline in Discipline::ALL {
        for workers in [1, 2, 3] {
            within(
                format!(
                    "{discipline:?}, {workers} workers: {ROUNDS} rounds of nested batches to return \
                     (a worker waiting on a batch must run queued jobs)"
                ),
                move || {
                    let pool = Arc::new(ThreadPool::new(workers, discipline).unwrap());
                    for round in 0..ROUNDS {
                        let sums = pool.batch((0..4u64).map(|i| {
                            let pool = Arc::clone(&pool);
                            move || {
                                let pool2 = Arc::clone(&pool);
                                pool.batch((0..3u64).map(move |j| {
                                    let pool = Arc::clone(&pool2);
                                    move || pool.batch([move || i * 10 + j])[0]
                                }))
                                .iter()
                                .sum::<u64>()
                            }
                        }));
                        let want: Vec<u64> = (0..4).map(|i| 3 * i * 10 + 3).collect();
                        assert_eq!(sums, want, "{discipline:?}, round {round}");
                    }
                },
            );
        }
    }
}

/// Pools built and dropped while their workers are still falling asleep: every drop returns
/// (a worker that sleeps through the close would never be joined) and runs what was queued.
#[test]
fn a_pool_dropped_as_its_workers_fall_asleep_joins_them() {
    const POOLS: usize = scaled(2_000);
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: {POOLS} pools to be dropped and joined"), move || {
            for i in 0..POOLS {
                let ran = Arc::new(AtomicUsize::new(0));
                let pool = ThreadPool::new(1 + i % 3, discipline).unwrap();
                for _ in 0..i % 4 {
                    let ran = Arc::clone(&ran);
                    pool.spawn(move || {
                        ran.fetch_add(1, SeqCst);
                    });
                }
                jitter(i % 300);
                drop(pool);
                assert_eq!(ran.load(SeqCst), i % 4, "{discipline:?}: pool {i} dropped queued jobs");
            }
        });
    }
}
