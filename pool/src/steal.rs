//! The work-stealing queue: one deque per worker, and idle workers steal from busy ones.
//!
//! ```text
//!   batch of 12 jobs, 3 workers: dealt out in contiguous runs
//!   worker 0: [ 0  1  2  3 ]   takes from the front: 0, 1, 2…
//!   worker 1: [ 4  5  6  7 ]
//!   worker 2: [ 8  9 10 11 ]   ← worker 2 finished early: tries worker 0 first (the one
//!                                after it, wrapping round) and steals 3 from its back
//! ```
//!
//! Two roles, two methods, named as crossbeam-deque names them: the owner *pops* its own jobs
//! from the front of its deque, in the order they were dealt (`pop`); a thief *steals* from
//! the back of a victim's deque, the job its owner would reach last (`steal`), so owner and
//! thief work at opposite ends and a run is split where it hurts least.
//!
//! Each deque is a `parking_lot::Mutex<VecDeque>`: a lock per deque rather than the lock-free
//! Chase–Lev deque of rayon and crossbeam-deque, because this crate is safe Rust and a lesson.
//! The owner's lock is almost never contended (thieves come only when they ran dry), which is
//! what makes per-worker deques scale where one shared queue does not.
//!
//! Invariants:
//! - `work_count` is the number of jobs in all deques. It changes only under the lock of the
//!   deque that changes, in the same critical section, so a job is never "in flight": once
//!   counted it can be popped, and once popped it is no longer counted.
//! - So a worker that reads `work_count > 0` and then finds every deque empty has lost a race
//!   to another worker that took the job; retrying cannot spin for longer than others make
//!   progress. A worker that reads 0 has nothing to miss, and may sleep (`sleep.rs`).
//! - A worker exits only when the queue is closed and `work_count` is 0.

use std::collections::VecDeque;
use std::sync::atomic::Ordering::SeqCst;

use crate::queue::{Job, JobQueue, Popped};
use crate::sleep::Sleep;
use crate::sync::{AtomicBool, AtomicUsize, Mutex};

pub(crate) struct StealQueue {
    deques: Vec<Mutex<VecDeque<Job>>>,
    /// The number of jobs in all deques (see the invariants above).
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
            sleep: Sleep::default(),
        }
    }

    /// Appends `jobs` to deque `target` and counts them, under that deque's lock.
    fn land(&self, target: usize, jobs: impl IntoIterator<Item = Job>) {
        let mut deque = self.deques[target].lock();
        let before = deque.len();
        deque.extend(jobs);
        self.work_count.fetch_add(deque.len() - before, SeqCst);
    }

    /// The owner's role: worker `me` takes the job at the *front* of its own deque (the next
    /// in the order they were dealt) and uncounts it, under that deque's lock.
    fn pop(&self, me: usize) -> Option<Job> {
        let mut deque = self.deques[me].lock();
        let job = deque.pop_front()?;
        self.work_count.fetch_sub(1, SeqCst);
        Some(job)
    }

    /// The thief's role: takes the job at the *back* of deque `victim` (the one its owner
    /// would reach last) and uncounts it, under that deque's lock.
    fn steal(&self, victim: usize) -> Option<Job> {
        let mut deque = self.deques[victim].lock();
        let job = deque.pop_back()?;
        self.work_count.fetch_sub(1, SeqCst);
        Some(job)
    }

    /// Steals from the other deques in turn, starting with the next worker's so that
    /// thieves spread over victims instead of all raiding worker 0.
    fn steal_from_others(&self, me: Option<usize>) -> Option<Job> {
        let n = self.deques.len();
        let start = me.map_or(0, |m| m + 1);
        (0..n).map(|k| (start + k) % n).filter(|&v| Some(v) != me).find_map(|v| self.steal(v))
    }
}

