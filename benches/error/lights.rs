//! The lit scenes' part of the error bench: `cornell`, `cornell-smoke` and `next-week` under
//! the three `--light-sampling` settings (and mis with Russian roulette, adaptive mis, and
//! mis and bsdf guided, `--guiding on` with its default pilot), each measured by the time it
//! takes to reach the error that `bsdf` (the material's bounce only, the second book's
//! estimator) reaches at 1,024 spp.
//!
//! Every render uses the Sobol sampler (the command line's default) on the work-stealing
//! scheduler. The reference is `bsdf` at 2 × 8192 spp, two seeds, its own noise taken out of
//! every error as for the sky scenes: not an estimator the bench measures the speed of
//! against it (until 227b8c9 it was `mis`, which hid `mis`'s own 2.5% bias on cornell). Rows go to `error-lights-f32.csv` (or `-f64`); the
//! reference's noise is a row of its own (method `reference`, `setting` its spp).

use std::fmt::Write as _;
use std::path::Path;

use raypool::measure::plot::{LogSeries, log_log_plot};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::guiding::Guiding;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::{Real, to_f64};
use raypool::tracer::render::{Adaptive, RenderSettings, default_height};
use raypool::tracer::sampling::sampler::Sampler;

use super::report::time_to_reach;
use super::{PRECISION, Row, Setting, cached_reference, measure_rounds, read_csv, select, write_csv};

pub const SCENES: [&str; 3] = ["cornell", "cornell-smoke", "next-week"];

/// The uniform methods: (name, light sampling, Russian roulette, path guiding).
const METHODS: [(&str, LightSampling, bool, bool); 6] = [
    ("bsdf", LightSampling::Bsdf, false, false),
    ("mixture", LightSampling::Mixture, false, false),
    ("mis", LightSampling::Mis, false, false),
    ("mis+rr", LightSampling::Mis, true, false),
    ("mis+guided", LightSampling::Mis, false, true),
    ("bsdf+guided", LightSampling::Bsdf, false, true),
];
const ADAPTIVE: &str = "mis adaptive";
const TARGETS: [Real; 5] = [0.2, 0.1, 0.05, 0.025, 0.0125];

struct Config {
    width: u32,
    reference_spp_each: u32,
    /// bsdf's spp whose error is the goal; every uniform method runs 1, 2, 4, … this.
    goal_spp: u32,
    min_spp: u32,
}

fn config(quick: bool) -> Config {
    if quick {
        Config { width: 32, reference_spp_each: 512, goal_spp: 64, min_spp: 8 }
    } else {
        Config { width: 96, reference_spp_each: 8192, goal_spp: 1024, min_spp: 16 }
    }
}

/// Renders and measures every method on both scenes; writes `error-lights-{precision}.csv`.
pub fn measure(quick: bool, threads: usize, out_dir: &Path, footer: &str) {
    let config = config(quick);
    let mut rows = Vec::new();
    for name in SCENES {
        let file = builtin_scene(name, DEFAULT_SCENE_SEED).expect("built-in scene");
        let height = default_height(config.width, file.camera.aspect).expect("a sane aspect");
        let world = file.to_scene();
        let base = RenderSettings {
            width: config.width,
            height,
            max_depth: 50,
            seed: 1,
            sampler: Sampler::Sobol,
            light_sampling: LightSampling::Mis,
            ..Default::default()
        };
        let cache_name = format!("{name}-bsdf-sobol");
        let bsdf = RenderSettings { light_sampling: LightSampling::Bsdf, ..base };
        let reference = cached_reference(&cache_name, &world, bsdf, config.reference_spp_each, threads);
        rows.push(Row {
            scene: name.into(),
            precision: PRECISION.into(),
            method: "reference".into(),
            setting: f64::from(reference.spp),
            mean_spp: f64::from(reference.spp),
            seconds: 0.0,
            rmse: reference.noise,
            rel_mse: 0.0,
        });
        let at = Setting { scene: name, world: &world, base, reference: &reference, threads };
        let mut spp = 1;
        while spp <= config.goal_spp {
            let methods = METHODS.map(|(method, light_sampling, roulette, guided)| {
                let guiding = guided.then(|| Guiding::for_spp(spp));
                (method, RenderSettings { spp, light_sampling, roulette, guiding, ..base })
            });
            measure_rounds(&mut rows, &at, f64::from(spp), &methods);
            spp *= 2;
        }
        for target_error in TARGETS {
            let adaptive = Some(Adaptive { target_error, min_spp: config.min_spp });
            let settings = RenderSettings { spp: config.goal_spp, adaptive, ..base };
            measure_rounds(&mut rows, &at, to_f64(target_error), &[(ADAPTIVE, settings)]);
        }
    }
    // The first line names the run (command, machine, commit, date): the report quotes it.
    write_csv(&out_dir.join(format!("error-lights-{PRECISION}.csv")), &format!("# {footer}\n"), &rows);
}

