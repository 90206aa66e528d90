//! The course grader: a student's scheduler, or queue discipline, checked and then timed
//! against the reference on workloads that each expose one weakness.
//!
//! After Stanford CS149's task-library assignment: conformance first (a submission that
//! breaks the contract scores 0 and is not timed), then a suite of workloads, each scored by
//! the submission's time ÷ the reference's time *measured in the same run*, alternating the
//! two, so that a slow or busy machine moves both. A ratio of at most [`FULL_MARKS_RATIO`]
//! earns a workload's full point, [`ZERO_MARKS_RATIO`] or more none, linearly in between; the
//! score is the mean over workloads and thread counts, out of 100.
//!
//! | workload | what it exposes |
//! |---|---|
//! | `balanced` | nothing: every tile costs the same (the baseline) |
//! | `one-band` | a static split: all the cost sits in the bottom rows |
//! | `heavy-tail` | big chunks, or an expensive tile left to the end |
//! | `tiny-tiles` | per-job overhead: 2 × 2 tiles, four samples |
//! | `many-frames` | per-frame overhead: 160 small frames in a row (threads or a pool started per frame) |
//! | `nested` (queues only) | the waiting rule: bands as jobs, each waiting on a batch of its tiles |
//!
//! Each workload takes 0.1–0.5 s on one thread of this project's 2-CPU machine: long enough
//! that a round's ratio is not noise, short enough that grading at 1, 2 and 4 threads with 5
//! rounds takes about half a minute.
//!
//! The reference is the built-in `steal` mode for a scheduler, and the built-in `Stealing`
//! discipline under the same scheduler for a queue. Every workload's image is also compared
//! with the reference's, bit for bit.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use parking_lot::Mutex;
use pool::{Discipline, MakeQueue, ThreadPool};

use crate::error::Error;
use crate::files::image::Image;
use crate::files::output::write_text;
use crate::measure::machine::{Machine, Sweep, thread_counts};
use crate::measure::speedup::median;
use crate::scenes::format::SceneFile;
use crate::schedule::conformance;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, Scheduler, tiles_on};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::render::{RenderJob, RenderSettings, TileOutput, default_height};
use crate::tracer::sampling::sampler::Sampler;

/// A workload at most this many times slower than the reference earns its full point.
pub const FULL_MARKS_RATIO: f64 = 1.2;
/// A workload this many times slower than the reference, or more, earns nothing.
pub const ZERO_MARKS_RATIO: f64 = 2.0;

/// What is graded.
pub enum Entry<'a> {
    /// A scheduler, against the built-in `steal` mode.
    Scheduler(&'a dyn Scheduler),
    /// A queue discipline (see `pool::JobQueue`), against `Stealing`.
    Queue(MakeQueue),
}

/// A named submission.
pub struct Submission<'a> {
    /// The name in the report.
    pub name: String,
    /// The code.
    pub entry: Entry<'a>,
}

/// How to grade: the command line of `raypool grade` and of a starter's grade binary.
#[derive(clap::Args, Clone, Debug)]
pub struct Options {
    /// Thread counts, e.g. `--threads 1,2,4,8` [default: 1, 2, 4, … up to the cores, and the
    /// cores]
    #[arg(long, value_delimiter = ',', value_parser = at_least_one)]
    pub threads: Vec<usize>,
    /// Rounds per workload and thread count; a round times the submission and the reference
    /// once each, and the ratio reported is the median over rounds
    #[arg(long, default_value_t = 5)]
    pub rounds: usize,
    /// Where to write the report (Markdown)
    #[arg(long, default_value = "grade.md")]
    pub out: PathBuf,
}

/// A count of at least 1 (clap's parser for `--threads`).
pub fn at_least_one(text: &str) -> Result<usize, String> {
    match text.parse() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("'{text}' is not a count of at least 1")),
    }
}

