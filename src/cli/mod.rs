//! **The command line**: `raypool render | merge | simulate | scenes | scene | bench | grade |
//! compare`. Every failure is an [`Error`] that `main` prints on one line before exiting with
//! code 2 (130 or 143 when Ctrl-C or SIGTERM stopped a render: [`interrupt`]); a render too big
//! for the memory this process may use is refused before it starts ([`memory`]).

pub mod interrupt;
pub mod memory;

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use clap::{Args, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::cli::interrupt::Interrupt;
use crate::error::Error;
use crate::files::output::{Format, PendingOutput};
use crate::files::part::{Part, PartSettings, merge, scene_digest};
use crate::measure::machine::cpus;
use crate::measure::scaling::{Study, measure_costs, measure_rounds, write_report};
use crate::measure::speedup::Preset;
use crate::measure::speedup::report::write_reports;
use crate::scenes::builtin::{BUILTINS, DEFAULT_SCENE_SEED, builtin_scene};
use crate::scenes::format::SceneFile;
use crate::schedule::frame::{DEFAULT_TILE, Frame};
use crate::schedule::modes::{Schedule, render};
use crate::schedule::progressive::Cancel;
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::math::real::Real;
use crate::tracer::render::{Adaptive, MAX_SIDE, RenderJob, RenderSettings, default_height};
use crate::tracer::sampling::sampler::Sampler;
use crate::tracer::scene::{Accel, Scene};
use crate::tracer::tile::{Shard, Tile};

/// raypool: the book's ray tracer on hand-written thread pools.
#[derive(Debug, Parser)]
#[command(name = "raypool", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an image (.png, .ppm, .pfm or .exr), or one shard of it (.rpart).
    Render(RenderArgs),
    /// Merge the part files of a sharded render (`render --shard K/N`) into the image.
    Merge {
        /// Every part, shards 0 to N-1, in any order.
        #[arg(required = true, value_name = "PART")]
        parts: Vec<PathBuf>,
        /// The image (.png, .ppm, .pfm or .exr), written only if the parts are complete and agree.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
    },
    /// Predict every scheduler's speedup at many thread counts from one single-thread render,
    /// and with --measure check the prediction against real runs on this machine.
    Simulate(SimulateArgs),
    /// Watch the workers render, live, in a browser: serves a page on 127.0.0.1 and prints its
    /// address as the first line of stdout.
    View(ViewArgs),
    /// List the built-in scenes.
    Scenes,
    /// Measure every mode at 1…2×CPUs threads (or --threads) on the benchmark scenes; write
    /// tables and plots.
    Bench {
        /// Thread counts to measure, e.g. `--threads 1,2,4,8,16` [default: 1, 2, … 2 × CPUs].
        #[arg(long, value_delimiter = ',', value_parser = crate::measure::grade::at_least_one, conflicts_with = "paper")]
        threads: Vec<usize>,
        /// Small images and 3 runs, and the paper table at 2 spp (under 2 minutes on 2 cores),
        /// instead of the full preset.
        #[arg(long, conflicts_with = "paper")]
        quick: bool,
        /// Instead: the seed paper's table at 1200 × 800 (paper-table.md). Long: at 500 spp
        /// it is hours of CPU; pass a smaller --spp to estimate.
        #[arg(long)]
        paper: bool,
        /// Samples per pixel for --paper.
        #[arg(long, default_value_t = 500, requires = "paper", value_parser = clap::value_parser!(u32).range(1..))]
        spp: u32,
        /// Where to write speedup.md, speedup.csv and the plots.
        #[arg(long, default_value = "results", value_name = "DIR")]
        out_dir: PathBuf,
    },
    /// Grade a scheduler or a queue discipline as a course's grader does: the conformance
    /// check, then workloads that each expose one weakness, timed against the reference in
    /// the same run; prints the report and writes it to --out. (A student's own code is
    /// graded by the starter's grade binary: examples/course.)
    Grade {
        /// The built-in mode to grade.
        #[arg(long, required_unless_present = "discipline", conflicts_with = "discipline")]
        mode: Option<Schedule>,
        /// The built-in queue discipline to grade.
        #[arg(long, value_parser = ["shared", "locked", "stealing"])]
        discipline: Option<String>,
        /// Thread counts, rounds, report file.
        #[command(flatten)]
        options: crate::measure::grade::Options,
    },
    /// Compare two PFM images: RMSE, relative MSE, mean absolute error, largest error, PSNR.
    Compare {
        /// The image to judge.
        image: PathBuf,
        /// The reference.
        reference: PathBuf,
        /// Write a false-colour map of each pixel's error (PNG).
        #[arg(long, value_name = "PNG")]
        diff: Option<PathBuf>,
    },
    /// Print a scene as TOML (e.g. `raypool scene final > final.toml`).
    Scene {
        /// Built-in scene name (see `raypool scenes`).
        name: String,
        /// Seed of generated scenes (`final`).
        #[arg(long, default_value_t = DEFAULT_SCENE_SEED)]
        scene_seed: u64,
    },
}

