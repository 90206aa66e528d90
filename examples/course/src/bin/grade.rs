//! `cargo run --release --bin grade -- [--part scheduler|discipline] [--threads 1,2,4] [--out grade.md]`:
//! the conformance checks, then the grader's workloads, timed against raypool's own
//! `steal` mode and `Stealing` discipline in the same run. Prints and writes the report.

use raypool::measure::grade::{Entry, Submission, main as grade};
use raypool_course::{discipline, scheduler::TileQueue};

fn main() -> std::process::ExitCode {
    grade(&[
        Submission { name: "scheduler".into(), entry: Entry::Scheduler(&TileQueue) },
        Submission { name: "discipline".into(), entry: Entry::Queue(discipline::make) },
    ])
}
