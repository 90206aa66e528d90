//! Schedulers: who renders which tile. Each is a few lines around the one `render_tile`.
//!
//! - `serial`: the calling thread renders every row, top to bottom: the baseline.
//! - `static`: the seed paper's "naive multithreading": the rows are cut into `threads`
//!   contiguous blocks, one scoped thread each. Simple, but a block of sky finishes long
//!   before a block full of glass, and its thread then sits idle.

use std::ops::Range;

use crate::image::Image;
use crate::render::{RenderJob, Tile, TileOutput, render_tile};
use crate::sampler::RandomStreams;

/// How the image's tiles are distributed over threads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Schedule {
    /// One thread, rows in order.
    Serial,
    /// `threads` contiguous blocks of rows, one `std::thread::scope` thread each.
    #[value(name = "static")]
    StaticBlocks,
}

/// Reports progress: called with the number of pixels just finished, from any thread.
pub type Progress<'a> = &'a (dyn Fn(u64) + Sync);

/// A finished render: the image and the total number of rays cast.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub image: Image,
    /// Every ray cast, camera rays and bounces.
    pub rays: u64,
}

/// Renders `job` with `schedule` on `threads` threads (ignored by `Serial`).
pub fn render<S: RandomStreams>(
    job: &RenderJob,
    streams: &S,
    schedule: Schedule,
    threads: usize,
    progress: Progress,
) -> Rendered {
    let height = job.settings.height;
    let tiles = match schedule {
        Schedule::Serial => render_rows(job, streams, 0..height, progress),
        Schedule::StaticBlocks => std::thread::scope(|scope| {
            let workers: Vec<_> = row_blocks(height, threads)
                .map(|rows| scope.spawn(move || render_rows(job, streams, rows, progress)))
                .collect();
            workers.into_iter().flat_map(|w| w.join().expect("a render thread panicked")).collect()
        }),
    };
    let rays = tiles.iter().map(|t| t.rays).sum();
    Rendered { image: Image::from_tiles(job.settings.width, height, tiles), rays }
}

/// Renders rows `rows` one row-tile at a time (reporting each row as it finishes).
fn render_rows<S: RandomStreams>(
    job: &RenderJob,
    streams: &S,
    rows: Range<u32>,
    progress: Progress,
) -> Vec<TileOutput> {
    rows.map(|y| {
        let out = render_tile(job, streams, Tile::rows(job.settings.width, y..y + 1));
        progress(out.tile.area() as u64);
        out
    })
    .collect()
}

/// `height` rows cut into `parts` contiguous blocks whose sizes differ by at most one.
pub fn row_blocks(height: u32, parts: usize) -> impl Iterator<Item = Range<u32>> {
    let parts = parts.clamp(1, height.max(1) as usize) as u32;
    (0..parts).map(move |k| (k * height / parts)..((k + 1) * height / parts))
}
