//! `raypool simulate`: every row's and tile's cost timed on one thread, each scheduler's
//! speedup predicted from them at many thread counts, optionally checked against real runs
//! on this machine; prints the table and can write it as a report.

use crate::cli::args::SimulateArgs;
use crate::cli::output;
use crate::cli::settings::{load_scene, render_job, render_settings, scene_name};
use crate::cli::transport::Renderer;
use crate::error::Error;
use crate::measure::machine::cpus;
use crate::measure::scaling::{Study, measure_costs, measure_rounds, write_report};
use crate::schedule::random::RngChoice;

/// Runs `raypool simulate`.
pub fn run(args: &SimulateArgs) -> Result<(), Error> {
    let image = &args.image;
    let scene = load_scene(image)?;
    let settings = render_settings(image, &scene, RngChoice::PerSample, Renderer::CommandLine)?;
    let job = render_job(image, &scene, settings)?;
    let subject = format!(
        "{}, {} × {}, {} spp, depth {}, {}-pixel tiles",
        scene_name(image),
        settings.width,
        settings.height,
        settings.spp,
        settings.max_depth,
        image.tile
    );
    eprintln!("timing every row and tile of {subject} on one thread, {} passes", args.runs);
    let costs = measure_costs(job.clone(), image.tile, args.runs as usize);
    let mut threads: Vec<usize> = args.threads.iter().map(|&t| t as usize).collect();
    threads.sort_unstable();
    threads.dedup();
    let (mut serial_seconds, mut measured) = (None, Vec::new());
    if args.measure {
        let here: Vec<usize> = threads.iter().copied().filter(|t| (2..=cpus()).contains(t)).collect();
        eprintln!("measuring serial and every mode at {here:?} threads, {} rounds", args.runs);
        let (serial, runs) = measure_rounds(&job, image.tile, &here, args.runs as usize);
        (serial_seconds, measured) = (Some(serial), runs);
    }
    let command =
        std::iter::once("raypool".to_string()).chain(std::env::args().skip(1)).collect::<Vec<_>>().join(" ");
    let study = Study { subject, command, costs, threads, serial_seconds, measured };
    output(&study.table())?;
    if let Some(dir) = &args.report {
        write_report(dir, &study)?;
        eprintln!("wrote {0}/scaling.md, {0}/scaling.csv, {0}/scaling.png", dir.display());
    }
    Ok(())
}
