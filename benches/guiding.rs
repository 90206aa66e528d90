//! `cargo bench --bench guiding`: what the guide buys per sample and what it costs
//! (`results/guiding.md`; the time to a clean image is `cargo bench --bench error -- --only
//! lights`'s).
//!
//! - **Per sample**: the squared error of a guided pass against an unguided one of the same
//!   samples. Under each of `SEEDS` seeds, the learning passes of a guided render of
//!   `pilot + 32` spp run (to `pilot`), then its last pass, samples `pilot..pilot + 32`, is
//!   rendered alone into fresh sums; the unguided render takes the same samples under another
//!   seed. Both against the error bench's `bsdf` reference (`target/error-reference/`, 96 × 96,
//!   2 × 8192 spp; a scene without one is skipped: run the error bench first), summed over the
//!   seeds: the ratio of the mean squared errors (below 1: the guide helps), and of the passes'
//!   times.
//! - **Memory and learning time**: `cornell` at 400 × 400 and 600 × 600 (the third book's
//!   size), the guide after each learning pass of a `--guide-pilot 64` render: its cells,
//!   quadtree nodes and bytes, and the pass's time.
//!
//! `-- --quick`: two seeds, pilot 32 only, 400 × 400 only.

use std::sync::Arc;
use std::time::Instant;

use raypool::files::image::Image;
use raypool::files::output::read_pfm;
use raypool::measure::machine::{Machine, cpus};
use raypool::scenes::builtin::builtin_scene;
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, Scheduler};
use raypool::schedule::progressive::{Pass, Sums};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::guiding::guide::Guide;
use raypool::tracer::guiding::learning::Learning;
use raypool::tracer::guiding::{Guiding, bounds};
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::to_f64;
use raypool::tracer::render::{RenderJob, RenderSettings};

/// Samples of the pass measured.
const MEASURED: u32 = 32;

/// The reference's pixels (linear RGB, row-major, channels in turn), if the error bench left
/// one for `scene`.
fn reference(scene: &str) -> Option<Vec<f64>> {
    let base = format!("target/error-reference/{scene}-bsdf-sobol-96x96-8192-");
    let load = |half: &str| read_pfm(&std::fs::read(format!("{base}{half}.pfm")).ok()?).ok();
    let ((_, _, a), (_, _, b)) = (load("a")?, load("b")?);
    Some(
        a.iter()
            .zip(&b)
            .flat_map(|(x, y)| (0..3).map(move |c| (f64::from(x[c]) + f64::from(y[c])) / 2.0))
            .collect(),
    )
}

fn squared_error(image: &Image, reference: &[f64]) -> f64 {
    let pixels = image.pixels.iter().flat_map(|p| [p.x, p.y, p.z].map(to_f64));
    pixels.zip(reference).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() / reference.len() as f64
}

/// The learning passes of a guided render of `settings` up to `pilot`, each reporting its
/// guide and time to `each`; returns the last guide.
fn learn(frame: &Arc<Frame>, pilot: u32, mut each: impl FnMut(&Guide, f64)) -> Option<Arc<Guide>> {
    let job = frame.job();
    let (sums, mut guide) = (Sums::default(), None::<Arc<Guide>>);
    for samples in (Guiding { pilot }).passes(job.settings.spp).into_iter().filter(|s| s.end <= pilot) {
        let spp = samples.end - samples.start;
        let learning = Arc::new(match &guide {
            None => Learning::new(bounds(&job.scene), spp),
            Some(guide) => Learning::after(guide, spp),
        });
        let start = Instant::now();
        let pass = Pass { samples, sums: Arc::clone(&sums), counts: None };
        let learns = job.guided(guide.clone(), Some(Arc::clone(&learning)));
        Schedule::Stealing.render(&Arc::new(frame.as_ref().clone().with_job(learns).with_pass(pass)));
        let learnt = learning.finish();
        each(&learnt, start.elapsed().as_secs_f64());
        guide = Some(Arc::new(learnt));
    }
    guide
}

