//! The pool itself: building it, submitting jobs (fire-and-forget, or a batch whose results
//! come back), reading its statistics, and shutting it down.
//!
//! This file holds every method of [`ThreadPool`]; the machinery they stand on has a file per
//! concept (`worker.rs` the threads, `batch.rs` a batch and its waiting rule, `stats.rs` the
//! counters), so the type's interface reads in one place and each idea in its own.
//!
//! Lifetime: `build` starts every worker at once (named `pool-worker-0`, `pool-worker-1`,
//! …); they live exactly as long as the `ThreadPool`. Dropping the pool closes the queue,
//! lets the workers run every job already queued, and joins them: when `drop` returns, no
//! worker thread is left (unless the pool was dropped inside one of its own jobs: that worker
//! cannot join itself, and exits when the job returns; see `Drop`).

use std::fmt;
use std::sync::Arc;
use std::time::Instant;

use crate::batch::Batch;
use crate::discipline::Discipline;
use crate::queue::{Job, MakeQueue};
use crate::stats::{JobSpan, PoolStats, WorkerCounters};
use crate::sync::{JoinHandle, thread};
use crate::worker::Registry;

/// A fixed set of worker threads running jobs from a queue.
///
/// ```
/// use pool::{Discipline, ThreadPool};
/// let pool = ThreadPool::new(4, Discipline::Shared).unwrap();
/// assert_eq!(pool.workers(), 4);
/// let total: u64 = pool.batch((1..=100u64).map(|i| move || i)).into_iter().sum();
/// assert_eq!(total, 5050);
/// ```
pub struct ThreadPool {
    registry: Arc<Registry>,
    threads: Vec<JoinHandle<()>>,
    discipline: Option<Discipline>,
}

/// Why a pool could not be built.
///
/// ```
/// use pool::{BuildError, Discipline, ThreadPool};
/// assert!(matches!(ThreadPool::new(0, Discipline::Shared), Err(BuildError::NoWorkers)));
/// ```
#[derive(Debug)]
pub enum BuildError {
    /// A pool needs at least one worker (zero would accept jobs and never run them).
    NoWorkers,
    /// The operating system refused to start a thread.
    Spawn(std::io::Error),
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::NoWorkers => f.write_str("a thread pool needs at least one worker"),
            BuildError::Spawn(e) => write!(f, "cannot start a worker thread: {e}"),
        }
    }
}

impl std::error::Error for BuildError {}

/// Configures a [`ThreadPool`]: worker count, queue discipline, instrumentation.
///
/// ```
/// use pool::{Discipline, ThreadPool};
/// let pool = ThreadPool::builder().workers(2).discipline(Discipline::Locked).instrument(true).build().unwrap();
/// assert_eq!(pool.discipline(), Some(Discipline::Locked));
/// ```
#[derive(Clone, Debug)]
pub struct Builder {
    workers: usize,
    /// The built-in discipline chosen, or `None` for a queue given to [`Builder::queue`].
    discipline: Option<Discipline>,
    make_queue: MakeQueue,
    instrument: bool,
}

impl Builder {
    /// Number of worker threads (default: the machine's available parallelism).
    ///
    /// ```
    /// assert_eq!(pool::ThreadPool::builder().workers(3).build().unwrap().workers(), 3);
    /// ```
    pub fn workers(mut self, workers: usize) -> Builder {
        self.workers = workers;
        self
    }

    /// Queue discipline (default: [`Discipline::Shared`]).
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// let pool = ThreadPool::builder().discipline(Discipline::Stealing).build().unwrap();
    /// assert_eq!(pool.discipline(), Some(Discipline::Stealing));
    /// ```
    pub fn discipline(mut self, discipline: Discipline) -> Builder {
        (self.discipline, self.make_queue) = (Some(discipline), discipline.queue());
        self
    }

