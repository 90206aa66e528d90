//! A grade: each workload's score at each thread count, the points a time ratio earns, the
//! total out of 100, and the report as Markdown.
//!
//! A ratio of submission ÷ reference time of at most [`FULL_MARKS_RATIO`] earns a workload's
//! full point, [`ZERO_MARKS_RATIO`] or more none, linearly in between; the score is the mean
//! over workloads at 2 or more threads (on one thread every scheduler renders the same way).

use std::fmt::Write as _;

use crate::measure::machine::Machine;

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
