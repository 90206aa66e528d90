//! Adaptive sampling in two whole-image passes: a pilot that measures where the image is
//! noisy, then the samples each pixel was given, decided without looking at its own samples.
//!
//! Every pixel first takes `min_spp` samples (an even number), the pilot. A pixel's noise is
//! then the difference of its two independent half-estimates, the mean of its even- and of its
//! odd-numbered samples (Cycles' half-buffers), `|A − B|₁`. Each pixel is given a sample count
//! from its **neighbours'** pilot (its 3 × 3 window without itself): their mean `|A − B|₁`,
//! relative to the square root of their mean brightness, against the target (see
//! [`Adaptive`]). The second pass takes every pixel to its count.
//!
//! Why the neighbours and not the pixel itself: a pixel's count then depends only on other
//! pixels' random numbers, which are independent of its own (they are seeded per pixel), so
//! the mean of its samples is an unbiased estimate whatever count it gets. A rule that looks at
//! the pixel's own samples, even through half-buffers, stops more often where its first samples
//! happen to run low or agree, and was measured biased (`results/adaptive.md`). For the same
//! reason there is one decision, from the pilot alone: a second round of decisions would look at
//! neighbours' samples whose number was decided by this pixel's pilot.
//!
//! A shard (`render --shard`) also renders, on the calling thread, the pilots of the pixels next
//! to its tiles that other shards render: then its counts are the one-process counts, and
//! merged parts equal the one-process image (`tests/shard.rs`).
//!
//! Each pass is one batch of tiles on the chosen scheduler (a [`Pass`];
//! [`crate::schedule::modes::render`] hands this loop its scheduler as `run_pass`). A pixel's
//! count depends only on pilot samples, whose numbers depend only on (seed, pixel, sample), so
//! the image is the same under every scheduler and thread count.

use std::sync::Arc;

use glam::DVec3;

use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::progressive::{Pass, Sums};
use crate::tracer::math::real::to_f64;
use crate::tracer::render::{Adaptive, TileOutput};
use crate::tracer::tile::Tile;

/// Renders `frame` adaptively by `adaptive`, each pass by `run_pass` (a scheduler's render);
/// returns the image (the last pass's tiles carry every pixel's mean) and every pass's tiles
/// (for their rays, samples and timings). An error names a pixel a pass left out or rendered
/// twice (a scheduler breaking its contract).
pub fn render_adaptive(
    frame: &Arc<Frame>,
    adaptive: Adaptive,
    mut run_pass: impl FnMut(&Arc<Frame>) -> Vec<TileOutput>,
) -> Result<(Image, Vec<TileOutput>), String> {
    let settings = frame.job().settings;
    let (width, height) = (settings.width as usize, settings.height as usize);
    let sums = Sums::default();
    let pilot = adaptive.min_spp.max(2).next_multiple_of(2).min(settings.spp);
    let pass = |samples, counts| {
        let pass = Pass { samples, sums: Arc::clone(&sums), counts };
        Arc::new(frame.as_ref().clone().with_pass(pass))
    };
    let pilot_pass = pass(0..pilot, None);
    let mut tiles = run_pass(&pilot_pass);
    let mut image = frame.assemble(&tiles)?;
    // The pilots of the pixels next to a shard's tiles that other shards render (not part of
    // its image), on this thread: with them every pixel's count is the one-process count, so
    // merged parts equal the one-process image. A whole image has none.
    tiles.extend(ring(frame).into_iter().map(|strip| pilot_pass.render(strip)));
    let noise = halves(&sums, width, height);
    let counts = sample_counts(&noise, width, height, pilot, settings.spp, to_f64(adaptive.target_error));
    if counts.iter().any(|&n| n > pilot) {
        let rest = run_pass(&pass(pilot..settings.spp, Some(Arc::new(counts))));
        image = frame.assemble(&rest)?;
        tiles.extend(rest);
    }
    Ok((image, tiles))
}

