//! Run time against error: how far a render is from the converged image, and how fast that
//! distance falls as samples are added.
//!
//! Monte Carlo error falls as 1/√spp: on a log–log plot of RMSE against spp, a line of slope
//! −1/2. A renderer whose slope is flatter is biased (its error stops falling) or correlated
//! (its samples are not independent); steeper means the measurement is wrong.
//!
//! The reference is itself a render, of two independent halves with different seeds. Their
//! difference measures the reference's own noise, which is then taken out of every measured
//! error: `E|X − R|² = σ²(X) + σ²(R)` for independent X and R, so
//! `RMSE(X) = √(RMSE(X, R)² − σ²(R))`.

use std::sync::Arc;
use std::time::Instant;

use crate::files::image::Image;
use crate::measure::compare::{metrics, relative_weight};
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Rendered, Schedule, render};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::math::real::to_f32;
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::scene::Scene;

/// Seeds of the reference's two halves: far from the small seeds measured renders use.
const REFERENCE_SEEDS: [u64; 2] = [1_000_001, 1_000_002];

/// A converged image and how noisy it still is.
#[derive(Clone, Debug)]
pub struct Reference {
    /// The mean of the two halves.
    pub image: Image,
    /// The two halves (kept so that they can be cached and reloaded).
    halves: [Image; 2],
    /// Samples per pixel, both halves together.
    pub spp: u32,
    /// Its own RMSE, estimated from the two halves: `RMSE(a, b) / 2`.
    pub noise: f64,
}

impl Reference {
    /// The reference made of two independent halves (rendered with different seeds).
    ///
    /// ```
    /// # use raypool::{files::image::Image, measure::convergence::Reference, tracer::math::real::Vec3};
    /// let half = |v: f32| Image { width: 1, height: 1, pixels: vec![Vec3::splat(v.into())] };
    /// let r = Reference::from_halves(&half(0.4), &half(0.6), 64);
    /// assert!((r.noise - 0.1).abs() < 1e-6 && r.spp == 128);
    /// ```
    pub fn from_halves(a: &Image, b: &Image, spp_each: u32) -> Reference {
        let pixels = a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p + *q) * 0.5).collect();
        let image = Image { width: a.width, height: a.height, pixels };
        Reference { image, halves: [a.clone(), b.clone()], spp: 2 * spp_each, noise: rmse(a, b) / 2.0 }
    }

    /// The two independent halves it was made of.
    pub fn halves(&self) -> &[Image; 2] {
        &self.halves
    }

    /// Renders `scene` at `settings`' size, `spp_each` samples per pixel per half.
    pub fn render(scene: &Scene, settings: RenderSettings, spp_each: u32, threads: usize) -> Reference {
        let half = |seed| {
            let settings = RenderSettings { spp: spp_each, seed, adaptive: None, ..settings };
            timed_render(scene.clone(), settings, threads).0.image
        };
        Reference::from_halves(&half(REFERENCE_SEEDS[0]), &half(REFERENCE_SEEDS[1]), spp_each)
    }

    /// The RMSE of `image` against the converged image: measured against this reference,
    /// with the reference's own noise taken out (0 if the measurement is below it).
    pub fn error_of(&self, image: &Image) -> f64 {
        (rmse(image, &self.image).powi(2) - self.noise.powi(2)).max(0.0).sqrt()
    }

    /// The relative MSE of `image` (pbrt's and the denoising literature's measure): the mean
    /// over pixels and channels of (x − r)² / (r² + 0.01), so dark pixels' errors count as much
    /// as bright ones'. The reference's own share, (a − b)²/4 weighted alike, is taken out
    /// (0 if the measurement is below it).
    pub fn rel_mse_of(&self, image: &Image) -> f64 {
        let reference = rgb(&self.image);
        let error = metrics(&rgb(image), &reference).rel_mse;
        let [a, b] = &self.halves;
        let halves = rgb(a).into_iter().flatten().zip(rgb(b).into_iter().flatten());
        let noise: f64 = halves
            .zip(reference.iter().flatten())
            .map(|((a, b), &r)| relative_weight(f64::from(r)) * (f64::from(a) - f64::from(b)).powi(2) / 4.0)
            .sum();
        (error - noise / (reference.len() * 3).max(1) as f64).max(0.0)
    }
}

/// Renders with the work-stealing scheduler on `threads` threads; returns the render and its
/// wall time in seconds.
pub fn timed_render(scene: Scene, settings: RenderSettings, threads: usize) -> (Rendered, f64) {
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, threads, 16, Arc::new(|_| {})));
    let start = Instant::now();
    let rendered = render(&frame, &Schedule::Stealing);
    (rendered, start.elapsed().as_secs_f64())
}

/// Root mean squared difference over every channel of every pixel.
pub fn rmse(a: &Image, b: &Image) -> f64 {
    metrics(&rgb(a), &rgb(b)).rmse
}

/// An image's pixels as f32 RGB triples, as [`metrics`] takes them.
fn rgb(image: &Image) -> Vec<[f32; 3]> {
    image.pixels.iter().map(|p| [to_f32(p.x), to_f32(p.y), to_f32(p.z)]).collect()
}

/// The power law `y = c · x^k` that fits `points` best in log–log space (least squares):
/// returns `(k, ln c)`.
///
/// ```
/// let points: Vec<(f64, f64)> = [1.0, 4.0, 16.0].iter().map(|&n| (n, 0.3 / f64::sqrt(n))).collect();
/// let (slope, log_c) = raypool::measure::convergence::log_log_fit(&points);
/// assert!((slope + 0.5).abs() < 1e-12 && (log_c - 0.3f64.ln()).abs() < 1e-12);
/// ```
pub fn log_log_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = logs.iter().fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x / n, sy + y / n));
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}
