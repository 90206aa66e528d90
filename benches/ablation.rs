//! `cargo bench --bench ablation`: what each optimisation buys, switched off one at a time.
//!
//! One thread, the book's `final` scene at 600 × 400, 64 spp, depth 50; then the lit
//! `cornell` box at 200 × 200, 64 spp, under each `--light-sampling` setting. Each
//! configuration is rendered in rounds (every configuration of a table once per round, so a
//! slow spell of the machine hits all of them alike); the table gives the median wall time
//! and Mrays/s and the largest pixel difference to the default configuration's image (0
//! where the change is exact). Writes `results/ablation.md`. Pass `--quick` for a quarter of
//! the pixels and 16 spp.

use std::sync::Arc;
use std::time::Instant;

use raypool::files::image::Image;
use raypool::measure::machine::{Machine, results_dir};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, render};
use raypool::schedule::random::RngSource;
use raypool::schedule::random::SharedRng;
use raypool::tracer::geometry::sphere::Intersection;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::to_f64;
use raypool::tracer::render::{RenderJob, RenderSettings};
use raypool::tracer::sampling::independent::PerSample;
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::scene::{Accel, Scene};

/// One row of the table: a change to the default renderer.
struct Variant {
    name: &'static str,
    /// What the change is, exactly or statistically.
    kind: &'static str,
    scene: fn(Scene) -> Scene,
    settings: fn(RenderSettings) -> RenderSettings,
    /// The random streams, from the seed.
    streams: fn(u64) -> RngSource,
    /// Rounds to run (the flat loop is 8× slower: once is enough to see it).
    rounds: usize,
}

/// The default: independent numbers per pixel sample.
fn per_sample(seed: u64) -> RngSource {
    RngSource::PerSample(PerSample { seed })
}