/// The report's section on the lit scenes, from `error-lights-f32.csv` (empty if it is
/// missing), and one plot per scene, `error-lights-{scene}.png`.
pub fn report(out_dir: &Path, quick: bool) -> String {
    let path = out_dir.join("error-lights-f32.csv");
    let rows = read_csv(&path);
    if rows.is_empty() {
        return String::new();
    }
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let footer = text.lines().next().and_then(|l| l.strip_prefix("# ")).unwrap_or("run unnamed");
    let config = config(quick);
    let goal_spp = f64::from(config.goal_spp);
    let mut md = format!(
        "\n## Lit scenes: light sampling against bsdf's error at {goal_spp} spp\n\n\
         `{footer}` (`benches/error/lights.rs`)\n\nEvery render {w} × {w}, depth 50, \
         the Sobol sampler, {TIMING} timed runs interleaved over the methods, every core of the machine (`nproc`). The \
         reference: `bsdf` (not an estimator whose speed is measured against it), two halves of different seeds, \
         its noise taken out. *bsdf* follows the material only; \
         *mixture* is the third book's 50/50 mixture of light and material; *mis* casts a shadow ray at every diffuse \
         hit (by a chance at dim ones), weighed against the bounce by the power heuristic; *+rr*: Russian roulette after 4 rays; \
         *+guided*: `--guiding on` (passes of 1, 2, 4, … samples learn where light arrives, up to a quarter of the samples; \
         half of the guided bounces drawn from what was learnt; `results/guiding.md`); *adaptive*: \
         `--target-error E --min-spp {min} --max-spp {goal_spp}`. Time = where the method's error-against-time curve \
         crosses bsdf's error at {goal_spp} spp (log–log between the runs around it); ratio = that ÷ bsdf's time at \
         {goal_spp} spp. Every setting takes 16 edge points per sample where a pixel may see the light (`--edge-spots`). \
         RMSE weighs bright pixels (the light's own edges, seen through the glass sphere above all, whose noise \
         every setting shares) by their brightness; relMSE, (x − r)²/(r² + 0.01), weighs every pixel \
         alike.\n\n| scene | reference spp | reference noise (RMSE) |\n|---|---:|---:|\n",
        w = config.width,
        TIMING = super::TIMING_ROUNDS,
        min = config.min_spp,
    );
    for scene in SCENES {
        if let Some(r) = select(&rows, scene, "f32", "reference").first() {
            let _ = writeln!(md, "| {scene} | {} | {:.2e} |", r.setting, r.rmse);
        }
    }
    md += "\n| scene | light sampling | RMSE: time (s) | ratio | relMSE: time (s) | ratio |\n|---|---|---:|---:|---:|---:|\n";
    for scene in SCENES {
        let bsdf = select(&rows, scene, "f32", "bsdf");
        let Some(goal) = bsdf.iter().find(|r| r.setting == goal_spp) else { continue };
        for method in METHODS.iter().map(|m| m.0).chain([ADAPTIVE]) {
            let runs = select(&rows, scene, "f32", method);
            let cell = |error: fn(&Row) -> f64| match time_to_reach(&runs, error(goal), error) {
                Some(t) => format!("{t:.3} | **{:.3}×**", t / goal.seconds),
                None => "not reached | –".to_string(),
            };
            let _ = writeln!(md, "| {scene} | {method} | {} | {} |", cell(|r| r.rmse), cell(|r| r.rel_mse));
        }
    }
    md += &adaptive_table(&rows);
    md += "\n### Every run\n\n| scene | method | spp or E | mean spp | time (s) | RMSE | relMSE |\n|---|---|---:|---:|---:|---:|---:|\n";
    for r in rows.iter().filter(|r| r.precision == "f32" && r.method != "reference") {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.1} | {:.3} | {:.3e} | {:.3e} |",
            r.scene, r.method, r.setting, r.mean_spp, r.seconds, r.rmse, r.rel_mse
        );
    }
    for scene in SCENES {
        plot(&rows, scene, &out_dir.join(format!("error-lights-{scene}.png")), footer);
    }
    md
}

/// Adaptive mis against uniform mis (both Sobol) at equal error: the time uniform mis needs
/// for each adaptive run's error, interpolated on its own curve.
fn adaptive_table(rows: &[Row]) -> String {
    let mut md = "\n### Adaptive sampling against uniform Sobol (both mis), at equal error\n\n\
                  Gain = uniform mis's time to the adaptive run's error ÷ the adaptive run's time (above 1: \
                  adaptive is faster).\n\n| scene | E | mean spp | time (s) | RMSE | gain by RMSE | relMSE | gain by relMSE |\n\
                  |---|---:|---:|---:|---:|---:|---:|---:|\n"
        .to_string();
    for scene in SCENES {
        let uniform = select(rows, scene, "f32", "mis");
        for r in select(rows, scene, "f32", ADAPTIVE) {
            let gain = |error: fn(&Row) -> f64| {
                time_to_reach(&uniform, error(r), error)
                    .map_or("–".to_string(), |t| format!("{:.2}×", t / r.seconds))
            };
            let _ = writeln!(
                md,
                "| {scene} | {} | {:.1} | {:.3} | {:.3e} | {} | {:.3e} | {} |",
                r.setting,
                r.mean_spp,
                r.seconds,
                r.rmse,
                gain(|r| r.rmse),
                r.rel_mse,
                gain(|r| r.rel_mse)
            );
        }
    }
    md
}

fn plot(rows: &[Row], scene: &str, path: &Path, footer: &str) {
    let series: Vec<LogSeries> = METHODS
        .iter()
        .map(|m| m.0)
        .chain([ADAPTIVE])
        .map(|method| LogSeries {
            label: method.to_string(),
            points: select(rows, scene, "f32", method)
                .iter()
                .filter(|r| r.rmse > 0.0 && r.seconds > 0.0)
                .map(|r| (r.seconds, r.rmse))
                .collect(),
            triangles: method == ADAPTIVE,
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    if series.is_empty() {
        return;
    }
    let title = format!("{scene}: RMSE against run time, by light sampling");
    log_log_plot(path, &title, ("seconds", "RMSE (linear)"), footer, &series, -0.5)
        .expect("the plot is writable");
}
