//! Sleeping without losing a wake-up, for queues that have no blocking `pop` of their own.
//!
//! The work-stealing queue has one deque per worker, so no single lock or channel can tell a
//! worker "a job arrived somewhere". An idle worker must sleep, and a pusher must wake it,
//! without this race: the worker finds nothing, a job is pushed and a wake-up sent to nobody,
//! and only then does the worker fall asleep, with a job waiting.
//!
//! The protocol (each side writes its own counter, then a `SeqCst` fence, then reads the
//! other side's: Dekker's pattern):
//!
//! ```text
//!   sleeper                                pusher
//!   lock                                   work_count += 1     (publish the job)
//!   sleepers += 1                          fence(SeqCst)
//!   fence(SeqCst)                          if sleepers > 0:
//!   if work_count == 0 and not closed:         lock; notify; unlock
//!       wait (unlocks while asleep)
//!   sleepers -= 1; unlock
//! ```
//!
//! The two fences are ordered one way or the other. If the sleeper's comes first, the pusher
//! reads `sleepers` ≥ 1 and takes the lock, which it can only get once the sleeper is waiting
//! (or has not started to), and its notify wakes it. If the pusher's comes first, the
//! sleeper's check sees the job and does not wait. Pushers pay for the lock only while
//! someone sleeps.
//!
//! **Invariant:** a sleeper registers (`sleepers += 1`) *before* it looks for work. Swap those
//! two lines and the first case above breaks: the pusher can read 0 sleepers in the instant
//! between the sleeper's look and its registration, notify nobody, and the sleeper then
//! sleeps beside a job. `model_a_pusher_wakes_one_sleeper` below finds that interleaving.
//!
//! **Why fences, not just `SeqCst` loads.** `SeqCst` on every load and store also rules the
//! race out on real hardware (all `SeqCst` operations have one total order). But loom, the
//! model checker, treats a `SeqCst` load as an acquire load (loom issue #180) and would report
//! a lost wake-up that cannot happen. With fences, the argument above needs of `fence(SeqCst)`
//! only what the C++ memory model (which Rust's follows) promises: the two fences fall in one
//! total order, and a load after the later fence reads the store made before the earlier
//! fence, or a later one.
//!
//! **What loom checks here, and what it does not.** loom 0.7 models a `SeqCst` fence more
//! strongly than C++ does: besides acting as an acquire and a release fence, each one joins
//! its thread's history to one global clock that every later `SeqCst` fence joins back
//! (`fence_seqcst` in loom's `src/rt/atomic.rs`), so a later fence *happens after* every
//! earlier one, in whatever thread. C++ gives no such happens-before edge between the fences'
//! threads, only the ordering of the paragraph above. So the models check that no wake-up is
//! lost with that stronger fence, in every interleaving of their two or three threads up to
//! `LOOM_MAX_PREEMPTIONS` forced switches. They do not check that C++'s weaker fence is
//! enough: that rests on the two-case argument above, which uses only the property both
//! share, for the one pair of atomics the protocol reads across (`sleepers`, `work_count`).
//! Code that leaned on a fence for more (publishing other data through it, with no release
//! and acquire on the data's own path) could pass loom and fail on hardware; nothing here
//! does. Nor do the models cover more threads or switches than they run.
//!
//! **Cost.** One `fence(SeqCst)` per push (an `mfence` on x86), and one per trip to sleep.
//! Its own cost was not measured. What was measured (`results/pool-mutants-history.md`, "The
//! pool's speed"): the whole change that introduced it (the count moved under the deque's
//! lock, and the fences) against its parent, alternating pairs of Criterion medians for
//! 100,000 empty jobs on 2 workers: no slowdown of that change showed above the noise of the
//! unchanged control (rayon) between the two builds, and no more than that was shown.

use std::sync::atomic::Ordering::SeqCst;

use crate::sync::{AtomicUsize, Condvar, Mutex, fence};

/// The protocol's state; `Sleep::default()` is a new one (nobody asleep).
#[derive(Default)]
pub(crate) struct Sleep {
    lock: Mutex<()>,
    wake: Condvar,
    /// Threads inside `sleep_unless` (checking or waiting).
    sleepers: AtomicUsize,
}

impl Sleep {
    /// Sleeps until woken, unless `has_work()` is already true. `has_work` must read the
    /// atomics that the waking side writes *before* it calls [`Sleep::wake_one`] or
    /// [`Sleep::wake_all`]. May return spuriously: callers loop.
    pub(crate) fn sleep_unless(&self, has_work: impl Fn() -> bool) {
        let mut guard = self.lock.lock();
        self.sleepers.fetch_add(1, SeqCst);
        fence(SeqCst);
        if !has_work() {
            self.wake.wait(&mut guard);
        }
        self.sleepers.fetch_sub(1, SeqCst);
    }

    /// Wakes one sleeper, if any (after one job was published).
    pub(crate) fn wake_one(&self) {
        if self.anyone_asleep() {
            let _guard = self.lock.lock();
            self.wake.notify_one();
        }
    }

    /// Wakes every sleeper (after many jobs were published, or on shutdown).
    pub(crate) fn wake_all(&self) {
        if self.anyone_asleep() {
            let _guard = self.lock.lock();
            self.wake.notify_all();
        }
    }

    /// The pusher's half of the protocol: its job is published, now look for sleepers.
    fn anyone_asleep(&self) -> bool {
        fence(SeqCst);
        self.sleepers.load(SeqCst) > 0
    }
}

/// Loom models: every interleaving of a pusher against sleepers (`.ci/run` runs them; see
/// `sync.rs`). A lost wake-up leaves a sleeper waiting forever, which loom reports as a
/// deadlock, with the interleaving that led there.
#[cfg(all(test, loom))]
mod model {
    use std::sync::Arc;
    use std::sync::atomic::Ordering::SeqCst;

    use super::Sleep;
    use crate::sync::{AtomicUsize, thread};

    /// A sleep protocol and a count of published jobs, as a queue would hold them.
    #[derive(Default)]
    struct Queue {
        sleep: Sleep,
        jobs: AtomicUsize,
    }

    impl Queue {
        fn push(&self) {
            self.jobs.fetch_add(1, SeqCst);
            self.sleep.wake_one();
        }

        /// A worker's loop: take a job if there is one, else sleep until there may be.
        fn take(&self) {
            loop {
                let taken = self.jobs.fetch_update(SeqCst, SeqCst, |n| n.checked_sub(1));
                if taken.is_ok() {
                    return;
                }
                self.sleep.sleep_unless(|| self.jobs.load(SeqCst) > 0);
            }
        }
    }

    #[test]
    fn model_a_pusher_wakes_one_sleeper() {
        loom::model(|| {
            let queue = Arc::new(Queue::default());
            let worker = thread::spawn({
                let queue = Arc::clone(&queue);
                move || queue.take()
            });
            queue.push();
            worker.join().unwrap();
        });
    }

    #[test]
    fn model_a_pusher_wakes_two_sleepers() {
        loom::model(|| {
            let queue = Arc::new(Queue::default());
            let workers: Vec<_> = (0..2)
                .map(|_| {
                    let queue = Arc::clone(&queue);
                    thread::spawn(move || queue.take())
                })
                .collect();
            queue.push();
            queue.push();
            workers.into_iter().for_each(|w| w.join().unwrap());
        });
    }
}
