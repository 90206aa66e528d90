//! `cargo bench --bench error`: run time against error for every sampling method, in f32 and
//! (with `--features f64`) f64.
//!
//! For each scene: a reference of 2 × 2048 spp (independent numbers, two seeds; cached under
//! `target/error-reference/`, outside git, and shared by the f32 and f64 runs), then renders
//! at 1, 2, 4, … 256 spp with each uniform method (independent or Sobol numbers, Russian
//! roulette off or on) and with adaptive sampling at several target errors, each timed and
//! measured against the reference by RMSE and by relative MSE (its own noise taken out, see
//! `raypool::measure::convergence`). The headline: each method's time to reach the error of
//! independent uniform sampling at 256 spp, interpolated on its error-against-time curve.
//! Writes `results/error-f32.csv` (or `-f64`), then `results/error.md` and `results/error.png`
//! from whichever of the two CSV files exist. Run it once without and once with
//! `--features f64` to compare the precisions. `--quick`: small images, for a smoke test.
//!
//! The scenes lit by emitters (`cornell`, `cornell-smoke`) are measured by [`lights`]: the
//! three `--light-sampling` settings against bsdf's error at 1,024 spp. `--only sky` or
//! `--only lights` runs one of the two parts, `--only report` neither; the report is rebuilt
//! from every CSV present. The sky scenes' tables and plot are written by [`report`].

mod lights;
mod report;

use std::fmt::Write as _;
use std::path::Path;

use raypool::files::image::Image;
use raypool::files::output::{Format, encode, read_pfm};
use raypool::measure::convergence::{Reference, timed_render};
use raypool::measure::machine::{Machine, cpus, results_dir};
use raypool::measure::speedup::median;
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::math::real::{Real, to_f64, vec3};
use raypool::tracer::render::default_height;
use raypool::tracer::render::{Adaptive, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::scene::Scene;

/// The uniform methods: (name, sampler, Russian roulette).
const METHODS: [(&str, Sampler, bool); 4] = [
    ("independent", Sampler::Independent, false),
    ("sobol", Sampler::Sobol, false),
    ("independent+rr", Sampler::Independent, true),
    ("sobol+rr", Sampler::Sobol, true),
];

const SCENES: [&str; 5] = ["final", "paper1", "paper2", "paper3", "three-spheres"];
const TARGETS: [Real; 8] = [0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.0015625];

/// The adaptive methods: (name, sampler).
const ADAPTIVE: [(&str, Sampler); 2] =
    [("adaptive", Sampler::Independent), ("sobol adaptive", Sampler::Sobol)];
const PRECISION: &str = if cfg!(feature = "f64") { "f64" } else { "f32" };
/// Runs per render whose median time a row reports: on a shared machine one run's time moves
/// by 10% and more from run to run (`results/perf.md`), and the headline ratios are ratios of
/// such times.
const TIMING_ROUNDS: usize = 3;

struct Config {
    width: u32,
    reference_spp_each: u32,
    max_spp: u32,
    min_spp: u32,
}

/// One measured render: a CSV row.
struct Row {
    scene: String,
    precision: String,
    /// One of [`METHODS`]' or [`ADAPTIVE`]'s names.
    method: String,
    /// spp for uniform; the target error for adaptive.
    setting: f64,
    mean_spp: f64,
    seconds: f64,
    rmse: f64,
    rel_mse: f64,
}

const CSV_HEADER: &str = "scene,precision,method,setting,mean_spp,seconds,rmse,rel_mse";

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let only = args.iter().position(|a| a == "--only").and_then(|k| args.get(k + 1)).map(String::as_str);
    assert!(
        only.is_none_or(|o| ["sky", "lights", "report"].contains(&o)),
        "--only takes sky, lights or report"
    );
    let config = if quick {
        Config { width: 48, reference_spp_each: 256, max_spp: 64, min_spp: 8 }
    } else {
        Config { width: 160, reference_spp_each: 2048, max_spp: 256, min_spp: 16 }
    };
    let out_dir = results_dir();
    let threads = cpus();
    let given: Vec<&str> = args.iter().skip(1).map(String::as_str).filter(|a| *a != "--bench").collect();
    let command = if given.is_empty() {
        "cargo bench --bench error".to_string()
    } else {
        format!("cargo bench --bench error -- {}", given.join(" "))
    };
    let footer = format!("{command} [--features f64]; {}", Machine::current().describe());
    let mut references = String::new();
    if only.is_none() || only == Some("sky") {
        references = measure_sky(&config, threads, &out_dir);
    }
    if only.is_none() || only == Some("lights") {
        lights::measure(quick, threads, &out_dir, &format!("{command}; {}", Machine::current().describe()));
    }
    // Both precisions' rows, where the other run's CSV exists.
    let mut all = Vec::new();
    for precision in ["f32", "f64"] {
        all.extend(read_csv(&out_dir.join(format!("error-{precision}.csv"))));
    }
    let mut sky_footer = footer.clone();
    if references.is_empty() {
        // Only the lights were measured: keep the sky part's header (its command, machine,
        // commit and references) from the last report.
        let previous = std::fs::read_to_string(out_dir.join("error.md")).unwrap_or_default();
        references = previous_references(&previous);
        sky_footer = previous_footer(&previous).unwrap_or(sky_footer);
    }
    let mut md = report::report(&all, &config, &references, &sky_footer, threads);
    md += &lights::report(&out_dir, quick);
    std::fs::write(out_dir.join("error.md"), &md).expect("error.md is writable");
    if !all.is_empty() {
        report::plot(&all, &out_dir.join("error.png"), &sky_footer);
    }
    println!("{md}\nwrote {}/error.md and its plots", out_dir.display());
}

