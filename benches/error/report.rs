//! The error bench's report on the sky scenes: `results/error.md`'s tables (the headline, the
//! slopes, uniform and adaptive sampling at equal error) and `results/error.png`, made from
//! the CSV rows alone, so that `--only report` rebuilds them without rendering.

use std::fmt::Write as _;
use std::path::Path;

use raypool::measure::convergence::log_log_fit;
use raypool::measure::plot::{LogSeries, log_log_plot};

use super::{ADAPTIVE, Config, METHODS, Row, SCENES, TIMING_ROUNDS, select};

/// The uniform-sampling time that reaches `rmse`, from the power law fitted to the uniform
/// runs of 4 spp and more (below that, fixed costs per render dominate the time).
fn uniform_time_for(uniform: &[&Row], rmse: f64) -> f64 {
    // `uniform`: independent uniform sampling's runs.
    let points: Vec<(f64, f64)> =
        uniform.iter().filter(|r| r.setting >= 4.0).map(|r| (r.rmse, r.seconds)).collect();
    let (k, log_c) = log_log_fit(&points);
    (log_c + k * rmse.ln()).exp()
}

/// The sky scenes' part of `results/error.md`.
pub fn report(rows: &[Row], config: &Config, references: &str, footer: &str, threads: usize) -> String {
    let mut md = format!(
        "# Run time against error\n\n`{footer}`\n\nEvery render: {} pixels wide (height from the scene's aspect), depth 50, \
         seed 1, work-stealing scheduler on {threads} threads; each time the median of {TIMING_ROUNDS} runs, interleaved over the methods. Error = RMSE over linear RGB against a \
         reference of two independent halves, with the reference's own noise (RMSE(a, b)/2) taken out \
         (`src/measure/convergence.rs`).\n\n| scene | size | reference spp | reference noise (RMSE) |\n|---|---|---:|---:|\n{references}\n",
        config.width
    );
    md += &headline(rows, config.max_spp);
    md += "## Slope of error against spp (independent uniform sampling, 1…256 spp)\n\nMonte Carlo error must fall as \
           spp^−1/2: the fitted log–log slope must be −0.5 ± 0.05.\n\n| scene | precision | slope | within ±0.05 |\n|---|---|---:|---|\n";
    for scene in SCENES {
        for precision in ["f32", "f64"] {
            let uniform = select(rows, scene, precision, "independent");
            if uniform.len() < 2 {
                continue;
            }
            let points: Vec<(f64, f64)> =
                uniform.iter().filter(|r| r.setting <= 256.0).map(|r| (r.setting, r.rmse)).collect();
            let (slope, _) = log_log_fit(&points);
            let ok = if (slope + 0.5).abs() <= 0.05 { "yes" } else { "**no**" };
            let _ = writeln!(md, "| {scene} | {precision} | {slope:.3} | {ok} |");
        }
    }
    md += "\n## Uniform sampling: time and error\n\n| scene | spp | f32 time (s) | f32 RMSE | f64 time (s) | f64 RMSE |\n|---|---:|---:|---:|---:|---:|\n";
    for scene in SCENES {
        let f32_rows = select(rows, scene, "f32", "independent");
        let f64_rows = select(rows, scene, "f64", "independent");
        for (k, r) in f32_rows.iter().enumerate() {
            let other = f64_rows
                .get(k)
                .map_or("– | –".to_string(), |o| format!("{:.3} | {:.3e}", o.seconds, o.rmse));
            let _ = writeln!(md, "| {scene} | {} | {:.3} | {:.3e} | {other} |", r.setting, r.seconds, r.rmse);
        }
    }
    md += &format!(
        "\n## Adaptive sampling against uniform, at equal error\n\nAdaptive: `--target-error E --min-spp {} \
         --max-spp {}`. \"Uniform time\" is the time uniform sampling needs for the same RMSE, from the power law \
         fitted to its runs of 4–512 spp; the gain is uniform time ÷ adaptive time.\n\n| scene | method | precision | E | mean spp | time (s) | RMSE | uniform time (s) | gain |\n|---|---|---|---:|---:|---:|---:|---:|---:|\n",
        config.min_spp,
        4 * config.max_spp
    );
    for scene in SCENES {
        for precision in ["f32", "f64"] {
            let uniform = select(rows, scene, precision, "independent");
            let adaptive = ADAPTIVE.iter().flat_map(|(method, _)| select(rows, scene, precision, method));
            for r in adaptive {
                let t = uniform_time_for(&uniform, r.rmse);
                let _ = writeln!(
                    md,
                    "| {scene} | {} | {precision} | {:.4} | {:.1} | {:.3} | {:.3e} | {t:.3} | {:.2}× |",
                    r.method,
                    r.setting,
                    r.mean_spp,
                    r.seconds,
                    r.rmse,
                    t / r.seconds
                );
            }
        }
    }
    md
}

