//! Adaptive sampling in whole-image passes, as production renderers do it: spend samples where
//! the image is still noisy, judged without looking at the samples' spread.
//!
//! Every pixel first takes `min_spp` samples (an even number). After each pass, a pixel's
//! error is the difference of its two independent half-estimates, the mean of its even- and of
//! its odd-numbered samples (Cycles' half-buffers), `|A − B|₁`. A pixel is converged when that
//! difference, averaged over its 3 × 3 window, is below the target times the square root of the
//! window's mean brightness; it goes on sampling while any pixel of its window has not
//! converged (dilation), so a noisy pixel's neighbours are not left behind. The next pass
//! doubles the samples of the pixels still going, up to `spp`.
//!
//! Each pass is one batch of tiles on the chosen scheduler (a [`Pass`] with the pixels still
//! going; [`crate::schedule::modes::render`] hands this loop its scheduler as `run_pass`); a pixel's decision depends only on its window's samples, whose numbers depend only
//! on (seed, pixel, sample), so the image is the same under every scheduler and thread count.
//! Judging by the difference of two independent halves instead of by the samples' own variance
//! is what keeps the stopping rule from favouring pixels whose first samples happen to agree.

use std::sync::Arc;

use glam::DVec3;

use crate::files::image::Image;
use crate::schedule::frame::Frame;
use crate::schedule::progressive::{Pass, Sums};
use crate::tracer::render::{Adaptive, TileOutput};

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
    let mut active = vec![true; width * height];
    let (mut done, mut next) = (0, adaptive.min_spp.max(2).next_multiple_of(2).min(settings.spp));
    let (mut image, mut tiles) = (None, Vec::new());
    while next > 0 && active.iter().any(|&a| a) {
        let pass = Pass {
            samples: done..done + next,
            sums: Arc::clone(&sums),
            active: Some(Arc::new(active.clone())),
        };
        let outputs = run_pass(&Arc::new(frame.as_ref().clone().with_pass(pass)));
        image = Some(frame.assemble(&outputs)?);
        tiles.extend(outputs);
        done += next;
        next = done.min(settings.spp - done);
        if next > 0 {
            let halves = halves(&sums, width, height);
            active = still_going(&active, &halves, width, height, f64::from(adaptive.target_error));
        }
    }
    Ok((image.expect("the first pass always runs: spp and min_spp are at least 1"), tiles))
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

/// The pixels that sample on: those still going whose 3 × 3 window holds an unconverged
/// pixel. A pixel is unconverged while its window's mean `|A − B|₁` is at least `target` ×
/// √(the window's mean brightness). (Normalising by the window's brightness rather than the
/// pixel's own keeps a pixel whose samples happen to run bright from stopping early for it.)
fn still_going(
    active: &[bool],
    halves: &[(f64, f64)],
    width: usize,
    height: usize,
    target: f64,
) -> Vec<bool> {
    let window = |x: usize, y: usize| {
        (y.saturating_sub(1)..(y + 2).min(height))
            .flat_map(move |j| (x.saturating_sub(1)..(x + 2).min(width)).map(move |i| j * width + i))
    };
    let unconverged: Vec<bool> = (0..width * height)
        .map(|k| {
            let (mut difference, mut brightness, mut n) = (0.0, 0.0, 0.0);
            for c in window(k % width, k / width) {
                (difference, brightness, n) = (difference + halves[c].0, brightness + halves[c].1, n + 1.0);
            }
            difference / n >= target * ((brightness / n).sqrt() + 1e-4)
        })
        .collect();
    (0..width * height).map(|k| active[k] && window(k % width, k / width).any(|c| unconverged[c])).collect()
}