/// What to render and how: the scene, the image size and the sampling (shared by `render`
/// and `simulate`).
#[derive(Debug, Args)]
pub struct ImageArgs {
    /// Built-in scene (see `raypool scenes`).
    #[arg(long, default_value = "final", conflicts_with = "scene_file")]
    pub scene: String,
    /// Scene file in raypool's TOML format, instead of a built-in scene.
    #[arg(long, value_name = "PATH")]
    pub scene_file: Option<PathBuf>,
    /// Seed of generated scenes (`final`).
    #[arg(long, default_value_t = DEFAULT_SCENE_SEED)]
    pub scene_seed: u64,
    /// Image width, pixels.
    #[arg(long, default_value_t = 400, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub width: u32,
    /// Image height, pixels [default: width ÷ the scene camera's aspect].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..), conflicts_with = "target_error")]
    pub spp: u32,
    /// Adaptive sampling: after --min-spp samples everywhere, a pixel takes samples in
    /// proportion to its neighbours' noise: k x --min-spp where the means of their even and of
    /// their odd samples differ by k x E x the square root of their brightness (e.g. 0.05).
    #[arg(long, value_name = "E", value_parser = positive_fraction, allow_negative_numbers = true)]
    pub target_error: Option<f64>,
    /// With --target-error: samples every pixel takes first (the pilot).
    #[arg(long, default_value_t = 16, requires = "target_error", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub min_spp: u32,
    /// With --target-error: the most samples a pixel takes.
    #[arg(long, default_value_t = 1024, requires = "target_error", value_parser = clap::value_parser!(u32).range(1..))]
    pub max_spp: u32,
    /// Russian roulette: after 4 rays, continue a path with probability equal to its
    /// brightest throughput channel (unbiased; changes the noise, not the mean).
    #[arg(long)]
    pub roulette: bool,
    /// Maximum rays per path, camera ray included (the book's max_depth).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub depth: u32,
    /// Seed of the pixel samples' random streams.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Pixel samples' numbers: an Owen-scrambled Sobol sequence per pixel (stratified: the
    /// same error in 0.3-0.6x the time, results/error.md), or independent numbers
    /// [default: sobol; independent with --rng shared].
    #[arg(long, value_enum)]
    pub sampler: Option<Sampler>,
    /// Tile side in pixels, for the tiled modes (pool, steal).
    #[arg(long, default_value_t = DEFAULT_TILE, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub tile: u32,
    /// How rays find the closest sphere: auto (every sphere below 6, the binary tree below
    /// 64, else the 4-wide tree), or one method for comparisons; all find the same hits.
    #[arg(long, value_enum, default_value_t = AccelChoice::Auto)]
    pub accel: AccelChoice,
}

/// Who renders, and with which random numbers (shared by `render` and `view`).
#[derive(Debug, Args)]
pub struct WorkerArgs {
    /// Worker threads [default: the number of CPUs].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub threads: Option<u32>,
    /// Scheduler: serial, static (T blocks of rows), interleaved (row r to thread r mod T),
    /// pool-rows (a job per row, shared queue), pool (tiles, shared queue), steal (tiles,
    /// work stealing).
    #[arg(long, value_enum, default_value_t = Schedule::Stealing)]
    pub mode: Schedule,
    /// Random numbers: per-sample streams (reproducible) or one generator behind a lock
    /// shared by all threads, as the seed paper's rand() (an ablation; not reproducible).
    #[arg(long, value_enum, default_value_t = RngChoice::PerSample)]
    pub rng: RngChoice,
}

