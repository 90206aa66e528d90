//! Jobs and the queue interface that every queue discipline implements.
//!
//! A *job* is a boxed closure run exactly once by some thread. A *queue discipline* decides
//! where a submitted job waits and which thread takes it. The pool talks to its queue only
//! through [`JobQueue`], so the three disciplines (`shared.rs`, `locked.rs`, `steal.rs`) can be
//! read, and measured, side by side.
//!
//! Invariants every implementation keeps:
//! - a pushed job is popped at most once (no duplication) and, unless the pool is dropped
//!   mid-flight by a panic, exactly once (no loss);
//! - `wait_pop` returns `None` only after `close` *and* once no job is left: dropping a pool
//!   runs what was queued;
//! - an idle worker blocks inside `wait_pop` without spinning.

use std::sync::Arc;

use crate::latch::CountLatch;

/// A unit of work: run once, on some thread.
pub(crate) struct Job {
    /// The work itself.
    pub body: Box<dyn FnOnce() + Send + 'static>,
    /// The batch latch to count down once the job has run *and* been recorded in the
    /// worker's statistics (so a batch's caller always sees complete statistics).
    pub latch: Option<Arc<CountLatch>>,
}

impl Job {
    /// A job that belongs to no batch.
    pub fn detached(body: impl FnOnce() + Send + 'static) -> Job {
        Job { body: Box::new(body), latch: None }
    }
}

/// A job taken from a queue, and whether it was taken from another worker's deque.
pub(crate) struct Popped {
    pub job: Job,
    pub stolen: bool,
}

/// How a [`ThreadPool`](crate::ThreadPool) queues its jobs, chosen at construction.
///
/// ```
/// use pool::{Discipline, ThreadPool};
/// for discipline in Discipline::ALL {
///     let pool = ThreadPool::new(2, discipline).unwrap();
///     assert_eq!(pool.batch((0..4).map(|i| move || i * i)), vec![0, 1, 4, 9]);
/// }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Discipline {
    /// One FIFO shared by all workers: a multi-producer multi-consumer channel. The seed
    /// paper's thread pool. Every push and pop touches the same channel.
    #[default]
    Shared,
    /// One `Mutex<VecDeque>` with a `Condvar`: the textbook monitor-based pool, kept to
    /// compare with the channel.
    Locked,
    /// One deque per worker: a worker takes from the front of its own and, when it is empty,
    /// steals from the back of another's. Batches are dealt out in contiguous runs, so
    /// stealing is what balances an uneven load.
    Stealing,
}

impl Discipline {
    /// Every discipline. The pool's tests (`pool/tests/`) and its benchmark (`cargo bench
    /// --bench pool`) iterate over this list, so a discipline added here is tested and
    /// measured with no other list to edit.
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// for discipline in Discipline::ALL {
    ///     let pool = ThreadPool::new(2, discipline).unwrap();
    ///     assert_eq!(pool.discipline(), discipline);
    /// }
    /// assert_eq!(Discipline::ALL.len(), 3);
    /// ```
    pub const ALL: [Discipline; 3] = [Discipline::Shared, Discipline::Locked, Discipline::Stealing];
}

/// The operations the pool needs from a queue discipline. `me` is the calling worker's
/// index, or `None` for a thread that is not one of the pool's workers.
pub(crate) trait JobQueue: Send + Sync {
    /// Queues one job.
    fn push(&self, job: Job, me: Option<usize>);
    /// Queues many jobs at once (a batch): a discipline may spread them out.
    fn push_batch(&self, jobs: Vec<Job>, me: Option<usize>) {
        for job in jobs {
            self.push(job, me);
        }
    }
    /// Takes a job if one is ready, without blocking.
    fn try_pop(&self, me: Option<usize>) -> Option<Popped>;
    /// Worker `me` takes a job, sleeping while there is none; `None` once closed and empty.
    fn wait_pop(&self, me: usize) -> Option<Popped>;
    /// No more jobs will be pushed by the pool's owner: wake every sleeping worker so that
    /// each can drain the queue and exit.
    fn close(&self);
}

/// What the loom models of every discipline share (`.ci/run` runs them; see `sync.rs`).
#[cfg(all(test, loom))]
pub(crate) mod model {
    use std::sync::Arc;
    use std::sync::atomic::Ordering::SeqCst;

    use super::{Job, JobQueue};
    use crate::sync::{AtomicUsize, thread};

    /// Counts how often each of a few jobs ran.
    pub(crate) struct Runs(Vec<AtomicUsize>);

    impl Runs {
        pub(crate) fn new(jobs: usize) -> Arc<Runs> {
            Arc::new(Runs((0..jobs).map(|_| AtomicUsize::new(0)).collect()))
        }

        /// Job `i`, which counts its run.
        pub(crate) fn job(self: &Arc<Runs>, i: usize) -> Job {
            let runs = Arc::clone(self);
            Job::detached(move || {
                runs.0[i].fetch_add(1, SeqCst);
            })
        }

        pub(crate) fn assert_each_ran_once(&self) {
            let counts: Vec<usize> = self.0.iter().map(|r| r.load(SeqCst)).collect();
            assert!(counts.iter().all(|&c| c == 1), "runs per job: {counts:?}, want 1 each");
        }
    }

    /// Runs jobs from `queue` as `me` until `take` finds none.
    pub(crate) fn run_until_none(take: impl Fn() -> Option<super::Popped>) {
        while let Some(popped) = take() {
            (popped.job.body)();
        }
    }

    /// Two workers wait for jobs; the owner pushes two and closes the queue. Every job runs
    /// exactly once, and both workers return (none sleeps through the close).
    pub(crate) fn two_workers_drain_then_exit(queue: Arc<dyn JobQueue>) {
        let runs = Runs::new(2);
        let workers: Vec<_> = (0..2)
            .map(|me| {
                let queue = Arc::clone(&queue);
                thread::spawn(move || run_until_none(|| queue.wait_pop(me)))
            })
            .collect();
        queue.push(runs.job(0), None);
        queue.push(runs.job(1), None);
        queue.close();
        workers.into_iter().for_each(|w| w.join().unwrap());
        runs.assert_each_ran_once();
    }
}
