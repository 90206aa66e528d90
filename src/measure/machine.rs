//! The machine a measurement runs on: how many CPUs this process may use (the one place
//! that asks), the thread counts a measurement runs at by default, and which machine, commit
//! and day a measurement was made on (every committed figure says so).

use std::path::PathBuf;
use std::process::Command;

/// The environment variable that moves every benchmark's output away from `results/`
/// (`benches/all.sh --out-dir DIR` sets it), so a reader can regenerate the tables beside the
/// committed ones and compare.
pub const RESULTS_ENV: &str = "RAYPOOL_RESULTS";

/// Where benchmarks write their tables and plots: `$RAYPOOL_RESULTS` if set, else `results`
/// (relative to the repository root, where `cargo bench` runs), created if missing.
///
/// ```
/// // Without the variable, the committed folder.
/// if std::env::var_os(raypool::measure::machine::RESULTS_ENV).is_none() {
///     assert_eq!(raypool::measure::machine::results_dir(), std::path::Path::new("results"));
/// }
/// ```
pub fn results_dir() -> PathBuf {
    let dir = std::env::var_os(RESULTS_ENV).map_or_else(|| PathBuf::from("results"), PathBuf::from);
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// The logical CPUs this process may use (`nproc`; 1 where the system cannot tell): the
/// default worker count of a render and the top of a benchmark's thread counts.
pub fn cpus() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The thread counts a measurement runs at when none are given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// 1, 2, 3, … 2 × CPUs: every count, past the CPUs too (the speedup benchmark).
    EveryCountToTwiceTheCpus,
    /// 1, 2, 4, … the powers of two below the CPUs, and the CPUs (the grader).
    DoublingsToTheCpus,
}

/// The thread counts to measure: `asked`, or `sweep` of this machine's CPUs when it is empty.
///
/// ```
/// use raypool::measure::machine::{Sweep, thread_counts};
/// assert_eq!(thread_counts(&[1, 4, 64], Sweep::DoublingsToTheCpus), vec![1, 4, 64]);
/// assert_eq!(thread_counts(&[], Sweep::EveryCountToTwiceTheCpus)[0], 1);
/// assert_eq!(thread_counts(&[], Sweep::DoublingsToTheCpus)[0], 1);
/// ```
pub fn thread_counts(asked: &[usize], sweep: Sweep) -> Vec<usize> {
    if !asked.is_empty() {
        return asked.to_vec();
    }
    let cpus = cpus();
    match sweep {
        Sweep::EveryCountToTwiceTheCpus => (1..=2 * cpus).collect(),
        Sweep::DoublingsToTheCpus => {
            let mut counts: Vec<usize> =
                std::iter::successors(Some(1), |t| Some(t * 2)).take_while(|&t| t < cpus).collect();
            counts.push(cpus);
            counts
        }
    }
}

/// A description of where and when a benchmark ran.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Machine {
    /// Logical CPUs available to this process (`nproc`).
    pub cpus: usize,
    /// CPU model name from `/proc/cpuinfo` ("unknown" elsewhere).
    pub cpu_model: String,
    /// UTC date, `YYYY-MM-DD`.
    pub date: String,
    /// Short git commit of the working tree, `+dirty` if code (anything outside `results/`)
    /// has uncommitted changes.
    pub commit: String,
}

impl Machine {
    /// Reads the current machine, date and commit.
    pub fn current() -> Machine {
        let cpu_model = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_owned())
            })
            .unwrap_or_else(|| "unknown".into());
        let commit = command("git", &["rev-parse", "--short", "HEAD"]).unwrap_or_else(|| "unknown".into());
        // Uncommitted measurements under results/ do not make the measured code "dirty".
        let status = ["status", "--porcelain", "--untracked-files=no", "--", ".", ":!results"];
        let dirty = command("git", &status).is_some_and(|s| !s.is_empty());
        Machine {
            cpus: cpus(),
            cpu_model,
            date: command("date", &["-u", "+%Y-%m-%d"]).unwrap_or_else(|| "unknown".into()),
            commit: if dirty { format!("{commit}+dirty") } else { commit },
        }
    }

    /// One Markdown line: `nproc 2, AMD EPYC, commit abc1234, 2026-11-22`.
    pub fn describe(&self) -> String {
        format!("nproc {}, {}, commit {}, {}", self.cpus, self.cpu_model, self.commit, self.date)
    }
}

/// This machine's host name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`, else "unknown").
pub fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_owned())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

fn command(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}
