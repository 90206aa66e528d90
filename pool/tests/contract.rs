//! The pool's contract, for every queue discipline: every job runs exactly once, results
//! come back in order, panics are contained, nesting cannot deadlock, drop runs what is
//! queued.
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering::Relaxed};
use std::time::Duration;

use common::{quiet_deliberate_panics, scaled, spin, wait_until, within};
use pool::{BuildError, Discipline, ThreadPool};

#[test]
fn a_million_jobs_each_run_exactly_once() {
    const JOBS: usize = scaled(1_000_000);
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the million-job batch to return"), move || {
            let pool = ThreadPool::new(4, discipline).unwrap();
            let runs: Arc<Vec<AtomicU8>> = Arc::new((0..JOBS).map(|_| AtomicU8::new(0)).collect());
            let ids = pool.batch((0..JOBS).map(|id| {
                let runs = Arc::clone(&runs);
                move || {
                    runs[id].fetch_add(1, Relaxed);
                    id
                }
            }));
            assert!(ids.iter().enumerate().all(|(i, &id)| i == id), "{discipline:?}: results out of order");
            let wrong: Vec<_> = (0..JOBS).filter(|&id| runs[id].load(Relaxed) != 1).take(5).collect();
            assert!(
                wrong.is_empty(),
                "{discipline:?}: jobs {wrong:?} ran {:?} times",
                runs[wrong[0]].load(Relaxed)
            );
            assert_eq!(pool.stats().total_jobs(), JOBS as u64);
        });
    }
}

#[test]
fn fire_and_forget_jobs_from_many_threads_all_run() {
    const PER_THREAD: usize = scaled(50_000);
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the pool to run 200,000 spawned jobs and be dropped"), move || {
            let counter = Arc::new(AtomicUsize::new(0));
            {
                let pool = ThreadPool::new(3, discipline).unwrap();
                std::thread::scope(|s| {
                    for _ in 0..4 {
                        s.spawn(|| {
                            for _ in 0..PER_THREAD {
                                let counter = Arc::clone(&counter);
                                pool.spawn(move || {
                                    counter.fetch_add(1, Relaxed);
                                });
                            }
                        });
                    }
                });
            } // drop: runs everything queued
            assert_eq!(counter.load(Relaxed), 4 * PER_THREAD, "{discipline:?}");
        });
    }
}

#[test]
fn random_job_lengths_keep_order_and_count() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch of 500 uneven jobs to return"), move || {
            let pool =
                ThreadPool::builder().workers(3).discipline(discipline).instrument(true).build().unwrap();
            // A cheap deterministic pseudo-random length per job: 0–200 µs.
            let lengths: Vec<u64> = (0..500u64).map(|i| (i.wrapping_mul(2_654_435_761) >> 7) % 200).collect();
            let start = std::time::Instant::now();
            let out = pool.batch(lengths.iter().map(|&us| {
                move || {
                    spin(us);
                    us
                }
            }));
            let wall = start.elapsed();
            assert_eq!(out, lengths, "{discipline:?}");
            let stats = pool.stats();
            assert_eq!(
                stats.total_jobs(),
                500,
                "{discipline:?}: the batch returned before every job was recorded"
            );
            let busy: Duration = stats.workers.iter().map(|w| w.busy).sum();
            assert!(busy >= Duration::from_micros(lengths.iter().sum()), "{discipline:?}: busy {busy:?}");
            // Three workers cannot be busy for longer than three times the batch's wall time.
            assert!(busy <= 3 * wall, "{discipline:?}: busy {busy:?} in a batch of {wall:?} on 3 workers");
            let spans = pool.take_trace();
            assert_eq!(spans.len(), 500);
            let span_sum: Duration = spans.iter().map(|s| s.end - s.start).sum();
            assert_eq!(span_sum, busy, "{discipline:?}: busy time is the sum of the spans");
        });
    }
}

