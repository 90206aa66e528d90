//! Do two estimators render the same mean image? Each is rendered under independent seeds;
//! per square block of pixels, and for the whole image, the mean over the seeds and its
//! standard error come from the spread between the seeds' renders, never from within one
//! image (the estimators are heavy-tailed: a pixel's samples say little about its mean's
//! error). Two estimates then differ by `z` combined standard errors, and a bias is seen
//! only if it exceeds `4.5` of them: the comparison's power, stated with every verdict.
//! `tests/agreement.rs` asserts with it; `benches/accuracy.rs` writes `results/accuracy.md`.

use std::sync::Arc;

use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, render};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::scene::Scene;

/// How many standard errors a bias must reach to be seen in a block (and in the whole
/// image, [`WHOLE_Z`]): a block's limit allows for the many blocks compared.
pub const BLOCK_Z: f64 = 4.5;
/// See [`BLOCK_Z`].
pub const WHOLE_Z: f64 = 4.0;

/// The grey means of an image's `side` × `side` blocks, row by row, then the whole image's.
///
/// ```
/// use raypool::files::image::Image;
/// use raypool::measure::agreement::block_means;
/// use raypool::tracer::math::real::Vec3;
/// let pixels = (0..16).map(|k| Vec3::splat(if k % 4 < 2 { 1.0 } else { 0.0 })).collect();
/// let image = Image { width: 4, height: 4, pixels };
/// assert_eq!(block_means(&image, 2), vec![1.0, 0.0, 1.0, 0.0, 0.5]);
/// ```
pub fn block_means(image: &Image, side: u32) -> Vec<f64> {
    let across = image.width.div_ceil(side);
    let blocks = (across * image.height.div_ceil(side)) as usize;
    let (mut sums, mut counts) = (vec![0.0; blocks + 1], vec![0usize; blocks + 1]);
    for (k, pixel) in image.pixels.iter().enumerate() {
        let (x, y) = (k as u32 % image.width, k as u32 / image.width);
        let grey = (f64::from(pixel.x) + f64::from(pixel.y) + f64::from(pixel.z)) / 3.0;
        for b in [(y / side * across + x / side) as usize, blocks] {
            sums[b] += grey;
            counts[b] += 1;
        }
    }
    sums.iter().zip(&counts).map(|(s, &n)| s / n as f64).collect()
}

/// One region's mean over the seeds and the standard error of that mean.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The mean over the seeds.
    pub mean: f64,
    /// Its standard error, from the spread between the seeds.
    pub error: f64,
}

/// Per region (as [`block_means`] lists them), the estimate over `renders`, one per seed.
pub fn over_seeds(renders: &[Vec<f64>]) -> Vec<Estimate> {
    let n = renders.len() as f64;
    (0..renders.first().map_or(0, Vec::len))
        .map(|b| {
            let mean = renders.iter().map(|r| r[b]).sum::<f64>() / n;
            let variance = renders.iter().map(|r| (r[b] - mean).powi(2)).sum::<f64>() / (n - 1.0);
            Estimate { mean, error: (variance / n).sqrt() }
        })
        .collect()
}

/// How one estimator's regions compare with a reference's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Agreement {
    /// The whole image's bias, a share of the reference's mean.
    pub whole_bias: f64,
    /// Its standard error, as a share of the reference's mean.
    pub whole_error: f64,
    /// The largest `|z|` of a block (a block that neither estimate renders with any noise
    /// counts 0 if the two agree to a millionth, else infinity).
    pub worst_z: f64,
    /// The block with the largest `|z|`.
    pub worst_block: usize,
    /// The smallest bias a block must have to be seen ([`BLOCK_Z`] standard errors), as a
    /// share of its mean: the weakest block's.
    pub detectable: f64,
    /// The weakest block.
    pub weakest_block: usize,
}

impl Agreement {
    /// Whether every block lies within [`BLOCK_Z`] and the whole image within [`WHOLE_Z`].
    pub fn agrees(&self) -> bool {
        self.worst_z <= BLOCK_Z && (self.whole_bias / self.whole_error).abs() <= WHOLE_Z
    }
}

/// `ours` against `reference`, region by region (the last region the whole image).
pub fn compare(ours: &[Estimate], reference: &[Estimate]) -> Agreement {
    let whole = ours.len() - 1;
    let mut agreement = Agreement {
        whole_bias: ours[whole].mean / reference[whole].mean - 1.0,
        whole_error: ours[whole].error.hypot(reference[whole].error) / reference[whole].mean,
        worst_z: 0.0,
        worst_block: 0,
        detectable: 0.0,
        weakest_block: 0,
    };
    for (b, (o, r)) in ours.iter().zip(reference).take(whole).enumerate() {
        let error = o.error.hypot(r.error);
        let z = match error > 0.0 {
            true => ((o.mean - r.mean) / error).abs(),
            false if (o.mean - r.mean).abs() <= 1e-6 * r.mean.abs() => 0.0,
            false => f64::INFINITY,
        };
        if z > agreement.worst_z {
            (agreement.worst_z, agreement.worst_block) = (z, b);
        }
        let detectable = BLOCK_Z * error / r.mean.abs();
        if detectable > agreement.detectable {
            (agreement.detectable, agreement.weakest_block) = (detectable, b);
        }
    }
    agreement
}

/// `scene` rendered under `settings` once per seed of `seeds` (each replacing the settings'
/// seed) on `threads` threads, each render's [`block_means`].
pub fn renders(
    scene: &Scene,
    settings: RenderSettings,
    seeds: std::ops::Range<u64>,
    side: u32,
    threads: usize,
) -> Vec<Vec<f64>> {
    seeds
        .map(|seed| {
            let settings = RenderSettings { seed, ..settings };
            let rng = RngSource::new(&settings, RngChoice::PerSample);
            let job = RenderJob::new(scene.clone(), settings);
            let frame = Arc::new(Frame::new(job, rng, threads, 16, Arc::new(|_| {})));
            block_means(&render(&frame, &Schedule::Stealing).image, side)
        })
        .collect()
}
