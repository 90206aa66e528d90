//! **The course grader**: a student's scheduler, or queue discipline, checked and then timed
//! against the reference on workloads that each expose one weakness.
//!
//! After Stanford CS149's task-library assignment: conformance first (a submission that
//! breaks the contract scores 0 and is not timed), then a suite of workloads
//! ([`workloads`](mod@workloads)), each scored by the submission's time ÷ the reference's time
//! *measured in the same run*, alternating the two, so that a slow or busy machine moves both;
//! [`report`] turns the ratios into points and the points into a score out of 100.
//!
//! The reference is the built-in `steal` mode for a scheduler, and the built-in `Stealing`
//! discipline under the same scheduler for a queue ([`on_queue`]). Every workload's image is
//! also compared with the reference's, bit for bit. This file grades: [`grade`],
//! [`grade_and_report`], and [`main`], the whole of a starter's grade binary.

pub mod workloads;
pub mod on_queue;
pub mod report;

use std::path::PathBuf;
use std::time::Instant;

use pool::{Discipline, MakeQueue};

use crate::error::Error;
use crate::files::image::Image;
use crate::files::output::write_text;
use crate::measure::grade::on_queue::OnQueue;
use crate::measure::grade::report::{Report, Score, points};
use crate::measure::grade::workloads::{Workload, workloads};
use crate::measure::machine::{Machine, Sweep, thread_counts};
use crate::measure::speedup::median;
use crate::schedule::conformance;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, Scheduler};
use crate::tracer::render::TileOutput;

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