#[test]
fn a_panicking_batch_job_is_reraised_after_the_others_finish() {
    quiet_deliberate_panics();
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch with panicking jobs to return"), move || {
            let pool = ThreadPool::new(2, discipline).unwrap();
            let finished = Arc::new(AtomicUsize::new(0));
            let jobs: Vec<Box<dyn FnOnce() -> usize + Send>> = (0..20usize)
                .map(|i| {
                    let finished = Arc::clone(&finished);
                    Box::new(move || {
                        if i % 7 == 3 {
                            panic!("deliberate panic in job {i}");
                        }
                        spin(100);
                        finished.fetch_add(1, Relaxed);
                        i
                    }) as Box<dyn FnOnce() -> usize + Send>
                })
                .collect();
            let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| pool.batch(jobs)));
            let payload = caught.expect_err("the batch must re-raise the job's panic");
            let message = payload.downcast_ref::<String>().cloned().unwrap_or_default();
            assert_eq!(
                message, "deliberate panic in job 3",
                "{discipline:?}: the first panic in submission order"
            );
            assert_eq!(finished.load(Relaxed), 17, "{discipline:?}: the other jobs all ran");
            // The pool is unharmed: same workers, still working.
            assert_eq!(pool.batch((0..100).map(|i| move || i)).len(), 100);
        });
    }
}

#[test]
fn panicking_spawned_jobs_do_not_kill_workers() {
    quiet_deliberate_panics();
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch after 50 panicking jobs to return"), move || {
            let pool = ThreadPool::new(2, discipline).unwrap();
            for _ in 0..50 {
                pool.spawn(|| panic!("deliberate panic"));
            }
            // Both workers survive 50 panics and still run a batch.
            assert_eq!(pool.batch((0..10).map(|i| move || i * 2)).iter().sum::<i32>(), 90);
            // The batch can finish while the last panicking jobs are still being counted.
            let panics = || pool.stats().workers.iter().map(|w| w.panics).sum::<u64>();
            let deadline = std::time::Instant::now() + Duration::from_secs(10);
            while panics() < 50 && std::time::Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(1));
            }
            assert_eq!(panics(), 50, "{discipline:?}");
        });
    }
}

#[test]
fn nested_batches_do_not_deadlock_even_on_one_worker() {
    for discipline in Discipline::ALL {
        within(
            format!(
                "{discipline:?}: the nested batches to return (a worker waiting on a batch must run queued jobs)"
            ),
            move || {
                for workers in [1, 2, 4] {
                    let pool = Arc::new(ThreadPool::new(workers, discipline).unwrap());
                    // Every outer job waits on an inner batch: with `workers` outer jobs running, a
                    // pool whose waiting workers did not help would have nobody to run the inner ones.
                    let outer = pool.batch((0..8u64).map(|i| {
                        let pool = Arc::clone(&pool);
                        move || {
                            let inner = pool.batch((0..10u64).map(move |j| move || i * 100 + j));
                            // And one level deeper.
                            let deeper = pool.batch([move || i]);
                            inner.iter().sum::<u64>() + deeper[0]
                        }
                    }));
                    let expected: Vec<u64> =
                        (0..8).map(|i| (0..10).map(|j| i * 100 + j).sum::<u64>() + i).collect();
                    assert_eq!(outer, expected, "{discipline:?} with {workers} workers");
                }
            },
        );
    }
}

#[test]
fn drop_runs_every_queued_job_then_joins() {
    for discipline in Discipline::ALL {
        within(
            format!("{discipline:?}: drop to return (it runs the queued jobs, then joins every worker)"),
            move || {
                let done = Arc::new(AtomicUsize::new(0));
                let pool = ThreadPool::new(2, discipline).unwrap();
                for _ in 0..200 {
                    let done = Arc::clone(&done);
                    pool.spawn(move || {
                        spin(200);
                        done.fetch_add(1, Relaxed);
                    });
                }
                drop(pool); // most of the 200 jobs are still queued here
                assert_eq!(done.load(Relaxed), 200, "{discipline:?}");
            },
        );
    }
}

