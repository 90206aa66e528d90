//! `cargo bench --bench bias`: is every sampling method's mean image the true one? Issue #11's
//! check with more seeds than a test can afford (`tests/render.rs` runs the same comparison
//! at 24 seeds). Writes `results/bias.md`; `-- --quick` takes a quarter of the seeds.
//!
//! 1. **Against a converged reference**, the setting in which the old adaptive rule was found
//!    biased (`results/adaptive.md`): `paper1`, 48 × 32, depth 20, 400 seeds, whole-image mean
//!    minus the mean of a 2 × 8192-spp reference, in standard errors (the seeds' spread and the
//!    reference's own noise).
//! 2. **Paired with independent uniform sampling** on the four scenes: per seed, the
//!    method's image mean minus independent uniform sampling's at the same seed, over 256 seeds.

use std::fmt::Write as _;
use std::sync::Arc;

use raypool::measure::convergence::Reference;
use raypool::measure::machine::{Machine, cpus, results_dir};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, render};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::render::{Adaptive, RenderJob, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::scene::Scene;

/// A method: its name and how it changes the uniform settings.
type Method = (&'static str, fn(RenderSettings) -> RenderSettings);

const METHODS: [Method; 5] = [
    ("sobol", |s| RenderSettings { sampler: Sampler::Sobol, ..s }),
    ("independent + roulette", |s| RenderSettings { roulette: true, ..s }),
    ("sobol + roulette", |s| RenderSettings { sampler: Sampler::Sobol, roulette: true, ..s }),
    ("independent adaptive", adaptive),
    ("sobol adaptive", |s| RenderSettings { sampler: Sampler::Sobol, ..adaptive(s) }),
];

/// Adaptive sampling from a pilot of 8 samples up to 4 × the uniform spp, at E = 0.1.
fn adaptive(s: RenderSettings) -> RenderSettings {
    RenderSettings { spp: 4 * s.spp, adaptive: Some(Adaptive { target_error: 0.1, min_spp: 8 }), ..s }
}

fn image_mean(scene: &Scene, settings: RenderSettings, threads: usize) -> f64 {
    let job = RenderJob::new(scene.clone(), settings);
    let frame = Arc::new(Frame::new(
        job,
        RngSource::new(&settings, RngChoice::PerSample),
        threads,
        16,
        Arc::new(|_| {}),
    ));
    render(&frame, &Schedule::Stealing).image.mean()
}

/// Mean and standard error of the mean of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

fn main() {
    let threads = cpus();
    let scene_of = |name: &str| builtin_scene(name, DEFAULT_SCENE_SEED).expect("built-in").to_scene();
    let mut md = String::from("# Bias: every sampling method's mean image\n\n");
    // `--quick` (for `benches/all.sh --quick`): a quarter of the seeds and of the reference.
    let quick = std::env::args().any(|a| a == "--quick");

    // 1. Against a converged reference.
    let (seeds, reference_spp) = if quick { (100, 2048) } else { (400, 8192) };
    let base = RenderSettings {
        width: 48,
        height: 32,
        spp: 64,
        max_depth: 20,
        sampler: Sampler::Independent,
        ..Default::default()
    };
    let scene = scene_of("paper1");
    let reference = Reference::render(&scene, base, reference_spp, threads);
    let reference_mean = reference.image.mean();
    let reference_error = reference.noise / (f64::from(base.width * base.height)).sqrt();
    let _ = write!(
        md,
        "## Against a converged reference\n\n`paper1`, {} × {}, depth {}, {seeds} seeds, against a \
         2 × {reference_spp}-spp reference (independent numbers). Adaptive: `--target-error 0.1 \
         --min-spp 8 --max-spp 256`. The standard error combines the seeds' spread and the \
         reference's noise ({:.4}% of the mean).\n\n| method | image mean − reference | standard error | in standard errors |\n|---|---:|---:|---:|\n",
        base.width,
        base.height,
        base.max_depth,
        100.0 * reference_error / reference_mean
    );
    let uniform: Method = ("independent uniform, 64 spp", |s| s);
    for (name, method) in [uniform].iter().chain(&METHODS) {
        let settings = method(base);
        let means: Vec<f64> = (1..=seeds)
            .map(|seed| image_mean(&scene, RenderSettings { seed, ..settings }, threads))
            .collect();
        let (mean, spread) = mean_and_error(&means);
        let error = (spread.powi(2) + reference_error.powi(2)).sqrt();
        let off = mean - reference_mean;
        eprintln!("paper1 {name}: {off:+.3e}, {:+.2} SE", off / error);
        let percent = |x: f64| 100.0 * x / reference_mean;
        let _ =
            writeln!(md, "| {name} | {:+.4}% | {:.4}% | {:+.2} |", percent(off), percent(error), off / error);
    }

    // 2. Paired with independent uniform sampling.
    let seeds = if quick { 64 } else { 256 };
    let base = RenderSettings {
        width: 32,
        height: 21,
        spp: 16,
        max_depth: 50,
        sampler: Sampler::Independent,
        ..Default::default()
    };
    let _ = write!(
        md,
        "\n## Paired with independent uniform sampling\n\n{} × {}, {} spp (adaptive: E 0.1, \
         pilot 8, at most {} spp), depth {}, {seeds} seeds: per seed, the method's image mean minus \
         independent uniform sampling's at the same seed; the mean of those differences, relative \
         to the image mean, its standard error, and the two's ratio.\n\n| scene | method | mean difference | standard error | in standard errors |\n|---|---|---:|---:|---:|\n",
        base.width,
        base.height,
        base.spp,
        4 * base.spp,
        base.max_depth
    );
    for name in ["final", "paper3", "three-spheres", "furnace"] {
        let scene = scene_of(name);
        let uniform: Vec<f64> =
            (0..seeds).map(|seed| image_mean(&scene, RenderSettings { seed, ..base }, threads)).collect();
        let level = uniform.iter().sum::<f64>() / seeds as f64;
        for (method, change) in METHODS {
            let settings = change(base);
            let differences: Vec<f64> = (0..seeds)
                .zip(&uniform)
                .map(|(seed, u)| image_mean(&scene, RenderSettings { seed, ..settings }, threads) - u)
                .collect();
            let (mean, error) = mean_and_error(&differences);
            let in_errors = if error > 0.0 { format!("{:+.2}", mean / error) } else { "identical".into() };
            eprintln!("{name} {method}: {mean:+.3e}, {in_errors} SE");
            let percent = |x: f64| 100.0 * x / level;
            let _ = writeln!(
                md,
                "| {name} | {method} | {:+.4}% | {:.4}% | {in_errors} |",
                percent(mean),
                percent(error)
            );
        }
    }
    let command = if quick { "cargo bench --bench bias -- --quick" } else { "cargo bench --bench bias" };
    let _ = writeln!(md, "\n`{command}`; {}", Machine::current().describe());
    std::fs::write(results_dir().join("bias.md"), &md).expect("the output directory is writable");
    println!("{md}");
}
