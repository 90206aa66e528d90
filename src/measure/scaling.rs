//! The scaling model: what each scheduler would do with 8, 64 or 256 threads, predicted from
//! one single-thread render.
//!
//! [`measure_costs`] renders the image once on one thread, row by row and again tile by tile,
//! timing every unit. [`predict`] then replays those costs on `T` virtual workers under each
//! scheduler's own rule, the rules of [`crate::schedule::modes`]:
//!
//! | mode | rule replayed |
//! |---|---|
//! | `static` | `T` contiguous blocks of rows; worker `k` renders block `k` |
//! | `interleaved` | row `r` to worker `r mod T` |
//! | `pool-rows` | rows in order, each to the worker that becomes free first |
//! | `pool` | tiles in order, each to the worker that becomes free first |
//! | `steal` | tiles dealt into `T` contiguous runs; a worker takes its own from the front, and when it runs dry steals from the back of the next non-empty run after its own |
//!
//! The predicted time is the last worker's finishing time; the speedup is the one-thread
//! time (the sum of the row costs) over it. Every unit is assumed to cost on `T` threads what
//! it cost on one: the model leaves out memory bandwidth and shared caches, lock and queue
//! contention, the cost of a job and of a steal, SMT siblings sharing a core, and turbo
//! clocks that drop when more cores are busy. So it is an upper bound set by load balance
//! alone, and the gap to a measured speedup is what those leave-outs cost.

use std::collections::VecDeque;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use crate::error::{Error, io_reason};
use crate::files::output::write_text;
use crate::measure::machine::Machine;
use crate::measure::plot::{ModelLine, efficiency_plot};
use crate::measure::speedup::median;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Rendered, Schedule, render};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::render::RenderJob;

/// Seconds each unit of work took on one thread.
#[derive(Clone, Debug, PartialEq)]
pub struct Costs {
    /// One per image row, top to bottom.
    pub rows: Vec<f64>,
    /// One per tile, in row-major grid order.
    pub tiles: Vec<f64>,
}

impl Costs {
    /// The one-thread time: all rows in order, as `serial` renders them.
    pub fn serial(&self) -> f64 {
        self.rows.iter().sum()
    }
}

/// Renders `job` on the calling thread by rows and by tiles of `tile` pixels, `passes` times
/// each, timing each row and tile; a unit's cost is its median over the passes (one pass
/// on a shared machine catches another process's bursts in a few units). Row and tile passes
/// alternate, so a slow minute of the machine weighs on both alike.
pub fn measure_costs(job: RenderJob, tile: u32, passes: usize) -> Costs {
    let rng = RngSource::new(&job.settings, RngChoice::PerSample);
    let frame = Frame::new(job, rng, 1, tile, Arc::new(|_| {}));
    let (rows, tiles) = (frame.rows(), frame.tiles());
    let mut row_times: Vec<Vec<f64>> = vec![Vec::new(); rows.len()];
    let mut tile_times: Vec<Vec<f64>> = vec![Vec::new(); tiles.len()];
    for _ in 0..passes.max(1) {
        for (units, times) in [(&rows, &mut row_times), (&tiles, &mut tile_times)] {
            for (unit, times) in units.iter().zip(times.iter_mut()) {
                let out = frame.render(*unit);
                times.push(out.timing.map_or(0.0, |t| (t.end - t.start).as_secs_f64()));
            }
        }
    }
    Costs {
        rows: row_times.into_iter().map(|mut v| median(&mut v)).collect(),
        tiles: tile_times.into_iter().map(|mut v| median(&mut v)).collect(),
    }
}

/// What the model predicts for one mode at one thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prediction {
    /// The mode.
    pub mode: Schedule,
    /// Threads.
    pub threads: usize,
    /// Predicted seconds: the last worker's finishing time.
    pub seconds: f64,
    /// One-thread time over `seconds`.
    pub speedup: f64,
    /// Busiest worker's time over the mean of the workers that got any work.
    pub imbalance: f64,
}

