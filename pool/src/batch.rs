//! Batches: submit many jobs, wait for all of them, get their results in submission order.
//!
//! ```text
//!   caller: batch([f0, f1, f2, f3])
//!      │  wraps each fᵢ:  run fᵢ, catching a panic → store in slot i; the worker then
//!      │                  records the job and counts the batch's latch down
//!      │  pushes the 4 wrapped jobs (one push_batch)
//!      ▼
//!   wait until the latch reaches 0 ─── a worker of this pool runs queued jobs meanwhile
//!      │                            └─ any other thread sleeps on the latch
//!      ▼
//!   slots → [r0, r1, r2, r3], or re-raise the first panic (after all jobs have finished)
//! ```
//!
//! **The waiting rule.** A pool has a fixed number of workers. If a job submits a batch and
//! its worker simply blocked until the batch finished, a pool whose every worker did that
//! would have nobody left to run the batches: deadlock. So a *worker* that waits runs queued
//! jobs (any pool job, not only its own batch's) until its batch is done; it sleeps only when
//! the queue is empty, which means all its batch's jobs have been taken by threads that will
//! finish them. A thread that is *not* a worker never runs jobs: it sleeps until the batch is
//! done, so a pool of `T` workers always computes on exactly `T` threads.
//!
//! **Panics.** A panicking job is caught where it runs; its slot holds the panic, the others
//! still run, and `batch` re-raises the first panic (in submission order) in the caller once
//! every job has finished. The pool stays usable.
//!
//! **Where the code is.** This file owns what a batch *is*: [`Batch`], its result slots, its
//! latch and the waiting rule. It adds no method to `ThreadPool`: every method of the pool,
//! `batch` included, is in `pool.rs`, so that a reader looking for one of them opens one
//! file; `ThreadPool::batch` there is four lines that make a `Batch`, push its jobs and wait.
//!
//! Invariant: a batch's results are read only once its latch is done, and the latch is done
//! only once every job has stored its result and been recorded (`worker.rs`); so every slot
//! is full when it is read.

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::Arc;
use std::thread;

use crate::latch::CountLatch;
use crate::queue::Job;
use crate::sync::Mutex;
use crate::worker::Registry;

/// Where a batch's jobs leave their results, one slot each.
type Slots<T> = Vec<Mutex<Option<thread::Result<T>>>>;

/// A batch in flight: one result slot per job, and the latch its jobs count down.
pub(crate) struct Batch<T> {
    slots: Arc<Slots<T>>,
    latch: Arc<CountLatch>,
}

impl<T: Send + 'static> Batch<T> {
    /// The batch of `jobs`, and the jobs to push: each runs its closure, catching a panic,
    /// and stores the outcome in its slot; its worker then counts the latch down.
    pub(crate) fn new<F>(jobs: Vec<F>) -> (Batch<T>, Vec<Job>)
    where
        F: FnOnce() -> T + Send + 'static,
    {
        let slots: Arc<Slots<T>> = Arc::new(jobs.iter().map(|_| Mutex::new(None)).collect());
        let latch = Arc::new(CountLatch::new(jobs.len()));
        let wrapped = jobs
            .into_iter()
            .enumerate()
            .map(|(i, job)| {
                let slots = Arc::clone(&slots);
                let body = move || *slots[i].lock() = Some(catch_unwind(AssertUnwindSafe(job)));
                // The worker counts the latch down after recording the job (see worker.rs).
                Job { body: Box::new(body), latch: Some(Arc::clone(&latch)) }
            })
            .collect();
        (Batch { slots, latch }, wrapped)
    }

    /// Waits by the waiting rule (worker `me` of `registry` helps, any other thread sleeps),
    /// then returns the results in submission order, or re-raises the first panic.
    pub(crate) fn wait(self, registry: &Registry, me: Option<usize>) -> Vec<T> {
        wait(registry, me, &self.latch);
        let results: Vec<_> =
            self.slots.iter().map(|slot| slot.lock().take().expect("every job stored a result")).collect();
        results.into_iter().map(|r| r.unwrap_or_else(|panic| resume_unwind(panic))).collect()
    }
}

/// Waits for `latch` by the waiting rule: worker `me` helps, other threads sleep.
fn wait(registry: &Registry, me: Option<usize>, latch: &CountLatch) {
    if let Some(me) = me {
        while !latch.is_done() {
            match registry.queue.try_pop(Some(me)) {
                Some(popped) => registry.run(me, popped),
                None => break, // every job of ours is taken: sleep until they are done
            }
        }
    }
    latch.wait();
}
