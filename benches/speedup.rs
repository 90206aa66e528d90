//! `cargo bench --bench speedup`: the full speedup benchmark (see `raypool::measure::speedup`), with a
//! rayon baseline that the `raypool bench` command cannot have (rayon is only a
//! dev-dependency). Writes `results/speedup.{md,csv,png}` and `results/timeline-*.png`.

use std::sync::Arc;

use rayon::prelude::*;
use raypool::measure::machine::results_dir;
use raypool::measure::speedup::report::write_reports;
use raypool::measure::speedup::{Contender, Preset, run};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::Scheduler;
use raypool::tracer::render::TileOutput;

/// The same tiles as `pool` and `steal`, distributed by rayon's `par_iter` on a rayon pool
/// of `frame.threads` threads.
struct Rayon;

impl Scheduler for Rayon {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(frame.threads).build().expect("rayon starts");
        pool.install(|| frame.tiles().into_par_iter().map(|tile| frame.render(tile)).collect())
    }
}

fn main() {
    // `cargo bench` passes `--bench`; `-- --quick` and `-- --threads 1,2,4` are ours.
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let threads: Vec<usize> = match args.iter().position(|a| a == "--threads") {
        Some(k) => args
            .get(k + 1)
            .map_or("", String::as_str)
            .split(',')
            .map(|t| match t.parse() {
                Ok(t) if t > 0 => t,
                _ => {
                    eprintln!("--threads takes a list of counts of at least 1, e.g. --threads 1,2,4");
                    std::process::exit(2)
                }
            })
            .collect(),
        None => Vec::new(),
    };
    let preset = Preset { threads, ..if quick { Preset::quick() } else { Preset::full() } };
    let extra = [Contender { name: "rayon".into(), scheduler: &Rayon }];
    let outcome = run(&preset, &extra, |line| eprintln!("{line}")).expect("the benchmark scenes render");
    let command =
        if quick { "cargo bench --bench speedup -- --quick" } else { "cargo bench --bench speedup" };
    let dir = results_dir();
    write_reports(&dir, &preset, &outcome, command).expect("the output directory is writable");
    println!("{}", std::fs::read_to_string(dir.join("speedup.md")).unwrap_or_default());
}
