//! The speedup benchmark behind `raypool bench` and `cargo bench --bench speedup`: every
//! mode at 1, 2, …, 2 × cores threads (or the list given) on the benchmark scenes, medians of several runs, and
//! the seed paper's shared-`rand()` ablation. Writes `speedup.md`, `speedup.csv`,
//! `speedup.png` and two timelines into the output directory.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use crate::error::Error;
use crate::files::output::write_text;
use crate::measure::machine::{Machine, Sweep, cpus, thread_counts};
use crate::measure::plot::{Series, speedup_plot, timeline_plot};
use crate::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use crate::schedule::frame::{DEFAULT_TILE, Frame};
use crate::schedule::modes::{Rendered, Schedule, Scheduler, render};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::render::{RenderJob, RenderSettings, default_height};
use crate::tracer::sampling::sampler::Sampler;

/// Sizes and repetitions of one benchmark run.
#[derive(Clone, Debug)]
pub struct Preset {
    /// Name shown in the report.
    pub name: &'static str,
    /// Image width (height from each scene's aspect).
    pub width: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Runs per configuration; the median is reported.
    pub runs: usize,
    /// Scenes and their max depth: the paper's figures at its depth 10, `final` at the
    /// book's 50.
    pub scenes: Vec<(&'static str, u32)>,
    /// Scenes that also get the shared-generator rows.
    pub shared_rng_scenes: Vec<&'static str>,
    /// Thread counts to measure; empty for 1, 2, … 2 × cores.
    pub threads: Vec<usize>,
}

impl Preset {
    /// `raypool bench --quick`: small images, three runs; under two minutes on 2 cores.
    pub fn quick() -> Preset {
        Preset { name: "quick", width: 240, spp: 16, runs: 3, ..Preset::full() }
    }

    /// `cargo bench --bench speedup`: the committed results.
    pub fn full() -> Preset {
        Preset {
            name: "full",
            width: 400,
            spp: 32,
            runs: 7,
            scenes: vec![("final", 50), ("paper1", 10), ("paper2", 10), ("paper3", 10)],
            shared_rng_scenes: vec!["paper1", "final"],
            threads: Vec::new(),
        }
    }
}

/// Per-thread `(start, end)` seconds of each tile a thread rendered.
pub type Lanes = Vec<Vec<(f64, f64)>>;

/// A scheduler under test, with the name the tables use.
pub struct Contender<'a> {
    /// Name in the tables and plots.
    pub name: String,
    /// The scheduler.
    pub scheduler: &'a dyn Scheduler,
}

/// One measured configuration.
#[derive(Clone, Debug)]
pub struct Row {
    /// Scene name.
    pub scene: &'static str,
    /// Contender name.
    pub mode: String,
    /// "per-sample" or "shared".
    pub rng: &'static str,
    /// Threads given to the scheduler.
    pub threads: usize,
    /// Every run's wall time, seconds, in round order.
    pub seconds: Vec<f64>,
    /// Rays cast in one run.
    pub rays: u64,
    /// Median load imbalance (busiest thread ÷ mean).
    pub imbalance: f64,
    /// Speedup over serial: the median over rounds of (serial time ÷ this time) in the same
    /// round, a ratio of two measurements taken seconds apart.
    pub speedup: f64,
    /// Likewise, the median over rounds of (this time ÷ rayon's time at the same thread
    /// count), when a rayon contender ran.
    pub vs_rayon: Option<f64>,
}

impl Row {
    /// Median wall time, seconds.
    pub fn median(&self) -> f64 {
        median(&mut self.seconds.clone())
    }

    /// Speedup ÷ threads.
    pub fn efficiency(&self) -> f64 {
        self.speedup / self.threads as f64
    }
}

/// Everything one benchmark run produced.
pub struct Outcome {
    /// All rows, scene by scene.
    pub rows: Vec<Row>,
    /// `final`'s tile timelines at the measured thread count nearest the cores, by mode.
    pub timelines: Vec<(String, Lanes)>,
    /// Thread counts measured.
    pub thread_counts: Vec<usize>,
}

