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
//!
//! The passes, and the guide each draws from, are one [`Plan`], which the viewer follows too
//! (`view/session.rs`): it cuts each of the plan's passes into progressive passes of its own
//! size, all drawing from the pass's guide and learning into its statistics, which sum to the
//! same bits however the pass is cut. So the viewer's last image is `render`'s.

use std::ops::Range;
use std::sync::Arc;

use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::progressive::{Pass, Sums};
use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::learning::Learning;
use crate::tracer::guiding::{Guiding, bounds, takes};
use crate::tracer::math::aabb::Aabb;
use crate::tracer::render::{RenderJob, TileOutput};
use crate::tracer::scene::Scene;
use crate::tracer::tile::Shard;

/// The passes of a guided render, in order, each with the guide it draws from and the
/// statistics it learns into.
///
/// Invariant: a pass's statistics become the next pass's guide only when the next pass is
/// asked for ([`Plan::next_pass`]), which the caller does once every tile of the pass is in.
///
/// ```
/// use raypool::scenes::builtin::builtin_scene;
/// use raypool::schedule::guided::Plan;
/// use raypool::tracer::guiding::Guiding;
/// let passes = |scene: &str, guiding| {
///     let scene = builtin_scene(scene, 0).unwrap().to_scene();
///     let mut plan = Plan::new(&scene, 16, guiding);
///     std::iter::from_fn(|| plan.next_pass().map(|p| (p.samples.clone(), p.learns()))).collect::<Vec<_>>()
/// };
/// let guided = Some(Guiding { pilot: 4 });
/// assert_eq!(passes("cornell", guided), [(0..1, true), (1..2, true), (2..4, true), (4..16, false)]);
/// // No lights to learn from: one pass of every sample.
/// assert_eq!(passes("three-spheres", guided), [(0..16, false)]);
/// ```
#[derive(Debug)]
pub struct Plan {
    /// The sample ranges still to come.
    passes: std::vec::IntoIter<Range<u32>>,
    /// The box the spatial tree cuts; `None` for a render that learns nothing.
    bounds: Option<Aabb>,
    /// The guide the latest pass draws from.
    guide: Option<Arc<Guide>>,
    /// What the latest pass learns into.
    learning: Option<Arc<Learning>>,
}

/// One pass of a [`Plan`]: its samples, the guide it draws from, what it learns into.
#[derive(Debug)]
pub struct GuidedPass {
    /// The samples it takes of every pixel.
    pub samples: Range<u32>,
    guide: Option<Arc<Guide>>,
    learning: Option<Arc<Learning>>,
}

impl Plan {
    /// The plan of a render of `scene` at `spp` samples per pixel guided by `guiding`:
    /// [`Guiding::passes`]; unguided, or of a scene that takes no guide, one pass of every
    /// sample, drawing from no guide.
    pub fn new(scene: &Scene, spp: u32, guiding: Option<Guiding>) -> Plan {
        let (passes, bounds) = match guiding.filter(|_| takes(scene)) {
            Some(guiding) => (guiding.passes(spp), Some(bounds(scene))),
            None => (std::iter::once(0..spp).collect(), None),
        };
        Plan { passes: passes.into_iter(), bounds, guide: None, learning: None }
    }

    /// The next pass, or `None` after the last. Call it only once every tile of the pass
    /// before is rendered (the scheduler has returned them all, so every thread's additions
    /// are in): that pass's statistics become the guide this one draws from.
    pub fn next_pass(&mut self) -> Option<GuidedPass> {
        let samples = self.passes.next()?;
        if let Some(learnt) = self.learning.take() {
            self.guide = Some(Arc::new(learnt.finish()));
        }
        let spp = samples.end - samples.start;
        // Every pass but the last learns.
        let learns = self.bounds.filter(|_| !self.passes.as_slice().is_empty());
        self.learning = learns.map(|bounds| {
            Arc::new(match &self.guide {
                None => Learning::new(bounds, spp),
                Some(guide) => Learning::after(guide, spp),
            })
        });
        Some(GuidedPass { samples, guide: self.guide.clone(), learning: self.learning.clone() })
    }
}

impl GuidedPass {
    /// Whether it learns the next pass's guide (every pass of a guided render but the last).
    pub fn learns(&self) -> bool {
        self.learning.is_some()
    }

    /// `job` as this pass renders it: drawing from the pass's guide, and learning if `learn`
    /// and the pass learns. Its settings ask for no guiding: the pass is one frame, the plan
    /// around it is the guided render, so a frame of it rendered by
    /// [`render`](crate::schedule::modes::render) starts no plan of its own.
    pub fn job(&self, job: &RenderJob, learn: bool) -> RenderJob {
        let mut job = job.guided(self.guide.clone(), self.learning.clone().filter(|_| learn));
        job.settings.guiding = None;
        job
    }
}

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
    let sharded = frame.shard() != Shard::WHOLE;
    let mut plan = Plan::new(&job.scene, job.settings.spp, Some(guiding));
    let (mut tiles, mut last) = (Vec::new(), Vec::new());
    while let Some(pass) = plan.next_pass() {
        if sharded && pass.learns() {
            let whole = Pass { samples: pass.samples.clone(), sums: Sums::default(), counts: None };
            let learn = frame.as_ref().clone().sharded(Shard::WHOLE).with_job(pass.job(job, true));
            // Their rays were cast here, their samples are other shards' pixels.
            let learnt = run_pass(&Arc::new(learn.with_pass(whole)));
            tiles.extend(learnt.into_iter().map(|t| TileOutput { samples: 0, ..t }));
        }
        let own = Pass { samples: pass.samples.clone(), sums: Arc::clone(&sums), counts: None };
        let pass_frame = Arc::new(frame.as_ref().clone().with_job(pass.job(job, !sharded)).with_pass(own));
        tiles.append(&mut last);
        last = run_pass(&pass_frame);
        if frame.is_cancelled() {
            break;
        }
    }
    let image = if frame.is_cancelled() {
        Image { width: 0, height: 0, pixels: Vec::new() }
    } else {
        frame.assemble(&last)?
    };
    tiles.append(&mut last);
    Ok((image, tiles))
}
