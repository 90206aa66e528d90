//! The synchronisation types of the crate, named in one place so that a model checker can
//! swap them.
//!
//! Every mutex, condition variable, atomic, thread and thread-local of the pool comes from
//! here. In a normal build they are the ones the pool has always used: `parking_lot`'s
//! `Mutex` and `Condvar`, `std`'s atomics and threads. Built with `RUSTFLAGS="--cfg loom"`,
//! they are [loom](https://docs.rs/loom)'s instead: loom runs a small test many times, once
//! for every way its threads can interleave (bounded by `LOOM_MAX_PREEMPTIONS`), and fails
//! with the interleaving that breaks an assertion or leaves every thread blocked (a lost
//! wake-up shows up as loom's "deadlock"). The rest of the crate never knows which it got.
//! This is how tokio (`src/loom/`) and crossbeam (`crossbeam-utils/src/sync/`) check their
//! synchronisation.
//!
//! Loom's `Mutex` and `Condvar` have `std`'s interface (`lock()` returns a `Result`, `wait`
//! takes the guard by value); the small wrappers below give them `parking_lot`'s (`lock()`
//! returns the guard, `wait(&mut guard)`), which is the one the pool is written against.
//!
//! Not swapped: `Arc` (loom's only adds leak checks) and crossbeam's channel, which loom
//! cannot see inside; the `Shared` queue is therefore not model-checked (`pool/tests/loom.rs`
//! says why, and what covers it instead).
//!
//! ```text
//!   cargo test -p pool                                    parking_lot + std, real threads
//!   RUSTFLAGS="--cfg loom" cargo test -p pool --lib ...   loom, every interleaving
//! ```

#[cfg(not(loom))]
pub(crate) use parking_lot::{Condvar, Mutex};
#[cfg(not(loom))]
pub(crate) use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, fence};
#[cfg(not(loom))]
pub(crate) use std::thread::{self, JoinHandle};
#[cfg(not(loom))]
pub(crate) use std::thread_local;

#[cfg(loom)]
pub(crate) use loom::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, fence};
#[cfg(loom)]
pub(crate) use loom::thread::{self, JoinHandle};
#[cfg(loom)]
pub(crate) use loom::thread_local;
#[cfg(loom)]
pub(crate) use loom_locks::{Condvar, Mutex};

/// Loom's mutex and condition variable behind `parking_lot`'s interface.
#[cfg(loom)]
mod loom_locks {
    use std::ops::{Deref, DerefMut};

    /// A mutex that never poisons: a panic while locked is a failed model anyway.
    #[derive(Debug, Default)]
    pub(crate) struct Mutex<T>(loom::sync::Mutex<T>);

    /// Holds the lock; `None` only for the instant `Condvar::wait` hands it to loom.
    pub(crate) struct MutexGuard<'a, T>(Option<loom::sync::MutexGuard<'a, T>>);

    impl<T> Mutex<T> {
        pub(crate) fn new(value: T) -> Mutex<T> {
            Mutex(loom::sync::Mutex::new(value))
        }

        #[track_caller]
        pub(crate) fn lock(&self) -> MutexGuard<'_, T> {
            MutexGuard(Some(self.0.lock().expect("loom mutexes poison only after a failed model")))
        }
    }

    impl<T> Deref for MutexGuard<'_, T> {
        type Target = T;
        fn deref(&self) -> &T {
            self.0.as_ref().expect("the guard holds the lock")
        }
    }

    impl<T> DerefMut for MutexGuard<'_, T> {
        fn deref_mut(&mut self) -> &mut T {
            self.0.as_mut().expect("the guard holds the lock")
        }
    }

    #[derive(Debug, Default)]
    pub(crate) struct Condvar(loom::sync::Condvar);

    impl Condvar {
        pub(crate) fn new() -> Condvar {
            Condvar(loom::sync::Condvar::new())
        }

        /// Releases the guard's lock, sleeps until notified, and takes the lock again.
        #[track_caller]
        pub(crate) fn wait<T>(&self, guard: &mut MutexGuard<'_, T>) {
            let held = guard.0.take().expect("the guard holds the lock");
            guard.0 = Some(self.0.wait(held).expect("loom mutexes poison only after a failed model"));
        }

        pub(crate) fn notify_one(&self) {
            self.0.notify_one();
        }

        pub(crate) fn notify_all(&self) {
            self.0.notify_all();
        }
    }
}
