//! `cargo bench --bench accuracy`: does every light-transport setting render every lit
//! scene's mean image? Issue #55's long run, beside `tests/agreement.rs` (which runs cornell
//! in CI at a block's power of 3–12%). Per scene, a `bsdf` reference of many seeds, then
//! each setting over independent seeds; per 8 × 8 block of a 64 × 64 render and for the
//! whole image, the bias with its standard error from the seeds' spread, the worst block's
//! `|z|`, and the smallest bias the comparison would see (4.5 standard errors): written to
//! `results/accuracy.md`. `-- --quick` takes a quarter of the seeds; `-- SCENE…` only those.

#[path = "../tests/rooms/mod.rs"]
mod rooms;

use std::fmt::Write as _;
use std::time::Instant;

use raypool::measure::agreement::{BLOCK_Z, WHOLE_Z, compare, over_seeds, renders};
use raypool::measure::machine::{Machine, cpus, results_dir};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::scenes::format::SceneFile;
use raypool::tracer::guiding::Guiding;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::render::{Adaptive, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::scene::Scene;

/// The settings compared with `bsdf`, each from the uniform `mis` at `spp` and `depth`.
fn settings(spp: u32, depth: u32) -> Vec<(&'static str, RenderSettings)> {
    let mis = RenderSettings { width: 64, height: 64, spp, max_depth: depth, ..Default::default() };
    let adaptive = Some(Adaptive { target_error: 0.05, min_spp: spp / 4 });
    // Path guiding learns in passes up to a quarter of the samples (`--guiding on`'s default).
    // Guided `bsdf` takes twice the samples (and learns from twice as many): its paths find
    // the light by bouncing alone, and at `spp` its whole image's power fell short of 0.5%.
    let guiding = Some(Guiding::for_spp(spp));
    let guided_bsdf = Some(Guiding::for_spp(2 * spp));
    vec![
        ("mis", mis),
        ("mis, independent", RenderSettings { sampler: Sampler::Independent, ..mis }),
        ("mis, no edge points", RenderSettings { edge_spots: 0, ..mis }),
        ("mis, roulette", RenderSettings { roulette: true, ..mis }),
        ("mis, adaptive", RenderSettings { adaptive, spp: 2 * spp, ..mis }),
        ("mixture", RenderSettings { light_sampling: LightSampling::Mixture, ..mis }),
        ("bdpt", RenderSettings { light_sampling: LightSampling::Bdpt, spp: spp / 2, ..mis }),
        ("mis, guided", RenderSettings { guiding, ..mis }),
        (
            "bsdf, guided",
            RenderSettings { guiding: guided_bsdf, light_sampling: LightSampling::Bsdf, spp: 2 * spp, ..mis },
        ),
    ]
}

/// The lit scenes: the books' three and a room lit by lights in a turned group, a triangle
/// and a moving sphere (`tests/rooms`), each with its depth: the room is closed, so its paths
/// would all run to 50 rays; at 8 every setting still estimates the same image.
fn scenes(asked: &[String]) -> Vec<(String, Scene, u32)> {
    let builtin = |name: &str| builtin_scene(name, DEFAULT_SCENE_SEED).expect("built-in").to_scene();
    let room = || SceneFile::parse(&rooms::lit_room(), "lit-room.toml").expect("the lit room").to_scene();
    let all = ["cornell", "cornell-smoke", "next-week", "lit-room"];
    all.iter()
        .filter(|name| asked.is_empty() || asked.iter().any(|a| a == *name))
        .map(|&name| match name {
            "lit-room" => (name.to_owned(), room(), 8),
            _ => (name.to_owned(), builtin(name), 50),
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let quick = std::env::args().any(|a| a == "--quick");
    // Many seeds of few samples: a block's mean per render is heavy-tailed (`tests/agreement.rs`).
    let (reference_seeds, seeds, spp) = if quick { (16, 24, 16) } else { (48, 96, 32) };
    let threads = cpus();
    let started = Instant::now();
    let mut md = format!(
        "# Accuracy: every light-transport setting against `bsdf`\n\n\
         Per scene, 64 × 64, depth 50 (the lit room 8): a `bsdf` reference of {reference_seeds} seeds × 1,024 spp, then each \
         setting over {seeds} other seeds ({spp} spp; adaptive up to {}, bdpt {}; guided: `--guiding on`, learning passes up to {}, guided bsdf {} spp learning up to {}). Standard errors from the \
         spread between seeds, both sides combined. *Detectable* is the smallest bias the comparison would \
         see ({BLOCK_Z} standard errors in the weakest block; {WHOLE_Z} for the whole image). Every row must \
         read `yes`: blocks within {BLOCK_Z}, the whole within {WHOLE_Z}.\n\n\
         | scene | setting | whole bias ± SE | detectable (whole) | worst block \\|z\\| | detectable (weakest block) | agrees |\n\
         |---|---|---:|---:|---:|---:|---|\n",
        2 * spp,
        spp / 2,
        spp / 4,
        2 * spp,
        spp / 2
    );
    for (name, scene, depth) in scenes(&args) {
        let bsdf = RenderSettings {
            width: 64,
            height: 64,
            spp: 1024,
            max_depth: depth,
            light_sampling: LightSampling::Bsdf,
            ..Default::default()
        };
        let reference =
            over_seeds(&renders(&scene, bsdf, 1_000_000..1_000_000 + reference_seeds, 8, threads));
        for (setting, settings) in settings(spp, depth) {
            let ours = over_seeds(&renders(&scene, settings, 2_000_000..2_000_000 + seeds, 8, threads));
            let a = compare(&ours, &reference);
            let _ = writeln!(
                md,
                "| {name} | {setting} | {:+.3}% ± {:.3}% | {:.2}% | {:.1} (block {}) | {:.1}% (block {}) | {} |",
                100.0 * a.whole_bias,
                100.0 * a.whole_error,
                100.0 * WHOLE_Z * a.whole_error,
                a.worst_z,
                a.worst_block,
                100.0 * a.detectable,
                a.weakest_block,
                if a.agrees() { "yes" } else { "**no**" }
            );
            eprintln!("{name}, {setting}: {a:?} ({:.0} s)", started.elapsed().as_secs_f64());
        }
    }
    let command = format!("cargo bench --bench accuracy --{}", if quick { " --quick" } else { "" });
    let _ = writeln!(
        md,
        "\nBlocks are numbered row by row from the top left. `{command}` ({:.0} s); {}",
        started.elapsed().as_secs_f64(),
        Machine::current().describe()
    );
    let path = results_dir().join("accuracy.md");
    std::fs::write(&path, md).expect("write results/accuracy.md");
    println!("wrote {}", path.display());
}
