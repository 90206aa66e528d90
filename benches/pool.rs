//! `cargo bench --bench pool`: what a job costs on each queue discipline, and how well each
//! balances an uneven batch. Writes `results/pool.md`. See `benches/README.md`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::Criterion;
use pool::{Discipline, ThreadPool};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use raypool::measure::machine::{Machine, cpus, results_dir};

/// Empty jobs per batch in the overhead benchmark.
const JOBS: usize = 100_000;
/// `std::thread::spawn` is ~1000× dearer per job: fewer jobs keep that row short.
const THREAD_JOBS: usize = 2_000;
/// Jobs in the imbalanced batch, and repetitions of it (the median is reported).
const UNEVEN_JOBS: usize = 10_000;
const UNEVEN_RUNS: usize = 7;

fn main() {
    let workers = cpus();
    let mut criterion =
        Criterion::default().configure_from_args().sample_size(20).warm_up_time(Duration::from_secs(1));
    overhead(&mut criterion, workers);
    criterion.final_summary();
    let costs = uneven_costs();
    let mut sorted = costs.clone();
    sorted.sort();
    let uneven = [
        ("random order", uneven_batch(workers, &costs)),
        ("sorted, longest last", uneven_batch(workers, &sorted)),
    ];
    let report = report(workers, &uneven);
    std::fs::write(results_dir().join("pool.md"), &report).expect("the output directory is writable");
    println!("\n{report}");
}

/// Criterion group `overhead`: 100,000 empty jobs through each pool, and the baselines.
fn overhead(c: &mut Criterion, workers: usize) {
    let mut group = c.benchmark_group("overhead");
    for discipline in Discipline::ALL {
        let pool = ThreadPool::new(workers, discipline).expect("pool starts");
        group.bench_function(format!("{discipline:?}"), |b| b.iter(|| pool.batch((0..JOBS).map(|_| || ()))));
    }
    let rayon = rayon::ThreadPoolBuilder::new().num_threads(workers).build().expect("rayon starts");
    group.bench_function("rayon", |b| {
        b.iter(|| {
            rayon.scope(|s| {
                for _ in 0..JOBS {
                    s.spawn(|_| ());
                }
            })
        })
    });
    group.bench_function("thread-per-job", |b| {
        b.iter(|| {
            let threads: Vec<_> = (0..THREAD_JOBS).map(|_| std::thread::spawn(|| ())).collect();
            threads.into_iter().for_each(|t| t.join().expect("empty thread"));
        })
    });
    group.finish();
}

/// Criterion's median estimate for `overhead/<name>`, in nanoseconds per iteration.
fn criterion_median(name: &str) -> Option<f64> {
    let path = Path::new("target/criterion/overhead").join(name).join("new/estimates.json");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    json["median"]["point_estimate"].as_f64()
}

/// One row of the imbalanced-batch table.
struct Uneven {
    name: String,
    /// Median wall time over the ideal `total work ÷ workers`.
    wall_over_ideal: f64,
    median_wall: Duration,
    /// Busiest worker's busy time over the mean (pool modes only).
    imbalance: Option<f64>,
}

/// 10,000 jobs of Pareto-distributed length (α = 1.5, minimum 10 µs, capped at 5 ms): most
/// are short, a few are hundreds of times longer, in random order.
fn uneven_costs() -> Vec<Duration> {
    let mut rng = SmallRng::seed_from_u64(12);
    (0..UNEVEN_JOBS)
        .map(|_| {
            let u: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
            Duration::from_secs_f64((10e-6 / u.powf(1.0 / 1.5)).min(5e-3))
        })
        .collect()
}

fn spin(d: Duration) {
    let start = Instant::now();
    while start.elapsed() < d {
        std::hint::spin_loop();
    }
}