/// `scene` under `settings`, on every core.
fn frame(scene: &str, settings: RenderSettings) -> Arc<Frame> {
    let scene = builtin_scene(scene, 0).expect("a built-in scene").to_scene();
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    Arc::new(Frame::new(RenderJob::new(scene, settings), rng, cpus(), 16, Arc::new(|_| {})))
}

/// Samples `pilot..pilot + MEASURED` of `frame`, drawn from `guide`, alone: the image and
/// the time.
fn measured_pass(frame: &Arc<Frame>, pilot: u32, guide: Option<Arc<Guide>>) -> (Image, f64) {
    let pass = Pass { samples: pilot..pilot + MEASURED, sums: Sums::default(), counts: None };
    let job = frame.job().guided(guide, None);
    let pass = Arc::new(frame.as_ref().clone().with_job(job).with_pass(pass));
    let start = Instant::now();
    let tiles = Schedule::Stealing.render(&pass);
    (pass.assemble(&tiles).expect("every tile"), start.elapsed().as_secs_f64())
}

fn per_sample(quick: bool) {
    let seeds = if quick { 2 } else { 8 };
    println!(
        "## Per sample: the guided pass against the unguided, {MEASURED} spp, 96 × 96, {seeds} seeds\n\n\
         | scene | light sampling | pilot | MSE guided ÷ unguided | time guided ÷ unguided |\n|---|---|---:|---:|---:|"
    );
    for scene in ["cornell", "cornell-smoke", "next-week"] {
        let Some(reference) = reference(scene) else {
            println!(
                "| {scene} | – | – | no reference: run `cargo bench --bench error -- --only lights` | – |"
            );
            continue;
        };
        for light_sampling in [LightSampling::Mis, LightSampling::Bsdf] {
            for pilot in if quick { vec![32] } else { vec![32, 128] } {
                let (mut errors, mut times) = ([0.0; 2], [0.0; 2]);
                for seed in 1..=seeds {
                    let settings = RenderSettings {
                        width: 96,
                        height: 96,
                        spp: pilot + MEASURED,
                        seed,
                        light_sampling,
                        ..Default::default()
                    };
                    let guided = frame(scene, settings);
                    let guide = learn(&guided, pilot, |_, _| {});
                    let unguided = frame(scene, RenderSettings { seed: seed + 1000, ..settings });
                    for (k, (frame, guide)) in [(&guided, guide), (&unguided, None)].into_iter().enumerate() {
                        let (image, seconds) = measured_pass(frame, pilot, guide);
                        errors[k] += squared_error(&image, &reference);
                        times[k] += seconds;
                    }
                }
                println!(
                    "| {scene} | {} | {pilot} | {:.3} | {:.2} |",
                    light_sampling.name(),
                    errors[0] / errors[1],
                    times[0] / times[1]
                );
            }
        }
    }
}

fn memory(quick: bool) {
    println!(
        "\n## The guide after each learning pass: `cornell`, mis, `--guide-pilot 64`\n\n\
         | size | pass (samples) | cells | quadtree nodes | guide's bytes | pass time (s) |\n|---|---|---:|---:|---:|---:|"
    );
    for side in if quick { vec![400] } else { vec![400, 600] } {
        let settings = RenderSettings { width: side, height: side, spp: 128, ..Default::default() };
        let (mut start, frame) = (0, frame("cornell", settings));
        learn(&frame, 64, |guide, seconds| {
            let nodes: usize = guide.distributions().iter().map(|d| d.shape().len()).sum();
            let end = start + guide.spp();
            println!(
                "| {side} × {side} | {start}..{end} | {} | {nodes} | {} | {seconds:.2} |",
                guide.bounces().len(),
                guide.bytes()
            );
            start = end;
        });
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let command =
        if quick { "cargo bench --bench guiding -- --quick" } else { "cargo bench --bench guiding" };
    println!("`{command}`; {}\n", Machine::current().describe());
    per_sample(quick);
    memory(quick);
}