/// The sky scenes' part: every sampling method at every setting, written to
/// `error-{precision}.csv`; returns the references' table rows.
fn measure_sky(config: &Config, threads: usize, out_dir: &Path) -> String {
    let mut rows = Vec::new();
    let mut references = String::new();
    for name in SCENES {
        let file = builtin_scene(name, DEFAULT_SCENE_SEED).expect("built-in scene");
        let height = default_height(config.width, file.camera.aspect).expect("a sane aspect");
        let scene = file.to_scene();
        let base =
            RenderSettings { width: config.width, height, max_depth: 50, seed: 1, ..Default::default() };
        let reference = cached_reference(name, &scene, base, config.reference_spp_each, threads);
        let _ = writeln!(
            references,
            "| {name} | {} × {height} | {} | {:.2e} |",
            config.width, reference.spp, reference.noise
        );
        let measure = |rows: &mut Vec<Row>, setting: f64, methods: &[(&str, RenderSettings)]| {
            let at = Setting { scene: name, world: &scene, base, reference: &reference, threads };
            measure_rounds(rows, &at, setting, methods);
        };
        // To twice the goal's spp, so a method noisier than independent sampling (roulette)
        // can still reach its error.
        let mut spp = 1;
        while spp <= 2 * config.max_spp {
            let methods = METHODS.map(|(method, sampler, roulette)| {
                (method, RenderSettings { spp, sampler, roulette, ..base })
            });
            measure(&mut rows, spp as f64, &methods);
            spp *= 2;
        }
        for target_error in TARGETS {
            let methods = ADAPTIVE.map(|(method, sampler)| {
                let adaptive = Some(Adaptive { target_error, min_spp: config.min_spp });
                (method, RenderSettings { spp: 4 * config.max_spp, adaptive, sampler, ..base })
            });
            measure(&mut rows, to_f64(target_error), &methods);
        }
    }
    write_csv(&out_dir.join(format!("error-{PRECISION}.csv")), "", &rows);
    references
}

/// Writes `rows` as CSV under [`CSV_HEADER`], after `preamble` (lines [`read_csv`] skips).
fn write_csv(path: &Path, preamble: &str, rows: &[Row]) {
    let csv: String = rows
        .iter()
        .map(|r| {
            format!(
                "{},{},{},{:.4},{:.3},{:.5},{:.6e},{:.6e}\n",
                r.scene, r.precision, r.method, r.setting, r.mean_spp, r.seconds, r.rmse, r.rel_mse
            )
        })
        .collect();
    std::fs::write(path, format!("{preamble}{CSV_HEADER}\n{csv}")).expect("the CSV is writable");
}

/// The footer line (command, machine, commit, date) of an earlier report `text`.
fn previous_footer(text: &str) -> Option<String> {
    let line = text.lines().find(|l| l.starts_with('`'))?;
    Some(line.trim_matches('`').to_string())
}

