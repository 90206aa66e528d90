//! `cargo bench --bench denoise`: how much closer to the converged image does the denoiser
//! (`src/denoise/`) bring a 1-sample image, and what does it cost? Writes
//! `results/denoise.md` and `results/denoise-final.png` (1 spp | denoised | reference).
//!
//! Per scene, 400 wide (the viewer's width), default sampler: a 256-spp reference at seed 99,
//! then for seeds 1–3 the 1-spp image and its denoised twin, each RMSE against the reference,
//! over the whole image and inside surfaces (pixels whose 3 × 3 neighbourhood is one surface
//! by the guides: `Guides::inside_surfaces`, where the error is noise, not a silhouette's
//! aliasing). Then the denoiser's time at 400 and at 200 wide (a navigation frame's size at
//! the viewer's usual start resolution), guides and filter apart, median of 9, on every CPU.
//! `-- --quick`: 200 wide, a 64-spp reference.

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::{Duration, Instant};

use raypool::denoise::atrous::Filter;
use raypool::denoise::guide::Guides;
use raypool::measure::machine::{Machine, cpus, results_dir};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, render};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::math::real::Vec3;
use raypool::{Image, RenderJob, RenderSettings};

const SCENES: [&str; 4] = ["final", "three-spheres", "cornell", "next-week"];

/// One seed's RMSEs (1 spp, denoised): over the whole image, inside surfaces; and the share
/// of pixels inside surfaces.
struct Errors {
    whole: (f64, f64),
    inside: (f64, f64),
    share: f64,
}

fn rendered(job: &RenderJob, threads: usize) -> Image {
    let rng = RngSource::new(&job.settings, RngChoice::PerSample);
    let frame = Arc::new(Frame::new(job.clone(), rng, threads, 16, Arc::new(|_| {})));
    render(&frame, &Schedule::Stealing).image
}

fn rmse(a: &[Vec3], b: &[Vec3], pixels: &[usize]) -> f64 {
    let squares: f64 = pixels.iter().map(|&k| f64::from((a[k] - b[k]).length_squared())).sum();
    (squares / (3 * pixels.len()) as f64).sqrt()
}

fn median(mut values: Vec<Duration>) -> f64 {
    values.sort();
    values[values.len() / 2].as_secs_f64() * 1e3
}

/// Median times (ms) of the guides and of the filter for `job`'s image `image`.
fn timing(job: &RenderJob, image: &Image, threads: usize) -> (f64, f64) {
    let (mut guides_took, mut filter_took) = (Vec::new(), Vec::new());
    for _ in 0..9 {
        let start = Instant::now();
        let guides = Guides::of(job, threads);
        guides_took.push(start.elapsed());
        let start = Instant::now();
        std::hint::black_box(Filter::default().apply(&image.pixels, &guides, threads));
        filter_took.push(start.elapsed());
    }
    (median(guides_took), median(filter_took))
}

