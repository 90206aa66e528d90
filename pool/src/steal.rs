//! The work-stealing queue: one deque per worker, and idle workers steal from busy ones.
//!
//! ```text
//!   batch of 12 jobs, 3 workers: dealt out in contiguous runs
//!   worker 0: [ 0  1  2  3 ]   takes from the front: 0, 1, 2…
//!   worker 1: [ 4  5  6  7 ]
//!   worker 2: [ 8  9 10 11 ]   ← worker 2 finished early: steals 7 from worker 1's back
//! ```
//!
//! A worker takes its own jobs from the front of its deque, in the order they were dealt;
//! a thief takes from the *back* of a victim's deque, the job its owner would reach last,
//! so owner and thief work at opposite ends and a run is split where it hurts least.
//!
//! Each deque is a `parking_lot::Mutex<VecDeque>`: a lock per deque rather than the lock-free
//! Chase–Lev deque of rayon and crossbeam-deque, because this crate is safe Rust and a lesson.
//! The owner's lock is almost never contended (thieves come only when they ran dry), which is
//! what makes per-worker deques scale where one shared queue does not.
//!
//! Invariants: `work_count` ≥ the number of jobs in all deques (it is raised *before* a job is
//! pushed and lowered *after* one is popped), so a sleeper that sees 0 really has nothing to
//! miss; a worker exits only when the queue is closed and `work_count` is 0.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::SeqCst};

use parking_lot::Mutex;

use crate::queue::{Job, JobQueue, Popped};
use crate::sleep::Sleep;

pub(crate) struct StealQueue {
    deques: Vec<Mutex<VecDeque<Job>>>,
    /// Upper bound of the jobs queued in all deques (see the invariants above).
    work_count: AtomicUsize,
    closed: AtomicBool,
    /// Where the next job from a non-worker thread goes (round robin).
    next_deque: AtomicUsize,
    sleep: Sleep,
}

impl StealQueue {
    pub(crate) fn new(workers: usize) -> StealQueue {
        StealQueue {
            deques: (0..workers).map(|_| Mutex::new(VecDeque::new())).collect(),
            work_count: AtomicUsize::new(0),
            closed: AtomicBool::new(false),
            next_deque: AtomicUsize::new(0),
            sleep: Sleep::new(),
        }
    }

    fn pop_own(&self, me: usize) -> Option<Job> {
        self.deques[me].lock().pop_front()
    }

    /// Steals from the back of the other deques, starting with the next worker's so that
    /// thieves spread over victims instead of all raiding worker 0.
    fn steal(&self, me: Option<usize>) -> Option<Job> {
        let n = self.deques.len();
        let start = me.map_or(0, |m| m + 1);
        (0..n)
            .map(|k| (start + k) % n)
            .filter(|&v| Some(v) != me)
            .find_map(|v| self.deques[v].lock().pop_back())
    }
}

impl JobQueue for StealQueue {
    fn push(&self, job: Job, me: Option<usize>) {
        let target = me.unwrap_or_else(|| self.next_deque.fetch_add(1, SeqCst) % self.deques.len());
        self.work_count.fetch_add(1, SeqCst);
        self.deques[target].lock().push_back(job);
        self.sleep.wake_one();
    }

    /// Deals the batch out in `workers` contiguous runs, run `k` to worker `k`'s deque.
    fn push_batch(&self, jobs: Vec<Job>, _me: Option<usize>) {
        let (total, n) = (jobs.len(), self.deques.len());
        self.work_count.fetch_add(total, SeqCst);
        let mut jobs = jobs.into_iter();
        for (k, deque) in self.deques.iter().enumerate() {
            let run = (k + 1) * total / n - k * total / n;
            deque.lock().extend(jobs.by_ref().take(run));
        }
        debug_assert!(jobs.next().is_none(), "every job was dealt");
        self.sleep.wake_all();
    }

    fn try_pop(&self, me: Option<usize>) -> Option<Popped> {
        let popped = match me.and_then(|m| self.pop_own(m)) {
            Some(job) => Popped { job, stolen: false },
            None => Popped { job: self.steal(me)?, stolen: true },
        };
        self.work_count.fetch_sub(1, SeqCst);
        Some(popped)
    }

    fn wait_pop(&self, me: usize) -> Option<Popped> {
        loop {
            if let Some(popped) = self.try_pop(Some(me)) {
                return Some(popped);
            }
            if self.closed.load(SeqCst) && self.work_count.load(SeqCst) == 0 {
                return None;
            }
            // A job being pushed raised `work_count` before landing in a deque: if the
            // count is not 0, retry instead of sleeping.
            self.sleep.sleep_unless(|| self.work_count.load(SeqCst) > 0 || self.closed.load(SeqCst));
        }
    }

    fn close(&self) {
        self.closed.store(true, SeqCst);
        self.sleep.wake_all();
    }
}
