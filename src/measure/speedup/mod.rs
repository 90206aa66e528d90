//! **The speedup benchmark** behind `raypool bench` and `cargo bench --bench speedup`: every
//! mode at 1, 2, …, 2 × cores threads (or the list given) on the benchmark scenes, in rounds
//! that run every configuration once, medians over the rounds, and the seed paper's
//! shared-`rand()` ablation.
//!
//! This file runs the benchmark ([`Preset`] → [`run`] → [`Outcome`]); [`report`] writes its
//! `speedup.md`, `speedup.csv`, `speedup.png` and two timelines, and [`paper`] reproduces the
//! seed paper's table at its own size.

pub mod report;
pub mod paper;

use std::sync::Arc;
use std::time::Instant;

use crate::error::Error;
use crate::measure::machine::{Sweep, cpus, thread_counts};
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

    /// This preset on `scenes` instead (when not empty): the paper's figures at its depth
    /// 10, every other scene at the book's 50.
    pub fn on(self, scenes: &[&'static str]) -> Preset {
        if scenes.is_empty() {
            return self;
        }
        let depth = |name: &str| if name.starts_with("paper") { 10 } else { 50 };
        Preset { scenes: scenes.iter().map(|&name| (name, depth(name))).collect(), ..self }
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
