//! The one render loop: [`render_tile`] traces every sample of every pixel of a [`Tile`]. (The
//! `raypool render` command is `src/cli/render.rs`, which schedules calls of this loop.)
//!
//! Every scheduler (serial, static split, pools…) only decides which thread calls
//! `render_tile` on which tile; none of them has a render loop of its own. Because a pixel's
//! value depends only on the scene, the settings and its own random streams (see
//! `sampling/`), the image is bit-identical whatever the schedule.
//!
//! One part lives beside it: [`path`], one sample's path (the book's `ray_color`). Where a
//! pixel may see a light, a sample also takes the extra camera points of
//! [`crate::tracer::lighting::edges::Edges`].

pub mod path;

use std::sync::Arc;
use std::thread::ThreadId;
use std::time::Duration;

use crate::error::Error;
use crate::tracer::bidir::connect::{Bidir, Paths, Streams};
use crate::tracer::camera::{Camera, CameraSettings};
use crate::tracer::geometry::hit::Hit;
use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::learning::Learning;
use crate::tracer::guiding::trail::Trail;
use crate::tracer::guiding::{Guiding, takes};
use crate::tracer::lighting::edges::Edges;
use crate::tracer::lights::LightSampling;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, to_dvec3};
use crate::tracer::sampling::independent::{PerSample, mix};
use crate::tracer::sampling::keys::{LIGHT_PATHS_KEY, MEDIA_KEY};
use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams, Sampler};
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::splats::Splats;
pub use crate::tracer::tile::PixelSums;
use crate::tracer::tile::Tile;
use crate::tracer::world::object::Probe;
use path::{CameraRay, Guided, trace};

/// Largest accepted image side, pixels (the command line and every other entry point check it).
pub const MAX_SIDE: u32 = 16384;

/// The height that gives `aspect` (width ÷ height) at `width`, at least 1 pixel.
pub fn default_height(width: u32, aspect: f64) -> Result<u32, Error> {
    let h = (width as f64 / aspect).round().max(1.0);
    if h > MAX_SIDE as f64 {
        return Err(Error::new(format!(
            "height {h} (width ÷ camera.aspect) is above {MAX_SIDE}: pass --height"
        )));
    }
    Ok(h as u32)
}

/// Image size and sampling parameters of one render.
///
/// ```
/// use raypool::tracer::render::RenderSettings;
/// let settings = RenderSettings { width: 64, height: 48, spp: 8, ..RenderSettings::default() };
/// assert!(settings.stop_black_paths && !settings.roulette && settings.adaptive.is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Samples per pixel; with [`RenderSettings::adaptive`], the most a pixel may take.
    pub spp: u32,
    /// Maximum rays per path (camera ray included): the book's `max_depth`.
    pub max_depth: u32,
    /// Seed of every pixel sample's random stream.
    pub seed: u64,
    /// End a path whose throughput is exactly black: nothing it meets can add light, so
    /// the image is unchanged (only fewer rays are cast). On by default.
    pub stop_black_paths: bool,
    /// Russian roulette after [`ROULETTE_AFTER`] rays: a path survives with probability
    /// `p` = its largest throughput channel (at most 0.95) and is weighted by `1/p`, so the
    /// mean image is unchanged while dim paths end early. Off by default (it changes the
    /// noise, so images differ from those without it).
    pub roulette: bool,
    /// Adaptive sampling; `None` for `spp` samples in every pixel.
    pub adaptive: Option<Adaptive>,
    /// Which numbers the samples draw: independent, or a scrambled Sobol sequence per pixel.
    pub sampler: Sampler,
    /// How a path at a diffuse surface finds the scene's lights (a scene without lights
    /// ignores it).
    pub light_sampling: LightSampling,
    /// Extra points per sample, in the pixels that may see a light, for the light they see
    /// directly ([`Edges`]); 0 for none. [`EDGE_SPOTS`] by default.
    pub edge_spots: u32,
    /// Path guiding, in passes that learn where light comes from (`--guiding on`); `None`
    /// (the default) for none.
    pub guiding: Option<Guiding>,
}

