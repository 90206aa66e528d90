//! **The course grader**: a student's scheduler, or queue discipline, checked and then timed
//! against the reference on workloads that each expose one weakness.
//!
//! After Stanford CS149's task-library assignment: conformance first (a submission that
//! breaks the contract scores 0 and is not timed), then a suite of workloads
//! ([`workloads`](mod@workloads)), each scored by the submission's time ÷ the reference's time
//! *measured in the same run*, alternating the two, so that a slow machine moves both;
//! [`judge`] refuses to score times from a machine too busy to run threads in parallel, or
//! rounds that disagree; [`report`] turns the ratios into points and the points into a score
//! out of 100.
//!
//! Every timed frame is watched from inside ([`Observer`]): a submission that breaks the
//! conformance rules only when timed (more threads, a tile rendered twice) earns nothing for
//! that workload, and the observed load imbalance judges the workloads whose cost sits in one
//! part of the image, which a busy machine does not change.
//!
//! The reference is the built-in `steal` scheduling (tiles as jobs on a work-stealing pool)
//! on one pool kept for the whole run, for a scheduler, and the built-in `Stealing` discipline
//! under the same scheduler for a queue ([`on_queue`]). Every workload's image is also
//! compared with the reference's, bit for bit. This file grades ([`grade`]); [`run`] holds
//! [`grade_and_report`] and [`main`], the whole of a starter's grade binary.

pub mod workloads;
pub mod on_queue;
pub mod judge;
pub mod report;
pub mod run;

pub use run::{command_line, grade_and_report, main};

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use pool::{Discipline, MakeQueue};

use crate::error::Error;
use crate::files::image::Image;
use crate::measure::grade::on_queue::OnQueue;
use crate::measure::grade::report::{MachineCheck, Report, Score};
use crate::measure::grade::workloads::{Workload, workloads};
use crate::measure::machine::{Machine, Sweep, thread_counts};
use crate::measure::speedup::median;
use crate::schedule::conformance;
use crate::schedule::frame::Frame;
use crate::schedule::modes::Scheduler;
use crate::schedule::observe::Observer;
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
    /// The score out of 100 below which the run exits with code 1 (a failed conformance
    /// always does; code 3: the machine was too busy to judge)
    #[arg(long, default_value_t = 50.0, value_parser = pass_mark)]
    pub pass: f64,
}

/// A pass mark from 0 to 100 (clap's parser for `--pass`).
pub fn pass_mark(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(p) if (0.0..=100.0).contains(&p) => Ok(p),
        _ => Err(format!("'{text}' is not a score from 0 to 100")),
    }
}

/// A count of at least 1 (clap's parser for `--threads`).
pub fn at_least_one(text: &str) -> Result<usize, String> {
    match text.parse() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("'{text}' is not a count of at least 1")),
    }
}

/// Grades `submission`: conformance at every thread count of `options`, then the workloads,
/// thread count by thread count, each between two machine checks. `log` gets a progress
/// line per step.
pub fn grade(submission: &Submission, options: &Options, mut log: impl FnMut(&str)) -> Result<Report, Error> {
    let counts = thread_counts(&options.threads, Sweep::DoublingsToTheCpus);
    let queue = matches!(submission.entry, Entry::Queue(_));
    let on_queue;
    let (scheduler, reference_scheduler, reference): (&dyn Scheduler, OnQueue, _) = match &submission.entry {
        Entry::Scheduler(s) => (
            *s,
            OnQueue::new(Discipline::Stealing.queue(), false),
            "the built-in `steal` scheduling (tiles as jobs on a work-stealing pool), on one pool kept for the whole run",
        ),
        Entry::Queue(make) => {
            on_queue = OnQueue::new(*make, false);
            let reference = OnQueue::new(Discipline::Stealing.queue(), false);
            (&on_queue, reference, "the built-in `Stealing` discipline, same scheduler")
        }
    };
    let mut report = Report {
        name: submission.name.clone(),
        reference,
        conformance: Ok(Vec::new()),
        scores: Vec::new(),
        machine_checks: Vec::new(),
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
    let suite = workloads(queue);
    let pick = |workload: &Workload| -> (&dyn Scheduler, &dyn Scheduler) {
        match (&nested, &nested_reference) {
            (Some(n), Some(r)) if workload.nested => (n, r),
            _ => (scheduler, &reference_scheduler),
        }
    };
    let rounds = options.rounds.max(1);
    let time_row = |workload: &Workload, threads: usize| -> Result<Score, Error> {
        let (sub, refr) = pick(workload);
        let mut score = time_workload(workload, threads, sub, refr, rounds)?;
        for _ in 1..judge::ATTEMPTS {
            if score.unjudged.is_none() {
                break;
            }
            score = time_workload(workload, threads, sub, refr, rounds)?;
        }
        Ok(score)
    };
    for &threads in &counts {
        // The speedup check needs a second thread count to compare with: none at 1 thread.
        let check = |report: &mut Report| -> Result<Option<String>, Error> {
            if threads == 1 {
                return Ok(None);
            }
            let speedup = judge::reference_speedup(&reference_scheduler, &suite[0], threads)?;
            let busy = judge::too_busy(speedup, threads);
            report.machine_checks.push(MachineCheck {
                threads,
                speedup: Some(speedup),
                others: None,
                busy: busy.clone(),
            });
            Ok(busy)
        };
        let mut rows = Vec::new();
        let mut busy = None;
        for attempt in 1..=judge::ATTEMPTS {
            busy = check(&mut report)?;
            if busy.is_none() {
                let usage = judge::Usage::now();
                rows = suite.iter().map(|w| time_row(w, threads)).collect::<Result<_, _>>()?;
                let others = usage.and_then(|u| u.others_since());
                busy = judge::competing(others, threads);
                report.machine_checks.push(MachineCheck {
                    threads,
                    speedup: None,
                    others,
                    busy: busy.clone(),
                });
                busy = busy.or(check(&mut report)?);
            }
            let Some(why) = &busy else { break };
            log(&format!("attempt {attempt} at {threads} threads: {why}"));
            if attempt < judge::ATTEMPTS {
                std::thread::sleep(std::time::Duration::from_secs(2));
            }
        }
        if let Some(why) = busy {
            rows = suite.iter().map(|w| Score::unjudged(w, threads, &why)).collect();
        }
        for score in rows {
            log(&format!(
                "{:<12} {threads:>3} threads: {:.2}× the reference, {:.2} points{}",
                score.workload,
                score.ratio,
                score.points,
                score.unjudged.as_ref().map_or(String::new(), |w| format!(" ({w})"))
            ));
            report.scores.push(score);
        }
    }
    Ok(report)
}

/// Conformance at every count asked for: the queue's own check first for a queue.
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
    let mut checked = counts.to_vec();
    checked.sort_unstable();
    checked.dedup();
    for &threads in &checked {
        conformance::check(scheduler, threads).map_err(|e| format!("with frame.threads = {threads}: {e}"))?;
        log(&format!("conformance: passed with frame.threads = {threads}"));
    }
    Ok(checked)
}

