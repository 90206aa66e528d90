//! Sleeping without losing a wake-up, for queues that have no blocking `pop` of their own.
//!
//! The work-stealing queue has one deque per worker, so no single lock or channel can tell a
//! worker "a job arrived somewhere". An idle worker must sleep, and a pusher must wake it,
//! without this race: the worker finds nothing, a job is pushed and a wake-up sent to nobody,
//! and only then does the worker fall asleep, with a job waiting.
//!
//! The protocol (all atomics `SeqCst`, so all threads agree on one order of these steps):
//!
//! ```text
//!   sleeper                                pusher
//!   lock                                   work_count += 1     (publish the job)
//!   sleepers += 1                          if sleepers > 0:
//!   if work_count == 0 and not closed:         lock; notify; unlock
//!       wait (unlocks while asleep)
//!   sleepers -= 1; unlock
//! ```
//!
//! Either the pusher reads `sleepers` after the sleeper incremented it (then it takes the
//! lock, which it can only get once the sleeper is waiting, and its notify wakes it), or
//! before (then its own `work_count += 1` came earlier still, and the sleeper's check sees
//! the job and does not wait). Pushers pay for the lock only while someone sleeps.

use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};

use parking_lot::{Condvar, Mutex};

pub(crate) struct Sleep {
    lock: Mutex<()>,
    wake: Condvar,
    /// Threads inside `sleep_unless` (checking or waiting).
    sleepers: AtomicUsize,
}

impl Sleep {
    pub(crate) fn new() -> Sleep {
        Sleep { lock: Mutex::new(()), wake: Condvar::new(), sleepers: AtomicUsize::new(0) }
    }

    /// Sleeps until woken, unless `has_work()` (which must read `SeqCst` atomics that the
    /// waking side writes before calling [`Sleep::wake_one`] or [`Sleep::wake_all`]) is
    /// already true. May return spuriously: callers loop.
    pub(crate) fn sleep_unless(&self, has_work: impl Fn() -> bool) {
        let mut guard = self.lock.lock();
        self.sleepers.fetch_add(1, SeqCst);
        if !has_work() {
            self.wake.wait(&mut guard);
        }
        self.sleepers.fetch_sub(1, SeqCst);
    }

    /// Wakes one sleeper, if any (after one job was published).
    pub(crate) fn wake_one(&self) {
        if self.sleepers.load(SeqCst) > 0 {
            let _guard = self.lock.lock();
            self.wake.notify_one();
        }
    }

    /// Wakes every sleeper (after many jobs were published, or on shutdown).
    pub(crate) fn wake_all(&self) {
        if self.sleepers.load(SeqCst) > 0 {
            let _guard = self.lock.lock();
            self.wake.notify_all();
        }
    }
}
