//! The one render loop: [`render_tile`] traces every sample of every pixel of a [`Tile`].
//!
//! Every scheduler (serial, static split, pools…) only decides which thread calls
//! `render_tile` on which tile; none of them has a render loop of its own. Because a pixel's
//! value depends only on the scene, the settings and its own random streams (see
//! `sampler.rs`), the image is bit-identical whatever the schedule.

use crate::camera::Camera;
use crate::frame::TileTiming;
use crate::ray::Ray;
use crate::real::{Real, Vec3};
use crate::sampler::RandomStreams;
use crate::scene::Scene;

/// Image size and sampling parameters of one render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum rays per path (camera ray included): the book's `max_depth`.
    pub max_depth: u32,
    /// Seed of every pixel sample's random stream.
    pub seed: u64,
}

/// A rectangle of pixels: columns `x..x + width`, rows `y..y + height` (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tile {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Tile {
    /// The tile of whole rows `rows.start..rows.end` of an image `width` wide.
    pub fn rows(width: u32, rows: std::ops::Range<u32>) -> Tile {
        Tile { x: 0, y: rows.start, width, height: rows.end - rows.start }
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        self.width as usize * self.height as usize
    }
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
    /// Which thread rendered it, and when (set by [`Frame::render`](crate::frame::Frame::render)).
    pub timing: Option<TileTiming>,
}

/// Everything a tile needs, immutable for the whole render (shareable between threads).
#[derive(Clone, Debug)]
pub struct RenderJob {
    /// The scene.
    pub scene: Scene,
    /// The camera, set up for `settings`' image size.
    pub camera: Camera,
    /// Size and sampling.
    pub settings: RenderSettings,
}

impl RenderJob {
    /// Prepares a render of `scene` with `settings`.
    pub fn new(scene: Scene, settings: RenderSettings) -> RenderJob {
        let camera = Camera::new(&scene.camera, settings.width, settings.height);
        RenderJob { scene, camera, settings }
    }
}

/// Renders every pixel of `tile`, drawing each sample's random numbers from `streams`.
pub fn render_tile<S: RandomStreams>(job: &RenderJob, streams: &S, tile: Tile) -> TileOutput {
    let RenderSettings { width, spp, max_depth, .. } = job.settings;
    let mut pixels = Vec::with_capacity(tile.area());
    let mut rays = 0;
    for j in tile.y..tile.y + tile.height {
        for i in tile.x..tile.x + tile.width {
            let pixel = j as u64 * width as u64 + i as u64;
            let mut sum = Vec3::ZERO;
            for sample in 0..spp {
                let mut rng = streams.stream(pixel, sample as u64);
                let ray = job.camera.ray(i, j, &mut rng);
                sum += trace(&job.scene, ray, max_depth, &mut rng, &mut rays);
            }
            pixels.push(sum / spp as Real);
        }
    }
    TileOutput { tile, pixels, rays, timing: None }
}

/// The radiance arriving along `ray`: the book's `ray_color`, as a loop. A path casts at
/// most `max_depth` rays; one still bouncing after that contributes black. Adds the number
/// of rays cast to `rays`.
pub fn trace<R: rand::Rng + ?Sized>(
    scene: &Scene,
    mut ray: Ray,
    max_depth: u32,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let mut throughput = Vec3::ONE;
    for _ in 0..max_depth {
        *rays += 1;
        let Some(hit) = scene.hit(&ray, Real::INFINITY) else {
            return throughput * scene.background.radiance(ray.dir);
        };
        let Some(scatter) = scene.material(&hit).scatter(ray.dir, &hit, rng) else {
            return Vec3::ZERO;
        };
        throughput *= scatter.attenuation;
        ray = hit.spawn(scatter.direction);
    }
    Vec3::ZERO
}