#[test]
fn jobs_spawned_by_jobs_during_drop_still_run() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: drop to return while jobs were still spawning jobs"), move || {
            let done = Arc::new(AtomicUsize::new(0));
            let pool = Arc::new(ThreadPool::new(2, discipline).unwrap());
            for _ in 0..20 {
                let (done, inner_pool) = (Arc::clone(&done), Arc::clone(&pool));
                pool.spawn(move || {
                    spin(100);
                    let done = Arc::clone(&done);
                    inner_pool.spawn(move || {
                        done.fetch_add(1, Relaxed);
                    });
                });
            }
            // The last Arc may be dropped by a job on a worker thread: that must not hang.
            drop(pool);
            let deadline = std::time::Instant::now() + Duration::from_secs(10);
            while done.load(Relaxed) < 20 && std::time::Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(1));
            }
            assert_eq!(done.load(Relaxed), 20, "{discipline:?}");
        });
    }
}

#[test]
fn one_worker_runs_everything_in_order() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch on one worker to return"), move || {
            let pool =
                ThreadPool::builder().workers(1).discipline(discipline).instrument(true).build().unwrap();
            let log = Arc::new(parking_lot::Mutex::new(Vec::new()));
            pool.batch((0..100).map(|i| {
                let log = Arc::clone(&log);
                move || log.lock().push(i)
            }));
            assert_eq!(*log.lock(), (0..100).collect::<Vec<_>>(), "{discipline:?}: FIFO with one worker");
            assert!(pool.take_trace().iter().all(|s| s.worker == 0 && !s.stolen));
        });
    }
}

#[test]
fn sixty_four_workers_on_a_small_machine() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch on 64 workers to return"), move || {
            let pool = ThreadPool::new(64, discipline).unwrap();
            let names =
                pool.batch((0..640).map(|_| || std::thread::current().name().unwrap_or("").to_owned()));
            assert!(names.iter().all(|n| n.starts_with("pool-worker-")), "{discipline:?}");
            assert_eq!(pool.stats().workers.len(), 64);
        });
    }
}

#[test]
fn zero_workers_is_an_error_not_a_hang() {
    for discipline in Discipline::ALL {
        let error = ThreadPool::new(0, discipline).err().expect("zero workers must fail");
        assert!(matches!(error, BuildError::NoWorkers));
        assert!(error.to_string().contains("at least one worker"));
    }
}

#[test]
fn empty_batch_returns_at_once() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the empty batch to return"), move || {
            let pool = ThreadPool::new(2, discipline).unwrap();
            let none: Vec<Box<dyn FnOnce() -> u8 + Send>> = Vec::new();
            assert!(pool.batch(none).is_empty());
        });
    }
}

#[test]
fn stealing_balances_an_uneven_batch() {
    within("Stealing: the uneven batch to return", || {
        let pool = ThreadPool::builder()
            .workers(2)
            .discipline(Discipline::Stealing)
            .instrument(true)
            .build()
            .unwrap();
        // Dealt as [0..50) to worker 0 and [50..100) to worker 1. Job 0 holds worker 0 until job 1
        // has run; job 1 sits behind it in worker 0's own deque, so only a thief can run it: the
        // test does not depend on how the OS schedules the two workers.
        let job1_ran = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let waited = pool.batch((0..100u64).map(|i| {
            let job1_ran = Arc::clone(&job1_ran);
            move || match i {
                0 => wait_until(&job1_ran, Duration::from_secs(10)),
                1 => {
                    job1_ran.store(true, Relaxed);
                    true
                }
                _ => true,
            }
        }));
        assert!(waited[0], "job 1 was never stolen from behind the blocked job 0");
        let stats = pool.stats();
        assert!(stats.workers[1].jobs_stolen > 0, "worker 1 ran dry and must have stolen: {stats:?}");
        let spans = pool.take_trace();
        assert!(spans.iter().any(|s| s.stolen && s.worker == 1));
    });
}

