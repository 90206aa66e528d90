//! Navigation frames: while the camera moves, the viewer first renders a small 1-sample
//! frame (a "start resolution", as Blender's viewport does), which the page scales up, then
//! refines at full size in place once the camera has rested [`REFINE_AFTER`]; the next move
//! cancels the refinement.
//!
//! The frame's size is chosen by the time the last one took: a frame rendered at `1/d` of
//! each side costs about `1/d²` of the full one, so after a frame that took `t` at divisor `d`
//! the divisor that would take [`FRAME_BUDGET`] is `d·√(t / budget)`; the next divisor moves
//! halfway towards it (so one slow frame, a page opening say, does not throw it to the
//! limit) and stays within `1..=`[`MAX_DIVISOR`]. Its pixels go to the page as one binary
//! answer (`GET /preview.rgba`: 8-bit RGBA, drawn with one `putImageData`), not as tiles.
//!
//! A navigation frame is denoised unless the page turned it off (`denoise=0`): the guides and
//! the filter of [`crate::denoise`], on the session's threads, their time counted in the
//! frame's (so the start resolution makes room for them).
//!
//! Invariant: a navigation frame is never the image `/image.*` serves (that is always the
//! full-size render's latest pass, as `raypool render` makes it).

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::denoise::denoise;
use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::kept::KeptPool;
use crate::schedule::modes::render;
use crate::schedule::progressive::Cancel;
use crate::schedule::random::RngSource;
use crate::tracer::render::RenderSettings;
use crate::view::request::Config;

/// The render time a navigation frame aims at: a third of a 30-frames-a-second frame, so the
/// request, the page's fetch and its drawing fit in the rest.
pub const FRAME_BUDGET: Duration = Duration::from_millis(10);

/// How long the full-size render waits after a navigation frame: a camera still moving sends
/// its next move by then (the page sends it as soon as the frame is on screen), and meanwhile
/// the page's fetching and drawing have the CPUs to themselves.
pub const REFINE_AFTER: Duration = Duration::from_millis(50);

/// The smallest start resolution: an eighth of each side.
pub const MAX_DIVISOR: f64 = 8.0;

/// The divisor of the next navigation frame, learnt from the last ones.
#[derive(Clone, Copy, Debug)]
pub struct StartResolution {
    divisor: f64,
}

impl Default for StartResolution {
    /// Half of each side, until a first frame is timed.
    fn default() -> StartResolution {
        StartResolution { divisor: 2.0 }
    }
}

impl StartResolution {
    /// The divisor of each side for the next frame.
    ///
    /// ```
    /// use raypool::view::preview::StartResolution;
    /// let mut start = StartResolution::default();
    /// assert_eq!(start.divisor(), 2);
    /// for _ in 0..10 {
    ///     let d = start.divisor();
    ///     // A frame that costs 40 ms at full size takes 40/d² ms.
    ///     start.record(d, std::time::Duration::from_secs_f64(0.040 / f64::from(d * d)));
    /// }
    /// assert_eq!(start.divisor(), 2, "40 ms at full size: half of each side takes 10 ms");
    /// ```
    pub fn divisor(&self) -> u32 {
        self.divisor.round() as u32
    }

    /// Learns from a frame rendered at divisor `used` in `took`.
    pub fn record(&mut self, used: u32, took: Duration) {
        let ideal = f64::from(used) * (took.as_secs_f64() / FRAME_BUDGET.as_secs_f64()).sqrt();
        self.divisor = (0.5 * self.divisor + 0.5 * ideal).clamp(1.0, MAX_DIVISOR);
    }
}

/// One navigation frame, as the page fetches it.
#[derive(Clone, Debug)]
pub struct Preview {
    /// The render it belongs to.
    pub generation: u64,
    /// Its size, pixels.
    pub width: u32,
    /// Its height, pixels.
    pub height: u32,
    /// The divisor of each side it was rendered at.
    pub divisor: u32,
    /// Its render time, denoising included.
    pub took: Duration,
    /// The denoiser's share of `took`, if the frame was denoised.
    pub denoising: Option<Duration>,
    /// 8-bit RGBA, row by row (as the page's `ImageData` wants it), shared by every reader.
    pub rgba: Arc<[u8]>,
}

/// Renders `config`'s scene at `1/divisor` of each side, 1 sample per pixel, on `pool`, and
/// denoises it if `config.denoise`; `None` if `cancel` stopped it.
pub fn render_preview(
    generation: u64,
    config: &Config,
    divisor: u32,
    pool: &KeptPool,
    cancel: &Cancel,
) -> Option<Preview> {
    let full = config.job.settings;
    let settings = RenderSettings {
        width: full.width.div_ceil(divisor),
        height: full.height.div_ceil(divisor),
        spp: 1,
        ..full
    };
    let job = config.job.with_camera(&config.scene.camera, settings);
    let rng = RngSource::new(&settings, config.rng);
    let frame = Frame::new(job.clone(), rng, config.threads, config.tile, Arc::new(|_| {}))
        .with_cancel(cancel.clone());
    let started = Instant::now();
    let mut image = render(&Arc::new(frame), &pool.with_mode(config.mode)).image;
    if cancel.is_cancelled() {
        return None;
    }
    let denoising = config.denoise.then(|| {
        let start = Instant::now();
        image = denoise(&job, &image, config.threads);
        start.elapsed()
    });
    let took = started.elapsed();
    let rgba = rgba(&image).into();
    let (width, height) = (settings.width, settings.height);
    Some(Preview { generation, width, height, divisor, took, denoising, rgba })
}

/// Waits [`REFINE_AFTER`]; `false` if `cancel` (the next move) came first.
pub fn camera_rested(cancel: &Cancel) -> bool {
    let start = Instant::now();
    while start.elapsed() < REFINE_AFTER {
        if cancel.is_cancelled() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    !cancel.is_cancelled()
}

/// `image` as 8-bit RGBA, gamma as in the PNG files.
fn rgba(image: &Image) -> Vec<u8> {
    image.to_rgb8().chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect()
}
