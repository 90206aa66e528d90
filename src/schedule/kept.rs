//! A built-in mode whose pool outlives one render: for a sequence of renders (the viewer's
//! passes, a session's camera moves, a grader's frames) that should pay for starting threads
//! once, not once per render.
//!
//! [`KeptPool`] renders a pool mode's jobs on a pool it keeps; the modes on scoped threads
//! (serial, static, interleaved) start their threads per render, as they are defined to. A
//! render that asks for another thread count or discipline replaces the pool (the old one's
//! idle workers end as it drops). Invariant: at most one pool is kept, and it has the
//! discipline and worker count of the last pool-mode render.

use std::sync::Arc;

use parking_lot::Mutex;
use pool::{Discipline, ThreadPool};

use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, Scheduler, tiles_on};
use crate::tracer::render::TileOutput;

/// `mode`, on a pool kept from one render to the next.
pub struct KeptPool {
    mode: Schedule,
    pool: Arc<Mutex<Option<Arc<ThreadPool>>>>,
}

impl KeptPool {
    /// `mode`, keeping its pool between renders.
    ///
    /// ```
    /// use raypool::schedule::{conformance::test_frame, kept::KeptPool, modes::{Schedule, Scheduler}};
    /// let steal = KeptPool::new(Schedule::Stealing);
    /// let frame = test_frame(2);
    /// let threads: std::collections::HashSet<_> = (0..5)
    ///     .flat_map(|_| steal.render(&frame))
    ///     .filter_map(|t| Some(t.timing?.thread))
    ///     .collect();
    /// assert!(threads.len() <= 2, "five renders, one pool of 2 workers");
    /// ```
    pub fn new(mode: Schedule) -> KeptPool {
        KeptPool { mode, pool: Arc::default() }
    }

    /// The same kept pool under another mode (a session's next request).
    pub fn with_mode(&self, mode: Schedule) -> KeptPool {
        KeptPool { mode, pool: Arc::clone(&self.pool) }
    }

    fn pool(&self, discipline: Discipline, workers: usize) -> Arc<ThreadPool> {
        let mut kept = self.pool.lock();
        match &*kept {
            Some(pool) if pool.workers() == workers && pool.discipline() == Some(discipline) => {
                Arc::clone(pool)
            }
            _ => {
                let pool = Arc::new(
                    ThreadPool::new(workers, discipline).expect("a pool of at least one worker starts"),
                );
                *kept = Some(Arc::clone(&pool));
                pool
            }
        }
    }
}

impl Scheduler for KeptPool {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        match self.mode.pool_jobs(frame) {
            Some((discipline, jobs)) => tiles_on(&self.pool(discipline, frame.threads), frame, jobs),
            None => self.mode.render(frame),
        }
    }
}
