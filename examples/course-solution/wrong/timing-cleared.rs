//! A cheat, for the instructor to see that the check is not fooled: a thread per tile (far
//! more threads than `frame.threads`) that clears each tile's `timing`, the field an earlier
//! check counted threads from. The frame's own hooks still see every thread.

use std::sync::Arc;

use raypool::{Frame, Scheduler, TileOutput};

/// One scoped thread per tile, with the evidence wiped.
pub struct TileQueue;

impl Scheduler for TileQueue {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        std::thread::scope(|scope| {
            let threads: Vec<_> =
                frame.tiles().into_iter().map(|tile| scope.spawn(move || frame.render(tile))).collect();
            threads
                .into_iter()
                .map(|t| TileOutput { timing: None, ..t.join().expect("a render thread panicked") })
                .collect()
        })
    }
}
