//! The course kit (examples/course, examples/course-solution): the conformance check catches
//! the two wrong schedulers an instructor expects, with a reason a student understands; the
//! solution passes; the built-in modes pass it again and again (not flaky); and the grader
//! scores what it should.

mod deadline;

use deadline::within;
use raypool::measure::grade::report::points;
use raypool::measure::grade::{Entry, Options, Submission, grade};
use raypool::schedule::conformance::check;
use raypool::schedule::modes::Schedule;

#[path = "../examples/course-solution/scheduler.rs"]
mod solution;

#[path = "../examples/course-solution/discipline.rs"]
mod steal_half;

#[path = "../examples/course-solution/wrong/calling-thread.rs"]
mod calling_thread;

#[path = "../examples/course-solution/wrong/thread-per-tile.rs"]
mod thread_per_tile;

#[test]
fn the_solution_conforms() {
    within("the conformance check of the solution to finish", || {
        for threads in [1, 2, 3, 8] {
            check(&solution::TileQueue, threads).unwrap_or_else(|e| panic!("{threads} threads: {e}"));
        }
        pool::conformance::check(steal_half::make).unwrap();
    });
}

#[test]
fn a_scheduler_on_the_calling_thread_only_fails_in_words_a_student_understands() {
    within("the conformance check of a calling-thread scheduler to give up", || {
        check(&calling_thread::TileQueue, 1).expect("on one thread, the calling thread is right");
        let error = check(&calling_thread::TileQueue, 2).unwrap_err();
        assert!(error.contains("never had 2 tiles rendering at the same time (at most 1)"), "{error}");
        assert!(error.contains("rendered on the calling thread"), "{error}");
    });
}

#[test]
fn a_thread_per_tile_fails_in_words_a_student_understands() {
    within("the conformance check of a thread-per-tile scheduler to finish", || {
        for threads in [1, 2, 8] {
            let error = check(&thread_per_tile::TileQueue, threads).unwrap_err();
            assert!(error.contains("rendered on 54 different threads"), "{error}");
            assert!(error.contains(&format!("frame.threads = {threads}")), "{error}");
        }
    });
}

/// Every built-in parallel mode, on 2, 3 and 8 threads, `CONFORMANCE_ROUNDS` times (25 by
/// default; the course issue's evidence ran 1,000).
#[test]
fn the_builtin_modes_pass_the_check_every_time() {
    let rounds: usize = std::env::var("CONFORMANCE_ROUNDS").ok().and_then(|r| r.parse().ok()).unwrap_or(25);
    within("the repeated conformance checks of the built-in modes to finish", move || {
        for round in 0..rounds {
            for schedule in &Schedule::ALL[1..] {
                for threads in [2, 3, 8] {
                    check(schedule, threads)
                        .unwrap_or_else(|e| panic!("round {round}, {schedule:?} on {threads} threads: {e}"));
                }
            }
        }
        eprintln!("the built-in modes passed the conformance check {rounds} times in a row");
    });
}

#[test]
fn points_fall_from_one_to_zero_between_the_two_ratios() {
    assert_eq!((points(0.5), points(1.2), points(2.0), points(3.0)), (1.0, 1.0, 0.0, 0.0));
    assert!((points(1.6) - 0.5).abs() < 1e-12);
}

fn options(threads: Vec<usize>) -> Options {
    Options { threads, rounds: 1, out: "unused.md".into() }
}

#[test]
fn the_grader_times_a_conforming_submission_on_every_workload_and_thread_count() {
    within("the grading of the solution to finish", || {
        let submission =
            Submission { name: "solution".into(), entry: Entry::Scheduler(&solution::TileQueue) };
        let report = grade(&submission, &options(vec![1, 2]), |_| {}).unwrap();
        assert_eq!(report.conformance, Ok(vec![1, 2]));
        let workloads: Vec<&str> = report.scores.iter().map(|s| s.workload).collect();
        assert_eq!(workloads.len(), 12, "6 workloads × 2 thread counts: {workloads:?}");
        assert!(report.scores.iter().all(|s| s.failure.is_none() && s.ratio > 0.0), "same images");
        assert_eq!(report.scored().len(), 6, "the 1-thread rows are a baseline");
        let markdown = report.markdown("test");
        assert!(markdown.contains("Machine: nproc") && markdown.contains("**Score: "), "{markdown}");
    });
}

#[test]
fn the_grader_scores_a_nonconforming_submission_zero_without_timing_it() {
    within("the grading of a thread-per-tile scheduler to finish", || {
        let submission =
            Submission { name: "per tile".into(), entry: Entry::Scheduler(&thread_per_tile::TileQueue) };
        let report = grade(&submission, &options(vec![2]), |_| {}).unwrap();
        let error = report.conformance.as_ref().unwrap_err();
        assert!(error.starts_with("with frame.threads = 1: tiles were rendered on 54"), "{error}");
        assert!(report.scores.is_empty());
        assert_eq!(report.score(), 0.0);
        assert!(report.markdown("test").contains("Conformance: **FAILED**"));
    });
}

#[test]
fn the_grader_grades_a_queue_with_the_nested_workload() {
    within("the grading of the steal-half queue to finish", || {
        let submission = Submission { name: "steal half".into(), entry: Entry::Queue(steal_half::make) };
        let report = grade(&submission, &options(vec![2]), |_| {}).unwrap();
        assert!(report.conformance.is_ok(), "{:?}", report.conformance);
        assert!(report.scores.iter().any(|s| s.workload == "nested"));
        assert!(report.scores.iter().all(|s| s.failure.is_none()));
    });
}