/// Options of `raypool render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene, image size and sampling.
    #[command(flatten)]
    pub image: ImageArgs,
    /// Threads, scheduler and random numbers.
    #[command(flatten)]
    pub workers: WorkerArgs,
    /// Render only shard K of N: the tiles (of --tile) whose row-major index is K mod N,
    /// into a part file (--out NAME.rpart) for `raypool merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Output; the extension picks the format: .png, .ppm (P6), .pfm or .exr (linear float), or
    /// .rpart (a part file of --shard, or of the whole image without it).
    #[arg(long, default_value = "render.png")]
    pub out: PathBuf,
}

/// Options of `raypool view` (and of each render the page asks for).
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The scene, image size and sampling (--spp: the samples the passes accumulate up to).
    #[command(flatten)]
    pub image: ImageArgs,
    /// Threads, scheduler and random numbers.
    #[command(flatten)]
    pub workers: WorkerArgs,
    /// Port to serve on; 0 takes a free one.
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// Address to serve on instead of 127.0.0.1 (e.g. 0.0.0.0 exposes the viewer to the network).
    #[arg(long, value_name = "ADDR")]
    pub bind: Option<std::net::IpAddr>,
}

/// Options of `raypool simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The scene, image size and sampling.
    #[command(flatten)]
    pub image: ImageArgs,
    /// Thread counts to predict, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16,32,64,128,256", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub threads: Vec<u32>,
    /// Also render every mode at each of those thread counts this machine has CPUs for
    /// (2 and up), and print the measured speedup beside the predicted one.
    #[arg(long)]
    pub measure: bool,
    /// One-thread passes timing the rows and tiles (each unit's median counts), and with
    /// --measure, rounds of real runs (each round runs serial and every mode once).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Write scaling.md, scaling.csv and scaling.png into this directory.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
}

/// The `--accel` choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AccelChoice {
    /// The scene's default: every sphere below 6 spheres, the binary tree below 64, else
    /// the 4-wide tree.
    Auto,
    /// Every sphere tested.
    Flat,
    /// The binary SAH tree.
    Binary,
    /// The 4-wide tree, leaves tested one sphere at a time.
    Wide,
    /// The 4-wide tree, leaves tested four spheres at once in SIMD lanes.
    WidePackets,
    /// The 4-wide tree, huge spheres (a ground) kept out of it and tested first.
    WideHugeApart,
}

impl AccelChoice {
    /// The scene with this method applied.
    pub fn apply(self, scene: Scene) -> Scene {
        match self {
            AccelChoice::Auto => scene,
            AccelChoice::Flat => scene.with_accel(Accel::Flat),
            AccelChoice::Binary => scene.with_accel(Accel::Binary),
            AccelChoice::Wide => scene.with_accel(Accel::Wide),
            AccelChoice::WidePackets => scene.with_accel(Accel::WidePackets),
            AccelChoice::WideHugeApart => scene.with_accel(Accel::WideHugeApart),
        }
    }
}

/// Samples per pixel of the paper table that `raypool bench --quick` writes.
const QUICK_PAPER_SPP: u32 = 2;

/// clap's error as one line: the problem (its first paragraph), without the usage block.
pub fn one_line(e: &clap::Error) -> String {
    // clap names the problem in its first paragraph (one line, or a line ending in ':'
    // followed by the missing arguments); a usage block follows. Keep the paragraph.
    let text = e.render().to_string();
    let problem: Vec<&str> = text.lines().map(str::trim).take_while(|l| !l.is_empty()).collect();
    let problem = problem.join(" ");
    let problem = problem.trim_start_matches("error: ");
    if problem.is_empty() { "invalid command line".to_string() } else { problem.to_string() }
}

