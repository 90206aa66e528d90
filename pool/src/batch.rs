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

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::Arc;
use std::thread;

use crate::latch::CountLatch;
use crate::pool::ThreadPool;
use crate::queue::Job;
use crate::sync::Mutex;
use crate::worker::Registry;

/// Where a batch's jobs leave their results, one slot each.
type Slots<T> = Vec<Mutex<Option<thread::Result<T>>>>;

impl ThreadPool {
    /// Runs every job of `jobs` on the pool and returns their results in submission order.
    ///
    /// May be called from inside a job (a nested batch): a worker that waits runs other
    /// queued jobs meanwhile, so nesting cannot deadlock the pool (see the module docs).
    ///
    /// # Panics
    /// If a job panics, `batch` waits for all the others, then re-raises the first panic
    /// (in submission order). The pool and its workers are unaffected.
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// let pool = ThreadPool::new(3, Discipline::Stealing).unwrap();
    /// let squares = pool.batch((0..10u64).map(|i| move || i * i));
    /// assert_eq!(squares, (0..10).map(|i| i * i).collect::<Vec<_>>());
    /// ```
    pub fn batch<T, F, I>(&self, jobs: I) -> Vec<T>
    where
        I: IntoIterator<Item = F>,
        F: FnOnce() -> T + Send + 'static,
        T: Send + 'static,
    {
        let jobs: Vec<F> = jobs.into_iter().collect();
        let slots: Arc<Slots<T>> = Arc::new(jobs.iter().map(|_| Mutex::new(None)).collect());
        let latch = Arc::new(CountLatch::new(jobs.len()));
        let wrapped: Vec<Job> = jobs
            .into_iter()
            .enumerate()
            .map(|(i, job)| {
                let slots = Arc::clone(&slots);
                let body = move || *slots[i].lock() = Some(catch_unwind(AssertUnwindSafe(job)));
                // The worker counts the latch down after recording the job (see worker.rs).
                Job { body: Box::new(body), latch: Some(Arc::clone(&latch)) }
            })
            .collect();
        let registry = &self.registry;
        let me = registry.current_worker();
        registry.queue.push_batch(wrapped, me);
        wait(registry, me, &latch);
        let results: Vec<_> =
            slots.iter().map(|slot| slot.lock().take().expect("every job stored a result")).collect();
        results.into_iter().map(|r| r.unwrap_or_else(|panic| resume_unwind(panic))).collect()
    }
}

/// Waits for `latch` by the waiting rule: worker `me` helps, other threads sleep.
fn wait(registry: &Arc<Registry>, me: Option<usize>, latch: &CountLatch) {
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
