//! What a set of flags resolves to: the scene (`--scene` or `--scene-file`), the render
//! settings (the image's size, the sampling and the sampler rule), the job, and the worker
//! threads. The commands and the viewer's requests resolve their flags here, so each rule is
//! written once; the viewer imports this file and [`crate::cli::args`], never the commands.

use crate::cli::args::{ImageArgs, WorkerArgs};
use crate::cli::transport::{Integrator, Renderer, Transport};
use crate::error::Error;
use crate::measure::machine::cpus;
use crate::scenes::builtin::builtin_scene;
use crate::scenes::format::SceneFile;
use crate::schedule::random::RngChoice;
use crate::tracer::accel::isa::Isa;
use crate::tracer::render::{RenderJob, RenderSettings, default_height};
use crate::tracer::sampling::sampler::Sampler;

/// The scene chosen by `--scene` / `--scene-file`.
pub fn load_scene(args: &ImageArgs) -> Result<SceneFile, Error> {
    match &args.scene_file {
        Some(path) => SceneFile::read(path),
        None => builtin_scene(&args.scene, args.scene_seed),
    }
}

/// The scene's name in messages and reports: the `--scene-file` path, else the `--scene` name.
pub fn scene_name(args: &ImageArgs) -> String {
    args.scene_file.as_ref().map_or(args.scene.clone(), |path| path.display().to_string())
}

/// The render settings the flags ask for, for `scene` (whose camera gives the height when
/// `--height` does not), rendered by `renderer` with random numbers from `rng`. The light
/// transport and the sampling are admitted by [`Transport::new`].
pub fn render_settings(
    args: &ImageArgs,
    scene: &SceneFile,
    rng: RngChoice,
    renderer: Renderer,
) -> Result<RenderSettings, Error> {
    let height = match args.height {
        Some(h) => h,
        None => default_height(args.width, scene.camera.aspect)?,
    };
    let mut settings = RenderSettings {
        width: args.width,
        height,
        max_depth: args.depth,
        seed: args.seed,
        sampler: sampler(args, rng)?,
        edge_spots: args.edge_spots,
        ..RenderSettings::default()
    };
    Transport::new(args, renderer)?.apply(&mut settings);
    Ok(settings)
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

/// The job to render: `scene` with the `--accel` method and the vector instructions of
/// [`isa`], under `settings`, if their light transport admits the scene
/// ([`Integrator::admits`]).
pub fn render_job(args: &ImageArgs, scene: &SceneFile, settings: RenderSettings) -> Result<RenderJob, Error> {
    let scene = scene.to_scene().with_isa(isa()?);
    Integrator::of(&settings).admits(&scene)?;
    Ok(RenderJob::new(args.accel.apply(scene), settings))
}

/// The vector instructions searches use: `RAYPOOL_ISA`'s level (`sse2`, `avx2`, `avx512`),
/// for tests and benchmarks, else [`Isa::best`] (the widest the CPU has). Every level renders the same
/// bytes.
pub fn isa() -> Result<Isa, Error> {
    match std::env::var("RAYPOOL_ISA") {
        Ok(name) => Isa::named(&name).map_err(|e| Error::new(format!("RAYPOOL_ISA: {e}"))),
        Err(_) => Ok(Isa::best()),
    }
}

/// The worker threads `--threads` asks for, else one per CPU.
pub fn worker_threads(args: &WorkerArgs) -> usize {
    args.threads.map_or_else(cpus, |t| t as usize)
}