/// The edge points each sample takes where a pixel may see a light: past 16, more buy little
/// (on `cornell`: `results/lights.md`).
pub const EDGE_SPOTS: u32 = 16;

impl Default for RenderSettings {
    /// The command line's defaults: 400 × 267, 32 spp, depth 50, seed 1, the default sampler.
    fn default() -> RenderSettings {
        RenderSettings {
            width: 400,
            height: 267,
            spp: 32,
            max_depth: 50,
            seed: 1,
            stop_black_paths: true,
            roulette: false,
            adaptive: None,
            sampler: Sampler::default(),
            light_sampling: LightSampling::default(),
            edge_spots: EDGE_SPOTS,
            guiding: None,
        }
    }
}

/// Russian roulette starts once a path has cast this many rays (its first bounces are
/// where most of its light comes from, so they are never cut).
pub const ROULETTE_AFTER: u32 = 4;

/// Adaptive sampling, in two whole-image passes (see [`crate::schedule::adaptive`]): every
/// pixel takes `min_spp` samples (the pilot), then the samples it was given from its
/// neighbours' pilot, up to the settings' `spp`. A pixel whose 3 × 3 neighbours' two
/// half-estimates (even and odd samples) differ on average by `k × target_error × √brightness`
/// takes `k × min_spp` samples (at least `min_spp`): samples in proportion to the noise, so
/// halving `target_error` doubles the samples of every pixel above `min_spp`. Its own samples
/// never decide its count, which keeps the image's mean unbiased.
///
/// ```
/// use raypool::tracer::render::Adaptive;
/// let adaptive = Adaptive { target_error: 0.02, min_spp: 16 };
/// assert!(adaptive.target_error > 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    /// The neighbours' half-estimate difference, relative to √brightness, at which a pixel
    /// takes only `min_spp` samples (e.g. 0.05).
    pub target_error: Real,
    /// Samples every pixel takes first, the pilot (rounded up to an even number).
    pub min_spp: u32,
}

/// A rendered tile: its pixels (row-major, linear RGB means) and how many rays it cast.
#[derive(Clone, Debug, PartialEq)]
pub struct TileOutput {
    /// Which tile.
    pub tile: Tile,
    /// `tile.area()` pixel values, row-major.
    pub pixels: Vec<Vec3>,
    /// Every ray cast: camera rays and each bounce.
    pub rays: u64,
    /// Camera samples taken (`spp × area`, or fewer with adaptive sampling).
    pub samples: u64,
    /// Light its samples' light paths carried to the camera, in any pixel of the image
    /// (`--light-sampling bdpt`; empty otherwise): added to the image once every tile is in,
    /// divided by the samples per pixel.
    pub splats: Splats,
    /// Which thread rendered it, and when (set by [`Frame::render`](crate::schedule::frame::Frame::render)).
    pub timing: Option<TileTiming>,
}

/// When and on which thread a tile was rendered (relative to the frame's start).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileTiming {
    /// The rendering thread.
    pub thread: ThreadId,
    /// Start, since the frame was created.
    pub start: Duration,
    /// End, since the frame was created.
    pub end: Duration,
}

/// Everything a tile needs, immutable for the whole render (shareable between threads).
#[derive(Clone, Debug)]
pub struct RenderJob {
    /// The scene, shared by the jobs that see it from other cameras or at other sizes (its
    /// own `camera` is the one [`RenderJob::new`] used, not necessarily this job's).
    pub scene: Arc<Scene>,
    /// The camera, set up for `settings`' image size.
    pub camera: Camera,
    /// Size and sampling.
    pub settings: RenderSettings,
    /// The guide a guided pass draws its bounces from (`guiding/`); `None` otherwise.
    pub guide: Option<Arc<Guide>>,
    /// What a guided pass learns into; `None` if it learns nothing.
    pub learning: Option<Arc<Learning>>,
}

impl RenderJob {
    /// Prepares a render of `scene` with `settings`.
    pub fn new(scene: Scene, settings: RenderSettings) -> RenderJob {
        let camera = Camera::new(&scene.camera, settings.width, settings.height);
        RenderJob { scene: Arc::new(scene), camera, settings, guide: None, learning: None }
    }

