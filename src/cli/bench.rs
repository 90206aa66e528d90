//! `raypool bench`: the speedup benchmark (every mode at many thread counts) written as
//! tables, a plot and timelines, with `--quick` a rough paper table too; or with `--paper`
//! the seed paper's table alone.

use std::path::Path;

use crate::cli::args::BenchArgs;
use crate::error::Error;
use crate::measure::machine::cpus;
use crate::measure::speedup::paper::{paper_table, write_paper_table};
use crate::measure::speedup::report::write_reports;
use crate::measure::speedup::{Preset, run as run_benchmark};

/// Samples per pixel of the paper table that `raypool bench --quick` writes.
const QUICK_PAPER_SPP: u32 = 2;

/// Runs `raypool bench`.
pub fn run(args: &BenchArgs) -> Result<(), Error> {
    let out_dir = &args.out_dir;
    if args.paper {
        let spp = args.spp;
        write_paper(out_dir, spp, &format!("raypool bench --paper --spp {spp}"))?;
        eprintln!("wrote {}/paper-table.md", out_dir.display());
        return Ok(());
    }
    let quick = args.quick;
    let preset = if quick { Preset::quick() } else { Preset::full() };
    let preset = Preset { threads: args.threads.clone(), ..preset }.on(&args.scenes);
    let outcome = run_benchmark(&preset, &[], |line| eprintln!("{line}"))?;
    let command = bench_command(args);
    write_reports(out_dir, &preset, &outcome, &command)?;
    eprintln!("wrote {}/speedup.md, speedup.csv, speedup.png, timeline-*.png", out_dir.display());
    if quick {
        // A rough paper table too: 2 spp, scaled to the paper's 500 (labelled so).
        write_paper(out_dir, QUICK_PAPER_SPP, &command)?;
        eprintln!("wrote {}/paper-table.md (at {QUICK_PAPER_SPP} spp)", out_dir.display());
    }
    Ok(())
}

/// The command line that reproduces this run, for the report.
fn bench_command(args: &BenchArgs) -> String {
    let mut command = String::from("raypool bench");
    if args.quick {
        command.push_str(" --quick");
    }
    if !args.scenes.is_empty() {
        command += &format!(" --scenes {}", args.scenes.join(","));
    }
    if !args.threads.is_empty() {
        let threads: Vec<String> = args.threads.iter().map(usize::to_string).collect();
        command += &format!(" --threads {}", threads.join(","));
    }
    command
}

/// Renders the paper's table at `spp` on one thread per CPU and writes `paper-table.md`.
fn write_paper(out_dir: &Path, spp: u32, command: &str) -> Result<(), Error> {
    let threads = cpus();
    let cells = paper_table(spp, threads, |line| eprintln!("{line}"))?;
    write_paper_table(out_dir, &cells, spp, threads, command)
}