/// Side by side: 1 spp | denoised | reference, as one PNG.
fn strip(images: [&Image; 3], path: &std::path::Path) {
    let (w, h) = (images[0].width, images[0].height);
    let mut out = image::RgbImage::new(3 * w, h);
    for (k, picture) in images.iter().enumerate() {
        let rgb = picture.to_rgb8();
        for (i, p) in rgb.chunks_exact(3).enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            out.put_pixel(k as u32 * w + x, y, image::Rgb([p[0], p[1], p[2]]));
        }
    }
    out.save(path).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let (width, reference_spp) = if quick { (200, 64) } else { (400, 256) };
    let threads = cpus();
    let mut table = String::new();
    let mut costs = String::new();
    let mut by_passes = String::new();
    for name in SCENES {
        let file = builtin_scene(name, DEFAULT_SCENE_SEED).expect("built-in");
        let height = (f64::from(width) / file.camera.aspect).round() as u32;
        let base = RenderSettings { width, height, spp: 1, ..RenderSettings::default() };
        let job = RenderJob::new(file.to_scene(), base);
        let reference = rendered(
            &job.with_camera(&file.camera, RenderSettings { spp: reference_spp, seed: 99, ..base }),
            threads,
        );
        let mut cells = Vec::new();
        for seed in 1..=3 {
            let seeded = job.with_camera(&file.camera, RenderSettings { seed, ..base });
            let noisy = rendered(&seeded, threads);
            let guides = Guides::of(&seeded, threads);
            let denoised = Filter::default().apply(&noisy.pixels, &guides, threads);
            let all: Vec<usize> = (0..noisy.pixels.len()).collect();
            let inside = guides.inside_surfaces();
            let whole =
                (rmse(&noisy.pixels, &reference.pixels, &all), rmse(&denoised, &reference.pixels, &all));
            let surfaces = (
                rmse(&noisy.pixels, &reference.pixels, &inside),
                rmse(&denoised, &reference.pixels, &inside),
            );
            eprintln!("{name} seed {seed}: whole {whole:?}, inside {surfaces:?}");
            cells.push(Errors { whole, inside: surfaces, share: inside.len() as f64 / all.len() as f64 });
            if name == "final" {
                let row: Vec<String> = (1..=5)
                    .map(|passes| {
                        let filtered =
                            Filter { passes, ..Filter::default() }.apply(&noisy.pixels, &guides, threads);
                        format!("{:.2}", surfaces.0 / rmse(&filtered, &reference.pixels, &inside))
                    })
                    .collect();
                let _ = writeln!(by_passes, "| {seed} | {} |", row.join(" | "));
            }
            if name == "final" && seed == 1 {
                let denoised = Image { width, height, pixels: denoised };
                strip([&noisy, &denoised, &reference], &results_dir().join("denoise-final.png"));
            }
        }
        let factors = |pick: fn(&Errors) -> (f64, f64)| {
            let f: Vec<String> = cells.iter().map(pick).map(|(a, b)| format!("{:.2}", a / b)).collect();
            f.join(", ")
        };
        let Errors { whole: first_whole, inside: first_inside, share } = cells[0];
        let _ = writeln!(
            table,
            "| {name} | {width} × {height} | {:.4} → {:.4} | **{}** | {:.0}% | {:.4} → {:.4} | **{}** |",
            first_whole.0,
            first_whole.1,
            factors(|c| c.whole),
            100.0 * share,
            first_inside.0,
            first_inside.1,
            factors(|c| c.inside),
        );
        for w in [width, width / 2] {
            let h = (f64::from(w) / file.camera.aspect).round() as u32;
            let small = job.with_camera(&file.camera, RenderSettings { width: w, height: h, ..base });
            let (guides_ms, filter_ms) = timing(&small, &rendered(&small, threads), threads);
            let _ = writeln!(
                costs,
                "| {name} | {w} × {h} | {guides_ms:.1} | {filter_ms:.1} | {:.1} |",
                guides_ms + filter_ms
            );
        }
    }
    let report = format!(
        "# The denoiser: a 1-sample image against the converged one\n\n\
         Machine: {machine}, {threads} threads.\n\
         Command: `cargo bench --bench denoise{quick}`.\n\n\
         The edge-avoiding à-trous filter (`src/denoise/`: 3 passes of a 3 × 3 kernel, guided by\n\
         each pixel's first hit: albedo, normal, tangent plane; mirrors and glass followed to\n\
         what they show) on a 1-spp image, the default sampler; RMSE against a {reference_spp}-spp\n\
         reference at another seed. \"Inside surfaces\": pixels whose 3 × 3 neighbourhood is one\n\
         surface by the guides (`Guides::inside_surfaces`). Factors for seeds 1, 2, 3; the RMSEs\n\
         are seed 1's.\n\n\
         | scene | size | RMSE 1 spp → denoised | × less error | inside surfaces | there: RMSE | × less error |\n\
         |---|---|---|---|---:|---|---|\n{table}\n\
         Cost, on {threads} threads, median of 9 (ms):\n\n\
         | scene | size | guides | filter | both |\n|---|---|---:|---:|---:|\n{costs}\n\
         By passes, on `final`: × less error inside surfaces (the default is 3).\n\n\
         | seed | 1 pass | 2 | 3 | 4 | 5 |\n|---|---:|---:|---:|---:|---:|\n{by_passes}\n\
         `results/denoise-final.png`: `final`, seed 1: 1 spp | denoised | the reference.\n",
        machine = Machine::current().describe(),
        quick = if quick { " -- --quick" } else { "" },
    );
    let path = results_dir().join("denoise.md");
    std::fs::write(&path, &report).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    print!("{report}");
}