/// One timed render of a workload (its `frames` frames): its seconds, and the last frame's
/// tiles with the median imbalance the frames saw, or what rule the frames saw broken.
/// Watching costs both sides alike; checking what was seen happens after the clock stops.
fn timed(
    scheduler: &dyn Scheduler,
    workload: &Workload,
    frame: &Arc<Frame>,
) -> (f64, Result<(Vec<TileOutput>, f64), String>) {
    let start = Instant::now();
    let renders: Vec<(Arc<Observer>, Vec<TileOutput>)> = (0..workload.frames)
        .map(|_| {
            let (observer, watched) = Observer::watch(frame);
            (observer, scheduler.render(&watched))
        })
        .collect();
    let seconds = start.elapsed().as_secs_f64();
    let mut imbalances = Vec::new();
    for (observer, tiles) in &renders {
        if let Err(e) = observer.verify(frame, tiles, frame.threads) {
            return (seconds, Err(e));
        }
        imbalances.push(observer.imbalance(frame.threads));
    }
    let last = renders.into_iter().last().map(|(_, tiles)| tiles).unwrap_or_default();
    (seconds, Ok((last, median(&mut imbalances))))
}

/// Times `workload` on `threads` threads: `rounds` rounds, each timing the submission and
/// the reference once (in alternating order), every frame watched.
fn time_workload(
    workload: &Workload,
    threads: usize,
    submission: &dyn Scheduler,
    reference: &dyn Scheduler,
    rounds: usize,
) -> Result<Score, Error> {
    let frame = workload.frame(threads)?;
    let (mut times, mut imbalances) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
    let mut failure = None;
    for round in 0..rounds {
        let ((s, sub), (r, refr)) = if round % 2 == 0 {
            let s = timed(submission, workload, &frame);
            (s, timed(reference, workload, &frame))
        } else {
            let r = timed(reference, workload, &frame);
            (timed(submission, workload, &frame), r)
        };
        times.0.push(s);
        times.1.push(r);
        let (ref_tiles, ref_imbalance) =
            refr.map_err(|e| Error::new(format!("the reference broke a rule: {e}")))?;
        imbalances.1.push(ref_imbalance);
        match sub {
            Err(e) => failure = failure.or(Some(format!("when timed: {e}"))),
            Ok((tiles, imbalance)) => {
                imbalances.0.push(imbalance);
                if round == 0 {
                    failure = failure.or(same_image(&frame, &tiles, &ref_tiles).err());
                }
            }
        }
    }
    let ratios: Vec<f64> = times.0.iter().zip(&times.1).map(|(s, r)| s / r).collect();
    // No imbalance for a submission whose every round broke a rule (it earns nothing).
    let median_of = |xs: &mut Vec<f64>| if xs.is_empty() { f64::NAN } else { median(xs).max(1.0) };
    let imbalance = (median_of(&mut imbalances.0), median_of(&mut imbalances.1));
    Ok(Score::measured(
        workload,
        threads,
        (median(&mut times.0), median(&mut times.1)),
        ratios,
        imbalance,
        failure,
    ))
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