#[test]
fn a_waiting_worker_returns_as_soon_as_its_batch_is_done() {
    // One worker runs job A, which waits on an inner batch [x]; x spawns job J. Once x is done,
    // A's batch is done: the worker must return to A at once, not first run J (or whatever
    // else is queued), or a nested batch's latency would grow with the whole queue.
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the nested batch to return"), move || {
            let pool = Arc::new(ThreadPool::new(1, discipline).unwrap());
            let j_ran = Arc::new(AtomicUsize::new(0));
            let (inner_pool, j) = (Arc::clone(&pool), Arc::clone(&j_ran));
            let seen_by_a = pool.batch([move || {
                let spawner = Arc::clone(&inner_pool);
                inner_pool.batch([move || {
                    spawner.spawn(move || {
                        j.fetch_add(1, Relaxed);
                    })
                }]);
                j_ran.load(Relaxed)
            }]);
            assert_eq!(
                seen_by_a,
                vec![0],
                "{discipline:?}: the waiting worker ran a job queued after its batch"
            );
        });
    }
}

#[test]
fn statistics_record_idle_time_and_an_empty_pool_is_balanced() {
    assert_eq!(pool::PoolStats::default().imbalance(), 1.0, "no workers: nothing to be unbalanced");
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the batch after an idle spell to return"), move || {
            let pool =
                ThreadPool::builder().workers(2).discipline(discipline).instrument(true).build().unwrap();
            assert_eq!(pool.stats().imbalance(), 1.0, "{discipline:?}: nothing measured yet");
            std::thread::sleep(Duration::from_millis(50));
            pool.batch((0..2).map(|_| || spin(1000)));
            let idle = pool.stats().workers.iter().map(|w| w.idle).max().unwrap();
            assert!(
                idle >= Duration::from_millis(40),
                "{discipline:?}: 50 ms asleep recorded as {idle:?} idle"
            );
        });
    }
}

#[test]
fn every_thief_reaches_every_victim() {
    // Three workers; the batch [0 1 | 2 3 | 4 5] is dealt two jobs each. Jobs 0 and 2 hold
    // workers 0 and 1 until job 3 has run, and job 3 sits behind job 2 in worker 1's deque:
    // only worker 2, once it has run 4 and 5 and stolen 1 from worker 0, can steal it.
    within("Stealing, 3 workers: the batch whose job 3 only a thief can run to return", || {
        let pool = ThreadPool::builder().workers(3).discipline(Discipline::Stealing).build().unwrap();
        let job3_ran = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let waited = pool.batch((0..6u64).map(|i| {
            let job3_ran = Arc::clone(&job3_ran);
            move || match i {
                0 | 2 => wait_until(&job3_ran, Duration::from_secs(10)),
                3 => {
                    job3_ran.store(true, Relaxed);
                    true
                }
                _ => true,
            }
        }));
        assert!(
            waited[0] && waited[2],
            "job 3 was never stolen from behind the blocked job 2: some thief skips a victim"
        );
    });
}

#[test]
fn a_worker_of_another_pool_never_runs_this_pools_jobs() {
    // A job on pool A waits on a batch of pool B while B's only worker is busy. A's worker is
    // not B's: it must sleep, not help, so B's jobs still run on B's own thread only.
    for discipline in Discipline::ALL {
        within(
            format!("{discipline:?}: a batch submitted to one pool from another's job to return"),
            move || {
                let a = ThreadPool::new(1, discipline).unwrap();
                let b = Arc::new(ThreadPool::new(1, discipline).unwrap());
                let b_thread = b.batch([|| std::thread::current().id()])[0];
                let go = Arc::new(std::sync::atomic::AtomicBool::new(false));
                let hold = Arc::clone(&go);
                b.spawn(move || {
                    wait_until(&hold, Duration::from_secs(10));
                });
                let release = Arc::clone(&go);
                let releaser = std::thread::spawn(move || {
                    std::thread::sleep(Duration::from_millis(100));
                    release.store(true, Relaxed);
                });
                let b_in_a = Arc::clone(&b);
                let threads = a.batch([move || b_in_a.batch((0..4).map(|_| || std::thread::current().id()))]);
                releaser.join().unwrap();
                assert!(
                    threads[0].iter().all(|&t| t == b_thread),
                    "{discipline:?}: pool B's jobs ran on a thread that is not B's worker"
                );
            },
        );
    }
}
