//! A grade: each workload's score at each thread count, the points a time ratio earns, the
//! total out of 100, and the report as Markdown.
//!
//! A ratio of submission ÷ reference time of at most [`FULL_MARKS_RATIO`] earns a workload's
//! full point, [`ZERO_MARKS_RATIO`] or more none, linearly in between; a workload judged by
//! balance too (its cost sits in one part of the image) earns at most what the ratio of the
//! observed load imbalances (submission ÷ reference) earns on the same scale. A row the
//! machine could not judge ([`judge`]) earns nothing. The score is the mean
//! over workloads at 2 or more threads (on one thread every scheduler renders the same way).

use std::fmt::Write as _;

use crate::measure::grade::judge;
use crate::measure::grade::workloads::Workload;
use crate::measure::machine::Machine;
use crate::measure::speedup::median;

/// A workload at most this many times slower than the reference earns its full point.
pub const FULL_MARKS_RATIO: f64 = 1.2;
/// A workload this many times slower than the reference, or more, earns nothing.
pub const ZERO_MARKS_RATIO: f64 = 2.0;

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
    /// Submission ÷ reference, one per round (each round times both, back to back).
    pub ratios: Vec<f64>,
    /// Median of [`Score::ratios`]: not the ratio of the two medians of `seconds`, which
    /// may come from different rounds.
    pub ratio: f64,
    /// Median load imbalance the frames saw, submission and reference (1.0: perfect).
    pub imbalance: (f64, f64),
    /// Whether the points are capped by the imbalances' ratio too.
    pub judged_by_balance: bool,
    /// 0 to 1.
    pub points: f64,
    /// Why the workload earned nothing although it was timed (a wrong image, a rule broken
    /// when timed).
    pub failure: Option<String>,
    /// Why its time could not be judged (a busy machine, rounds that disagree): no points.
    pub unjudged: Option<String>,
}

impl Score {
    /// A timed row: its points from the rounds' ratios and the imbalances.
    pub fn measured(
        workload: &Workload,
        threads: usize,
        seconds: (f64, f64),
        ratios: Vec<f64>,
        imbalance: (f64, f64),
        failure: Option<String>,
    ) -> Score {
        let ratio = median(&mut ratios.clone());
        let unjudged = judge::disagreement(&ratios);
        let mut earned = points(ratio);
        if workload.judged_by_balance {
            earned = earned.min(points(imbalance.0 / imbalance.1));
        }
        if failure.is_some() || unjudged.is_some() {
            earned = 0.0;
        }
        Score {
            workload: workload.name,
            exposes: workload.exposes,
            threads,
            seconds,
            ratios,
            ratio,
            imbalance,
            judged_by_balance: workload.judged_by_balance,
            points: earned,
            failure,
            unjudged,
        }
    }

    /// A row left unjudged (`why`): no times, no points.
    pub fn unjudged(workload: &Workload, threads: usize, why: &str) -> Score {
        Score {
            workload: workload.name,
            exposes: workload.exposes,
            threads,
            seconds: (f64::NAN, f64::NAN),
            ratios: Vec::new(),
            ratio: f64::NAN,
            imbalance: (f64::NAN, f64::NAN),
            judged_by_balance: workload.judged_by_balance,
            points: 0.0,
            failure: None,
            unjudged: Some(why.to_string()),
        }
    }
}

/// One machine check, before or after a thread count's rows (see [`judge`]).
#[derive(Clone, Debug)]
pub struct MachineCheck {
    /// Threads.
    pub threads: usize,
    /// The reference's own speedup on `balanced` at `threads` over 1 thread (`None` for a
    /// measurement of the other processes only).
    pub speedup: Option<f64>,
    /// The CPUs other processes kept busy on average while the rows were timed, where the
    /// system says.
    pub others: Option<f64>,
    /// Why the machine was too busy, if it was.
    pub busy: Option<String>,
}

/// What a grade run concludes, and its exit code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Conformance passed and the score reached the pass mark (exit code 0).
    Passed,
    /// Conformance failed, or the score is below the pass mark (exit code 1).
    Failed,
    /// Some counted rows could not be judged on this machine (exit code 3).
    Unjudged,
}

impl Verdict {
    /// The exit code of a grade run that concluded this.
    pub fn exit_code(self) -> u8 {
        match self {
            Verdict::Passed => 0,
            Verdict::Failed => 1,
            Verdict::Unjudged => 3,
        }
    }
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
    /// Each thread count's machine checks, in order (retries included).
    pub machine_checks: Vec<MachineCheck>,
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

    /// The score out of 100: the mean of [`Report::scored`]'s points (an unjudged row earns
    /// none); 0 if conformance failed.
    pub fn score(&self) -> f64 {
        let scored = self.scored();
        if self.conformance.is_err() || scored.is_empty() {
            return 0.0;
        }
        100.0 * scored.iter().map(|s| s.points).sum::<f64>() / scored.len() as f64
    }

    /// How many counted rows could not be judged.
    pub fn unjudged(&self) -> usize {
        self.scored().iter().filter(|s| s.unjudged.is_some()).count()
    }