const VARIANTS: [Variant; 11] = [
    Variant {
        name: "default (all on)",
        kind: "reference",
        scene: |s| s,
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "binary SAH tree instead of the 4-wide one (the previous default)",
        kind: "exact (tested)",
        scene: |s| s.with_accel(Accel::Binary),
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "4-wide tree, leaves tested as 4-lane SIMD packets",
        kind: "exact (tested)",
        scene: |s| s.with_accel(Accel::WidePackets),
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "4-wide tree, huge spheres (the ground) kept out and tested first",
        kind: "exact (tested)",
        scene: |s| s.with_accel(Accel::WideHugeApart),
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "no BVH: every sphere tested",
        kind: "exact (tested)",
        scene: Scene::without_bvh,
        settings: |s| s,
        streams: per_sample,
        rounds: 1,
    },
    Variant {
        name: "textbook sphere test, t_min 0.001",
        kind: "not exact: other rounding",
        scene: |s| s.with_intersection(Intersection::Textbook),
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "no black-path stop",
        kind: "exact",
        scene: |s| s,
        settings: |s| RenderSettings { stop_black_paths: false, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "Russian roulette on (off by default)",
        kind: "unbiased: other noise",
        scene: |s| s,
        settings: |s| RenderSettings { roulette: true, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "light sampling bsdf instead of mis (final has no emitters: nothing to aim at)",
        kind: "exact",
        scene: |s| s,
        settings: |s| RenderSettings { light_sampling: LightSampling::Bsdf, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "Sobol sampler (the command line's default) instead of independent numbers",
        kind: "other noise: less error per sample",
        scene: |s| s,
        settings: |s| s,
        streams: |seed| RngSource::Sobol(SobolStreams::new(seed)),
        rounds: 3,
    },
    Variant {
        name: "one locked RNG instead of per-sample streams",
        kind: "other noise",
        scene: |s| s,
        settings: |s| s,
        streams: |seed| RngSource::Shared(Arc::new(SharedRng::new(seed))),
        rounds: 3,
    },
];

/// The lit scene's table: how each way of finding the lights costs per sample (the error
/// each reaches is `results/error.md`'s).
const LIT_VARIANTS: [Variant; 5] = [
    Variant {
        name: "default: light sampling mis (a shadow ray at every diffuse hit, by a chance at dim ones; 16 edge points)",
        kind: "reference",
        scene: |s| s,
        settings: |s| s,
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "light sampling mixture (half the bounces aimed at the light)",
        kind: "unbiased: other noise",
        scene: |s| s,
        settings: |s| RenderSettings { light_sampling: LightSampling::Mixture, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "light sampling bsdf (the material's bounce only)",
        kind: "unbiased: other noise",
        scene: |s| s,
        settings: |s| RenderSettings { light_sampling: LightSampling::Bsdf, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "mis with Russian roulette",
        kind: "unbiased: other noise",
        scene: |s| s,
        settings: |s| RenderSettings { roulette: true, ..s },
        streams: per_sample,
        rounds: 3,
    },
    Variant {
        name: "no edge points (`--edge-spots 0`: the light's edge pixels count the camera ray's own hit)",
        kind: "unbiased: other noise",
        scene: |s| s,
        settings: |s| RenderSettings { edge_spots: 0, ..s },
        streams: per_sample,
        rounds: 3,
    },
];

/// One table: a scene at a size, and its variants.
struct Table {
    scene: &'static str,
    size: (u32, u32),
    variants: &'static [Variant],
}

const TABLES: [Table; 2] = [
    Table { scene: "final", size: (600, 400), variants: &VARIANTS },
    Table { scene: "cornell", size: (200, 200), variants: &LIT_VARIANTS },
];

struct Measured {
    seconds: Vec<f64>,
    rays: u64,
    image: Image,
}

fn run(scene: &str, variant: &Variant, base: RenderSettings) -> Measured {
    let scene =
        (variant.scene)(builtin_scene(scene, DEFAULT_SCENE_SEED).expect("a built-in scene").to_scene());
    let settings = (variant.settings)(base);
    let rng = (variant.streams)(settings.seed);
    let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, 1, 16, Arc::new(|_| {})));
    let start = Instant::now();
    let out = render(&frame, &Schedule::Serial);
    Measured { seconds: vec![start.elapsed().as_secs_f64()], rays: out.rays, image: out.image }
}

fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn largest_difference(a: &Image, b: &Image) -> f64 {
    a.pixels.iter().zip(&b.pixels).map(|(p, q)| to_f64((*p - *q).abs().max_element())).fold(0.0, f64::max)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let mut md = format!(
        "# Ablation: each optimisation switched off\n\nMachine: {}.\nCommand: `cargo bench --bench ablation{}`. \
         One thread (serial), depth 50, seed 1, independent numbers per sample; median of the runs listed.\n",
        Machine::current().describe(),
        if quick { " -- --quick" } else { "" }
    );
    for table in &TABLES {
        md += &measure_table(table, quick);
    }
    let path = results_dir().join("ablation.md");
    std::fs::write(&path, &md).expect("the output directory is writable");
    println!("{md}\nwrote {}", path.display());
}

/// Renders every variant of `table` in rounds; its Markdown section.
fn measure_table(table: &Table, quick: bool) -> String {
    let (width, height, spp) =
        if quick { (table.size.0 / 2, table.size.1 / 2, 16) } else { (table.size.0, table.size.1, 64) };
    let base = RenderSettings {
        width,
        height,
        spp,
        max_depth: 50,
        seed: 1,
        sampler: Sampler::Independent,
        ..Default::default()
    };
    let mut measured: Vec<Option<Measured>> = table.variants.iter().map(|_| None).collect();
    for round in 0..3 {
        for (variant, slot) in table.variants.iter().zip(measured.iter_mut()) {
            if round >= variant.rounds {
                continue;
            }
            let m = run(table.scene, variant, base);
            eprintln!("round {round}: {}: {}: {:.3} s", table.scene, variant.name, m.seconds[0]);
            match slot {
                Some(kept) => kept.seconds.extend(m.seconds),
                None => *slot = Some(m),
            }
        }
    }
    let measured: Vec<Measured> = measured.into_iter().map(|m| m.expect("every variant ran")).collect();
    let reference = &measured[0];
    let mut md = format!(
        "\n## `{}`, {width} × {height}, {spp} spp\n\n\
         | change | kind | runs (s) | median (s) | rays | Mrays/s | × default time | largest pixel difference |\n\
         |---|---|---|---:|---:|---:|---:|---:|\n",
        table.scene
    );
    for (variant, m) in table.variants.iter().zip(&measured) {
        let runs: Vec<String> = m.seconds.iter().map(|s| format!("{s:.2}")).collect();
        let t = median(&m.seconds);
        md += &format!(
            "| {} | {} | {} | {t:.2} | {} | {:.2} | {:.2} | {:.3e} |\n",
            variant.name,
            variant.kind,
            runs.join(", "),
            m.rays,
            m.rays as f64 / t / 1e6,
            t / median(&reference.seconds),
            largest_difference(&m.image, &reference.image),
        );
    }
    md
}