fn uneven_batch(workers: usize, costs: &[Duration]) -> Vec<Uneven> {
    let ideal = costs.iter().sum::<Duration>() / workers as u32;
    let median = |mut walls: Vec<Duration>| {
        walls.sort();
        walls[walls.len() / 2]
    };
    let row = |name, walls: Vec<Duration>, imbalance| {
        let median_wall = median(walls);
        Uneven {
            name,
            wall_over_ideal: median_wall.as_secs_f64() / ideal.as_secs_f64(),
            median_wall,
            imbalance,
        }
    };
    let mut rows = Vec::new();
    for discipline in Discipline::ALL {
        let name = format!("{discipline:?}");
        let pool =
            ThreadPool::builder().workers(workers).discipline(discipline).instrument(true).build().unwrap();
        let mut imbalances = Vec::new();
        let walls = (0..UNEVEN_RUNS)
            .map(|_| {
                pool.reset_stats();
                let start = Instant::now();
                pool.batch(costs.iter().map(|&d| move || spin(d)));
                let wall = start.elapsed();
                imbalances.push(pool.stats().imbalance());
                wall
            })
            .collect();
        imbalances.sort_by(f64::total_cmp);
        rows.push(row(name, walls, Some(imbalances[imbalances.len() / 2])));
    }
    let chunk = costs.len().div_ceil(workers);
    let static_walls = (0..UNEVEN_RUNS)
        .map(|_| {
            let start = Instant::now();
            std::thread::scope(|s| {
                for block in costs.chunks(chunk) {
                    s.spawn(move || block.iter().for_each(|&d| spin(d)));
                }
            });
            start.elapsed()
        })
        .collect();
    rows.push(row("static split".into(), static_walls, None));
    let rayon = rayon::ThreadPoolBuilder::new().num_threads(workers).build().unwrap();
    let rayon_walls = (0..UNEVEN_RUNS)
        .map(|_| {
            use rayon::prelude::*;
            let start = Instant::now();
            rayon.install(|| costs.par_iter().for_each(|&d| spin(d)));
            start.elapsed()
        })
        .collect();
    rows.push(row("rayon par_iter".into(), rayon_walls, None));
    rows
}

fn report(workers: usize, uneven: &[(&str, Vec<Uneven>)]) -> String {
    let machine = Machine::current();
    let mut md = String::new();
    let _ = writeln!(md, "# Pool benchmarks\n");
    let _ =
        writeln!(md, "Command: `cargo bench --bench pool` · {workers} workers · {}\n", machine.describe());
    let _ = writeln!(md, "## Per-job overhead: {JOBS} empty jobs through one batch\n");
    let _ = writeln!(
        md,
        "Criterion medians (20 samples). The caller submits and sleeps; only the {workers} workers run jobs.\n"
    );
    let _ = writeln!(md, "| queue | time for {JOBS} jobs | per job | × rayon |\n|---|---:|---:|---:|");
    let rayon = criterion_median("rayon");
    let names = Discipline::ALL.map(|d| format!("{d:?}"));
    for name in names.iter().map(String::as_str).chain(["rayon"]) {
        match criterion_median(name) {
            Some(ns) => {
                let ratio = rayon.map_or("n/a".into(), |r| format!("{:.2}", ns / r));
                let _ =
                    writeln!(md, "| {name} | {:.2} ms | {:.0} ns | {ratio} |", ns / 1e6, ns / JOBS as f64);
            }
            None => {
                let _ = writeln!(md, "| {name} | not measured (filtered out) | | |");
            }
        }
    }
    if let Some(ns) = criterion_median("thread-per-job") {
        let _ = writeln!(
            md,
            "| `std::thread::spawn` per job ({THREAD_JOBS} jobs) | {:.2} ms | {:.0} ns | {} |",
            ns / 1e6,
            ns / THREAD_JOBS as f64,
            rayon.map_or("n/a".into(), |r| format!("{:.0}", (ns / THREAD_JOBS as f64) / (r / JOBS as f64)))
        );
    }
    let ideal = uneven_costs().iter().sum::<Duration>() / workers as u32;
    let _ = writeln!(md, "\n## Imbalanced batch: {UNEVEN_JOBS} jobs of heavy-tailed length\n");
    let _ = writeln!(
        md,
        "Job lengths are Pareto (α = 1.5, ≥ 10 µs, ≤ 5 ms), busy-waited; total work {:.3} s, ideal wall time (work ÷ {workers}) {:.3} s. Median of {UNEVEN_RUNS} runs. \
         *Random order* spreads the long jobs evenly, so even a static split is balanced by the law of large numbers; \
         *sorted* puts them all at the end, as an image puts its expensive rows together: the static split gives one thread nearly all the work, \
         and the Stealing pool, which deals the batch out in the same contiguous runs, must steal to recover.\n",
        ideal.as_secs_f64() * workers as f64,
        ideal.as_secs_f64()
    );
    let _ = writeln!(
        md,
        "| order | mode | median wall | wall ÷ ideal | imbalance (max busy ÷ mean busy) |\n|---|---|---:|---:|---:|"
    );
    for (order, rows) in uneven {
        for u in rows {
            let imbalance = u.imbalance.map_or("–".into(), |i| format!("{i:.3}"));
            let _ = writeln!(
                md,
                "| {order} | {} | {:.3} s | {:.3} | {imbalance} |",
                u.name,
                u.median_wall.as_secs_f64(),
                u.wall_over_ideal
            );
        }
    }
    md
}