    /// The same scene, shared, not rebuilt, seen by `camera` with `settings`: how the viewer
    /// moves the camera or renders a smaller frame without building the scene's tree again.
    pub fn with_camera(&self, camera: &CameraSettings, settings: RenderSettings) -> RenderJob {
        let scene = Arc::clone(&self.scene);
        let camera = Camera::new(camera, settings.width, settings.height);
        RenderJob { scene, camera, settings, guide: None, learning: None }
    }

    /// The same job (its scene shared) as one pass of a guided render: drawing bounces from
    /// `guide`, learning into `learning`.
    pub fn guided(&self, guide: Option<Arc<Guide>>, learning: Option<Arc<Learning>>) -> RenderJob {
        RenderJob { guide, learning, ..self.clone() }
    }
}

/// Renders every pixel of `tile`, drawing each sample's random numbers from `streams`.
pub fn render_tile<S: RandomStreams>(job: &RenderJob, streams: &S, tile: Tile) -> TileOutput {
    render_tile_with(job, streams, tile, |ray| job.scene.hit(ray, Real::INFINITY))
}

/// [`render_tile`], with each ray's closest hit found by `closest_hit` instead of the scene's
/// own search: how `cargo bench --bench embree` traces the same paths over another library's
/// hierarchy. Materials, background and camera are still the job's. For a first-book scene
/// only (a second-book scene's world searches itself, and `closest_hit` is not called).
pub fn render_tile_with<S: RandomStreams>(
    job: &RenderJob,
    streams: &S,
    tile: Tile,
    closest_hit: impl Fn(&Ray) -> Option<Hit>,
) -> TileOutput {
    let mut sums = PixelSums::new(tile.area());
    let rays = accumulate(job, streams, tile, |_, _| 0..job.settings.spp, &mut sums, closest_hit);
    let splats = std::mem::take(&mut sums.splats);
    TileOutput { tile, pixels: sums.means(), rays, samples: sums.samples(), splats, timing: None }
}

/// Adds samples `samples(i, j)` (sample numbers, for example `0..1`, then `1..4`; an empty
/// range for a pixel that takes none) of every pixel `(i, j)` of `tile` to `sums` (the tile's
/// pixels, row-major), drawing from `streams`; returns the rays cast. This is the one render
/// loop: [`render_tile`] is one call of it for `0..spp`, the viewer's progressive passes and
/// adaptive sampling's passes are successive calls.
///
/// # Panics
/// If `sums` does not hold `tile.area()` pixels.
pub fn accumulate_tile<S: RandomStreams>(
    job: &RenderJob,
    streams: &S,
    tile: Tile,
    samples: impl Fn(u32, u32) -> std::ops::Range<u32>,
    sums: &mut PixelSums,
) -> u64 {
    accumulate(job, streams, tile, samples, sums, |ray| job.scene.hit(ray, Real::INFINITY))
}

/// [`accumulate_tile`] with the closest-hit search of a first-book scene passed in (the
/// scene's, or another library's). The one pixel loop, in two instantiations chosen once per
/// call: a first-book scene's paths ([`trace`] without the world's work), or a second-book
/// scene's (emission, textures, time and media; `closest_hit` is then unused: its world has
/// its own search).
fn accumulate<S: RandomStreams>(
    job: &RenderJob,
    streams: &S,
    tile: Tile,
    samples: impl Fn(u32, u32) -> std::ops::Range<u32>,
    sums: &mut PixelSums,
    closest_hit: impl Fn(&Ray) -> Option<Hit>,
) -> u64 {
    if job.scene.is_first_book() {
        accumulate_paths::<S, false>(job, streams, tile, samples, sums, closest_hit)
    } else {
        accumulate_paths::<S, true>(job, streams, tile, samples, sums, closest_hit)
    }
}