/// Each method's time to reach the error of independent uniform sampling at `max_spp`, by
/// RMSE and by relative MSE, and Sobol's slope.
fn headline(rows: &[Row], max_spp: u32) -> String {
    let mut md = format!(
        "## Time to the error of independent uniform sampling at {max_spp} spp\n\nFor each method (adaptive ones along \
         their target errors E = 0.2 … 0.0016), the time at which its error-against-time curve crosses the error that independent uniform sampling reaches at {max_spp} spp, \
         interpolated log–log between the two runs around the crossing; the ratio is that time ÷ independent \
         uniform sampling's own time at {max_spp} spp (below 1: faster to the same error). \"+rr\": Russian \
         roulette.\n\n\
         | scene | method | RMSE: time (s) | ratio | relMSE: time (s) | ratio |\n|---|---|---:|---:|---:|---:|\n"
    );
    for scene in SCENES {
        let independent = select(rows, scene, "f32", "independent");
        let Some(goal) = independent.iter().find(|r| r.setting == f64::from(max_spp)) else { continue };
        for method in METHODS.iter().map(|m| m.0).chain(ADAPTIVE.iter().map(|m| m.0)) {
            let runs = select(rows, scene, "f32", method);
            let cell = |error: fn(&Row) -> f64| match time_to_reach(&runs, error(goal), error) {
                Some(t) => format!("{t:.3} | {:.2}×", t / goal.seconds),
                None => format!("not within {} spp | –", 2 * max_spp),
            };
            let _ = writeln!(md, "| {scene} | {method} | {} | {} |", cell(|r| r.rmse), cell(|r| r.rel_mse));
        }
    }
    md += "\n### Sobol's error slope (RMSE against spp, log–log)\n\n| scene | 1–16 spp | 16–256 spp | 1–256 spp |\n|---|---:|---:|---:|\n";
    for scene in SCENES {
        let runs = select(rows, scene, "f32", "sobol");
        let slope = |lo: f64, hi: f64| {
            let points: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| r.setting >= lo && r.setting <= hi)
                .map(|r| (r.setting, r.rmse))
                .collect();
            if points.len() < 2 { "–".to_string() } else { format!("{:.3}", log_log_fit(&points).0) }
        };
        let _ = writeln!(
            md,
            "| {scene} | {} | {} | {} |",
            slope(1.0, 16.0),
            slope(16.0, 256.0),
            slope(1.0, 256.0)
        );
    }
    md + "\n"
}

/// When `runs` (in increasing spp) first reach `goal` by `error`: log–log interpolation
/// between the runs on either side; the first run's time if it is already there.
pub fn time_to_reach(runs: &[&Row], goal: f64, error: fn(&Row) -> f64) -> Option<f64> {
    let first = runs.first()?;
    if error(first) <= goal {
        return Some(first.seconds);
    }
    runs.windows(2).find(|w| error(w[1]) <= goal).map(|w| {
        let (e0, e1) = (error(w[0]).ln(), error(w[1]).ln());
        let (t0, t1) = (w[0].seconds.ln(), w[1].seconds.ln());
        let at = if e1 < e0 { (goal.ln() - e0) / (e1 - e0) } else { 1.0 };
        (t0 + at * (t1 - t0)).exp()
    })
}

/// `results/error.png`: RMSE against time on `final`, one line per method.
pub fn plot(rows: &[Row], path: &Path, footer: &str) {
    // One line per method on `final` (the other scenes are in the tables).
    let mut series = Vec::new();
    let methods = METHODS.iter().map(|m| m.0).chain(ADAPTIVE.iter().map(|m| m.0));
    for method in methods {
        let points: Vec<(f64, f64)> = select(rows, "final", "f32", method)
            .iter()
            .filter(|r| r.rmse > 0.0)
            .map(|r| (r.seconds, r.rmse))
            .collect();
        if !points.is_empty() {
            let label =
                if method == "adaptive" { "independent adaptive".to_string() } else { method.to_string() };
            series.push(LogSeries { label, points, triangles: method.ends_with("adaptive") });
        }
    }
    log_log_plot(
        path,
        "final: RMSE against run time, by method",
        ("seconds", "RMSE (linear)"),
        footer,
        &series,
        -0.5,
    )
    .expect("error.png is writable");
}
