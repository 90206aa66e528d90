//! What a frame itself saw a scheduler do: which threads rendered, which pixels went through
//! [`Frame::render`] and how often, and how busy each thread was.
//!
//! A scheduler returns tiles, and a tile carries a `timing` the scheduler could overwrite;
//! a check built on what comes back can be talked past (a tile rendered twice and returned
//! once, a tile rendered by calling the tracer directly, a `timing` set to `None`). An
//! [`Observer`] instead watches from inside the frame: [`Observer::watch`] gives a copy of the
//! frame whose start and end hooks record every tile on the thread that renders it. Those
//! hooks run inside `Frame::render`, which a scheduler cannot skip if it wants pixels from the
//! frame's own random streams, and cannot reach into.
//!
//! Invariants, under the observer's lock: `rendered[p]` counts the times pixel `p` was
//! started through `Frame::render`; `threads` lists each thread that started a tile, once;
//! `busy[k]` sums the render times of the tiles that `threads[k]` finished (the times come
//! from `Frame::render` itself, just before the end hook sees them).

use std::sync::Arc;
use std::thread::ThreadId;

use parking_lot::Mutex;

use crate::schedule::frame::Frame;
use crate::tracer::render::TileOutput;
use crate::tracer::tile::Tile;

/// Records one render of a frame; make one per render (see the module's invariants).
pub struct Observer {
    width: u32,
    seen: Mutex<Seen>,
}

#[derive(Default)]
struct Seen {
    rendered: Vec<u16>,
    threads: Vec<ThreadId>,
    busy: Vec<f64>,
}

impl Observer {
    /// An observer of one render of `frame`, and the frame to hand the scheduler: `frame`
    /// with hooks that report to the observer (any hooks `frame` had still run first).
    ///
    /// ```
    /// use raypool::schedule::{conformance::test_frame, modes::{Schedule, Scheduler}, observe::Observer};
    /// let frame = test_frame(2);
    /// let (observer, watched) = Observer::watch(&frame);
    /// let tiles = Schedule::Stealing.render(&watched);
    /// assert_eq!(observer.verify(&frame, &tiles, 2), Ok(()));
    /// assert!(observer.threads() <= 2 && observer.imbalance(2) >= 1.0);
    /// ```
    pub fn watch(frame: &Arc<Frame>) -> (Arc<Observer>, Arc<Frame>) {
        let pixels = frame.width() as usize * frame.height() as usize;
        let seen = Seen { rendered: vec![0; pixels], ..Seen::default() };
        let observer = Arc::new(Observer { width: frame.width(), seen: Mutex::new(seen) });
        let (on_start, on_end) = (Arc::clone(&observer), Arc::clone(&observer));
        let watched = (**frame)
            .clone()
            .with_start_hook(Arc::new(move |tile| on_start.started(tile)))
            .with_tile_hook(Arc::new(move |out| on_end.finished(out)));
        (observer, Arc::new(watched))
    }

    fn started(&self, tile: Tile) {
        let me = std::thread::current().id();
        let mut seen = self.seen.lock();
        if !seen.threads.contains(&me) {
            seen.threads.push(me);
            seen.busy.push(0.0);
        }
        for y in tile.y..tile.y + tile.height {
            let row = y as usize * self.width as usize;
            for count in &mut seen.rendered[row + tile.x as usize..row + (tile.x + tile.width) as usize] {
                *count = count.saturating_add(1);
            }
        }
    }

    fn finished(&self, out: &TileOutput) {
        // `Frame::render` set this timing a moment ago, on this thread: the scheduler has not
        // had the tile yet.
        let Some(timing) = out.timing else { return };
        let mut seen = self.seen.lock();
        if let Some(k) = seen.threads.iter().position(|t| *t == timing.thread) {
            seen.busy[k] += (timing.end - timing.start).as_secs_f64();
        }
    }

    /// How many distinct threads rendered tiles.
    pub fn threads(&self) -> usize {
        self.seen.lock().threads.len()
    }

    /// Load imbalance over `threads` threads (the busiest thread's render time over the mean;
    /// a thread that rendered nothing counts as idle): 1.0 is perfect balance.
    pub fn imbalance(&self, threads: usize) -> f64 {
        let mut busy = self.seen.lock().busy.clone();
        busy.resize(busy.len().max(threads), 0.0);
        pool::imbalance(&busy)
    }

    /// The rules that what the frame saw must keep, for a scheduler asked for `threads`
    /// threads that returned `tiles`: every pixel of `frame` went through `Frame::render`
    /// exactly once, on at most `threads` distinct threads, and the tiles returned are those
    /// rendered, each pixel once. The error says what the scheduler did, for a student.
    pub fn verify(&self, frame: &Frame, tiles: &[TileOutput], threads: usize) -> Result<(), String> {
        let seen = self.seen.lock();
        let at = |k: usize| (k % self.width as usize, k / self.width as usize);
        let frame_pixels: usize = frame.tiles().iter().map(Tile::area).sum();
        let never = seen.rendered.iter().filter(|&&n| n == 0).count();
        if never > seen.rendered.len() - frame_pixels {
            let first = seen.rendered.iter().position(|&n| n == 0).map(at).unwrap_or_default();
            return Err(format!(
                "{} of the frame's {frame_pixels} pixels never went through frame.render (the first at \
                 {first:?}): render every tile by calling frame.render(tile), not the tracer directly, \
                 and skip none",
                never - (seen.rendered.len() - frame_pixels)
            ));
        }
        if let Some(k) = seen.rendered.iter().position(|&n| n > 1) {
            return Err(format!(
                "pixel {:?} went through frame.render {} times: render each tile exactly once (a tile \
                 rendered twice costs its time twice, even if only one copy is returned)",
                at(k),
                seen.rendered[k]
            ));
        }
        if seen.threads.len() > threads {
            return Err(format!(
                "tiles were rendered on {} different threads, but the frame asked for at most \
                 frame.threads = {threads}: start that many threads (or a pool of that many workers) \
                 and give each of them many tiles, not one thread per tile",
                seen.threads.len()
            ));
        }
        drop(seen);
        frame.assemble(tiles).map(|_| ())
    }
}
