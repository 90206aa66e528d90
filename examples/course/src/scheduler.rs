//! Part 1: a dynamic scheduler.
//!
//! Render every tile of the frame exactly once, by calling `frame.render(tile)`, on
//! `frame.threads` threads (no more distinct threads than that; with two or more, they must
//! render at the same time), and return the rendered tiles (in any order). Instead of giving
//! each thread a fixed share (raypool's `static` mode, which the grader's `one-band`
//! workload punishes), keep the tiles in one shared queue: each thread takes the next tile
//! until none is left.
//!
//! Hints: `std::thread::scope` lets threads borrow `frame` and the tile list; an
//! `AtomicUsize` holding the index of the next tile is all the queue you need
//! (`fetch_add(1, Ordering::Relaxed)` hands out each index once). The conformance check
//! (README.md, "The rules the check enforces") watches from inside the frame: it fails a
//! scheduler that renders on the calling thread only, on a thread per tile, or any tile
//! twice.

use std::sync::Arc;

use raypool::{Frame, Scheduler, TileOutput};

/// Tiles from a shared queue, on `frame.threads` threads.
pub struct TileQueue;

impl Scheduler for TileQueue {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let _tiles = frame.tiles();
        todo!("start frame.threads threads; each takes tiles from a shared counter until none is left")
    }
}