/// One workload of the suite.
struct Workload {
    name: &'static str,
    exposes: &'static str,
    scene: &'static str,
    width: u32,
    spp: u32,
    tile: u32,
    /// Frames rendered back to back per timing.
    frames: usize,
    /// Queues only: render through nested batches.
    nested: bool,
}

const FLAT: &str = include_str!("workloads/flat.toml");

/// The suite (the table in the module docs).
fn workloads(queue: bool) -> Vec<Workload> {
    let base = Workload {
        name: "balanced",
        exposes: "nothing: every tile costs the same",
        scene: FLAT,
        width: 480,
        spp: 12,
        tile: 16,
        frames: 1,
        nested: false,
    };
    let mut suite = vec![
        Workload { ..base },
        Workload {
            name: "one-band",
            exposes: "a static split: the cost is all in the bottom rows",
            scene: include_str!("workloads/band.toml"),
            ..base
        },
        Workload {
            name: "heavy-tail",
            exposes: "big chunks: a few tiles, all in the upper half, cost ten times the others",
            scene: include_str!("workloads/tail.toml"),
            spp: 16,
            ..base
        },
        Workload {
            name: "tiny-tiles",
            exposes: "per-job overhead: 2 × 2 tiles, 4 samples",
            spp: 4,
            tile: 2,
            ..base
        },
        Workload {
            name: "many-frames",
            exposes: "per-frame overhead: 160 frames of 64 × 36 in a row",
            width: 64,
            spp: 2,
            frames: 160,
            ..base
        },
    ];
    if queue {
        suite.push(Workload {
            name: "nested",
            exposes: "the waiting rule: each band of tiles is a job waiting on its tiles' batch",
            nested: true,
            ..base
        });
    }
    suite
}

impl Workload {
    fn frame(&self, threads: usize) -> Result<Arc<Frame>, Error> {
        let scene = SceneFile::parse(self.scene, self.name)?;
        let height = default_height(self.width, scene.camera.aspect)?;
        let settings = RenderSettings {
            width: self.width,
            height,
            spp: self.spp,
            max_depth: 50,
            seed: 7,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let rng = RngSource::new(&settings, RngChoice::PerSample);
        Ok(Arc::new(Frame::new(
            RenderJob::new(scene.to_scene(), settings),
            rng,
            threads,
            self.tile,
            Arc::new(|_| {}),
        )))
    }
}

/// Tiles as jobs on a pool of a given queue, kept from one render to the next (so that
/// `many-frames` times the queue, not the starting of threads); `nested` renders each band
/// of tiles as one job that submits its tiles as a batch and waits for it.
pub struct OnQueue {
    make: MakeQueue,
    nested: bool,
    pools: Mutex<Vec<Arc<ThreadPool>>>,
}

impl OnQueue {
    /// A scheduler on pools built with `make`'s queues.
    ///
    /// ```
    /// use raypool::measure::grade::OnQueue;
    /// let on_locked = OnQueue::new(pool::Discipline::Locked.queue(), true);
    /// raypool::schedule::conformance::check(&on_locked, 2).unwrap();
    /// ```
    pub fn new(make: MakeQueue, nested: bool) -> OnQueue {
        OnQueue { make, nested, pools: Mutex::new(Vec::new()) }
    }

    fn pool(&self, workers: usize) -> Arc<ThreadPool> {
        let mut pools = self.pools.lock();
        if let Some(pool) = pools.iter().find(|p| p.workers() == workers) {
            return Arc::clone(pool);
        }
        let pool = ThreadPool::builder()
            .workers(workers)
            .queue(self.make)
            .build()
            .expect("the pool's threads start");
        pools.push(Arc::new(pool));
        Arc::clone(pools.last().expect("just pushed"))
    }
}

impl Scheduler for OnQueue {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let pool = self.pool(frame.threads);
        let tiles = frame.tiles();
        if !self.nested {
            return tiles_on(&pool, frame, tiles);
        }
        let bands: Vec<Vec<_>> = tiles.chunk_by(|a, b| a.y == b.y).map(<[_]>::to_vec).collect();
        let bands = pool.batch(bands.into_iter().map(|band| {
            let (frame, pool) = (Arc::clone(frame), Arc::clone(&pool));
            move || tiles_on(&pool, &frame, band)
        }));
        bands.into_iter().flatten().collect()
    }
}

