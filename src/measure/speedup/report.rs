//! The speedup benchmark's reports: the table as Markdown (`speedup.md`) and CSV
//! (`speedup.csv`), the speedup curves of `final` (`speedup.png`) and its tile timelines at the
//! thread count nearest the cores (`timeline-static.png`, `timeline-steal.png`), each labelled
//! with the command and the machine.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::files::output::write_text;
use crate::measure::machine::Machine;
use crate::measure::plot::{Series, speedup_plot, timeline_plot};
use crate::measure::speedup::{Outcome, Preset};
use crate::schedule::frame::DEFAULT_TILE;

/// Writes `speedup.md`, `speedup.csv`, `speedup.png`, `timeline-static.png` and
/// `timeline-steal.png` into `dir`. `command` is the command line that produced `outcome`.
pub fn write_reports(dir: &Path, preset: &Preset, outcome: &Outcome, command: &str) -> Result<(), Error> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::new(format!("cannot create '{}': {e}", dir.display())))?;
    let machine = Machine::current();
    write_text(&dir.join("speedup.csv"), &csv(outcome))?;
    write_text(&dir.join("speedup.md"), &markdown(preset, outcome, command, &machine))?;
    let series: Vec<Series> = outcome
        .rows
        .iter()
        .filter(|r| r.scene == "final" && r.rng == "per-sample" && r.mode != "serial")
        .fold(Vec::<Series>::new(), |mut acc, r| {
            match acc.iter_mut().find(|s| s.label == r.mode) {
                Some(s) => s.points.push((r.threads, r.speedup)),
                None => acc.push(Series { label: r.mode.clone(), points: vec![(r.threads, r.speedup)] }),
            }
            acc
        });
    let title = format!(
        "final, {} px wide, {} spp: speedup over serial ({} CPUs, {})",
        preset.width, preset.spp, machine.cpus, machine.date
    );
    let footer = format!("{command} · {}", machine.describe());
    speedup_plot(&dir.join("speedup.png"), &title, &footer, &series)?;
    for (mode, lanes) in &outcome.timelines {
        let title = format!(
            "final, mode {mode}, {} threads: tiles per thread (nproc {}, {})",
            lanes.len(),
            machine.cpus,
            machine.date
        );
        timeline_plot(&dir.join(format!("timeline-{mode}.png")), &title, &footer, lanes)?;
    }
    Ok(())
}

fn csv(outcome: &Outcome) -> String {
    let mut out = String::from(
        "scene,mode,rng,threads,median_s,runs_s,speedup,efficiency,imbalance,rays,mrays_per_s\n",
    );
    for r in &outcome.rows {
        let runs: Vec<String> = r.seconds.iter().map(|s| format!("{s:.4}")).collect();
        let _ = writeln!(
            out,
            "{},{},{},{},{:.4},{},{:.3},{:.3},{},{:.3},{},{:.2}",
            r.scene,
            r.mode,
            r.rng,
            r.threads,
            r.median(),
            runs.join(" "),
            r.speedup,
            r.efficiency(),
            r.vs_rayon.map_or(String::new(), |v| format!("{v:.4}")),
            r.imbalance,
            r.rays,
            r.rays as f64 / r.median() / 1e6
        );
    }
    out
}

fn markdown(preset: &Preset, outcome: &Outcome, command: &str, machine: &Machine) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Speedup: modes × threads\n");
    let _ = writeln!(md, "Command: `{command}` (preset `{}`) · {}\n", preset.name, machine.describe());
    let _ = writeln!(
        md,
        "Each scene rendered {} wide at {} spp (height from its aspect), tiles of {DEFAULT_TILE} px; the paper's figures at max depth 10 (the paper's), every other scene at 50 (the book's). \
         The benchmark runs in {} rounds; each round renders every configuration once, so that a shared machine's \
         drift over minutes hits every configuration alike. *median* is the median wall time; *speedup* is the median over rounds \
         of serial ÷ this configuration within the same round, and *× rayon* the median of this ÷ rayon at the same thread count \
         (both ratios of measurements taken seconds apart); efficiency = speedup ÷ threads; \
         imbalance = busiest thread's rendering time ÷ mean over the threads that rendered (1.000 = perfect). \
         Every per-sample row renders the same image, bit for bit.\n",
        preset.width, preset.spp, preset.runs
    );
    let scenes: Vec<&str> = preset.scenes.iter().map(|s| s.0).collect();
    for scene in scenes {
        let _ = writeln!(md, "## {scene}\n");
        let _ = writeln!(
            md,
            "| mode | rng | threads | median | speedup | efficiency | × rayon | imbalance | Mrays/s |\n|---|---|---:|---:|---:|---:|---:|---:|---:|"
        );
        for r in outcome.rows.iter().filter(|r| r.scene == scene) {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.3} s | {:.2} | {:.0}% | {} | {:.3} | {:.2} |",
                r.mode,
                r.rng,
                r.threads,
                r.median(),
                r.speedup,
                100.0 * r.efficiency(),
                r.vs_rayon.map_or("–".into(), |v| format!("{v:.3}")),
                r.imbalance,
                r.rays as f64 / r.median() / 1e6
            );
        }
        md.push('\n');
    }
    let _ = writeln!(md, "Thread counts measured: {:?}.", outcome.thread_counts);
    md
}
