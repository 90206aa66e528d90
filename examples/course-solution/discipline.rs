//! Part 2, solved (the instructor's copy: not for the students' folder).
//!
//! Jobs live in per-worker deques; *how many* are queued lives in one counter beside the
//! condition variable the workers sleep on. That counter is the whole sleep protocol:
//! - `push` puts the job in a deque first, then raises the count and wakes one sleeper;
//! - a worker sleeps only while the count is 0 (checked and slept on under one lock: no
//!   lost wake-up), and takes a job by lowering the count first, which *claims* one of the
//!   jobs certainly sitting in some deque; then it looks for it: its own deque's front, else
//!   another's back half, keeping all but one of the stolen jobs in its own deque.
//!
//! Invariant: queued jobs (in deques) ≥ count ≥ 0, and every claim finds a job. A claimer may
//! look twice while a thief carries jobs between two deques (neither holds them for a
//! moment); it never sleeps with a job queued, and never spins with nothing queued.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};

use pool::{Job, JobQueue, Popped};

/// One deque per worker; an idle worker steals half of a victim's jobs.
pub struct StealHalf {
    deques: Vec<Mutex<VecDeque<Job>>>,
    /// Jobs queued and not yet claimed, and whether the queue is closed.
    count: Mutex<(usize, bool)>,
    available: Condvar,
    /// Where the next push from outside the pool goes.
    next: AtomicUsize,
}

impl StealHalf {
    /// The queue of a pool of `workers` workers.
    pub fn new(workers: usize) -> StealHalf {
        StealHalf {
            deques: (0..workers.max(1)).map(|_| Mutex::new(VecDeque::new())).collect(),
            count: Mutex::new((0, false)),
            available: Condvar::new(),
            next: AtomicUsize::new(0),
        }
    }

    /// Takes a claimed job: own deque first, then half of another's.
    fn take(&self, me: Option<usize>) -> Popped {
        let n = self.deques.len();
        loop {
            if let Some(job) = me.and_then(|me| self.deques[me].lock().unwrap().pop_front()) {
                return Popped { job, stolen: false };
            }
            let start = me.map_or(0, |me| me + 1);
            for victim in (start..start + n).map(|v| v % n).filter(|&v| Some(v) != me) {
                let mut deque = self.deques[victim].lock().unwrap();
                let Some(job) = deque.pop_back() else { continue };
                if let Some(me) = me {
                    let keep = deque.len() / 2;
                    let half: Vec<Job> = deque.drain(keep..).collect();
                    drop(deque); // never hold two deques' locks at once
                    self.deques[me].lock().unwrap().extend(half);
                }
                return Popped { job, stolen: true };
            }
        }
    }
}

impl JobQueue for StealHalf {
    fn push(&self, job: Job, me: Option<usize>) {
        let k = me.unwrap_or_else(|| self.next.fetch_add(1, Ordering::Relaxed) % self.deques.len());
        self.deques[k].lock().unwrap().push_back(job);
        self.count.lock().unwrap().0 += 1;
        self.available.notify_one();
    }

    fn try_pop(&self, me: Option<usize>) -> Option<Popped> {
        {
            let mut count = self.count.lock().unwrap();
            if count.0 == 0 {
                return None;
            }
            count.0 -= 1;
        }
        Some(self.take(me))
    }

    fn wait_pop(&self, me: usize) -> Option<Popped> {
        {
            let mut count = self.count.lock().unwrap();
            while count.0 == 0 {
                if count.1 {
                    return None;
                }
                count = self.available.wait(count).unwrap();
            }
            count.0 -= 1;
        }
        Some(self.take(Some(me)))
    }

    fn close(&self) {
        self.count.lock().unwrap().1 = true;
        self.available.notify_all();
    }
}

/// How the pool makes this queue (what `pool::ThreadPool::builder().queue(…)` takes).
pub fn make(workers: usize) -> Box<dyn JobQueue> {
    Box::new(StealHalf::new(workers))
}
