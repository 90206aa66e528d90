//! Part 2: a queue discipline for raypool's thread pool, "steal half".
//!
//! Each worker owns a deque. A worker pops jobs from the *front* of its own deque; when it
//! is empty, it takes the *back half* of another worker's deque at once (running one of those
//! jobs, keeping the rest in its own deque), so that it steals less often than raypool's
//! `Stealing` discipline, which takes one job per theft. A thread that is not a worker
//! (`me == None`) pushes to the deques in turn.
//!
//! The pool calls these five methods; read `pool/src/queue.rs` for their contract and
//! `pool/src/steal.rs` for one way to keep it. The hard part is sleeping: a worker with
//! nothing to do must block (on a `Condvar`), never spin, and must never sleep through a
//! push or a `close` (a lost wake-up hangs the pool). Hint: count the queued jobs under one
//! `Mutex` with the `Condvar`; a worker that decrements that count has claimed a job that
//! is certainly in some deque.

use pool::{Job, JobQueue, Popped};

/// One deque per worker; an idle worker steals half of a victim's jobs.
pub struct StealHalf {
    // Your fields.
}

impl StealHalf {
    /// The queue of a pool of `workers` workers.
    pub fn new(_workers: usize) -> StealHalf {
        todo!("one deque per worker, and what a worker needs to sleep")
    }
}

impl JobQueue for StealHalf {
    fn push(&self, _job: Job, _me: Option<usize>) {
        todo!("a worker pushes to its own deque; another thread to the deques in turn; wake a sleeper")
    }

    fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
        todo!("a job if one is queued (own deque first, else steal half), without blocking")
    }

    fn wait_pop(&self, _me: usize) -> Option<Popped> {
        todo!("like try_pop, but sleep while nothing is queued; None once closed and empty")
    }

    fn close(&self) {
        todo!("no more pushes from the owner: wake every sleeper so each drains and exits")
    }
}

/// How the pool makes this queue (what `pool::ThreadPool::builder().queue(…)` takes).
pub fn make(workers: usize) -> Box<dyn JobQueue> {
    Box::new(StealHalf::new(workers))
}