    /// A queue discipline of your own instead of a built-in one: `make` is called once, with
    /// the worker count, when the pool is built. See [`JobQueue`](crate::JobQueue) for a
    /// complete example.
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// // Any function from a worker count to a boxed queue will do; here, a built-in one.
    /// let pool = ThreadPool::builder().workers(2).queue(Discipline::Locked.queue()).build().unwrap();
    /// assert_eq!(pool.batch([|| 1, || 2]), vec![1, 2]);
    /// assert_eq!(pool.discipline(), None);
    /// ```
    pub fn queue(mut self, make: MakeQueue) -> Builder {
        (self.discipline, self.make_queue) = (None, make);
        self
    }

    /// Time every job and keep a [`JobSpan`] per job (default: off; costs four clock reads
    /// per job: the wait for it and its run).
    ///
    /// ```
    /// let pool = pool::ThreadPool::builder().workers(1).instrument(true).build().unwrap();
    /// pool.batch([|| std::thread::sleep(std::time::Duration::from_millis(5))]);
    /// assert!(pool.stats().workers[0].busy.as_millis() >= 5);
    /// ```
    pub fn instrument(mut self, on: bool) -> Builder {
        self.instrument = on;
        self
    }

    /// Starts the workers.
    ///
    /// # Errors
    /// [`BuildError::NoWorkers`] for zero workers; [`BuildError::Spawn`] if a thread cannot
    /// be started (the workers already started are shut down again).
    ///
    /// ```
    /// assert!(pool::ThreadPool::builder().workers(0).build().is_err());
    /// ```
    pub fn build(self) -> Result<ThreadPool, BuildError> {
        if self.workers == 0 {
            return Err(BuildError::NoWorkers);
        }
        let registry = Arc::new(Registry {
            queue: (self.make_queue)(self.workers),
            counters: (0..self.workers).map(|_| WorkerCounters::default()).collect(),
            instrument: self.instrument,
            epoch: Instant::now(),
        });
        let mut pool =
            ThreadPool { registry, threads: Vec::with_capacity(self.workers), discipline: self.discipline };
        for me in 0..self.workers {
            let registry = Arc::clone(&pool.registry);
            let thread = thread::Builder::new()
                .name(format!("pool-worker-{me}"))
                .spawn(move || registry.main_loop(me));
            // On failure, dropping `pool` shuts down the workers started so far.
            pool.threads.push(thread.map_err(BuildError::Spawn)?);
        }
        Ok(pool)
    }
}

impl ThreadPool {
    /// A pool of `workers` threads with the given queue discipline, not instrumented.
    ///
    /// # Errors
    /// See [`Builder::build`].
    ///
    /// ```
    /// let pool = pool::ThreadPool::new(2, pool::Discipline::Shared).unwrap();
    /// assert_eq!(pool.workers(), 2);
    /// ```
    pub fn new(workers: usize, discipline: Discipline) -> Result<ThreadPool, BuildError> {
        ThreadPool::builder().workers(workers).discipline(discipline).build()
    }

    /// A [`Builder`] with the defaults.
    ///
    /// ```
    /// let pool = pool::ThreadPool::builder().build().unwrap();
    /// assert!(pool.workers() >= 1);
    /// ```
    pub fn builder() -> Builder {
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
        let discipline = Discipline::default();
        Builder { workers, discipline: Some(discipline), make_queue: discipline.queue(), instrument: false }
    }

