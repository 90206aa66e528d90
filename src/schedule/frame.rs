//! A frame being rendered: what every scheduler receives, and the only way it renders.
//!
//! A [`Frame`] bundles the render job, the random source, the thread count and tile size a
//! scheduler should use, and the progress callback; optionally a shard (which tiles), a
//! progressive pass (which samples, added to running sums), a cancel flag and a hook that sees
//! every finished tile. It is cheap to share (`Arc<Frame>`) and
//! `'static`, so it can travel into thread-pool jobs. [`Frame::render`] renders one tile with
//! the one render loop and notes which thread rendered it and when, so load imbalance and
//! timelines are measured the same way for every scheduler, a student's included.

use std::sync::Arc;
use std::time::Instant;

use crate::files::image::Image;
use crate::schedule::progressive::{Cancel, Pass};
use crate::schedule::random::RngSource;
use crate::tracer::render::{RenderJob, TileOutput, TileTiming, render_tile};
use crate::tracer::sampling::sampler::RandomStreams;
use crate::tracer::splats::Splats;
use crate::tracer::tile::{Shard, Tile};

/// Default tile side for the tiled modes, pixels (measured: `results/tile-size.md`).
pub const DEFAULT_TILE: u32 = 16;

/// Reports progress: called with the number of pixels just finished, from any thread.
pub type Progress = Arc<dyn Fn(u64) + Send + Sync>;

/// Sees every tile the moment it is finished (with its timing), from the rendering thread.
pub type TileHook = Arc<dyn Fn(&TileOutput) + Send + Sync>;

/// Sees every tile just before it is rendered, from the rendering thread (the conformance
/// check uses it to see how many threads render at once).
pub type StartHook = Arc<dyn Fn(Tile) + Send + Sync>;

/// One render in progress, as handed to a [`Scheduler`](crate::schedule::modes::Scheduler).
#[derive(Clone)]
pub struct Frame {
    job: Arc<RenderJob>,
    rng: RngSource,
    /// How many threads the scheduler should compute on.
    pub threads: usize,
    /// Side of the square tiles that [`Frame::tiles`] cuts, in pixels.
    pub tile_size: u32,
    shard: Shard,
    pass: Option<Pass>,
    cancel: Option<Cancel>,
    on_tile: Option<TileHook>,
    on_start: Option<StartHook>,
    progress: Progress,
    epoch: Instant,
}

