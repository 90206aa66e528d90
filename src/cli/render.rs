//! `raypool render`: one image, or one shard of it as a part file, rendered by the chosen
//! scheduler with a progress bar on a terminal, refused before it starts if it would not fit
//! in memory, stopped cleanly by Ctrl-C, denoised if asked; prints one line of figures when done.

use std::io::IsTerminal;
use std::sync::Arc;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::cli::args::RenderArgs;
use crate::cli::interrupt::Interrupt;
use crate::cli::memory;
use crate::cli::settings::{load_scene, render_job, render_settings, worker_threads};
use crate::cli::transport::{Renderer, Sampling};
use crate::denoise::denoise;
use crate::error::Error;
use crate::files::output::{Format, PendingOutput};
use crate::files::part::{Part, PartSettings, scene_digest};
use crate::measure::machine::host;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, render};
use crate::schedule::progressive::Cancel;
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::math::real::Vec3;
use crate::tracer::render::RenderSettings;
use crate::tracer::tile::{Shard, Tile};

/// Runs `raypool render`.
pub fn run(args: &RenderArgs) -> Result<(), Error> {
    let image = &args.image;
    let scene = load_scene(image)?;
    let settings = render_settings(image, &scene, args.workers.rng, Renderer::CommandLine)?;
    let threads = worker_threads(&args.workers);
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
    let job = render_job(image, &scene, settings)?;
    let frame = Arc::new(
        Frame::new(job.clone(), rng, threads, image.tile, progress).sharded(shard).with_cancel(cancel),
    );

    let start = Instant::now();
    let mut rendered = render(&frame, &args.workers.mode);
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    interrupt.check()?; // dropping `output` deletes its temporary file
    let denoised = args.denoise.then(|| {
        let start = Instant::now();
        rendered.image = denoise(&job, &rendered.image, threads);
        format!(", denoised in {:.3} s", start.elapsed().as_secs_f64())
    });
    // A whole image with no light in it, though the scene has lights: most likely a light
    // turned away from what it should light (lights emit from their front face only).
    let unlit = shard == Shard::WHOLE
        && !job.scene.lights().is_empty()
        && rendered.image.pixels.iter().all(|&p| p == Vec3::ZERO);
    if output.format() == Format::Part {
        let digest = scene_digest(&scene.to_toml());
        let mut part = Part::new(
            PartSettings::new(digest, &settings, image.tile, shard.count),
            shard,
            &frame.tiles(),
            &rendered.image,
            std::mem::take(&mut rendered.splats),
        );
        (part.header.rays, part.header.samples) = (rendered.rays, rendered.samples);
        (part.header.seconds, part.header.host) = (seconds, host());
        drop(rendered.image); // the part holds the shard's pixels now
        output.write_with(|out| part.write_to(out).map_err(|e| e.to_string()))?;
    } else {
        output.write(&rendered.image)?;
    }

    let threads_used = if args.workers.mode == Schedule::Serial { 1 } else { threads };
    let mode = args.workers.mode.name();
    let shard_note = if shard == Shard::WHOLE { String::new() } else { format!(", shard {shard}") };
    eprintln!(
        "{}x{}{shard_note}, {} spp, depth {}, mode {mode}, threads {threads_used}: {seconds:.3} s, {} rays, {:.2} Mrays/s{} -> {}",
        settings.width,
        settings.height,
        spp_summary(&settings, rendered.samples, pixels),
        settings.max_depth,
        rendered.rays,
        rendered.rays as f64 / seconds / 1e6,
        denoised.unwrap_or_default(),
        args.out.display()
    );
    if unlit {
        eprintln!(
            "raypool: warning: every pixel is black, yet the scene has lights: a light gives off light from its front face only (a quad's is where u × v points, a disc's where its normal points); turn it towards the scene"
        );
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
    if format == Format::Part && args.denoise {
        return Err(Error::new(
            "--denoise needs the whole image (a pixel is filtered with its neighbours): write .png, .ppm, .pfm or .exr, and denoise no part file",
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

/// "32" for uniform sampling; "mean 41.3 of 16..1024" for adaptive sampling.
fn spp_summary(settings: &RenderSettings, samples: u64, pixels: usize) -> String {
    match Sampling::of(settings) {
        Sampling::Fixed { spp } => spp.to_string(),
        Sampling::Adaptive { min_spp, max_spp, .. } => {
            let mean = samples as f64 / pixels.max(1) as f64;
            format!("mean {mean:.1} of {min_spp}..{max_spp}")
        }
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