/// Runs one parsed command line (all but `view`, which the viewer layer runs: see `main.rs`).
pub fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::View(_) => Err(Error::new("raypool view is run by raypool::view::run")),
        Command::Render(args) => render_command(&args),
        Command::Merge { parts, out } => merge_command(&parts, &out),
        Command::Simulate(args) => simulate_command(&args),
        Command::Scenes => {
            for b in BUILTINS {
                println!("{:<14} {}", b.name, b.about);
            }
            Ok(())
        }
        Command::Bench { paper: true, spp, out_dir, .. } => {
            let threads = cpus();
            let cells = crate::measure::speedup::paper::paper_table(spp, threads, |line| eprintln!("{line}"))?;
            let command = format!("raypool bench --paper --spp {spp}");
            crate::measure::speedup::paper::write_paper_table(&out_dir, &cells, spp, threads, &command)?;
            eprintln!("wrote {}/paper-table.md", out_dir.display());
            Ok(())
        }
        Command::Bench { quick, out_dir, threads, .. } => {
            let preset = Preset { threads, ..if quick { Preset::quick() } else { Preset::full() } };
            let outcome = crate::measure::speedup::run(&preset, &[], |line| eprintln!("{line}"))?;
            let command = if quick { "raypool bench --quick" } else { "raypool bench" };
            write_reports(&out_dir, &preset, &outcome, command)?;
            eprintln!("wrote {}/speedup.md, speedup.csv, speedup.png, timeline-*.png", out_dir.display());
            if quick {
                // A rough paper table too: 2 spp, scaled to the paper's 500 (labelled so).
                let threads = cpus();
                let cells = crate::measure::speedup::paper::paper_table(QUICK_PAPER_SPP, threads, |line| {
                    eprintln!("{line}")
                })?;
                crate::measure::speedup::paper::write_paper_table(
                    &out_dir,
                    &cells,
                    QUICK_PAPER_SPP,
                    threads,
                    command,
                )?;
                eprintln!("wrote {}/paper-table.md (at {QUICK_PAPER_SPP} spp)", out_dir.display());
            }
            Ok(())
        }
        Command::Grade { mode, discipline, options } => {
            use crate::measure::grade::{Entry, Submission, grade_and_report};
            let submission = match (&mode, discipline.as_deref()) {
                (Some(mode), _) => {
                    Submission { name: format!("mode {}", mode.name()), entry: Entry::Scheduler(mode) }
                }
                (None, Some(name)) => {
                    let discipline = match name {
                        "locked" => pool::Discipline::Locked,
                        "stealing" => pool::Discipline::Stealing,
                        _ => pool::Discipline::Shared,
                    };
                    Submission { name: format!("discipline {name}"), entry: Entry::Queue(discipline.queue()) }
                }
                (None, None) => {
                    return Err(Error::new("raypool grade: name a submission: --mode or --discipline"));
                }
            };
            let command = std::env::args().collect::<Vec<_>>().join(" ");
            grade_and_report(&[&submission], &options, &command)
        }
        Command::Compare { image, reference, diff } => {
            let m = crate::measure::compare::compare_files(&image, &reference, diff.as_deref())?;
            println!(
                "rmse {:.6}  rel_mse {:.6}  mae {:.6}  max {:.6}  psnr {:.2} dB",
                m.rmse, m.rel_mse, m.mae, m.max_error, m.psnr
            );
            Ok(())
        }
        Command::Scene { name, scene_seed } => {
            print!("{}", builtin_scene(&name, scene_seed)?.to_toml());
            Ok(())
        }
    }
}

/// The scene chosen by `--scene` / `--scene-file`.
pub fn load_scene(args: &ImageArgs) -> Result<SceneFile, Error> {
    match &args.scene_file {
        Some(path) => SceneFile::read(path),
        None => builtin_scene(&args.scene, args.scene_seed),
    }
}

