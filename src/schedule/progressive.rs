//! Progressive rendering: an image refined pass after pass (1 sample per pixel, then 2, 4, …)
//! and cancellable between tiles, as the live viewer draws it.
//!
//! A [`Pass`] adds samples `a..b` of every pixel to running sums kept per tile across passes.
//! Samples are added in sample order with the one render loop
//! ([`accumulate_tile`]), so after a pass that ends at
//! `b` the image is, bit for bit, the image `raypool render --spp b` makes. A frame carrying a
//! pass is rendered by any [`Scheduler`](crate::schedule::modes::Scheduler): the schedulers do
//! not know about passes.
//!
//! Invariants: within one progressive render the tiles are the same every pass (the mode and
//! tile size do not change; a change starts a new render with new sums), and a tile's sums are
//! taken out of the map while its job renders, so no two threads ever hold them.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use parking_lot::Mutex;

use crate::tracer::render::{PixelSums, RenderJob, TileOutput, accumulate_tile};
use crate::tracer::sampling::sampler::RandomStreams;
use crate::tracer::tile::Tile;

/// Every tile's running sums, shared by the passes of one progressive render.
pub type Sums = Arc<Mutex<HashMap<Tile, PixelSums>>>;

/// One pass of a progressive render: which samples it adds, to which pixels, and the sums it
/// adds them to.
#[derive(Clone, Debug)]
pub struct Pass {
    /// Sample numbers this pass adds to every pixel it samples.
    pub samples: Range<u32>,
    /// The render's running sums.
    pub sums: Sums,
    /// Each pixel's sample count (row-major over the image): a pixel takes only the samples
    /// of `samples` below its count (none once it has them all); all of them when `None`.
    pub counts: Option<Arc<Vec<u32>>>,
}

impl Pass {
    /// Adds this pass's samples of `tile` to its running sums; the output's pixels are the
    /// means over samples `0..self.samples.end`.
    pub fn render<S: RandomStreams>(&self, job: &RenderJob, streams: &S, tile: Tile) -> TileOutput {
        let mut sums = self.sums.lock().remove(&tile).unwrap_or_else(|| PixelSums::new(tile.area()));
        let before = sums.samples();
        let width = job.settings.width as usize;
        let samples = |i: u32, j: u32| match &self.counts {
            Some(counts) => {
                let end = self.samples.end.min(counts[j as usize * width + i as usize]);
                self.samples.start..end.max(self.samples.start)
            }
            None => self.samples.clone(),
        };
        let rays = accumulate_tile(job, streams, tile, samples, &mut sums);
        let out = TileOutput {
            tile,
            pixels: sums.means(),
            rays,
            samples: sums.samples() - before,
            // Every splat of samples `0..end`, as the pixels are means over them.
            splats: sums.splats.clone(),
            timing: None,
        };
        self.sums.lock().insert(tile, sums);
        out
    }
}

/// A flag that cancels a render: every tile job checks it before it starts, so a cancelled
/// render stops within one tile's time and its remaining jobs return at once, unrendered.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// Asks the render to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether [`Cancel::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}
