//! A queue discipline graded as a scheduler: tiles as jobs on a pool built with the queue,
//! plain or through nested batches (the reference is the same scheduler on `Stealing`).

use std::sync::Arc;

use parking_lot::Mutex;
use pool::{MakeQueue, ThreadPool};

use crate::schedule::frame::Frame;
use crate::schedule::modes::{Scheduler, tiles_on};
use crate::tracer::render::TileOutput;

/// Tiles as jobs on a pool of a given queue, kept from one render to the next (so that
/// `many-frames` times the queue, not the starting of threads); `nested` renders each band
/// of tiles as one job that submits its tiles as a batch and waits for it.
pub struct OnQueue {
    make: MakeQueue,
    nested: bool,
    pools: Mutex<Vec<Arc<ThreadPool>>>,
}

impl OnQueue {
    /// A scheduler on pools built with `make`'s queues.
    ///
    /// ```
    /// use raypool::measure::grade::on_queue::OnQueue;
    /// let on_locked = OnQueue::new(pool::Discipline::Locked.queue(), true);
    /// raypool::schedule::conformance::check(&on_locked, 2).unwrap();
    /// ```
    pub fn new(make: MakeQueue, nested: bool) -> OnQueue {
        OnQueue { make, nested, pools: Mutex::new(Vec::new()) }
    }

    fn pool(&self, workers: usize) -> Arc<ThreadPool> {
        let mut pools = self.pools.lock();
        if let Some(pool) = pools.iter().find(|p| p.workers() == workers) {
            return Arc::clone(pool);
        }
        let pool = ThreadPool::builder()
            .workers(workers)
            .queue(self.make)
            .build()
            .expect("the pool's threads start");
        pools.push(Arc::new(pool));
        Arc::clone(pools.last().expect("just pushed"))
    }
}

impl Scheduler for OnQueue {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let pool = self.pool(frame.threads);
        let tiles = frame.tiles();
        if !self.nested {
            return tiles_on(&pool, frame, tiles);
        }
        let bands: Vec<Vec<_>> = tiles.chunk_by(|a, b| a.y == b.y).map(<[_]>::to_vec).collect();
        let bands = pool.batch(bands.into_iter().map(|band| {
            let (frame, pool) = (Arc::clone(frame), Arc::clone(&pool));
            move || tiles_on(&pool, &frame, band)
        }));
        bands.into_iter().flatten().collect()
    }
}
