//! What a set of flags resolves to: the scene (`--scene` or `--scene-file`), the render
//! settings (the image's size, the sampling and the sampler rule), the job, and the worker
//! threads. The commands and the viewer's requests resolve their flags here, so each rule is
//! written once; the viewer imports this file and [`crate::cli::args`], never the commands.

use crate::cli::args::{ImageArgs, WorkerArgs};
use crate::error::Error;
use crate::measure::machine::cpus;
use crate::scenes::builtin::builtin_scene;
use crate::scenes::format::SceneFile;
use crate::schedule::random::RngChoice;
use crate::tracer::lights::LightSampling;
use crate::tracer::math::real::Real;
use crate::tracer::render::{Adaptive, RenderJob, RenderSettings, default_height};
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
    if args.light_sampling == LightSampling::Bdpt {
        let refused =
            if adaptive.is_some() { Some("--target-error") } else { args.roulette.then_some("--roulette") };
        if let Some(flag) = refused {
            return Err(Error::new(format!(
                "--light-sampling bdpt does not take {flag}: its light paths are weighed against a fixed number of samples per pixel, and it ends no path by roulette"
            )));
        }
    }
    Ok(RenderSettings {
        width: args.width,
        height,
        spp: if adaptive.is_some() { args.max_spp } else { args.spp },
        max_depth: args.depth,
        seed: args.seed,
        roulette: args.roulette,
        adaptive,
        sampler: sampler(args, rng)?,
        light_sampling: args.light_sampling,
        edge_spots: args.edge_spots,
        ..RenderSettings::default()
    })
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

/// The job to render: `scene` with the `--accel` method, under `settings`. Refused: a scene
/// with meshes shaded by their files' normals under `--light-sampling bdpt` (see
/// [`Scene::has_shading_normals`](crate::tracer::scene::Scene::has_shading_normals)).
pub fn render_job(args: &ImageArgs, scene: &SceneFile, settings: RenderSettings) -> Result<RenderJob, Error> {
    let scene = scene.to_scene();
    if settings.light_sampling == LightSampling::Bdpt && scene.has_shading_normals() {
        return Err(Error::new(
            "--light-sampling bdpt does not take meshes shaded by their files' normals (its light paths would see them unlike the camera's): use mis",
        ));
    }
    Ok(RenderJob::new(args.accel.apply(scene), settings))
}

/// The worker threads `--threads` asks for, else one per CPU.
pub fn worker_threads(args: &WorkerArgs) -> usize {
    args.threads.map_or_else(cpus, |t| t as usize)
}
