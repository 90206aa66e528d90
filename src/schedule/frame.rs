//! A frame being rendered: what every scheduler receives, and the only way it renders.
//!
//! A [`Frame`] bundles the render job, the random source, the thread count and tile size a
//! scheduler should use, and the progress callback. It is cheap to share (`Arc<Frame>`) and
//! `'static`, so it can travel into thread-pool jobs. [`Frame::render`] renders one tile with
//! the one render loop and notes which thread rendered it and when, so load imbalance and
//! timelines are measured the same way for every scheduler, a student's included.

use std::sync::Arc;
use std::time::Instant;

use crate::files::image::Image;
use crate::tracer::render::{RenderJob, Tile, TileOutput, TileTiming, render_tile};
use crate::tracer::sampler::{PerSample, SharedRng};

/// Default tile side for the tiled modes, pixels (measured: `results/tile-size.md`).
pub const DEFAULT_TILE: u32 = 16;

/// Where pixel samples get their random numbers.
#[derive(Clone, Debug)]
pub enum RngSource {
    /// One independent stream per pixel sample: images are identical under any schedule.
    PerSample(PerSample),
    /// One generator behind a lock, shared by all threads (the seed paper's `rand()`).
    Shared(Arc<SharedRng>),
}

/// Reports progress: called with the number of pixels just finished, from any thread.
pub type Progress = Arc<dyn Fn(u64) + Send + Sync>;

/// One render in progress, as handed to a [`Scheduler`](crate::schedule::modes::Scheduler).
#[derive(Clone)]
pub struct Frame {
    job: Arc<RenderJob>,
    rng: RngSource,
    /// How many threads the scheduler should compute on.
    pub threads: usize,
    /// Side of the square tiles that [`Frame::tiles`] cuts, in pixels.
    pub tile_size: u32,
    progress: Progress,
    epoch: Instant,
}

impl Frame {
    /// A frame of `job`, to be computed on `threads` threads in tiles of `tile_size`.
    pub fn new(job: RenderJob, rng: RngSource, threads: usize, tile_size: u32, progress: Progress) -> Frame {
        Frame {
            job: Arc::new(job),
            rng,
            threads: threads.max(1),
            tile_size: tile_size.max(1),
            progress,
            epoch: Instant::now(),
        }
    }

    /// The render job (scene, camera, settings).
    pub fn job(&self) -> &RenderJob {
        &self.job
    }

    /// Image width, pixels.
    pub fn width(&self) -> u32 {
        self.job.settings.width
    }

    /// Image height, pixels.
    pub fn height(&self) -> u32 {
        self.job.settings.height
    }

    /// One tile per image row, top to bottom.
    pub fn rows(&self) -> Vec<Tile> {
        (0..self.height()).map(|y| Tile::rows(self.width(), y..y + 1)).collect()
    }

    /// Square tiles of `tile_size` (smaller at the right and bottom edges), in row-major
    /// order: left to right, then top to bottom.
    pub fn tiles(&self) -> Vec<Tile> {
        let (w, h, s) = (self.width(), self.height(), self.tile_size);
        (0..h.div_ceil(s))
            .flat_map(|ty| (0..w.div_ceil(s)).map(move |tx| (tx, ty)))
            .map(|(tx, ty)| Tile {
                x: tx * s,
                y: ty * s,
                width: s.min(w - tx * s),
                height: s.min(h - ty * s),
            })
            .collect()
    }

    /// Renders `tile` on the calling thread and reports its pixels as progress.
    pub fn render(&self, tile: Tile) -> TileOutput {
        let start = self.epoch.elapsed();
        let mut out = match &self.rng {
            RngSource::PerSample(streams) => render_tile(&self.job, streams, tile),
            RngSource::Shared(shared) => render_tile(&self.job, shared.as_ref(), tile),
        };
        out.timing =
            Some(TileTiming { thread: std::thread::current().id(), start, end: self.epoch.elapsed() });
        (self.progress)(tile.area() as u64);
        out
    }

    /// Assembles rendered tiles into the image, checking that they cover every pixel once.
    pub fn assemble(&self, tiles: &[TileOutput]) -> Result<Image, String> {
        Image::from_tiles(self.width(), self.height(), tiles)
    }
}