fn render_command(args: &RenderArgs) -> Result<(), Error> {
    let image = &args.image;
    let scene = load_scene(image)?;
    let settings = render_settings(image, &scene, args.workers.rng)?;
    let threads = args.workers.threads.map_or_else(cpus, |t| t as usize);
    let shard = check_shard(args, Format::from_path(&args.out)?)?;
    let pixels: usize =
        shard.tiles(&Tile::grid(settings.width, settings.height, image.tile)).iter().map(Tile::area).sum();
    let (width, height) = (settings.width, settings.height);
    let adaptive = settings.adaptive.is_some();
    let needed = memory::estimate(u64::from(width) * u64::from(height), pixels as u64, adaptive);
    memory::check(needed, threads, &format!("a {width} × {height} render"), adaptive)?;
    let output = PendingOutput::create(&args.out)?; // fail fast, before the long part
    // From here on, Ctrl-C stops the render and removes the temporary file.
    let cancel = Cancel::default();
    let interrupt = Interrupt::watch(cancel.clone(), output.temp_path().to_owned())?;
    let rng = RngSource::new(&settings, args.workers.rng);
    let bar = progress_bar(pixels as u64);
    let progress = {
        let bar = bar.clone();
        Arc::new(move |n| bar.inc(n))
    };
    let job = RenderJob::new(image.accel.apply(scene.to_scene()), settings);
    let frame =
        Arc::new(Frame::new(job, rng, threads, image.tile, progress).sharded(shard).with_cancel(cancel));

    let start = Instant::now();
    let rendered = render(&frame, &args.workers.mode);
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    interrupt.check()?; // dropping `output` deletes its temporary file
    if output.format() == Format::Part {
        let digest = scene_digest(&scene.to_toml());
        let mut part = Part::new(
            PartSettings::new(digest, &settings, image.tile, shard.count),
            shard,
            &frame.tiles(),
            &rendered.image,
        );
        (part.header.rays, part.header.samples) = (rendered.rays, rendered.samples);
        (part.header.seconds, part.header.host) = (seconds, crate::measure::machine::host());
        drop(rendered.image); // the part holds the shard's pixels now
        output.write_with(|out| part.write_to(out).map_err(|e| e.to_string()))?;
    } else {
        output.write(&rendered.image)?;
    }

    let threads_used = if args.workers.mode == Schedule::Serial { 1 } else { threads };
    let mode = args.workers.mode.name();
    let shard_note = if shard == Shard::WHOLE { String::new() } else { format!(", shard {shard}") };
    eprintln!(
        "{}x{}{shard_note}, {} spp, depth {}, mode {mode}, threads {threads_used}: {seconds:.3} s, {} rays, {:.2} Mrays/s -> {}",
        settings.width,
        settings.height,
        spp_summary(&settings, rendered.samples, pixels),
        settings.max_depth,
        rendered.rays,
        rendered.rays as f64 / seconds / 1e6,
        args.out.display()
    );
    Ok(())
}

/// `raypool simulate`: one-thread costs, predictions, and optionally measured runs.
fn simulate_command(args: &SimulateArgs) -> Result<(), Error> {
    let image = &args.image;
    let scene = load_scene(image)?;
    let settings = render_settings(image, &scene, RngChoice::PerSample)?;
    let job = RenderJob::new(image.accel.apply(scene.to_scene()), settings);
    let name = image.scene_file.as_ref().map_or(image.scene.clone(), |p| p.display().to_string());
    let subject = format!(
        "{name}, {} × {}, {} spp, depth {}, {}-pixel tiles",
        settings.width, settings.height, settings.spp, settings.max_depth, image.tile
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
    print!("{}", study.table());
    if let Some(dir) = &args.report {
        write_report(dir, &study)?;
        eprintln!("wrote {0}/scaling.md, {0}/scaling.csv, {0}/scaling.png", dir.display());
    }
    Ok(())
}

/// The shard to render: `--shard`, which needs a part file, or the whole image.
fn check_shard(args: &RenderArgs, format: Format) -> Result<Shard, Error> {
    if format == Format::Part && args.workers.rng == RngChoice::Shared {
        return Err(Error::new(
            "--rng shared draws numbers in whatever order threads run, so parts would not merge into one image: use --rng per-sample",
        ));
    }
    match args.shard {
        Some(shard) if format != Format::Part => Err(Error::new(format!(
            "--shard {shard} writes a part file: name it NAME.rpart (not '{}')",
            args.out.display()
        ))),
        Some(shard) => Ok(shard),
        None => Ok(Shard::WHOLE),
    }
}

/// `raypool merge`: reads every part, checks they are one image, writes it.
fn merge_command(paths: &[PathBuf], out: &std::path::Path) -> Result<(), Error> {
    let output = PendingOutput::create(out)?;
    if output.format() == Format::Part {
        return Err(Error::new(format!(
            "merge writes an image: name it .png, .ppm, .pfm or .exr (not '{}')",
            out.display()
        )));
    }
    let mut parts = Vec::with_capacity(paths.len());
    for path in paths {
        let name = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| Error::new(format!("{name}: cannot read: {}", crate::error::io_reason(&e))))?;
        let part = Part::from_bytes(&bytes).map_err(|e| Error::new(format!("{name}: {e}")))?;
        parts.push((name, part));
    }
    let image = merge(&parts)?;
    output.write(&image)?;
    let headers: Vec<_> = parts.iter().map(|(_, p)| &p.header).collect();
    let slowest = headers.iter().map(|h| h.seconds).fold(0.0, f64::max);
    let mut hosts: Vec<&str> = headers.iter().map(|h| h.host.as_str()).collect();
    hosts.sort_unstable();
    hosts.dedup();
    eprintln!(
        "merged {} parts from {} host(s): {}x{}, {} rays; slowest part {slowest:.3} s, all parts {:.3} s -> {}",
        parts.len(),
        hosts.len(),
        image.width,
        image.height,
        headers.iter().map(|h| h.rays).sum::<u64>(),
        headers.iter().map(|h| h.seconds).sum::<f64>(),
        out.display()
    );
    Ok(())
}