/// One workload at one thread count.
#[derive(Clone, Debug)]
pub struct Score {
    /// Workload name.
    pub workload: &'static str,
    /// What it exposes.
    pub exposes: &'static str,
    /// Threads given.
    pub threads: usize,
    /// Median seconds of the submission and of the reference.
    pub seconds: (f64, f64),
    /// Median over rounds of submission ÷ reference.
    pub ratio: f64,
    /// 0 to 1.
    pub points: f64,
    /// Why the workload earned nothing although it was timed (a wrong image).
    pub failure: Option<String>,
}

/// A graded submission.
pub struct Report {
    /// The submission's name.
    pub name: String,
    /// The reference's name.
    pub reference: &'static str,
    /// `Err` names the first thread count and rule the submission broke.
    pub conformance: Result<Vec<usize>, String>,
    /// One per workload and thread count (none when conformance failed).
    pub scores: Vec<Score>,
    /// Where and when.
    pub machine: Machine,
}

impl Report {
    /// The scores that count: those at 2 or more threads (on one thread every scheduler
    /// renders the same way, so those rows are a baseline), unless only 1 was measured.
    pub fn scored(&self) -> Vec<&Score> {
        let parallel: Vec<&Score> = self.scores.iter().filter(|s| s.threads > 1).collect();
        if parallel.is_empty() { self.scores.iter().collect() } else { parallel }
    }

    /// The score out of 100: the mean of [`Report::scored`]'s points; 0 if conformance failed.
    pub fn score(&self) -> f64 {
        let scored = self.scored();
        if self.conformance.is_err() || scored.is_empty() {
            return 0.0;
        }
        100.0 * scored.iter().map(|s| s.points).sum::<f64>() / scored.len() as f64
    }

    /// The report as Markdown; `command` is the command line that produced it.
    pub fn markdown(&self, command: &str) -> String {
        let mut md = format!("# Grade: {}\n\n", self.name);
        let _ = writeln!(md, "Machine: {}.  ", self.machine.describe());
        let _ = writeln!(md, "Command: `{command}`.  ");
        let _ = writeln!(
            md,
            "Reference: {}, timed in the same run, alternating with the submission. A workload earns \
             its point at ≤ {FULL_MARKS_RATIO}× the reference's time, nothing at ≥ {ZERO_MARKS_RATIO}×, \
             linearly in between; the score is the mean over workloads at 2 or more threads.\n",
            self.reference
        );
        match &self.conformance {
            Ok(counts) => {
                let _ = writeln!(md, "Conformance: **passed** at {counts:?} threads.\n");
            }
            Err(e) => {
                let _ = writeln!(md, "Conformance: **FAILED**: {e}\n\nNot timed.\n");
            }
        }
        if !self.scores.is_empty() {
            md.push_str(
                "| workload | what it exposes | threads | submission s | reference s | ratio | points |\n",
            );
            md.push_str("|---|---|---:|---:|---:|---:|---:|\n");
            let scored = self.scored();
            for s in &self.scores {
                let counted = if scored.iter().any(|c| std::ptr::eq(*c, s)) { "" } else { " (baseline)" };
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {:.4} | {:.4} | {:.2} | {:.2}{counted}{} |",
                    s.workload,
                    s.exposes,
                    s.threads,
                    s.seconds.0,
                    s.seconds.1,
                    s.ratio,
                    s.points,
                    s.failure.as_ref().map_or(String::new(), |f| format!(" ({f})"))
                );
            }
            md.push('\n');
        }
        let _ = writeln!(md, "**Score: {:.0} / 100**", self.score());
        md
    }
}