/// Replays `costs` on `threads` virtual workers under `mode`'s rule.
///
/// ```
/// use raypool::measure::scaling::{Costs, predict};
/// use raypool::Schedule;
/// // Four rows: the top two cost 1 s, the bottom two 3 s.
/// let costs = Costs { rows: vec![1.0, 1.0, 3.0, 3.0], tiles: vec![1.0, 1.0, 3.0, 3.0] };
/// let split = predict(&costs, Schedule::StaticBlocks, 2);
/// assert_eq!((split.seconds, split.speedup), (6.0, 8.0 / 6.0)); // one block has both 3 s rows
/// let dealt = predict(&costs, Schedule::Interleaved, 2);
/// assert_eq!(dealt.speedup, 2.0); // each thread gets a 1 s row and a 3 s row
/// ```
pub fn predict(costs: &Costs, mode: Schedule, threads: usize) -> Prediction {
    let t = threads.max(1);
    let busy = match mode {
        Schedule::Serial => vec![costs.serial()],
        Schedule::StaticBlocks => {
            let (rows, parts) = (&costs.rows, t.min(costs.rows.len()).max(1));
            (0..parts)
                .map(|k| rows[k * rows.len() / parts..(k + 1) * rows.len() / parts].iter().sum())
                .collect()
        }
        Schedule::Interleaved => (0..t).map(|k| costs.rows.iter().skip(k).step_by(t).sum()).collect(),
        Schedule::PoolRows => first_free(&costs.rows, t),
        Schedule::PoolTiles => first_free(&costs.tiles, t),
        Schedule::Stealing => stealing(&costs.tiles, t),
    };
    // No rule leaves a worker idle while work remains, so each finishes at its busy time.
    let seconds = busy.iter().copied().fold(0.0, f64::max);
    // Idle workers do not count as threads, as in a measured render's imbalance.
    let working: Vec<f64> = busy.into_iter().filter(|&b| b > 0.0).collect();
    Prediction {
        mode,
        threads: if mode == Schedule::Serial { 1 } else { t },
        seconds,
        speedup: if seconds > 0.0 { costs.serial() / seconds } else { 1.0 },
        imbalance: pool::imbalance(&working),
    }
}

/// A shared queue: each job, in order, goes to the worker that is free first (the lowest
/// numbered on a tie). Returns each worker's busy time.
fn first_free(costs: &[f64], t: usize) -> Vec<f64> {
    let mut busy = vec![0.0f64; t];
    for &cost in costs {
        let k = (0..t).min_by(|&a, &b| busy[a].total_cmp(&busy[b])).unwrap_or(0);
        busy[k] += cost;
    }
    busy
}

/// The Stealing pool: jobs dealt into `t` contiguous runs; the worker that is free first
/// takes the front of its own run, or else the back of the next non-empty run after its own.
/// Returns each worker's busy time.
fn stealing(costs: &[f64], t: usize) -> Vec<f64> {
    let n = costs.len();
    let mut runs: Vec<VecDeque<f64>> =
        (0..t).map(|k| costs[k * n / t..(k + 1) * n / t].iter().copied().collect()).collect();
    let mut busy = vec![0.0f64; t];
    let mut done = vec![false; t];
    // Events in time order: the earliest-free worker acts next, so every job still in a run
    // has not been started by anyone at that moment.
    while let Some(me) = (0..t).filter(|&k| !done[k]).min_by(|&a, &b| busy[a].total_cmp(&busy[b])) {
        let job =
            runs[me].pop_front().or_else(|| (1..t).map(|d| (me + d) % t).find_map(|v| runs[v].pop_back()));
        match job {
            Some(cost) => busy[me] += cost,
            None => done[me] = true,
        }
    }
    busy
}

/// The smallest thread count in `1..=limit` at which `mode` is predicted to reach `speedup`.
pub fn threads_to_reach(costs: &Costs, mode: Schedule, speedup: f64, limit: usize) -> Option<usize> {
    (1..=limit).find(|&t| predict(costs, mode, t).speedup >= speedup)
}

/// Real runs of one mode at one thread count, for checking the model against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// The mode.
    pub mode: Schedule,
    /// Threads.
    pub threads: usize,
    /// Median seconds over the rounds.
    pub seconds: f64,
    /// Median over the rounds of the serial run's time ÷ this run's, both of the same round.
    pub speedup: f64,
    /// Median load imbalance (see [`Rendered::imbalance`]).
    pub imbalance: f64,
}

/// Renders `job` serially and with every modelled mode at each of `threads`, in `rounds`
/// rounds that each run every configuration once (so a shared machine's drift over minutes
/// hits them alike). Returns the serial run's median seconds and each configuration's
/// figures, speedups as medians of per-round ratios.
pub fn measure_rounds(job: &RenderJob, tile: u32, threads: &[usize], rounds: usize) -> (f64, Vec<Measured>) {
    let configs: Vec<(Schedule, usize)> = std::iter::once((Schedule::Serial, 1))
        .chain(threads.iter().flat_map(|&t| MODELLED.map(|m| (m, t))))
        .collect();
    let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new(); configs.len()];
    for _ in 0..rounds.max(1) {
        for (&(mode, t), runs) in configs.iter().zip(&mut runs) {
            runs.push(run_once(job, tile, mode, t));
        }
    }
    let mut serial: Vec<f64> = runs[0].iter().map(|r| r.0).collect();
    let measured = configs
        .iter()
        .zip(&runs)
        .skip(1)
        .map(|(&(mode, threads), runs)| Measured {
            mode,
            threads,
            seconds: median(&mut runs.iter().map(|r| r.0).collect::<Vec<_>>()),
            speedup: median(&mut serial.iter().zip(runs).map(|(s, r)| s / r.0).collect::<Vec<_>>()),
            imbalance: median(&mut runs.iter().map(|r| r.1).collect::<Vec<_>>()),
        })
        .collect();
    (median(&mut serial), measured)
}

