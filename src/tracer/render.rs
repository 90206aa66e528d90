//! The one render loop: [`render_tile`] traces every sample of every pixel of a [`Tile`]. (The
//! `raypool render` command is `src/cli/render.rs`, which schedules calls of this loop.)
//!
//! Every scheduler (serial, static split, pools…) only decides which thread calls
//! `render_tile` on which tile; none of them has a render loop of its own. Because a pixel's
//! value depends only on the scene, the settings and its own random streams (see
//! `sampling/`), the image is bit-identical whatever the schedule.

use std::sync::Arc;
use std::thread::ThreadId;
use std::time::Duration;

use crate::error::Error;
use crate::tracer::bidir::connect::{Bidir, Paths};
use crate::tracer::bidir::splat::Splats;
use crate::tracer::camera::{Camera, CameraSettings};
use crate::tracer::geometry::hit::Hit;
use crate::tracer::lighting::manifold::{self, Passing, manifold_event};
use crate::tracer::lighting::{
    LightSampling, SHADOW_KEY, glint, lobe_pdf, mixture_bounce, next_event, power_heuristic,
};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, to_dvec3};
use crate::tracer::sampling::independent::{PerSample, mix};
use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams, SampleRng, Sampler};
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::Lobe;
pub use crate::tracer::tile::PixelSums;
use crate::tracer::tile::Tile;
use crate::tracer::world::object::Probe;

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
}

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
        }
    }
}

/// Mixed into the render seed for the media's numbers, so they are not any stream's.
const MEDIA_KEY: u64 = 0x6D65_6469_6100_0000;

/// Mixed into the render seed for the light paths' streams (`--light-sampling bdpt`).
const LIGHT_PATHS_KEY: u64 = 0x6C69_6768_7473_0000;

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
}

impl RenderJob {
    /// Prepares a render of `scene` with `settings`.
    pub fn new(scene: Scene, settings: RenderSettings) -> RenderJob {
        let camera = Camera::new(&scene.camera, settings.width, settings.height);
        RenderJob { scene: Arc::new(scene), camera, settings }
    }

    /// The same scene, shared, not rebuilt, seen by `camera` with `settings`: how the viewer
    /// moves the camera or renders a smaller frame without building the scene's tree again.
    pub fn with_camera(&self, camera: &CameraSettings, settings: RenderSettings) -> RenderJob {
        let scene = Arc::clone(&self.scene);
        RenderJob { scene, camera: Camera::new(camera, settings.width, settings.height), settings }
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
    let light_streams = PerSample { seed: mix(job.settings.seed ^ LIGHT_PATHS_KEY) };
    let mut paths = Paths::default();
    let pixels =
        (tile.y..tile.y + tile.height).flat_map(|j| (tile.x..tile.x + tile.width).map(move |i| (i, j)));
    for (k, (i, j)) in pixels.enumerate() {
        let pixel_streams = streams.pixel(j as u64 * width + i as u64);
        let light_pixel = bidir.map(|_| light_streams.pixel(j as u64 * width + i as u64));
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
            let start = Probe { time, medium_seed: path };
            let value = match (&bidir, &light_pixel) {
                (Some(bidir), Some(light_pixel)) => {
                    let mut light_rng = light_pixel.stream(sample as u64);
                    bidir.sample(
                        ray,
                        start,
                        &mut rng,
                        &mut light_rng,
                        &mut paths,
                        &mut sums.splats,
                        &mut rays,
                    )
                }
                _ => trace::<_, WORLD>(
                    &job.scene,
                    &closest_hit,
                    ray,
                    start,
                    &job.settings,
                    &mut rng,
                    &mut rays,
                ),
            };
            let value = to_dvec3(value);
            sums.add(k, sample, value);
        }
    }
    rays
}