    /// Passed at `pass` points out of 100, failed, or not judged.
    pub fn verdict(&self, pass: f64) -> Verdict {
        if self.conformance.is_err() {
            Verdict::Failed
        } else if self.unjudged() > 0 {
            Verdict::Unjudged
        } else if self.score() < pass {
            Verdict::Failed
        } else {
            Verdict::Passed
        }
    }

    /// The report as Markdown; `command` is the command line that produced it, `pass` the
    /// pass mark.
    pub fn markdown(&self, command: &str, pass: f64) -> String {
        let mut md = format!("# Grade: {}\n\n", self.name);
        let _ = writeln!(md, "Machine: {}.  ", self.machine.describe());
        let _ = writeln!(md, "Command: `{command}`.  ");
        let _ = writeln!(
            md,
            "Reference: {}, timed in the same run, back to back with the submission in every round \
             (alternating which goes first). A workload earns its point at ≤ {FULL_MARKS_RATIO}× the \
             reference's time, nothing at ≥ {ZERO_MARKS_RATIO}×, linearly in between; workloads marked \
             \"balance\" earn at most what the ratio of the observed load imbalances earns on the same \
             scale; the score is the mean over workloads at 2 or more threads. *ratio* is the median of \
             the rounds' own ratios (listed in *rounds*), so it need not equal the two median times' \
             ratio. *imbalance*: the busiest thread's render time over the mean, as the frame itself \
             saw it.\n",
            self.reference
        );
        match &self.conformance {
            Ok(counts) => {
                let _ = writeln!(
                    md,
                    "Conformance: **passed** at {counts:?} threads (observed from inside the frame).\n"
                );
            }
            Err(e) => {
                let _ = writeln!(md, "Conformance: **FAILED**: {e}\n\nNot timed.\n");
            }
        }
        if !self.machine_checks.is_empty() {
            md.push_str(
                "Machine checks, in order: the reference alone on `balanced`, its speedup at that many threads \
                 over 1 thread, before and after each thread count's rows (floor: half the ideal gain); and the \
                 CPUs other processes kept busy while the rows were timed.\n\n\
                 | threads | measured | value | limit | verdict |\n|---:|---|---:|---:|---|\n",
            );
            for c in &self.machine_checks {
                let verdict = if c.busy.is_some() { "**too busy to judge**" } else { "quiet enough" };
                let (what, value, limit) = match (c.speedup, c.others) {
                    (Some(speedup), _) => (
                        "the reference's speedup",
                        format!("{speedup:.2}"),
                        format!("≥ {:.2}", judge::speedup_floor(c.threads)),
                    ),
                    (None, Some(others)) => (
                        "other processes' CPUs",
                        format!("{others:.2}"),
                        format!("≤ {}", judge::OTHERS_LIMIT),
                    ),
                    (None, None) => ("other processes' CPUs", "not measurable here".into(), "–".into()),
                };
                let _ = writeln!(md, "| {} | {what} | {value} | {limit} | {verdict} |", c.threads);
            }
            md.push('\n');
        }
        if !self.scores.is_empty() {
            md.push_str(
                "| workload | what it exposes | threads | submission s | reference s | ratio | rounds | imbalance (sub / ref) | points |\n",
            );
            md.push_str("|---|---|---:|---:|---:|---:|---|---|---:|\n");
            let scored = self.scored();
            for s in &self.scores {
                let counted = if scored.iter().any(|c| std::ptr::eq(*c, s)) { "" } else { " (baseline)" };
                let rounds: Vec<String> = s.ratios.iter().map(|r| format!("{r:.2}")).collect();
                let balance = if s.judged_by_balance { " (balance)" } else { "" };
                let why =
                    s.failure.as_ref().or(s.unjudged.as_ref()).map_or(String::new(), |f| format!(" ({f})"));
                // An unjudged row has no measurements: a dash, not NaN.
                let number = |x: f64, digits: usize| {
                    if x.is_nan() { "–".to_string() } else { format!("{x:.digits$}") }
                };
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} | {} | {} | {} / {}{balance} | {:.2}{counted}{why} |",
                    s.workload,
                    s.exposes,
                    s.threads,
                    number(s.seconds.0, 4),
                    number(s.seconds.1, 4),
                    number(s.ratio, 2),
                    rounds.join(", "),
                    number(s.imbalance.0, 2),
                    number(s.imbalance.1, 2),
                    s.points,
                );
            }
            md.push('\n');
        }
        let _ = write!(md, "**Score: {:.0} / 100**", self.score());
        let _ = match self.verdict(pass) {
            Verdict::Passed => writeln!(md, " (pass mark {pass}: passed)"),
            Verdict::Failed => writeln!(md, " (pass mark {pass}: **not passed**)"),
            Verdict::Unjudged => writeln!(
                md,
                " — **incomplete**: {} counted rows could not be judged on this machine and earned \
                 nothing; grade again on a quiet machine",
                self.unjudged()
            ),
        };
        md
    }
}

/// Points for a ratio of submission ÷ reference time.
pub fn points(ratio: f64) -> f64 {
    ((ZERO_MARKS_RATIO - ratio) / (ZERO_MARKS_RATIO - FULL_MARKS_RATIO)).clamp(0.0, 1.0)
}