/// One render of `job` with `mode` on `threads` threads: (seconds, imbalance).
fn run_once(job: &RenderJob, tile: u32, mode: Schedule, threads: usize) -> (f64, f64) {
    let rng = RngSource::new(&job.settings, RngChoice::PerSample);
    let frame = Arc::new(Frame::new(job.clone(), rng, threads, tile, Arc::new(|_| {})));
    let start = Instant::now();
    let rendered: Rendered = render(&frame, &mode);
    (start.elapsed().as_secs_f64(), rendered.imbalance())
}

/// The modes the model predicts, in the speedup table's order (serial is the baseline).
pub const MODELLED: [Schedule; 5] = [
    Schedule::StaticBlocks,
    Schedule::Interleaved,
    Schedule::PoolRows,
    Schedule::PoolTiles,
    Schedule::Stealing,
];

/// The seed paper's speedup of its final image with its naive split: 88.98 → 20.66 minutes.
pub const PAPER_SPEEDUP: f64 = 88.98 / 20.66;

/// Everything `raypool simulate` found, for [`write_report`].
pub struct Study {
    /// What was rendered, one line ("final, 400 × 267, 16 spp, depth 50, 16-pixel tiles").
    pub subject: String,
    /// The command that made it.
    pub command: String,
    /// The one-thread costs.
    pub costs: Costs,
    /// Thread counts predicted.
    pub threads: Vec<usize>,
    /// The serial run's median seconds, if runs were measured.
    pub serial_seconds: Option<f64>,
    /// Measured runs of the modelled modes.
    pub measured: Vec<Measured>,
}

impl Study {
    /// The table printed by `raypool simulate`: predicted speedup (imbalance) per mode and
    /// thread count, then each measured run beside its prediction.
    pub fn table(&self) -> String {
        let mut text =
            format!("{}: one thread {:.3} s (sum of row costs)\n", self.subject, self.costs.serial());
        text += &format!("{:<12}", "mode \\ T");
        for t in &self.threads {
            text += &format!("{t:>15}");
        }
        for mode in MODELLED {
            text += &format!("\n{:<12}", mode.name());
            for &t in &self.threads {
                let p = predict(&self.costs, mode, t);
                text += &format!("{:>15}", format!("{:.2}× ({:.2})", p.speedup, p.imbalance));
            }
        }
        text += "\n  (predicted speedup over serial, and imbalance = busiest ÷ mean worker)\n";
        for (m, p) in self.validation() {
            let [mode, threads, predicted, measured, gap, pi, mi] = validation_cells(&m, &p);
            text += &format!(
                "{mode:<12}{threads:>4} threads: predicted {predicted}, measured {measured} ({gap}), imbalance predicted {pi}, measured {mi}\n"
            );
        }
        text
    }

    /// Each measured configuration with its prediction.
    pub fn validation(&self) -> Vec<(Measured, Prediction)> {
        self.measured.iter().map(|m| (*m, predict(&self.costs, m.mode, m.threads))).collect()
    }
}

/// A measured run beside its prediction, formatted: mode, threads, predicted and measured
/// speedup, the gap (measured ÷ predicted − 1), predicted and measured imbalance.
fn validation_cells(m: &Measured, p: &Prediction) -> [String; 7] {
    [
        m.mode.name().to_string(),
        m.threads.to_string(),
        format!("{:.2}×", p.speedup),
        format!("{:.2}×", m.speedup),
        format!("{:+.1}%", (m.speedup / p.speedup - 1.0) * 100.0),
        format!("{:.2}", p.imbalance),
        format!("{:.2}", m.imbalance),
    ]
}