/// Points for a ratio of submission ÷ reference time.
pub fn points(ratio: f64) -> f64 {
    ((ZERO_MARKS_RATIO - ratio) / (ZERO_MARKS_RATIO - FULL_MARKS_RATIO)).clamp(0.0, 1.0)
}

/// Grades `submission`: conformance at every thread count of `options` (and 1), then the
/// workloads. `log` gets a progress line per step.
pub fn grade(submission: &Submission, options: &Options, mut log: impl FnMut(&str)) -> Result<Report, Error> {
    let counts = thread_counts(&options.threads, Sweep::DoublingsToTheCpus);
    let queue = matches!(submission.entry, Entry::Queue(_));
    let on_queue;
    let (scheduler, reference_scheduler, reference): (&dyn Scheduler, Box<dyn Scheduler>, _) =
        match &submission.entry {
            Entry::Scheduler(s) => (*s, Box::new(Schedule::Stealing), "the built-in `steal` mode"),
            Entry::Queue(make) => {
                on_queue = OnQueue::new(*make, false);
                let reference = OnQueue::new(Discipline::Stealing.queue(), false);
                (&on_queue, Box::new(reference), "the built-in `Stealing` discipline, same scheduler")
            }
        };
    let mut report = Report {
        name: submission.name.clone(),
        reference,
        conformance: Ok(Vec::new()),
        scores: Vec::new(),
        machine: Machine::current(),
    };
    report.conformance = check_conformance(&submission.entry, scheduler, &counts, &mut log);
    if report.conformance.is_err() {
        return Ok(report);
    }
    // Nested renders need their own schedulers (a different way of submitting).
    let (nested, nested_reference) = match &submission.entry {
        Entry::Queue(make) => {
            (Some(OnQueue::new(*make, true)), Some(OnQueue::new(Discipline::Stealing.queue(), true)))
        }
        Entry::Scheduler(_) => (None, None),
    };
    for workload in workloads(queue) {
        let (sub, refr): (&dyn Scheduler, &dyn Scheduler) = match (&nested, &nested_reference) {
            (Some(n), Some(r)) if workload.nested => (n, r),
            _ => (scheduler, reference_scheduler.as_ref()),
        };
        for &threads in &counts {
            let score = time_workload(&workload, threads, sub, refr, options.rounds.max(1))?;
            log(&format!(
                "{:<12} {threads:>3} threads: {:.2}× the reference, {:.2} points",
                workload.name, score.ratio, score.points
            ));
            report.scores.push(score);
        }
    }
    Ok(report)
}

/// Conformance at 1 and every count: the queue's own check first for a queue.
fn check_conformance(
    entry: &Entry,
    scheduler: &dyn Scheduler,
    counts: &[usize],
    log: &mut impl FnMut(&str),
) -> Result<Vec<usize>, String> {
    if let Entry::Queue(make) = entry {
        pool::conformance::check(*make).map_err(|e| format!("the queue: {e}"))?;
        log("conformance: the queue keeps the pool's contract");
    }
    let mut checked: Vec<usize> = std::iter::once(1).chain(counts.iter().copied()).collect();
    checked.sort_unstable();
    checked.dedup();
    for &threads in &checked {
        conformance::check(scheduler, threads).map_err(|e| format!("with frame.threads = {threads}: {e}"))?;
        log(&format!("conformance: passed with frame.threads = {threads}"));
    }
    Ok(checked)
}