/// The pixels outside `frame`'s tiles (another shard's) that touch one of them, as strips one
/// pixel high, left to right, top to bottom.
fn ring(frame: &Frame) -> Vec<Tile> {
    let (width, height) = (frame.width() as usize, frame.height() as usize);
    let mut inside = vec![false; width * height];
    for tile in frame.tiles() {
        for y in tile.y..tile.y + tile.height {
            let row = y as usize * width;
            inside[row + tile.x as usize..row + (tile.x + tile.width) as usize].fill(true);
        }
    }
    let touches = |x: usize, y: usize| window(x, y, width, height).any(|c| inside[c]);
    let mut strips = Vec::new();
    for y in 0..height {
        let mut x = 0;
        while x < width {
            let start = x;
            while x < width && !inside[y * width + x] && touches(x, y) {
                x += 1;
            }
            if x > start {
                strips.push(Tile { x: start as u32, y: y as u32, width: (x - start) as u32, height: 1 });
            } else {
                x += 1;
            }
        }
    }
    strips
}

/// The row-major indices of the pixels of the 3 × 3 window around `(x, y)`, itself included,
/// clipped to the `width` × `height` image.
fn window(x: usize, y: usize, width: usize, height: usize) -> impl Iterator<Item = usize> {
    (y.saturating_sub(1)..(y + 2).min(height))
        .flat_map(move |j| (x.saturating_sub(1)..(x + 2).min(width)).map(move |i| j * width + i))
}

/// Each pixel's `(|A − B|₁, |A + B|₁ / 2)`: the difference of its half-estimates `A` (even
/// samples) and `B` (odd samples), and its brightness; zeros for a pixel without two samples.
fn halves(sums: &Sums, width: usize, height: usize) -> Vec<(f64, f64)> {
    let mut halves = vec![(0.0, 0.0); width * height];
    for (tile, tile_sums) in sums.lock().iter() {
        for k in 0..tile.area() {
            let (x, y) =
                (tile.x as usize + k % tile.width as usize, tile.y as usize + k / tile.width as usize);
            let (sum, odd, n) = tile_sums.pixel(k);
            if n >= 2 {
                let half = f64::from(n / 2);
                let (a, b) = ((sum - odd) / half, odd / half);
                halves[y * width + x] = (l1(a - b), l1(a + b) * 0.5);
            }
        }
    }
    halves
}

fn l1(v: DVec3) -> f64 {
    v.x.abs() + v.y.abs() + v.z.abs()
}

/// Each pixel's sample count, from its neighbours' pilot `noise` (`(|A − B|₁, brightness)` at
/// `pilot` samples): `pilot × d / (target × √b)` for the neighbours' mean difference `d` and
/// mean brightness `b`, rounded up to even and kept within `pilot..=max_spp`. A pixel without
/// neighbours (a 1 × 1 image) keeps its pilot.
///
/// Samples in proportion to the noise, not to its square: spending a budget of samples so
/// that the image's total squared error is least gives each pixel samples in proportion to
/// its standard deviation (Neyman's allocation); dividing by √b leans towards dark pixels, as
/// relative error asks (which would divide by `b`). On `final` it reaches a given error in
/// fewer rays than the square or the division by `b`, by RMSE and by relative MSE
/// (`results/adaptive.md`, the table of rules).
fn sample_counts(
    noise: &[(f64, f64)],
    width: usize,
    height: usize,
    pilot: u32,
    max_spp: u32,
    target: f64,
) -> Vec<u32> {
    (0..width * height)
        .map(|k| {
            let (mut difference, mut brightness, mut n) = (0.0, 0.0, 0.0);
            for c in window(k % width, k / width, width, height).filter(|&c| c != k) {
                (difference, brightness, n) = (difference + noise[c].0, brightness + noise[c].1, n + 1.0);
            }
            if n == 0.0 {
                return pilot;
            }
            let noisiness = (difference / n) / (target * ((brightness / n).sqrt() + 1e-4));
            let wanted = (f64::from(pilot) * noisiness).ceil().min(f64::from(max_spp)) as u32;
            wanted.next_multiple_of(2).clamp(pilot, max_spp)
        })
        .collect()
}
