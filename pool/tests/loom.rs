//! Loom models of the whole pool, through its public interface: a batch's caller returns only
//! after every job (and its bookkeeping), a worker that waits on a nested batch helps, and
//! dropping the pool runs what is queued and joins every worker.
//!
//! Run by `.ci/run` (see `pool/src/sync.rs` for what `--cfg loom` swaps):
//!
//! ```text
//! RUSTFLAGS="--cfg loom" LOOM_MAX_PREEMPTIONS=3 CARGO_TARGET_DIR=target/loom \
//!     cargo test -p pool --release --lib --test loom
//! ```
//!
//! The `Shared` discipline is not modelled: its queue is a crossbeam channel, which loom cannot
//! see inside (crossbeam checks its own channel). Its own logic, shutdown by disconnection, is
//! covered by the stress tests in `contract.rs` and `races.rs`.
#![cfg(loom)]

use std::sync::Arc;
use std::sync::atomic::Ordering::SeqCst;

use loom::sync::atomic::AtomicUsize;
use pool::{Discipline, ThreadPool};

/// The disciplines loom can see into.
const MODELLED: [Discipline; 2] = [Discipline::Locked, Discipline::Stealing];

/// A batch of two jobs on two workers returns both results, in order, with both jobs
/// already counted in the statistics: the latch opens only after a job's bookkeeping.
#[test]
fn model_batch_returns_after_every_job_and_its_bookkeeping() {
    for discipline in MODELLED {
        loom::model(move || {
            let pool = ThreadPool::new(2, discipline).unwrap();
            assert_eq!(pool.batch([|| 1, || 2]), vec![1, 2]);
            assert_eq!(pool.stats().total_jobs(), 2, "{discipline:?}: the caller saw unrecorded jobs");
        });
    }
}

/// One worker runs a job that waits on a nested batch: only the waiting rule (a waiting
/// worker runs queued jobs) lets it finish. A waiter that does not help leaves every thread
/// blocked, which loom reports as a deadlock.
#[test]
fn model_a_worker_waiting_on_a_nested_batch_helps() {
    for discipline in MODELLED {
        loom::model(move || {
            let pool = Arc::new(ThreadPool::new(1, discipline).unwrap());
            let inner = Arc::clone(&pool);
            let outer = pool.batch([move || inner.batch([|| 7])[0] + 1]);
            assert_eq!(outer, vec![8]);
        });
    }
}

/// Dropping a pool with jobs still queued runs them all and joins both workers.
#[test]
fn model_drop_runs_queued_jobs_and_joins() {
    for discipline in MODELLED {
        loom::model(move || {
            let ran = Arc::new(AtomicUsize::new(0));
            let pool = ThreadPool::new(2, discipline).unwrap();
            for _ in 0..2 {
                let ran = Arc::clone(&ran);
                pool.spawn(move || {
                    ran.fetch_add(1, SeqCst);
                });
            }
            drop(pool);
            assert_eq!(ran.load(SeqCst), 2, "{discipline:?}: drop returned before every queued job ran");
        });
    }
}
