//! Instrumentation: what each worker did, and (optionally) when each job ran.
//!
//! Counts (jobs run, stolen, panicked) are always kept: three relaxed atomic adds per job, on
//! counters only the worker that ran it writes. Times (busy, idle) and per-job spans cost four
//! clock reads per job (the wait and the run, each started and ended), measurable on empty
//! jobs, so they are kept only when the pool is built with
//! [`Builder::instrument`](crate::Builder::instrument).
//!
//! Each worker's counters sit on their own cache lines (`#[repr(align(128))]`): workers
//! updating neighbouring counters would otherwise slow each other down (false sharing).

use std::sync::atomic::Ordering::Relaxed;
use std::time::Duration;

use crate::sync::{AtomicU64, Mutex};

/// What one worker did since the pool was built (or since [`ThreadPool::reset_stats`]).
///
/// [`ThreadPool::reset_stats`]: crate::ThreadPool::reset_stats
///
/// ```
/// use pool::{Discipline, ThreadPool};
/// let pool = ThreadPool::new(2, Discipline::Stealing).unwrap();
/// pool.batch((0..100).map(|i| move || i));
/// let stats = pool.stats();
/// assert_eq!(stats.workers.iter().map(|w| w.jobs_run).sum::<u64>(), 100);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkerStats {
    /// Jobs this worker ran (stolen ones included).
    pub jobs_run: u64,
    /// Of those, jobs taken from another worker's deque (`Stealing` only).
    pub jobs_stolen: u64,
    /// Spawned jobs that panicked (a batch's job hands its panic to the batch's waiter,
    /// which panics in its turn, and is not counted here).
    pub panics: u64,
    /// Time spent running jobs (zero unless the pool is instrumented).
    pub busy: Duration,
    /// Time spent looking for or waiting for a job (zero unless instrumented).
    pub idle: Duration,
}

/// Every worker's [`WorkerStats`], indexed by worker number.
///
/// ```
/// use pool::ThreadPool;
/// let pool = ThreadPool::builder().workers(2).instrument(true).build().unwrap();
/// pool.batch((0..8).map(|_| || std::thread::sleep(std::time::Duration::from_millis(2))));
/// let stats = pool.stats();
/// assert_eq!(stats.total_jobs(), 8);
/// assert!(stats.imbalance() >= 1.0);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PoolStats {
    /// One entry per worker.
    pub workers: Vec<WorkerStats>,
}

impl PoolStats {
    /// Jobs run by all workers.
    ///
    /// ```
    /// let pool = pool::ThreadPool::new(3, pool::Discipline::Locked).unwrap();
    /// pool.batch((0..30).map(|i| move || i));
    /// assert_eq!(pool.stats().total_jobs(), 30);
    /// ```
    pub fn total_jobs(&self) -> u64 {
        self.workers.iter().map(|w| w.jobs_run).sum()
    }

    /// Load imbalance: the busiest worker's busy time over the mean busy time. 1.0 is a
    /// perfect balance; `T` (the worker count) means one worker did everything. Requires an
    /// instrumented pool; 1.0 when nothing was measured.
    ///
    /// ```
    /// use std::time::Duration;
    /// use pool::{PoolStats, WorkerStats};
    /// let busy = |ms| WorkerStats { busy: Duration::from_millis(ms), ..Default::default() };
    /// let stats = PoolStats { workers: vec![busy(30), busy(10)] };
    /// assert_eq!(stats.imbalance(), 1.5); // 30 ms against a mean of 20 ms
    /// ```
    pub fn imbalance(&self) -> f64 {
        imbalance(&self.workers.iter().map(|w| w.busy.as_secs_f64()).collect::<Vec<f64>>())
    }
}

/// Load imbalance of busy times, one per thread (any unit): the largest over the mean. 1.0 is
/// a perfect balance, the number of threads means one did everything; 1.0 when there is
/// nothing to compare (no threads, or no time at all). The one formula of the workspace:
/// [`PoolStats::imbalance`] and the renderer's schedulers both use it.
///
/// ```
/// assert_eq!(pool::imbalance(&[3.0, 1.0]), 1.5); // 3 against a mean of 2
/// assert_eq!(pool::imbalance(&[2.0, 2.0, 2.0]), 1.0);
/// assert_eq!(pool::imbalance(&[4.0, 0.0, 0.0, 0.0]), 4.0); // one thread of four did it all
/// assert_eq!(pool::imbalance(&[]), 1.0);
/// assert_eq!(pool::imbalance(&[0.0, 0.0]), 1.0);
/// ```
pub fn imbalance(busy: &[f64]) -> f64 {
    let mean = busy.iter().sum::<f64>() / busy.len().max(1) as f64;
    let max = busy.iter().copied().fold(0.0, f64::max);
    if mean > 0.0 { max / mean } else { 1.0 }
}

/// When and where one job ran (recorded only by an instrumented pool).
///
/// ```
/// use pool::ThreadPool;
/// let pool = ThreadPool::builder().workers(1).instrument(true).build().unwrap();
/// pool.batch([|| 1, || 2]);
/// let spans = pool.take_trace();
/// assert_eq!(spans.len(), 2);
/// assert!(spans.iter().all(|s| s.worker == 0 && s.start <= s.end));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JobSpan {
    /// Index of the worker that ran it.
    pub worker: usize,
    /// Start, since the pool was built.
    pub start: Duration,
    /// End, since the pool was built.
    pub end: Duration,
    /// Whether the worker stole it from another's deque.
    pub stolen: bool,
}

/// One worker's live counters, written only by that worker.
#[repr(align(128))]
#[derive(Default)]
pub(crate) struct WorkerCounters {
    jobs_run: AtomicU64,
    jobs_stolen: AtomicU64,
    panics: AtomicU64,
    busy_ns: AtomicU64,
    idle_ns: AtomicU64,
    spans: Mutex<Vec<JobSpan>>,
}

impl WorkerCounters {
    pub(crate) fn record_job(&self, stolen: bool, panicked: bool) {
        self.jobs_run.fetch_add(1, Relaxed);
        self.jobs_stolen.fetch_add(stolen as u64, Relaxed);
        self.panics.fetch_add(panicked as u64, Relaxed);
    }

    pub(crate) fn record_span(&self, span: JobSpan) {
        self.busy_ns.fetch_add((span.end - span.start).as_nanos() as u64, Relaxed);
        self.spans.lock().push(span);
    }

    pub(crate) fn record_idle(&self, idle: Duration) {
        self.idle_ns.fetch_add(idle.as_nanos() as u64, Relaxed);
    }

    pub(crate) fn snapshot(&self) -> WorkerStats {
        WorkerStats {
            jobs_run: self.jobs_run.load(Relaxed),
            jobs_stolen: self.jobs_stolen.load(Relaxed),
            panics: self.panics.load(Relaxed),
            busy: Duration::from_nanos(self.busy_ns.load(Relaxed)),
            idle: Duration::from_nanos(self.idle_ns.load(Relaxed)),
        }
    }

    pub(crate) fn take_spans(&self) -> Vec<JobSpan> {
        std::mem::take(&mut *self.spans.lock())
    }

    pub(crate) fn reset(&self) {
        for counter in [&self.jobs_run, &self.jobs_stolen, &self.panics, &self.busy_ns, &self.idle_ns] {
            counter.store(0, Relaxed);
        }
        self.spans.lock().clear();
    }
}