/// The radiance arriving along `ray`: the book's `ray_color`, as a loop. A path casts at most
/// `settings.max_depth` rays; one still bouncing after that contributes black. Adds the number
/// of rays cast to `rays`. Forced inline into the render loop: left to the compiler, `final`
/// took 1.8% more instructions (`results/perf.md`).
///
/// Without `WORLD` (a first-book scene), each ray's closest hit is found by `closest_hit` (the
/// scene's sphere search, `|ray| scene.hit(ray, Real::INFINITY)`, except in the Embree
/// benchmark), and nothing emits. With `WORLD`, the scene's world is searched with a
/// [`Probe`] carrying `time` (and, in a scene with media, a seed drawn for each ray), and every
/// surface hit adds what it emits, weighted by the path's throughput.
#[inline(always)]
pub fn trace<R: SampleRng + ?Sized, const WORLD: bool>(
    scene: &Scene,
    closest_hit: &impl Fn(&Ray) -> Option<Hit>,
    mut ray: Ray,
    start: Probe,
    settings: &RenderSettings,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    // Where the lights are sampled (a second-book scene with lights, and not `bsdf`).
    let aiming =
        if WORLD && !scene.lights().is_empty() { settings.light_sampling } else { LightSampling::Bsdf };
    // The previous hit's point and its material's density for the bounce that led here, if
    // that bounce was weighed against a light sample (MIS): an emitter it reaches is then
    // weighted by the power heuristic. Otherwise an emitter counts whole.
    let mut weighed: Option<(Vec3, Real)> = None;
    // Under `mis`, with glass balls and lights: each diffuse hit also aims at a light through
    // a ball (`lighting/manifold.rs`), and its bounce is followed through a ball to weigh a
    // light it meets there against that.
    let caustics = WORLD && aiming == LightSampling::Mis && !scene.casters().is_empty();
    let mut passing: Option<Passing> = None;
    // The weight of the light met next: below 1 after glass reflected the path (under `mis`,
    // `lighting::glint` counts that light).
    let mut mirrored = 1.0;
    for cast in 1..=settings.max_depth {
        *rays += 1;
        let medium_seed =
            if WORLD && scene.has_media() { mix(start.medium_seed ^ u64::from(cast)) } else { 0 };
        let found =
            if WORLD { scene.hit_world(&ray, &Probe { medium_seed, ..start }) } else { closest_hit(&ray) };
        let Some(hit) = found else {
            let sky = throughput * scene.background.radiance(ray.dir);
            return if WORLD { radiance + sky } else { sky };
        };
        rng.bounce(cast - 1);
        let material = scene.material(&hit);
        if WORLD {
            let emitted = material.emitted(&hit);
            let weight = match (weighed, passing) {
                _ if emitted == Vec3::ZERO => 1.0,
                (Some((from, bsdf_pdf)), _) => {
                    power_heuristic(bsdf_pdf, scene.lights().pdf_of_hit(from, &hit, emitted, start.time))
                }
                (None, Some(passing)) => passing.weight(scene, &hit, emitted),
                (None, None) => 1.0,
            };
            radiance += throughput * emitted * (weight * mirrored);
            mirrored = 1.0;
        }
        let Some(mut scatter) = material.scatter(ray.dir, &hit, &scene.textures, rng) else {
            return radiance;
        };
        weighed = None;
        // Not on a path's last ray: the reflection could not have met a light either.
        if aiming == LightSampling::Mis && cast < settings.max_depth {
            let probe = Probe { medium_seed, ..start };
            let (shown, next) = glint(scene, (&hit, material), (ray.dir, scatter.direction), probe, rays);
            (radiance, mirrored) = (radiance + throughput * shown, next);
        }
        // Tested first, so that a first-book scene (always `Bsdf`) has no further work here.
        let lobe = if aiming == LightSampling::Bsdf { None } else { material.lobe() };
        if caustics {
            passing = if lobe.is_some() {
                None
            } else {
                passing.and_then(|p| p.next(scene, &hit, scatter.direction))
            };
        }
        if let Some(lobe) = lobe {
            rng.light(cast - 1);
            match aiming {
                LightSampling::Mis if cast < settings.max_depth => {
                    let shadow = Probe { medium_seed: medium_seed ^ SHADOW_KEY, ..start };
                    let direct = next_event(scene, &hit, lobe, shadow, rng, rays);
                    radiance += throughput * scatter.attenuation * direct;
                    let bsdf_pdf = lobe_pdf(lobe, scatter.direction, hit.normal);
                    weighed = Some((hit.departure(), bsdf_pdf));
                    if caustics && lobe == Lobe::Cosine && cast + manifold::RAYS <= settings.max_depth {
                        // Fewer solves where the path carries little (`lighting/manifold.rs`).
                        let carried = throughput * scatter.attenuation;
                        let chance = (2.0 * carried.max_element()).min(1.0);
                        let focused = manifold_event(scene, &hit, (cast - 1, chance), shadow, rng, rays);
                        radiance += carried * focused;
                        let taken = (cast - 1, chance);
                        passing =
                            Some(Passing::leave(scene, hit.departure(), scatter.direction, bsdf_pdf, taken));
                    }
                }
                LightSampling::Mixture => {
                    let goes_on = mixture_bounce(scene.lights(), &hit, start.time, lobe, &mut scatter, rng);
                    if !goes_on {
                        return radiance;
                    }
                }
                _ => {}
            }
        }
        throughput *= scatter.attenuation;
        if settings.stop_black_paths && throughput == Vec3::ZERO {
            return radiance;
        }
        if settings.roulette && cast >= ROULETTE_AFTER {
            let survive = throughput.max_element().min(0.95);
            if uniform(rng) >= survive {
                return radiance;
            }
            throughput /= survive;
        }
        ray = hit.spawn(scatter.direction);
    }
    radiance
}