/// Renders one configuration once: (wall seconds, the render).
fn measure_once(
    job: &RenderJob,
    scheduler: &dyn Scheduler,
    threads: usize,
    shared_rng: bool,
) -> (f64, Rendered) {
    let rng =
        RngSource::new(&job.settings, if shared_rng { RngChoice::Shared } else { RngChoice::PerSample });
    let frame = Arc::new(Frame::new(job.clone(), rng, threads, DEFAULT_TILE, Arc::new(|_| {})));
    let start = Instant::now();
    let rendered = render(&frame, scheduler);
    (start.elapsed().as_secs_f64(), rendered)
}

/// One configuration of the benchmark: a scheduler, a thread count, a random source.
struct Config<'a> {
    mode: &'a str,
    scheduler: &'a dyn Scheduler,
    threads: usize,
    shared_rng: bool,
}

/// The median over rounds of `a[i] / b[i]`.
fn paired_ratio(a: &[f64], b: &[f64]) -> f64 {
    median(&mut a.iter().zip(b).map(|(x, y)| x / y).collect::<Vec<_>>())
}

/// The median of `values` (the upper one of an even count); sorts them.
pub fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// A render's tiles as per-thread lanes of `(start, end)` seconds, threads in order of
/// their first tile.
fn lanes(rendered: &Rendered) -> Lanes {
    let mut ids: Vec<std::thread::ThreadId> = Vec::new();
    let mut lanes: Lanes = Vec::new();
    let mut timeline = rendered.timeline.clone();
    timeline.sort_by_key(|(_, t)| t.start);
    for (_, t) in timeline {
        let lane = ids.iter().position(|&id| id == t.thread).unwrap_or_else(|| {
            ids.push(t.thread);
            lanes.push(Vec::new());
            ids.len() - 1
        });
        lanes[lane].push((t.start.as_secs_f64(), t.end.as_secs_f64()));
    }
    lanes
}

/// Every configuration measured on one scene: serial, each contender at each thread count,
/// and (for `shared_rng_rows`) the shared-generator rows of the paper's ablation.
fn configurations<'a>(
    builtins: &'a [Contender],
    extra: &'a [Contender],
    thread_counts: &[usize],
    shared_rng_rows: bool,
) -> Vec<Config<'a>> {
    let mut configs =
        vec![Config { mode: "serial", scheduler: &Schedule::Serial, threads: 1, shared_rng: false }];
    for contender in builtins.iter().chain(extra) {
        for &threads in thread_counts {
            configs.push(Config {
                mode: &contender.name,
                scheduler: contender.scheduler,
                threads,
                shared_rng: false,
            });
        }
    }
    if shared_rng_rows {
        configs.push(Config { mode: "serial", scheduler: &Schedule::Serial, threads: 1, shared_rng: true });
        for &threads in thread_counts.iter().filter(|&&t| t > 1) {
            configs.push(Config {
                mode: "static",
                scheduler: &Schedule::StaticBlocks,
                threads,
                shared_rng: true,
            });
        }
    }
    configs
}

