//! The locked queue: a `VecDeque` behind one mutex, with a condition variable for sleeping.
//!
//! The textbook pool: a monitor. (The Rust Book's chapter 21 pool shares a channel's receiver
//! behind a mutex; this is the same idea without the channel.) One lock protects both the jobs and the `closed`
//! flag, which is what makes the sleep correct: a worker checks "no job and not closed" and
//! goes to sleep *atomically* with respect to any push or close, because `Condvar::wait`
//! releases the lock only once the worker is registered as waiting. No wake-up is lost.

use std::collections::VecDeque;

use crate::queue::{Job, JobQueue, Popped};
use crate::sync::{Condvar, Mutex};

pub(crate) struct LockedQueue {
    state: Mutex<State>,
    /// Signalled on every push (one waiter) and on close (all waiters).
    available: Condvar,
}

/// Everything the lock protects.
struct State {
    jobs: VecDeque<Job>,
    closed: bool,
}

impl LockedQueue {
    pub(crate) fn new() -> LockedQueue {
        LockedQueue {
            state: Mutex::new(State { jobs: VecDeque::new(), closed: false }),
            available: Condvar::new(),
        }
    }
}

impl JobQueue for LockedQueue {
    fn push(&self, job: Job, _me: Option<usize>) {
        self.state.lock().jobs.push_back(job);
        self.available.notify_one();
    }

    fn push_batch(&self, jobs: Vec<Job>, _me: Option<usize>) {
        self.state.lock().jobs.extend(jobs);
        self.available.notify_all();
    }

    fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
        self.state.lock().jobs.pop_front().map(|job| Popped { job, stolen: false })
    }

    fn wait_pop(&self, _me: usize) -> Option<Popped> {
        let mut state = self.state.lock();
        loop {
            if let Some(job) = state.jobs.pop_front() {
                return Some(Popped { job, stolen: false });
            }
            if state.closed {
                return None;
            }
            self.available.wait(&mut state);
        }
    }

    fn close(&self) {
        self.state.lock().closed = true;
        self.available.notify_all();
    }
}

/// Loom model of the locked queue (`.ci/run` runs it; see `sync.rs`).
#[cfg(all(test, loom))]
mod model {
    use std::sync::Arc;

    use super::LockedQueue;
    use crate::queue::model::two_workers_drain_then_exit;

    #[test]
    fn model_workers_run_every_job_and_exit_on_close() {
        loom::model(|| two_workers_drain_then_exit(Arc::new(LockedQueue::new())));
    }
}