/// "32" for uniform sampling; "mean 41.3 of 16..1024" for adaptive sampling.
fn spp_summary(settings: &RenderSettings, samples: u64, pixels: usize) -> String {
    match settings.adaptive {
        None => settings.spp.to_string(),
        Some(a) => {
            let mean = samples as f64 / pixels.max(1) as f64;
            format!("mean {mean:.1} of {}..{}", a.min_spp, settings.spp)
        }
    }
}

/// The sampler the flags ask for: `--sampler`, else the default ([`Sampler`]'s), except under
/// `--rng shared` (one independent generator, which no sampler can steer).
fn sampler(args: &ImageArgs, rng: RngChoice) -> Result<Sampler, Error> {
    match (args.sampler, rng) {
        (Some(Sampler::Sobol), RngChoice::Shared) => Err(Error::new(
            "--rng shared is one independent generator for all threads: it cannot follow --sampler sobol",
        )),
        (_, RngChoice::Shared) => Ok(Sampler::Independent),
        (Some(sampler), RngChoice::PerSample) => Ok(sampler),
        (None, RngChoice::PerSample) => Ok(Sampler::default()),
    }
}

/// The render settings the flags ask for, for `scene` (whose camera gives the height when
/// `--height` does not), with random numbers from `rng`.
pub fn render_settings(args: &ImageArgs, scene: &SceneFile, rng: RngChoice) -> Result<RenderSettings, Error> {
    let height = match args.height {
        Some(h) => h,
        None => default_height(args.width, scene.camera.aspect)?,
    };
    let adaptive = match args.target_error {
        Some(target_error) if args.min_spp > args.max_spp => {
            return Err(Error::new(format!(
                "--min-spp {} is above --max-spp {} (with --target-error {target_error})",
                args.min_spp, args.max_spp
            )));
        }
        Some(target_error) => Some(Adaptive { target_error: target_error as Real, min_spp: args.min_spp }),
        None => None,
    };
    Ok(RenderSettings {
        width: args.width,
        height,
        spp: if adaptive.is_some() { args.max_spp } else { args.spp },
        max_depth: args.depth,
        seed: args.seed,
        roulette: args.roulette,
        adaptive,
        sampler: sampler(args, rng)?,
        ..RenderSettings::default()
    })
}

/// Parses a target error: a number in (0, 1].
fn positive_fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(e) if e > 0.0 && e <= 1.0 => Ok(e),
        Ok(_) => Err("must be above 0 and at most 1".to_string()),
        Err(_) => Err("not a number".to_string()),
    }
}

/// A bar on stderr when it is a terminal; hidden (and free) otherwise.
fn progress_bar(pixels: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(pixels), ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(pixels);
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {percent:>3}% eta {eta}") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}