/// Runs the benchmark: the built-in modes plus `extra` contenders (e.g. a rayon baseline).
/// `log` receives one line per measured configuration.
pub fn run(preset: &Preset, extra: &[Contender], mut log: impl FnMut(&str)) -> Result<Outcome, Error> {
    let cores = cpus();
    let thread_counts = thread_counts(&preset.threads, Sweep::EveryCountToTwiceTheCpus);
    let timeline_threads = thread_counts.iter().copied().min_by_key(|&t| t.abs_diff(cores)).unwrap_or(cores);
    let builtins: Vec<Contender> =
        Schedule::ALL[1..].iter().map(|s| Contender { name: s.name().to_owned(), scheduler: s }).collect();
    let mut rows = Vec::new();
    let mut timelines = Vec::new();
    for &(scene_name, depth) in &preset.scenes {
        let scene = builtin_scene(scene_name, DEFAULT_SCENE_SEED)?;
        let height = default_height(preset.width, scene.camera.aspect)?;
        let settings = RenderSettings {
            width: preset.width,
            height,
            spp: preset.spp,
            max_depth: depth,
            seed: 1,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let job = RenderJob::new(scene.to_scene(), settings);
        let configs =
            configurations(&builtins, extra, &thread_counts, preset.shared_rng_scenes.contains(&scene_name));
        // Round-robin: each round runs every configuration once, so a machine that slows down
        // or speeds up over the minutes of a benchmark affects every configuration alike.
        let mut seconds = vec![Vec::new(); configs.len()];
        let mut imbalances = vec![Vec::new(); configs.len()];
        let mut last = Vec::new();
        for round in 0..preset.runs.max(1) {
            last.clear();
            for (k, c) in configs.iter().enumerate() {
                let (s, rendered) = measure_once(&job, c.scheduler, c.threads, c.shared_rng);
                seconds[k].push(s);
                imbalances[k].push(rendered.imbalance());
                last.push(rendered);
            }
            log(&format!("{scene_name}: round {} of {} done", round + 1, preset.runs.max(1)));
        }
        for (k, c) in configs.iter().enumerate() {
            let rayon = configs
                .iter()
                .position(|r| r.mode == "rayon" && r.threads == c.threads && !r.shared_rng && !c.shared_rng);
            let row = Row {
                scene: scene_name,
                mode: c.mode.to_owned(),
                rng: if c.shared_rng { "shared" } else { "per-sample" },
                threads: c.threads,
                seconds: seconds[k].clone(),
                rays: last[k].rays,
                imbalance: median(&mut imbalances[k]),
                speedup: paired_ratio(&seconds[0], &seconds[k]),
                vs_rayon: rayon.map(|r| paired_ratio(&seconds[k], &seconds[r])),
            };
            let m = row.median();
            log(&format!(
                "{scene_name:<7} {:<12} {:<10} {:>2} threads: {m:>8.3} s  speedup {:>5.2}  imbalance {:.3}",
                row.mode, row.rng, row.threads, row.speedup, row.imbalance
            ));
            rows.push(row);
            if scene_name == "final"
                && !c.shared_rng
                && c.threads == timeline_threads
                && ["static", "steal"].contains(&c.mode)
            {
                timelines.push((c.mode.to_owned(), lanes(&last[k])));
            }
        }
    }
    Ok(Outcome { rows, timelines, thread_counts })
}

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
        "Each scene rendered {} wide at {} spp (height from its aspect), tiles of {DEFAULT_TILE} px; `final` at max depth 50 (the book's), the paper's figures at 10 (the paper's). \
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

/// The seed paper's final-report table (seconds on its authors' machine, core count unknown)
/// and its final image's figures (88.98 and 20.66 minutes), with the row each corresponds to.
const PAPER: [(&str, [Option<f64>; 3]); 4] = [
    ("final", [Some(88.98 * 60.0), Some(20.66 * 60.0), None]),
    ("paper1", [Some(208.0), Some(330.0), Some(353.0)]),
    ("paper2", [Some(308.0), Some(453.0), Some(482.0)]),
    ("paper3", [Some(532.0), Some(488.0), Some(511.0)]),
];

/// The paper's three rows, and the modes that reproduce them (with its shared generator)
/// and that fix them (with per-sample streams; the thread-pool row is fixed by our best mode).
const PAPER_ROWS: [(&str, Schedule, Schedule); 3] = [
    ("single-threaded", Schedule::Serial, Schedule::Serial),
    ("naive multithreading (static blocks)", Schedule::StaticBlocks, Schedule::StaticBlocks),
    ("thread pool (a job per scanline)", Schedule::PoolRows, Schedule::Stealing),
];

/// One cell pair of the paper table: our time with the shared generator and with streams.
pub struct PaperCell {
    /// Scene name.
    pub scene: &'static str,
    /// Max depth used.
    pub depth: u32,
    /// Index into the paper's three rows.
    pub row: usize,
    /// Wall seconds with one shared locked generator (the paper's `rand()`).
    pub shared: Option<f64>,
    /// Wall seconds with per-sample streams.
    pub per_sample: f64,
}

/// Renders the paper's configurations at 1200 × 800 and `spp` samples on `threads` threads,
/// one run each: the paper's depth 10 on all four scenes, and the book's depth 50 on
/// `final` (per-sample streams only).
pub fn paper_table(spp: u32, threads: usize, mut log: impl FnMut(&str)) -> Result<Vec<PaperCell>, Error> {
    let mut cells = Vec::new();
    let configs = PAPER.iter().map(|p| (p.0, 10, true)).chain([("final", 50, false)]);
    for (scene_name, depth, with_shared) in configs {
        let scene = builtin_scene(scene_name, DEFAULT_SCENE_SEED)?.to_scene();
        let settings = RenderSettings {
            width: 1200,
            height: 800,
            spp,
            max_depth: depth,
            seed: 1,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let job = RenderJob::new(scene, settings);
        for (row, &(label, theirs, ours)) in PAPER_ROWS.iter().enumerate() {
            let threads = if row == 0 { 1 } else { threads };
            let shared = with_shared.then(|| measure_once(&job, &theirs, threads, true).0);
            let per_sample = measure_once(&job, &ours, threads, false).0;
            let shared_text = shared.map_or("–".into(), |s| format!("{s:.1} s"));
            log(&format!(
                "{scene_name:<7} depth {depth:<2} {label:<38} shared {shared_text:>9}   per-sample {per_sample:>8.1} s"
            ));
            cells.push(PaperCell { scene: scene_name, depth, row, shared, per_sample });
        }
    }
    Ok(cells)
}

/// Writes `paper-table.md`: the paper's table beside ours.
pub fn write_paper_table(
    dir: &Path,
    cells: &[PaperCell],
    spp: u32,
    threads: usize,
    command: &str,
) -> Result<(), Error> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::new(format!("cannot create '{}': {e}", dir.display())))?;
    let machine = Machine::current();
    let scale = 500.0 / spp as f64;
    let mut md = String::new();
    let _ = writeln!(md, "# The paper's table, reproduced\n");
    let _ = writeln!(md, "Command: `{command}` · {}\n", machine.describe());
    let _ = writeln!(
        md,
        "1200 × 800 pixels, {spp} samples per pixel{}, one run per cell, {threads} threads for the parallel rows. \
         The paper's columns are its own measurements (seconds, its authors' machine, core count unknown; \
         the final image's two figures are its 88.98 and 20.66 minutes). \
         *Shared rand()* draws every random number from one generator behind a futex lock, as the paper's C `rand()` did; \
         *per-sample* gives each pixel sample its own stream (raypool's normal mode); its thread-pool row uses raypool's best mode, `steal`.\n",
        if spp == 500 {
            String::new()
        } else {
            format!(
                " (measured at {spp} spp and multiplied by {scale:.0} to estimate the paper's 500: render time is linear in spp)"
            )
        }
    );
    let _ = writeln!(
        md,
        "| scene | depth | row | paper | ours, shared rand() | ours, per-sample | per-sample speedup |\n|---|---:|---|---:|---:|---:|---:|"
    );
    for c in cells {
        let paper = PAPER.iter().find(|p| p.0 == c.scene && c.depth == 10).and_then(|p| p.1[c.row]);
        let serial = cells
            .iter()
            .find(|d| d.scene == c.scene && d.depth == c.depth && d.row == 0)
            .map_or(f64::NAN, |d| d.per_sample);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {:.1} s | {:.2}× |",
            c.scene,
            c.depth,
            PAPER_ROWS[c.row].0,
            paper.map_or("–".into(), |p| format!("{p:.0} s")),
            c.shared.map_or("–".into(), |s| format!("{:.1} s", s * scale)),
            c.per_sample * scale,
            serial / c.per_sample
        );
    }
    write_text(&dir.join("paper-table.md"), &md)
}