impl JobQueue for StealQueue {
    fn push(&self, job: Job, me: Option<usize>) {
        let target = me.unwrap_or_else(|| self.next_deque.fetch_add(1, SeqCst) % self.deques.len());
        self.land(target, [job]);
        self.sleep.wake_one();
    }

    /// Deals the batch out in `workers` contiguous runs, run `k` to worker `k`'s deque.
    fn push_batch(&self, jobs: Vec<Job>, _me: Option<usize>) {
        let (total, n) = (jobs.len(), self.deques.len());
        let mut jobs = jobs.into_iter();
        for k in 0..n {
            let run = (k + 1) * total / n - k * total / n;
            self.land(k, jobs.by_ref().take(run));
        }
        debug_assert!(jobs.next().is_none(), "every job was dealt");
        self.sleep.wake_all();
    }

    fn try_pop(&self, me: Option<usize>) -> Option<Popped> {
        match me.and_then(|m| self.pop(m)) {
            Some(job) => Some(Popped { job, stolen: false }),
            None => Some(Popped { job: self.steal_from_others(me)?, stolen: true }),
        }
    }

    fn wait_pop(&self, me: usize) -> Option<Popped> {
        loop {
            if let Some(popped) = self.try_pop(Some(me)) {
                return Some(popped);
            }
            if self.closed.load(SeqCst) && self.work_count.load(SeqCst) == 0 {
                return None;
            }
            // A job counted after this worker looked in its deque: retry instead of sleeping.
            self.sleep.sleep_unless(|| self.work_count.load(SeqCst) > 0 || self.closed.load(SeqCst));
        }
    }

    fn close(&self) {
        self.closed.store(true, SeqCst);
        self.sleep.wake_all();
    }
}

#[cfg(all(test, not(loom)))]
mod tests {
    use super::StealQueue;
    use crate::queue::{Job, JobQueue};

    /// A batch is dealt in contiguous runs whose lengths differ by at most one, in order.
    #[test]
    fn a_batch_is_dealt_in_contiguous_runs() {
        for (workers, jobs, runs) in [(3, 7, vec![2, 2, 3]), (4, 2, vec![0, 1, 0, 1]), (2, 10, vec![5, 5])] {
            let queue = StealQueue::new(workers);
            queue.push_batch((0..jobs).map(|_| Job::detached(|| ())).collect(), None);
            let lengths: Vec<usize> = queue.deques.iter().map(|d| d.lock().len()).collect();
            assert_eq!(lengths, runs, "{jobs} jobs on {workers} workers");
            assert_eq!(queue.work_count.load(std::sync::atomic::Ordering::SeqCst), jobs);
        }
    }
}

/// Loom models of the stealing queue (`.ci/run` runs them; see `sync.rs`).
#[cfg(all(test, loom))]
mod model {
    use std::sync::Arc;
    use std::sync::atomic::Ordering::SeqCst;

    use super::StealQueue;
    use crate::queue::JobQueue;
    use crate::queue::model::{Runs, run_until_none, two_workers_drain_then_exit};
    use crate::sync::thread;

    /// Worker 0 pops its own deque's front while worker 1 steals from its back.
    #[test]
    fn model_owner_and_thief_run_each_job_once() {
        loom::model(|| {
            let queue = Arc::new(StealQueue::new(2));
            let runs = Runs::new(2);
            queue.push(runs.job(0), Some(0));
            queue.push(runs.job(1), Some(0));
            let thief = thread::spawn({
                let queue = Arc::clone(&queue);
                move || run_until_none(|| queue.try_pop(Some(1)))
            });
            run_until_none(|| queue.try_pop(Some(0)));
            thief.join().unwrap();
            runs.assert_each_ran_once();
            assert_eq!(queue.work_count.load(SeqCst), 0, "work_count counts what is queued");
        });
    }

    #[test]
    fn model_workers_run_every_job_and_exit_on_close() {
        loom::model(|| two_workers_drain_then_exit(Arc::new(StealQueue::new(2))));
    }
}