/// The pixel loop: every sample of every pixel of `tile` through [`trace`], second-book work
/// included if `WORLD`.
#[inline(always)]
fn accumulate_paths<S: RandomStreams, const WORLD: bool>(
    job: &RenderJob,
    streams: &S,
    tile: Tile,
    samples: impl Fn(u32, u32) -> std::ops::Range<u32>,
    sums: &mut PixelSums,
    closest_hit: impl Fn(&Ray) -> Option<Hit>,
) -> u64 {
    assert_eq!(sums.len(), tile.area(), "one running sum per pixel of the tile");
    let width = job.settings.width as u64;
    let mut rays = 0;
    // Bidirectional samples where asked for and the scene has lights to start from.
    let bidir = (WORLD
        && job.settings.light_sampling == LightSampling::Bdpt
        && !job.scene.lights().is_empty())
    .then(|| Bidir {
        scene: &job.scene,
        camera: &job.camera,
        max_depth: job.settings.max_depth,
        width: job.settings.width,
    });
    let spots = if WORLD && bidir.is_none() { job.settings.edge_spots } else { 0 };
    let edges = Edges::new(&job.scene, &job.camera, spots);
    let light_streams = PerSample { seed: mix(job.settings.seed ^ LIGHT_PATHS_KEY) };
    let mut paths = Paths::default();
    // A guided pass's guide and statistics, where the scene takes a guide (and the bounce is
    // not the third book's mixture, which draws its own).
    let guiding = WORLD
        && bidir.is_none()
        && job.settings.light_sampling != LightSampling::Mixture
        && takes(&job.scene);
    let guide = job.guide.as_deref().filter(|_| guiding);
    let learning = job.learning.as_deref().filter(|_| guiding);
    let mut trail = Trail::default();
    let pixels =
        (tile.y..tile.y + tile.height).flat_map(|j| (tile.x..tile.x + tile.width).map(move |i| (i, j)));
    for (k, (i, j)) in pixels.enumerate() {
        let pixel_streams = streams.pixel(j as u64 * width + i as u64);
        let light_pixel = bidir.map(|_| light_streams.pixel(j as u64 * width + i as u64));
        let at_edges = edges.covers(i, j);
        for sample in samples(i, j) {
            let mut rng = pixel_streams.stream(sample as u64);
            let ray = job.camera.ray(i, j, &mut rng);
            // The shutter time, drawn only where something moves (after the camera's numbers,
            // so a still scene's numbers are those it always drew).
            let time = if WORLD && job.scene.has_motion() { uniform(&mut rng) } else { 0.0 };
            // Media draw from the path's identity, not from its stream: a medium (even one of
            // density 0) changes no other number the path draws.
            let path = if WORLD && job.scene.has_media() {
                mix(mix(job.settings.seed ^ MEDIA_KEY) ^ (j as u64 * width + i as u64))
                    ^ u64::from(sample) << 32
            } else {
                0
            };
            let start = Probe { time, medium_seed: path, isa: job.scene.isa() };
            let value = match (&bidir, &light_pixel) {
                (Some(bidir), Some(light_pixel)) => {
                    let mut light_rng = light_pixel.stream(sample as u64);
                    let streams = Streams { camera: &mut rng, light: &mut light_rng };
                    bidir.sample(ray, start, streams, &mut paths, &mut sums.splats, &mut rays)
                }
                _ => {
                    let guided = Guided { guide, trail: learning.map(|_| &mut trail) };
                    let traced = trace::<_, WORLD>(
                        &job.scene,
                        &closest_hit,
                        CameraRay { ray, start, first_light: !at_edges },
                        &job.settings,
                        guided,
                        &mut rng,
                        &mut rays,
                    );
                    if let Some(learning) = learning {
                        trail.learn(learning, traced);
                    }
                    // Where a pixel may see a light, its edge points count the light the
                    // camera ray meets first, in place of the path's (`lighting/edges.rs`).
                    if at_edges {
                        traced + edges.light(ray.origin, i, j, start, &mut rng, &mut rays)
                    } else {
                        traced
                    }
                }
            };
            let value = to_dvec3(value);
            sums.add(k, sample, value);
        }
    }
    rays
}
