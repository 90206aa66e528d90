//! Jobs and the queue interface that every queue discipline implements.
//!
//! A *job* is a boxed closure run exactly once by some thread. A *queue discipline* decides
//! where a submitted job waits and which thread takes it. The pool talks to its queue only
//! through [`JobQueue`], so the three disciplines (`locked.rs`, `shared.rs`, `steal.rs`) can be
//! read, and measured, side by side. This file knows none of them: they import it, and
//! `discipline.rs`, read after them, is where [`Discipline`](crate::Discipline) names and
//! builds them.
//!
//! [`JobQueue`] is public so that a discipline can also be written outside this crate (a
//! course assignment's, say) and given to [`Builder::queue`](crate::Builder::queue);
//! [`conformance::check`](crate::conformance::check) tells whether it keeps the invariants.
//!
//! Invariants every implementation keeps:
//! - a pushed job is popped at most once (no duplication) and, unless the pool is dropped
//!   mid-flight by a panic, exactly once (no loss);
//! - `wait_pop` returns `None` only after `close` *and* once no job is left: dropping a pool
//!   runs what was queued;
//! - an idle worker blocks inside `wait_pop` without spinning.

use std::sync::Arc;

use crate::latch::CountLatch;

/// A unit of work: run once, on some thread. Opaque to a queue, which only stores jobs and
/// hands them out; the pool's workers run them.
pub struct Job {
    /// The work itself.
    pub(crate) body: Box<dyn FnOnce() + Send + 'static>,
    /// The batch latch to count down once the job has run *and* been recorded in the
    /// worker's statistics (so a batch's caller always sees complete statistics).
    pub(crate) latch: Option<Arc<CountLatch>>,
}

impl Job {
    /// A job that belongs to no batch.
    pub(crate) fn detached(body: impl FnOnce() + Send + 'static) -> Job {
        Job { body: Box::new(body), latch: None }
    }
}

/// A job taken from a queue, and whether it was taken from another worker's deque (which
/// the pool counts in [`WorkerStats::jobs_stolen`](crate::WorkerStats::jobs_stolen)).
pub struct Popped {
    /// The job.
    pub job: Job,
    /// Taken from another worker's share of the queue.
    pub stolen: bool,
}

/// Makes the queue of a pool of `workers` workers: what [`Builder::queue`](crate::Builder::queue)
/// takes, and what [`Discipline::queue`](crate::Discipline::queue) gives for the built-in
/// disciplines.
///
/// ```
/// use pool::{Discipline, MakeQueue, ThreadPool};
/// let make: MakeQueue = Discipline::Stealing.queue();
/// let pool = ThreadPool::builder().workers(2).queue(make).build().unwrap();
/// assert_eq!(pool.batch([|| 'a', || 'b']), vec!['a', 'b']);
/// ```
pub type MakeQueue = fn(workers: usize) -> Box<dyn JobQueue>;

/// The operations the pool needs from a queue discipline. `me` is the calling worker's
/// index (`0..workers`), or `None` for a thread that is not one of the pool's workers.
///
/// An implementation keeps the invariants in this module's opening comment: a pushed job
/// is popped exactly once, `wait_pop` sleeps (without spinning) while there is nothing to
/// do and returns `None` only once closed *and* empty. A queue of its own, the textbook
/// monitor in a dozen lines, and a pool that uses it:
///
/// ```
/// use std::collections::VecDeque;
/// use std::sync::{Condvar, Mutex};
/// use pool::{Job, JobQueue, Popped, ThreadPool};
///
/// #[derive(Default)]
/// struct Monitor { state: Mutex<(VecDeque<Job>, bool)>, ready: Condvar }
///
/// impl JobQueue for Monitor {
///     fn push(&self, job: Job, _me: Option<usize>) {
///         self.state.lock().unwrap().0.push_back(job);
///         self.ready.notify_one();
///     }
///     fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
///         let job = self.state.lock().unwrap().0.pop_front()?;
///         Some(Popped { job, stolen: false })
///     }
///     fn wait_pop(&self, _me: usize) -> Option<Popped> {
///         let mut state = self.state.lock().unwrap();
///         loop {
///             if let Some(job) = state.0.pop_front() {
///                 return Some(Popped { job, stolen: false });
///             }
///             if state.1 {
///                 return None; // closed and empty
///             }
///             state = self.ready.wait(state).unwrap();
///         }
///     }
///     fn close(&self) {
///         self.state.lock().unwrap().1 = true;
///         self.ready.notify_all();
///     }
/// }
///
/// let pool = ThreadPool::builder().workers(3).queue(|_| Box::new(Monitor::default())).build().unwrap();
/// assert_eq!(pool.batch((0..5).map(|i| move || i + 1)), vec![1, 2, 3, 4, 5]);
/// assert_eq!(pool.discipline(), None, "not a built-in discipline");
/// pool::conformance::check(|_| Box::new(Monitor::default())).unwrap();
/// ```
pub trait JobQueue: Send + Sync {
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

/// What the loom models of the disciplines share (`.ci/run` runs them; see `sync.rs`): the
/// locked and stealing queues, whose locks and atomics loom can see (the shared queue is a
/// crossbeam channel, which it cannot).
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

    /// Runs the jobs that `take` hands out (a worker's `wait_pop`, a thief's `try_pop`) until
    /// it hands out none.
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
