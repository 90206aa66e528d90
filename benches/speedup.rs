//! `cargo bench --bench speedup`: the full speedup benchmark (see `raypool::measure::speedup`), with a
//! rayon baseline that the `raypool bench` command cannot have (rayon is only a
//! dev-dependency). Writes `results/speedup.{md,csv,png}` and `results/timeline-*.png`.

use std::path::Path;
use std::sync::Arc;

use rayon::prelude::*;
use raypool::measure::speedup::{Contender, Preset, run, write_reports};
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
    // `cargo bench` passes `--bench`; any other argument filters nothing here.
    let quick = std::env::args().any(|a| a == "--quick");
    let preset = if quick { Preset::quick() } else { Preset::full() };
    let extra = [Contender { name: "rayon".into(), scheduler: &Rayon }];
    let outcome = run(&preset, &extra, |line| eprintln!("{line}")).expect("the benchmark scenes render");
    let command =
        if quick { "cargo bench --bench speedup -- --quick" } else { "cargo bench --bench speedup" };
    write_reports(Path::new("results"), &preset, &outcome, command).expect("results/ is writable");
    println!("{}", std::fs::read_to_string("results/speedup.md").unwrap_or_default());
}
