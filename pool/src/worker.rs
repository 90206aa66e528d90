//! Workers: the threads of a pool, the state they share, and the loop each one runs.
//!
//! ```text
//!   loop {
//!       job = queue.wait_pop(me)      // sleeps while there is nothing to do
//!       None → return                 // the pool was dropped and the queue is empty
//!       run job, catching a panic     // a panicking job never kills its worker
//!       count it (and time it, if instrumented)
//!   }
//! ```
//!
//! Every worker knows its index and its pool through a thread-local, so that code running
//! inside a job can ask "am I a worker of this pool?": a batch submitted from a job then
//! runs other jobs while it waits instead of blocking a worker (see `batch.rs`).

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant;

use crate::queue::{JobQueue, Popped};
use crate::stats::{JobSpan, WorkerCounters};
use crate::sync::thread_local;

/// What a pool's workers and submitters share.
pub(crate) struct Registry {
    pub(crate) queue: Box<dyn JobQueue>,
    pub(crate) counters: Vec<WorkerCounters>,
    /// Time workers and record per-job spans.
    pub(crate) instrument: bool,
    /// Time zero of every [`JobSpan`].
    pub(crate) epoch: Instant,
}

thread_local! {
    /// `(address of the worker's Registry, worker index)`, or `(0, 0)` on other threads.
    // Not a `const` initialiser: loom's `thread_local!` takes none. The lazy check costs a
    // branch per `spawn` or `batch` call, not per job.
    #[allow(clippy::missing_const_for_thread_local)]
    static CURRENT: Cell<(usize, usize)> = Cell::new((0, 0));
}

impl Registry {
    /// This registry's identity, as recorded in a worker's thread-local. The address is
    /// stable and unique while any worker runs, because every worker holds an `Arc` to it.
    fn id(self: &Arc<Self>) -> usize {
        Arc::as_ptr(self) as *const () as usize
    }

    /// The calling thread's worker index if it is one of this pool's workers.
    pub(crate) fn current_worker(self: &Arc<Self>) -> Option<usize> {
        let (id, index) = CURRENT.with(Cell::get);
        (id == self.id()).then_some(index)
    }

    /// Worker `me`'s thread body.
    pub(crate) fn main_loop(self: Arc<Self>, me: usize) {
        CURRENT.with(|c| c.set((self.id(), me)));
        loop {
            let waiting_since = self.instrument.then(Instant::now);
            let Some(popped) = self.queue.wait_pop(me) else { break };
            if let Some(since) = waiting_since {
                self.counters[me].record_idle(since.elapsed());
            }
            self.run(me, popped);
        }
        CURRENT.with(|c| c.set((0, 0)));
    }

    /// Runs one job on worker `me`, catching its panic, and records it.
    pub(crate) fn run(&self, me: usize, Popped { job, stolen }: Popped) {
        let start = self.instrument.then(|| self.epoch.elapsed());
        // A batch job catches its own panic and hands it to the batch's waiter; this catch
        // is for fire-and-forget jobs, whose panic has nowhere to go but the counters.
        let panicked = catch_unwind(AssertUnwindSafe(job.body)).is_err();
        let counters = &self.counters[me];
        if let Some(start) = start {
            counters.record_span(JobSpan { worker: me, start, end: self.epoch.elapsed(), stolen });
        }
        counters.record_job(stolen, panicked);
        // Only now may the batch's caller wake up and read the statistics.
        if let Some(latch) = job.latch {
            latch.count_down();
        }
    }
}
