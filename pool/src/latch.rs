//! A count-down latch: a thread waits until `n` jobs have each counted down once.
//!
//! The count is an atomic so that finishing a job costs one atomic subtraction; the mutex and
//! condition variable are touched only by the job that brings the count to zero and by the
//! waiter's `wait` (once, if the count is already zero; a helping worker polls `is_done` and
//! calls `wait` only at the end). `done` is set under the lock, and the waiter checks it under
//! the lock before sleeping, so the final notification cannot be missed.
//!
//! Memory ordering: each job's `count_down` is a release (`AcqRel`) subtraction and the
//! waiter's `is_done` an acquire load, so whatever a job wrote before counting down (its
//! result) is visible to the waiter once it sees zero.

use std::sync::atomic::Ordering;

use crate::sync::{AtomicUsize, Condvar, Mutex};

pub(crate) struct CountLatch {
    remaining: AtomicUsize,
    done: Mutex<bool>,
    released: Condvar,
}

impl CountLatch {
    pub(crate) fn new(count: usize) -> CountLatch {
        CountLatch {
            remaining: AtomicUsize::new(count),
            done: Mutex::new(count == 0),
            released: Condvar::new(),
        }
    }

    /// One job finished.
    pub(crate) fn count_down(&self) {
        let before = self.remaining.fetch_sub(1, Ordering::AcqRel);
        debug_assert!(before > 0, "counted down more times than it was set to");
        if before == 1 {
            *self.done.lock() = true;
            self.released.notify_all();
        }
    }

    /// Whether every job has counted down.
    pub(crate) fn is_done(&self) -> bool {
        self.remaining.load(Ordering::Acquire) == 0
    }

    /// Blocks until every job has counted down.
    pub(crate) fn wait(&self) {
        let mut done = self.done.lock();
        while !*done {
            self.released.wait(&mut done);
        }
    }
}

/// Loom models of the latch (`.ci/run` runs them; see `sync.rs`).
#[cfg(all(test, loom))]
mod model {
    use std::sync::Arc;
    use std::sync::atomic::Ordering::Relaxed;

    use super::CountLatch;
    use crate::sync::{AtomicUsize, thread};

    /// Two jobs each write a result (a relaxed store, like any plain write) and count down.
    fn two_jobs() -> (Arc<CountLatch>, Arc<[AtomicUsize; 2]>) {
        let latch = Arc::new(CountLatch::new(2));
        let results = Arc::new([AtomicUsize::new(0), AtomicUsize::new(0)]);
        for i in 0..2 {
            let (latch, results) = (Arc::clone(&latch), Arc::clone(&results));
            thread::spawn(move || {
                results[i].store(i + 1, Relaxed);
                latch.count_down();
            });
        }
        (latch, results)
    }

    /// A sleeping waiter wakes once both have counted down, and sees both results.
    #[test]
    fn model_a_waiter_sees_every_result() {
        loom::model(|| {
            let (latch, results) = two_jobs();
            latch.wait();
            assert_eq!([results[0].load(Relaxed), results[1].load(Relaxed)], [1, 2]);
        });
    }

    /// A helping waiter polls `is_done` instead of sleeping; the same holds.
    #[test]
    fn model_a_polling_waiter_sees_every_result() {
        loom::model(|| {
            let (latch, results) = two_jobs();
            while !latch.is_done() {
                thread::yield_now();
            }
            assert_eq!([results[0].load(Relaxed), results[1].load(Relaxed)], [1, 2]);
        });
    }
}
