//! A count-down latch: a thread waits until `n` jobs have each counted down once.
//!
//! The count is an atomic so that finishing a job costs one atomic subtraction; the mutex and
//! condition variable are touched only by the job that brings the count to zero and by a
//! waiter that has to sleep. `done` is set under the lock, and the waiter checks it under the
//! lock before sleeping, so the final notification cannot be missed.
//!
//! Memory ordering: each job's `count_down` is a release (`AcqRel`) subtraction and the
//! waiter's `is_done` an acquire load, so whatever a job wrote before counting down (its
//! result) is visible to the waiter once it sees zero.

use std::sync::atomic::{AtomicUsize, Ordering};

use parking_lot::{Condvar, Mutex};

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