/// The references' table rows of an earlier report `text`.
fn previous_references(text: &str) -> String {
    let is_row = |l: &&str| l.starts_with("| ") && SCENES.iter().any(|s| l.starts_with(&format!("| {s} | ")));
    let rows: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("| scene | size |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .filter(is_row)
        .collect();
    rows.iter().map(|l| format!("{l}\n")).collect()
}

/// One scene's measurement context: its world, base settings and reference.
struct Setting<'a> {
    scene: &'a str,
    world: &'a Scene,
    base: RenderSettings,
    reference: &'a Reference,
    threads: usize,
}

/// Every method at one setting (`setting`: the spp, or the target error), measured: the
/// renders run in rounds, each running every method once, so the machine's drift over the
/// minutes hits the methods alike; a row's time is the median of its rounds (the images are
/// the same bits every round, so the first round's is measured).
fn measure_rounds(rows: &mut Vec<Row>, at: &Setting, setting: f64, methods: &[(&str, RenderSettings)]) {
    let mut seconds = vec![Vec::new(); methods.len()];
    let mut images = Vec::new();
    for round in 0..TIMING_ROUNDS {
        for (k, &(_, settings)) in methods.iter().enumerate() {
            let (out, time) = timed_render(at.world.clone(), settings, at.threads);
            seconds[k].push(time);
            if round == 0 {
                images.push(out);
            }
        }
    }
    for ((&(method, _), out), mut times) in methods.iter().zip(&images).zip(seconds) {
        let r = row(at.scene, method, setting, out, median(&mut times), at.reference, at.base);
        eprintln!(
            "{} {PRECISION} {method} {setting}: {:.1} spp, {:.3} s (median of {times:.3?}), rmse {:.3e}, relmse {:.3e}",
            at.scene, r.mean_spp, r.seconds, r.rmse, r.rel_mse
        );
        rows.push(r);
    }
}

fn row(
    scene: &str,
    method: &str,
    setting: f64,
    out: &raypool::schedule::modes::Rendered,
    seconds: f64,
    reference: &Reference,
    base: RenderSettings,
) -> Row {
    Row {
        scene: scene.into(),
        precision: PRECISION.into(),
        method: method.into(),
        setting,
        mean_spp: out.samples as f64 / (base.width as f64 * base.height as f64),
        seconds,
        rmse: reference.error_of(&out.image),
        rel_mse: reference.rel_mse_of(&out.image),
    }
}

/// The scene's reference, from the cache when an earlier run (of either precision) made it.
fn cached_reference(
    name: &str,
    scene: &Scene,
    base: RenderSettings,
    spp_each: u32,
    threads: usize,
) -> Reference {
    let dir = Path::new("target/error-reference");
    let stem = format!("{name}-{}x{}-{spp_each}", base.width, base.height);
    let paths = [dir.join(format!("{stem}-a.pfm")), dir.join(format!("{stem}-b.pfm"))];
    let load = |p: &Path| -> Option<Image> {
        let (width, height, pixels) = read_pfm(&std::fs::read(p).ok()?).ok()?;
        let pixels = pixels.iter().map(|c| vec3(c.map(f64::from))).collect();
        Some(Image { width, height, pixels })
    };
    if let (Some(a), Some(b)) = (load(&paths[0]), load(&paths[1])) {
        return Reference::from_halves(&a, &b, spp_each);
    }
    eprintln!("{name}: rendering the reference, 2 × {spp_each} spp");
    let reference = Reference::render(scene, base, spp_each, threads);
    let halves = reference.halves();
    std::fs::create_dir_all(dir).expect("target/ is writable");
    for (path, half) in paths.iter().zip(halves) {
        let mut bytes = Vec::new();
        encode(half, Format::Pfm, &mut bytes).expect("PFM encodes");
        std::fs::write(path, bytes).expect("the cache is writable");
    }
    reference
}

fn read_csv(path: &Path) -> Vec<Row> {
    let Ok(text) = std::fs::read_to_string(path) else { return Vec::new() };
    text.lines()
        .skip(1)
        .filter_map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |k: usize| f.get(k)?.parse::<f64>().ok();
            Some(Row {
                scene: f.first()?.to_string(),
                precision: f.get(1)?.to_string(),
                method: f.get(2)?.to_string(),
                setting: num(3)?,
                mean_spp: num(4)?,
                seconds: num(5)?,
                rmse: num(6)?,
                rel_mse: num(7)?,
            })
        })
        .collect()
}

fn select<'a>(rows: &'a [Row], scene: &str, precision: &str, method: &str) -> Vec<&'a Row> {
    rows.iter().filter(|r| r.scene == scene && r.precision == precision && r.method == method).collect()
}