impl Frame {
    /// A frame of `job` (owned, or shared as an `Arc` so that passes of one render do not copy
    /// the scene), to be computed on `threads` threads in tiles of `tile_size`.
    pub fn new(
        job: impl Into<Arc<RenderJob>>,
        rng: RngSource,
        threads: usize,
        tile_size: u32,
        progress: Progress,
    ) -> Frame {
        Frame {
            job: job.into(),
            rng,
            threads: threads.max(1),
            tile_size: tile_size.max(1),
            shard: Shard::WHOLE,
            pass: None,
            cancel: None,
            on_tile: None,
            on_start: None,
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

    /// The same frame rendering `job` instead (of the same size): how each pass of a guided
    /// render gets the guide the pass before it learnt (`guided.rs`).
    pub fn with_job(mut self, job: impl Into<Arc<RenderJob>>) -> Frame {
        self.job = job.into();
        self
    }

    /// The same frame restricted to `shard`: only that shard's tiles are rendered (see
    /// [`Shard`]), and [`Frame::rows`] and [`Frame::tiles`] hand out only its pixels.
    pub fn sharded(mut self, shard: Shard) -> Frame {
        self.shard = shard;
        self
    }

    /// The same frame as one progressive pass: each tile adds the pass's samples to its
    /// running sums instead of rendering from nothing (see [`Pass`]).
    pub fn with_pass(mut self, pass: Pass) -> Frame {
        self.pass = Some(pass);
        self
    }

    /// The same frame, stopped by `cancel`: once it is cancelled, tiles not yet started
    /// return at once, unrendered (black, no rays, no timing), and the hook does not see them.
    pub fn with_cancel(mut self, cancel: Cancel) -> Frame {
        self.cancel = Some(cancel);
        self
    }

    /// The same frame, calling `hook` with every tile as soon as it is rendered (after the
    /// tile hook the frame already had, if any).
    pub fn with_tile_hook(mut self, hook: TileHook) -> Frame {
        self.on_tile = Some(match self.on_tile.take() {
            Some(first) => Arc::new(move |out: &TileOutput| {
                first(out);
                hook(out);
            }),
            None => hook,
        });
        self
    }

    /// The same frame, calling `hook` with every tile just before it is rendered, on the
    /// thread that renders it (never for a tile skipped because the frame was cancelled;
    /// after the start hook the frame already had, if any).
    pub fn with_start_hook(mut self, hook: StartHook) -> Frame {
        self.on_start = Some(match self.on_start.take() {
            Some(first) => Arc::new(move |tile: Tile| {
                first(tile);
                hook(tile);
            }),
            None => hook,
        });
        self
    }

    /// Which shard of the image this frame renders ([`Shard::WHOLE`] unless
    /// [`Frame::sharded`]).
    pub fn shard(&self) -> Shard {
        self.shard
    }

    /// One tile per image row, top to bottom. In a shard, a row is the shard's part of it:
    /// one strip a pixel high per shard tile that crosses the row, left to right.
    pub fn rows(&self) -> Vec<Tile> {
        if self.shard == Shard::WHOLE {
            return (0..self.height()).map(|y| Tile::rows(self.width(), y..y + 1)).collect();
        }
        let tiles = self.tiles();
        // Grid tiles come in row-major order, so a band of tiles sharing `y` is contiguous.
        tiles
            .chunk_by(|a, b| a.y == b.y)
            .flat_map(|band| {
                (band[0].y..band[0].y + band[0].height).flat_map(move |y| {
                    band.iter().map(move |t| Tile { x: t.x, y, width: t.width, height: 1 })
                })
            })
            .collect()
    }

    /// Square tiles of `tile_size` (smaller at the right and bottom edges), in row-major
    /// order ([`Tile::grid`]); in a shard, only the shard's tiles.
    pub fn tiles(&self) -> Vec<Tile> {
        self.shard.tiles(&Tile::grid(self.width(), self.height(), self.tile_size))
    }

    /// How many pixels this frame renders: the whole image's, or its shard's.
    pub fn pixels(&self) -> u64 {
        self.tiles().iter().map(|t| t.area() as u64).sum()
    }

    /// Whether the frame's cancel flag ([`Frame::with_cancel`]) has been raised.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.as_ref().is_some_and(Cancel::is_cancelled)
    }

    /// Renders `tile` on the calling thread and reports its pixels as progress.
    pub fn render(&self, tile: Tile) -> TileOutput {
        if self.is_cancelled() {
            let pixels = vec![Default::default(); tile.area()];
            return TileOutput {
                tile,
                pixels,
                rays: 0,
                samples: 0,
                splats: Default::default(),
                timing: None,
            };
        }
        if let Some(hook) = &self.on_start {
            hook(tile);
        }
        let start = self.epoch.elapsed();
        let mut out = match &self.rng {
            RngSource::PerSample(streams) => self.render_with(streams, tile),
            RngSource::Sobol(streams) => self.render_with(streams, tile),
            RngSource::Shared(shared) => self.render_with(shared.as_ref(), tile),
        };
        out.timing =
            Some(TileTiming { thread: std::thread::current().id(), start, end: self.epoch.elapsed() });
        (self.progress)(tile.area() as u64);
        if let Some(hook) = &self.on_tile {
            hook(&out);
        }
        out
    }

    /// `tile` rendered whole, or this frame's pass of it, with `streams`.
    fn render_with<S: RandomStreams>(&self, streams: &S, tile: Tile) -> TileOutput {
        match &self.pass {
            None => render_tile(&self.job, streams, tile),
            Some(pass) => pass.render(&self.job, streams, tile),
        }
    }

    /// Assembles rendered tiles into the image, checking that they cover every pixel of the
    /// frame once (in a shard, the shard's pixels; the others stay black). A whole frame's
    /// image also gets the light its light paths splatted (`--light-sampling bdpt`); a shard's
    /// does not: that light lands in every shard's pixels, so it travels beside the image
    /// ([`Frame::splats`]) and is added when the parts merge.
    pub fn assemble(&self, tiles: &[TileOutput]) -> Result<Image, String> {
        if self.shard != Shard::WHOLE {
            return Image::from_tiles_within(self.width(), self.height(), &self.tiles(), tiles);
        }
        let mut image = Image::from_tiles(self.width(), self.height(), tiles)?;
        image.add_splats(&Frame::splats(tiles), self.paths());
        Ok(image)
    }

    /// Every tile's splats summed: in fixed point, so in any order of tiles to the same bits.
    pub fn splats(tiles: &[TileOutput]) -> Splats {
        let mut splats = Splats::default();
        tiles.iter().for_each(|t| splats.merge(&t.splats));
        splats
    }

    /// Light paths per pixel that the tiles' splats sum: one per sample taken so far (a
    /// progressive pass's end, else the settings' samples per pixel).
    pub fn paths(&self) -> u32 {
        self.pass.as_ref().map_or(self.job.settings.spp, |pass| pass.samples.end)
    }
}