/// Times `workload` on `threads` threads: `rounds` rounds, each timing the submission and
/// the reference once (in alternating order).
fn time_workload(
    workload: &Workload,
    threads: usize,
    submission: &dyn Scheduler,
    reference: &dyn Scheduler,
    rounds: usize,
) -> Result<Score, Error> {
    let frame = workload.frame(threads)?;
    let mut times = (Vec::new(), Vec::new());
    let mut failure = None;
    for round in 0..rounds {
        let time = |scheduler: &dyn Scheduler| {
            let start = Instant::now();
            let mut tiles = Vec::new();
            for _ in 0..workload.frames {
                tiles = scheduler.render(&frame);
            }
            (start.elapsed().as_secs_f64(), tiles)
        };
        let ((s, sub_tiles), (r, ref_tiles)) = if round % 2 == 0 {
            let s = time(submission);
            (s, time(reference))
        } else {
            let r = time(reference);
            (time(submission), r)
        };
        times.0.push(s);
        times.1.push(r);
        if round == 0 {
            failure = same_image(&frame, &sub_tiles, &ref_tiles).err();
        }
    }
    let ratio = median(&mut times.0.iter().zip(&times.1).map(|(s, r)| s / r).collect::<Vec<_>>());
    Ok(Score {
        workload: workload.name,
        exposes: workload.exposes,
        threads,
        seconds: (median(&mut times.0), median(&mut times.1)),
        ratio,
        points: if failure.is_some() { 0.0 } else { points(ratio) },
        failure,
    })
}

fn same_image(frame: &Frame, submission: &[TileOutput], reference: &[TileOutput]) -> Result<(), String> {
    let image: Image = frame.assemble(submission)?;
    let expected = frame.assemble(reference).expect("the reference covers the frame");
    if image.pixels == expected.pixels {
        Ok(())
    } else {
        Err("the image differs from the reference's".into())
    }
}

/// Grades each submission, prints the reports and writes them, one after the other, to
/// `options.out`: the body of `raypool grade` and of a starter's grade binary ([`main`]).
/// `command` is the command line, quoted in the reports.
pub fn grade_and_report(submissions: &[&Submission], options: &Options, command: &str) -> Result<(), Error> {
    let reports = submissions
        .iter()
        .map(|s| grade(s, options, |line| eprintln!("{line}")).map(|r| r.markdown(command)))
        .collect::<Result<Vec<_>, _>>()?;
    let all = reports.join("\n");
    write_text(&options.out, &all)?;
    println!("{all}");
    eprintln!("report written to {}", options.out.display());
    Ok(())
}

/// The command line of a starter's grade binary (see [`main`]).
#[derive(clap::Parser, Debug)]
#[command(about = "Grade this crate's submissions: conformance, then workloads timed against the reference")]
struct GradeCommand {
    /// Grade only this part (by name) [default: every part]
    #[arg(long)]
    part: Option<String>,
    /// Thread counts, rounds, report file.
    #[command(flatten)]
    options: Options,
}

/// The whole of a starter's grade binary: parses `--part`, `--threads`, `--rounds` and
/// `--out`, grades each submission (or the one named), prints the reports and writes them,
/// one after the other, to `--out`. Exit code 0 once graded (the score is in the report),
/// 2 for a bad command line or an unwritable report.
///
/// ```no_run
/// # struct MyScheduler;
/// # impl raypool::Scheduler for MyScheduler {
/// #     fn render(&self, f: &std::sync::Arc<raypool::Frame>) -> Vec<raypool::TileOutput> { unimplemented!() }
/// # }
/// use raypool::measure::grade::{Entry, Submission, main};
/// fn main_of_grade_rs() -> std::process::ExitCode {
///     main(&[Submission { name: "scheduler".into(), entry: Entry::Scheduler(&MyScheduler) }])
/// }
/// ```
pub fn main(submissions: &[Submission]) -> std::process::ExitCode {
    use clap::Parser as _;
    let command = GradeCommand::parse();
    let chosen: Vec<&Submission> =
        submissions.iter().filter(|s| command.part.as_ref().is_none_or(|p| *p == s.name)).collect();
    let names: Vec<&str> = submissions.iter().map(|s| s.name.as_str()).collect();
    let outcome = if chosen.is_empty() {
        Err(Error::new(format!("--part: no part named {:?} (parts: {})", command.part, names.join(", "))))
    } else {
        let line = std::env::args().collect::<Vec<_>>().join(" ");
        grade_and_report(&chosen, &command.options, &line)
    };
    match outcome {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("grade: error: {e}");
            std::process::ExitCode::from(e.exit_code())
        }
    }
}
