//! The scaling model (`raypool simulate`): each scheduler's rule replayed on known costs, and
//! the command's table and report.

mod deadline;

use std::process::Command;

use deadline::output_within;
use raypool::Schedule;
use raypool::measure::scaling::{Costs, predict, threads_to_reach};

/// Rows (and tiles) of 5, 1, 1, 1 seconds on two workers.
fn front_heavy() -> Costs {
    Costs { rows: vec![5.0, 1.0, 1.0, 1.0], tiles: vec![5.0, 1.0, 1.0, 1.0] }
}

#[test]
fn each_rule_on_a_front_heavy_image() {
    let costs = front_heavy();
    let speedup = |mode| predict(&costs, mode, 2).speedup;
    // Static: blocks [5, 1] and [1, 1]: 6 s.
    assert_eq!(speedup(Schedule::StaticBlocks), 8.0 / 6.0);
    // Interleaved: rows 0, 2 (6 s) and rows 1, 3 (2 s).
    assert_eq!(speedup(Schedule::Interleaved), 8.0 / 6.0);
    // A shared queue: 5 to worker 0, the three 1s to worker 1 while it is busy: 5 s.
    assert_eq!(speedup(Schedule::PoolRows), 8.0 / 5.0);
    assert_eq!(speedup(Schedule::PoolTiles), 8.0 / 5.0);
    // Stealing: runs [5, 1] and [1, 1]; worker 1 finishes its run at 2 s and steals the 1
    // from the back of worker 0's run, so worker 0 ends at 5 s (6 s without the steal).
    let steal = predict(&costs, Schedule::Stealing, 2);
    assert_eq!((steal.seconds, steal.speedup), (5.0, 8.0 / 5.0));
    assert_eq!(steal.imbalance, 5.0 / 4.0);
    assert_eq!(predict(&costs, Schedule::Serial, 7).threads, 1, "serial is one thread whatever T");
}

#[test]
fn thieves_take_from_the_back_and_only_what_nobody_started() {
    // Runs [5, 1, 1 | 1, 1, 1 | 1, 1, 1]: workers 1 and 2 finish at 3 s and each steals a 1
    // from the back of worker 0's run (worker 2 wrapping round to it), so worker 0 ends at 5 s,
    // not 7.
    let costs = Costs { rows: vec![], tiles: vec![5.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0] };
    let p = predict(&costs, Schedule::Stealing, 3);
    assert_eq!((p.seconds, p.imbalance), (5.0, 5.0 / (13.0 / 3.0)));
    // Runs [1, 1 | 1, 9 | 1, 1]: worker 1 has started its 9 before anyone runs dry, so there
    // is nothing to steal: 10 s.
    let costs = Costs { rows: vec![], tiles: vec![1.0, 1.0, 1.0, 9.0, 1.0, 1.0] };
    assert_eq!(predict(&costs, Schedule::Stealing, 3).seconds, 10.0);
}

#[test]
fn more_threads_than_work_leave_workers_idle_not_counted() {
    let costs = front_heavy();
    for mode in [Schedule::StaticBlocks, Schedule::Interleaved, Schedule::PoolTiles, Schedule::Stealing] {
        let p = predict(&costs, mode, 64);
        assert_eq!(p.seconds, 5.0, "{mode:?}: the 5 s unit bounds the time");
        assert_eq!(p.imbalance, 5.0 / 2.0, "{mode:?}: four busy workers, mean 2 s");
    }
    assert_eq!(threads_to_reach(&costs, Schedule::PoolTiles, 1.6, 64), Some(2));
    assert_eq!(threads_to_reach(&costs, Schedule::PoolTiles, 1.7, 64), None, "never past 8/5");
}

#[test]
fn uniform_work_scales_perfectly_in_every_mode() {
    let costs = Costs { rows: vec![1.0; 64], tiles: vec![0.5; 128] };
    for mode in [
        Schedule::StaticBlocks,
        Schedule::Interleaved,
        Schedule::PoolRows,
        Schedule::PoolTiles,
        Schedule::Stealing,
    ] {
        for t in [1, 2, 4, 8, 16, 32, 64] {
            let p = predict(&costs, mode, t);
            assert!(
                (p.speedup - t as f64).abs() < 1e-9 && (p.imbalance - 1.0).abs() < 1e-9,
                "{mode:?} at {t}: {p:?}"
            );
        }
    }
}

#[test]
fn simulate_prints_every_mode_and_writes_its_report() {
    let dir = std::env::temp_dir().join(format!("raypool-simulate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let report = dir.to_str().unwrap();
    let args = [
        "simulate",
        "--scene",
        "paper1",
        "--width",
        "48",
        "--spp",
        "2",
        "--threads",
        "1,4,2,64",
        "--measure",
        "--runs",
        "1",
        "--report",
        report,
    ];
    let out =
        output_within(Command::new(env!("CARGO_BIN_EXE_raypool")).args(args), "`raypool simulate` to exit");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for mode in ["static", "interleaved", "pool-rows", "pool", "steal"] {
        assert!(table.lines().any(|l| l.starts_with(&format!("{mode} "))), "{mode} row in:\n{table}");
    }
    assert!(table.contains("mode \\ T") && table.contains("64"), "{table}");
    if raypool::measure::machine::cpus() >= 2 {
        assert!(table.contains("steal          2 threads: predicted"), "{table}");
    }
    let md = std::fs::read_to_string(dir.join("scaling.md")).unwrap();
    assert!(md.contains("## Answers") && md.contains("What the model leaves out"), "{md}");
    let csv = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 5 * 4, "a row per mode and thread count");
    assert!(image::open(dir.join("scaling.png")).is_ok());

    let bad = output_within(
        Command::new(env!("CARGO_BIN_EXE_raypool")).args(["simulate", "--threads", "0,2"]),
        "`raypool simulate --threads 0,2` to exit",
    );
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&bad.stderr).lines().count(), 1);
}
