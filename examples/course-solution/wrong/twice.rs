//! A cheat, for the instructor to see that the check is not fooled: `frame.threads` threads
//! that each render *every* tile, and one copy of each returned. The returned tiles cover the
//! image once; the frame saw each tile rendered `frame.threads` times.

use std::sync::Arc;

use raypool::{Frame, Scheduler, TileOutput};

/// Every thread renders everything; the first thread's copies are returned.
pub struct TileQueue;

impl Scheduler for TileQueue {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let tiles = frame.tiles();
        std::thread::scope(|scope| {
            let threads: Vec<_> = (0..frame.threads)
                .map(|_| scope.spawn(|| tiles.iter().map(|&tile| frame.render(tile)).collect::<Vec<_>>()))
                .collect();
            let mut copies = threads.into_iter().map(|t| t.join().expect("a render thread panicked"));
            copies.next().unwrap_or_default()
        })
    }
}
