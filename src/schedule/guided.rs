//! A guided render (`--guiding on`) in passes, each a batch of tiles on the chosen scheduler:
//! every pass but the last learns, while it renders, where light comes from (statistics
//! every thread adds to), and once its tiles are all in, those statistics become the guide
//! the next pass draws its bounces from (`tracer/guiding/`).
//!
//! How the threads' work is joined: during a pass the threads add their bounces' estimates
//! to one shared [`Learning`], as integers (fixed point), which add to the same bits in any
//! order; the pass ends when the scheduler has every tile back, the point where all its
//! threads' additions are done (a scoped thread's join or the pool's latch orders them before
//! it); only then is the guide made, once, on this thread ([`Learning::finish`]). No thread
//! reads a guide while it changes: each pass's guide is fixed before the pass starts. So the
//! guide, and every pixel drawn with it, is the same whatever the scheduler, thread count and
//! tile size.
//!
//! The passes add their samples to running sums (a [`Pass`], as the viewer's progressive
//! passes do): sample `s` of a pixel is added in sample order whichever pass takes it, so the
//! image is every pass's samples together, each an unbiased estimate whatever guide drew it.
//! A scene that takes no guide (no lights: `final`) is rendered as without guiding, in one
//! pass, and costs nothing more.
//!
//! A shard (`render --shard`) learns from every pixel, as the one-process render does: each
//! shard runs the learning passes over the whole image (their pixels thrown away) and then
//! renders its own tiles' samples of the same pass with the guide the pass started with,
//! learning nothing. So every shard holds the one-process guides and pixels, and merged
//! parts equal the one-process image (`tests/shard.rs`), at the price of the learning passes
//! run in every shard.

use std::sync::Arc;

use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::progressive::{Pass, Sums};
use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::learning::Learning;
use crate::tracer::guiding::{Guiding, bounds, takes};
use crate::tracer::render::TileOutput;
use crate::tracer::tile::Shard;

/// Renders `frame` guided by `guiding`, each pass by `run_pass` (a scheduler's render);
/// returns the image (the last pass's tiles carry every pixel's mean over all passes) and
/// every pass's tiles (for their rays, samples and timings), or the error that names a pixel a
/// pass left out or rendered twice.
pub fn render_guided(
    frame: &Arc<Frame>,
    guiding: Guiding,
    mut run_pass: impl FnMut(&Arc<Frame>) -> Vec<TileOutput>,
) -> Result<(Image, Vec<TileOutput>), String> {
    let job = frame.job();
    if !takes(&job.scene) {
        let tiles = run_pass(frame);
        return frame.assemble(&tiles).map(|image| (image, tiles));
    }
    let sums = Sums::default();
    let passes = guiding.passes(job.settings.spp);
    let (mut guide, mut tiles, mut last) = (None::<Arc<Guide>>, Vec::new(), Vec::new());
    for (k, samples) in passes.iter().enumerate() {
        let spp = samples.end - samples.start;
        let learning = (k + 1 < passes.len()).then(|| {
            Arc::new(match &guide {
                None => Learning::new(bounds(&job.scene), spp),
                Some(guide) => Learning::after(guide, spp),
            })
        });
        let mut learns_here = learning.clone();
        if frame.shard() != Shard::WHOLE && learning.is_some() {
            let whole = Pass { samples: samples.clone(), sums: Sums::default(), counts: None };
            let job = job.guided(guide.clone(), learning.clone());
            let learn = Arc::new(frame.as_ref().clone().sharded(Shard::WHOLE).with_job(job).with_pass(whole));
            // Their rays were cast here, their samples are other shards' pixels.
            tiles.extend(run_pass(&learn).into_iter().map(|t| TileOutput { samples: 0, ..t }));
            learns_here = None;
        }
        let pass = Pass { samples: samples.clone(), sums: Arc::clone(&sums), counts: None };
        let guided = job.guided(guide.clone(), learns_here);
        let pass_frame = Arc::new(frame.as_ref().clone().with_job(guided).with_pass(pass));
        tiles.append(&mut last);
        last = run_pass(&pass_frame);
        if frame.is_cancelled() {
            break;
        }
        // Every thread's additions are in: the scheduler has returned every tile.
        guide = learning.map(|learning| Arc::new(learning.finish()));
    }
    let image = if frame.is_cancelled() {
        Image { width: 0, height: 0, pixels: Vec::new() }
    } else {
        frame.assemble(&last)?
    };
    tiles.append(&mut last);
    Ok((image, tiles))
}