    /// Runs `job` on some worker, some time; its result and panic go nowhere (a panic is
    /// counted in [`WorkerStats::panics`](crate::WorkerStats::panics)). Use
    /// [`ThreadPool::batch`] to wait for results.
    ///
    /// ```
    /// use std::sync::mpsc;
    /// let pool = pool::ThreadPool::new(2, pool::Discipline::Locked).unwrap();
    /// let (tx, rx) = mpsc::channel();
    /// pool.spawn(move || tx.send(6 * 7).unwrap());
    /// assert_eq!(rx.recv().unwrap(), 42);
    /// ```
    pub fn spawn<F: FnOnce() + Send + 'static>(&self, job: F) {
        let me = self.registry.current_worker();
        self.registry.queue.push(Job::detached(job), me);
    }

    /// Runs every job of `jobs` on the pool and returns their results in submission order.
    ///
    /// May be called from inside a job (a nested batch): a worker that waits runs other
    /// queued jobs meanwhile, so nesting cannot deadlock the pool (the waiting rule,
    /// `batch.rs`).
    ///
    /// # Panics
    /// If a job panics, `batch` waits for all the others, then re-raises the first panic
    /// (in submission order). The pool and its workers are unaffected.
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// let pool = ThreadPool::new(3, Discipline::Stealing).unwrap();
    /// let squares = pool.batch((0..10u64).map(|i| move || i * i));
    /// assert_eq!(squares, (0..10).map(|i| i * i).collect::<Vec<_>>());
    /// ```
    pub fn batch<T, F, I>(&self, jobs: I) -> Vec<T>
    where
        I: IntoIterator<Item = F>,
        F: FnOnce() -> T + Send + 'static,
        T: Send + 'static,
    {
        let (batch, jobs) = Batch::new(jobs.into_iter().collect());
        let me = self.registry.current_worker();
        self.registry.queue.push_batch(jobs, me);
        batch.wait(&self.registry, me)
    }

    /// Number of worker threads.
    ///
    /// ```
    /// assert_eq!(pool::ThreadPool::new(5, pool::Discipline::Stealing).unwrap().workers(), 5);
    /// ```
    pub fn workers(&self) -> usize {
        self.registry.counters.len()
    }

    /// The built-in queue discipline chosen at construction; `None` for a queue of one's own
    /// ([`Builder::queue`]).
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// assert_eq!(ThreadPool::new(1, Discipline::Locked).unwrap().discipline(), Some(Discipline::Locked));
    /// ```
    pub fn discipline(&self) -> Option<Discipline> {
        self.discipline
    }

    /// A snapshot of every worker's counters.
    ///
    /// ```
    /// let pool = pool::ThreadPool::new(2, pool::Discipline::Shared).unwrap();
    /// pool.batch((0..10).map(|_| || ()));
    /// assert_eq!(pool.stats().total_jobs(), 10);
    /// ```
    pub fn stats(&self) -> PoolStats {
        PoolStats { workers: self.registry.counters.iter().map(WorkerCounters::snapshot).collect() }
    }

    /// Takes the job spans recorded so far (empty unless instrumented), sorted by start.
    ///
    /// ```
    /// let pool = pool::ThreadPool::builder().workers(2).instrument(true).build().unwrap();
    /// pool.batch((0..6).map(|_| || ()));
    /// assert_eq!(pool.take_trace().len(), 6);
    /// assert!(pool.take_trace().is_empty(), "taken");
    /// ```
    pub fn take_trace(&self) -> Vec<JobSpan> {
        let mut spans: Vec<JobSpan> =
            self.registry.counters.iter().flat_map(WorkerCounters::take_spans).collect();
        spans.sort_by_key(|s| (s.start, s.worker));
        spans
    }

    /// Zeroes every counter and forgets recorded spans (e.g. between benchmark runs).
    ///
    /// ```
    /// let pool = pool::ThreadPool::new(1, pool::Discipline::Shared).unwrap();
    /// pool.batch([|| ()]);
    /// pool.reset_stats();
    /// assert_eq!(pool.stats().total_jobs(), 0);
    /// ```
    pub fn reset_stats(&self) {
        self.registry.counters.iter().for_each(WorkerCounters::reset);
    }
}

impl Drop for ThreadPool {
    /// Closes the queue, lets the workers finish every queued job, and joins them.
    ///
    /// If the last owner of the pool is dropped *inside one of its own jobs* (e.g. an
    /// `Arc<ThreadPool>` moved into a job), that worker cannot join itself: it is left to
    /// exit on its own as soon as the job returns.
    fn drop(&mut self) {
        self.registry.queue.close();
        let me = thread::current().id();
        for thread in self.threads.drain(..) {
            if thread.thread().id() != me {
                // A worker's loop catches job panics, so join fails only on a pool bug.
                thread.join().expect("a pool worker died");
            }
        }
    }
}