/// Writes `dir/scaling.md`, `scaling.csv` and `scaling.png` for `study`.
pub fn write_report(dir: &Path, study: &Study) -> Result<(), Error> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::new(format!("cannot create '{}': {}", dir.display(), io_reason(&e))))?;
    let machine = Machine::current();
    let mut csv = String::from(
        "mode,threads,predicted_speedup,predicted_imbalance,measured_speedup,measured_imbalance\n",
    );
    for mode in MODELLED {
        for &t in &study.threads {
            let p = predict(&study.costs, mode, t);
            let m = study.measured.iter().find(|m| m.mode == mode && m.threads == t);
            let (ms, mi) = m.map_or((String::new(), String::new()), |m| {
                (format!("{:.4}", m.speedup), format!("{:.4}", m.imbalance))
            });
            csv += &format!("{},{t},{:.4},{:.4},{ms},{mi}\n", mode.name(), p.speedup, p.imbalance);
        }
    }
    write_text(&dir.join("scaling.csv"), &csv)?;
    let lines: Vec<ModelLine> = MODELLED
        .iter()
        .map(|&mode| ModelLine {
            label: mode.name().to_string(),
            predicted: study.threads.iter().map(|&t| (t, predict(&study.costs, mode, t).speedup)).collect(),
            measured: study
                .measured
                .iter()
                .filter(|m| m.mode == mode)
                .map(|m| (m.threads, m.speedup))
                .collect(),
        })
        .collect();
    let footer = format!("{} — {}", study.command, machine.describe());
    let title = format!("Scaling model: {} (lines: model; triangles: measured)", study.subject);
    efficiency_plot(&dir.join("scaling.png"), &title, &footer, &lines)?;
    write_text(&dir.join("scaling.md"), &markdown(study, &machine))
}

fn markdown(study: &Study, machine: &Machine) -> String {
    let costs = &study.costs;
    let mut md = format!(
        "# Scaling model: each scheduler from 1 to {} threads\n\n\
         Made by `{}` on this machine: {}.\n\n\
         {}: one thread {:.3} s by rows ({} rows), {:.3} s by tiles ({} tiles); each row and tile timed in \
         that one-thread render, then replayed on T virtual workers under each mode's rule \
         (`src/measure/scaling.rs`). Plot: `scaling.png` (efficiency = speedup ÷ threads; lines: the model; triangles: measured). \
         Data: `scaling.csv`.\n\n## Predicted speedup over serial (imbalance: busiest ÷ mean worker)\n\n| mode |",
        study.threads.iter().max().unwrap_or(&1),
        study.command,
        machine.describe(),
        study.subject,
        costs.serial(),
        costs.rows.len(),
        costs.tiles.iter().sum::<f64>(),
        costs.tiles.len(),
    );
    for t in &study.threads {
        md += &format!(" {t} |");
    }
    md += "\n|---|";
    md += &"---:|".repeat(study.threads.len());
    for mode in MODELLED {
        md += &format!("\n| `{}` |", mode.name());
        for &t in &study.threads {
            let p = predict(costs, mode, t);
            md += &format!(" {:.2}× ({:.2}) |", p.speedup, p.imbalance);
        }
    }
    md += &format!(
        "\n\n`pool` and `steal` start above 1× because the one-thread render by tiles took {:.1}% less than by rows \
         (the same pixels and samples; a square tile's neighbouring rays likely reuse more of the cache than a \
         row's, not measured here).",
        (1.0 - costs.tiles.iter().sum::<f64>() / costs.serial()) * 100.0
    );
    md += "\n\n## The model against measured runs\n\n";
    match study.serial_seconds {
        None => md += "Not measured (run with `--measure`).\n",
        Some(serial) => {
            md += &format!(
                "Rounds that each run serial and every mode once; measured speedup = the median over rounds of serial ÷ \
                 the mode (serial's median: {serial:.3} s). Gap = measured ÷ predicted − 1.\n\n\
                 | mode | threads | predicted | measured | gap | imbalance predicted | imbalance measured |\n|---|---:|---:|---:|---:|---:|---:|\n"
            );
            for (m, p) in study.validation() {
                let [mode, threads, predicted, measured, gap, pi, mi] = validation_cells(&m, &p);
                md += &format!("| `{mode}` | {threads} | {predicted} | {measured} | {gap} | {pi} | {mi} |\n");
            }
        }
    }
    let limit = 4096;
    let needed = threads_to_reach(costs, Schedule::StaticBlocks, PAPER_SPEEDUP, limit)
        .map_or(format!("more than {limit}"), |t| t.to_string());
    md += &format!(
        "\n## Answers\n\n- The naive split (`static`) needs **{needed} threads** to reach the paper's {PAPER_SPEEDUP:.2}× \
         (88.98 → 20.66 minutes) on this image, by the model.\n- At 64 threads the model predicts: "
    );
    let at64: Vec<String> = MODELLED
        .iter()
        .map(|&mode| {
            let p = predict(costs, mode, 64);
            format!("`{}` {:.1}× (imbalance {:.2})", mode.name(), p.speedup, p.imbalance)
        })
        .collect();
    md += &at64.join(", ");
    md += ".\n\n## What the model leaves out\n\n\
           Every row and tile is assumed to cost on T threads what it cost on one, and handing out a job to cost nothing. \
           So the model is load balance alone, an upper bound: it leaves out memory bandwidth and shared caches, lock \
           and queue contention (one shared queue serves every worker of `pool` and `pool-rows`), the cost of a job \
           and of a steal, SMT siblings sharing a core's units, and turbo clocks that drop as more cores are busy. \
           The gap in the table above is what those cost on this machine.\n";
    md
}
