//! A render request, checked exactly as the command line checks it.
//!
//! The page asks for a render with `POST /render?mode=steal&threads=2&width=400&…`. Each query
//! parameter `name=value` becomes the flag `--name value` and the whole list is parsed by the
//! same clap definition as `raypool view`'s own flags, *on top of the flags in effect*, so a
//! request changes only what it names (`threads=1` keeps the scene, camera, mode and spp)
//! and gets the command line's limits (sizes ≤ 16384, threads ≤ 4096, …) and its one-line
//! messages. Four parameters are the page's own: `lookfrom=x,y,z` (the orbiting camera),
//! `preview=1` (the camera is moving: show a small frame first, see `session.rs`),
//! `denoise=1|0` (denoise those frames; on until a request turns it off) and a pasted scene
//! in the body. A request that names neither `scene` nor a pasted scene keeps
//! the current scene, camera included, and its built world (a camera move rebuilds no tree);
//! `height=auto` returns to the scene's aspect, and `guiding=off` drops a `--guide-pilot` in
//! effect.
//! Parameters that would reach outside the page are refused: `scene-file` (a path on the
//! server), `port`, `bind`, and adaptive sampling, which progressive passes do not do.

use std::sync::Arc;

use clap::{CommandFactory as _, FromArgMatches as _};

use crate::cli::args::{Switch, ViewArgs, one_line};
use crate::cli::settings::{load_scene, render_job, render_settings, scene_name, worker_threads};
use crate::cli::transport::Renderer;
use crate::error::Error;
use crate::measure::machine::cpus;
use crate::scenes::format::SceneFile;
use crate::schedule::modes::Schedule;
use crate::schedule::random::RngChoice;
use crate::tracer::render::RenderJob;

/// Largest pasted scene, bytes.
pub const MAX_PASTED_SCENE: usize = 1 << 20;

/// The largest image the viewer renders: 4 Mpixels (2048 × 2048). One pass keeps running sums
/// of 24 bytes a pixel and the page receives every pixel; `raypool render` has no such limit.
pub const MAX_PIXELS: u64 = 1 << 22;

/// The widest tile the viewer renders: a tile job of one pass then holds at most 4,096
/// samples (see `session.rs`), so a new request cancels the running render within one job.
pub const MAX_TILE: u32 = 64;

/// The most worker threads a viewer render may use: four per core this machine offers (past
/// one per core a render only waits; the margin shows it). Requests for more get a 400.
pub fn max_threads() -> usize {
    4 * cpus()
}

/// What `raypool view`'s flags parse into, for parsing a request the same way.
#[derive(Debug, clap::Parser)]
#[command(name = "view")]
struct ViewRequest {
    #[command(flatten)]
    args: ViewArgs,
}

/// Everything one render needs, checked: what a request or the command line asked for.
#[derive(Clone, Debug)]
pub struct Config {
    /// The scene's name (a built-in's, "pasted", or the file's path).
    pub name: String,
    /// The scene as data, camera included (served as `/scene.toml`).
    pub scene: SceneFile,
    /// Image size and sampling; `spp` is what the passes accumulate up to.
    pub job: Arc<RenderJob>,
    /// Worker threads.
    pub threads: usize,
    /// Scheduler.
    pub mode: Schedule,
    /// Tile side, pixels.
    pub tile: u32,
    /// Per-sample streams, or one generator behind a lock for all threads.
    pub rng: RngChoice,
    /// The flags in effect (the command line's, as later requests changed them): a request
    /// changes only what it names.
    pub args: ViewArgs,
    /// The camera is moving: show a navigation frame first (see [`crate::view::preview`]).
    pub preview: bool,
    /// Denoise the navigation frames ([`crate::denoise`]); on by default.
    pub denoise: bool,
}

/// Flags a request may not carry, with the reason.
const REFUSED: &[(&str, &str)] = &[
    ("scene-file", "the page cannot read files on the server: paste the scene instead"),
    ("port", "the port is chosen when the server starts"),
    ("bind", "the address is chosen when the server starts"),
    ("target-error", "the viewer renders progressive passes, not adaptive sampling"),
    ("min-spp", "the viewer renders progressive passes, not adaptive sampling"),
    ("max-spp", "the viewer renders progressive passes, not adaptive sampling"),
    ("help", "not a render setting"),
    ("version", "not a render setting"),
];

/// Parses a request's query string and body into a render [`Config`]: `current`'s, changed
/// as far as the request says.
pub fn parse(query: &str, body: &str, current: &Config) -> Result<Config, Error> {
    let mut argv = vec!["view".to_string()];
    let (mut lookfrom, mut roulette, mut names_scene, mut auto_height) = (None, None, false, false);
    let mut names_pilot = false;
    let (mut preview, mut denoise) = (false, current.denoise);
    for (name, value) in form_urlencoded::parse(query.as_bytes()) {
        if let Some((_, why)) = REFUSED.iter().find(|(refused, _)| *refused == name) {
            return Err(Error::new(format!("'{name}' cannot be set by a request: {why}")));
        }
        match name.as_ref() {
            "lookfrom" => lookfrom = Some(point(&value)?),
            "preview" => preview = on_or_off(name.as_ref(), &value)?,
            "denoise" => denoise = on_or_off(name.as_ref(), &value)?,
            // The height in effect stays unless named: `auto` names the scene's aspect again.
            "height" if value == "auto" => auto_height = true,
            // A flag's absence cannot switch it off on top of the flags in effect: say it.
            "roulette" => roulette = Some(on_or_off(name.as_ref(), &value)?),
            _ => {
                names_scene |= name == "scene" || name == "scene-seed";
                names_pilot |= name == "guide-pilot";
                argv.extend([format!("--{name}"), value.into_owned()]);
            }
        }
    }
    // The flags' defaults are dropped, so that a flag the request does not name keeps the
    // value in effect instead of going back to its default.
    let command = ViewRequest::command().mut_args(|arg| arg.default_value(None::<&str>));
    let matches = command.try_get_matches_from(&argv).map_err(|e| Error::new(one_line(&e)))?;
    let mut request = ViewRequest { args: current.args.clone() };
    request.update_from_arg_matches(&matches).map_err(|e| Error::new(one_line(&e)))?;
    let mut args = request.args;
    if let Some(on) = roulette {
        args.image.roulette = on;
    }
    if auto_height {
        args.image.height = None;
    }
    // `guiding=off` drops the pilot in effect, which without guiding would be refused.
    if args.image.guiding == Switch::Off && !names_pilot {
        args.image.guide_pilot = None;
    }
    let scene = if !body.trim().is_empty() {
        Some(("pasted scene".to_string(), SceneFile::parse(body, "pasted scene")?))
    } else if names_scene {
        args.image.scene_file = None; // a built-in named now replaces a file named at the start
        None
    } else {
        Some((current.name.clone(), current.scene.clone()))
    };
    let config = config(&args, scene, lookfrom, Some(current))?;
    Ok(Config { preview, denoise, ..config })
}

/// A yes-or-no parameter's value.
fn on_or_off(name: &str, value: &str) -> Result<bool, Error> {
    match value {
        "true" | "1" | "on" => Ok(true),
        "false" | "0" | "off" => Ok(false),
        other => Err(Error::new(format!("{name} must be true or false, not '{other}'"))),
    }
}

/// The render `args` ask for, of `scene` (named) or else the scene the flags name, seen from
/// `lookfrom` if given; `current`'s world is shared when only the camera or the image
/// settings differ.
pub fn config(
    args: &ViewArgs,
    scene: Option<(String, SceneFile)>,
    lookfrom: Option<[f64; 3]>,
    current: Option<&Config>,
) -> Result<Config, Error> {
    let image = &args.image;
    let (name, mut scene) = match scene {
        Some(named) => named,
        None => (scene_name(image), load_scene(image)?),
    };
    if let Some(eye) = lookfrom {
        move_camera(&mut scene, eye)?;
    }
    let settings = render_settings(image, &scene, args.workers.rng, Renderer::Viewer)?;
    let threads = worker_threads(&args.workers);
    if threads > max_threads() {
        return Err(Error::new(format!(
            "--threads {threads} is more than the viewer's limit of {} (four per core here)",
            max_threads()
        )));
    }
    let pixels = u64::from(settings.width) * u64::from(settings.height);
    if pixels > MAX_PIXELS {
        return Err(Error::new(format!(
            "{} × {} is more than the viewer's {} Mpixels (2048 × 2048); `raypool render` has no such limit",
            settings.width,
            settings.height,
            MAX_PIXELS >> 20
        )));
    }
    if settings.width > 4096 {
        return Err(Error::new(format!("--width {} is wider than the viewer's 4096", settings.width)));
    }
    if image.tile > MAX_TILE {
        return Err(Error::new(format!("--tile {} is wider than the viewer's {MAX_TILE}", image.tile)));
    }
    let job = match current.filter(|c| same_world(c, args, &scene)) {
        Some(c) => c.job.with_camera(&scene.camera, settings),
        None => render_job(image, &scene, settings)?,
    };
    Ok(Config {
        name,
        job: job.into(),
        preview: false,
        denoise: current.is_none_or(|c| c.denoise),
        scene,
        threads,
        mode: args.workers.mode,
        tile: image.tile,
        rng: args.workers.rng,
        args: args.clone(),
    })
}

/// Whether `current`'s built world is the one `scene` and `args` would build: the same scene
/// but for its camera, and the same `--accel`.
fn same_world(current: &Config, args: &ViewArgs, scene: &SceneFile) -> bool {
    current.args.image.accel == args.image.accel
        && SceneFile { camera: scene.camera.clone(), ..current.scene.clone() } == *scene
}

/// Puts the eye at `eye`, keeping what it looks at and the focus at the same relative depth.
fn move_camera(scene: &mut SceneFile, eye: [f64; 3]) -> Result<(), Error> {
    let c = &mut scene.camera;
    let distance = |p: [f64; 3]| (0..3).map(|k| (p[k] - c.lookat[k]).powi(2)).sum::<f64>().sqrt();
    let (before, after) = (distance(c.lookfrom), distance(eye));
    if after == 0.0 {
        return Err(Error::new(format!(
            "lookfrom {eye:?} is the camera's look-at point: it would look nowhere"
        )));
    }
    if before > 0.0 && after.is_finite() {
        // An absent focus_dist follows the eye by itself (it is the distance to lookat).
        c.focus_dist = c.focus_dist.map(|focus| focus * after / before);
    }
    c.lookfrom = eye;
    scene.validate().map_err(|e| Error::new(format!("lookfrom: {e}")))
}

/// `x,y,z` as three finite numbers.
fn point(text: &str) -> Result<[f64; 3], Error> {
    let bad = || Error::new(format!("lookfrom must be three finite numbers x,y,z, not '{text}'"));
    let numbers: Vec<f64> =
        text.split(',').map(|v| v.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    match numbers[..] {
        [x, y, z] if numbers.iter().all(|v| v.is_finite()) => Ok([x, y, z]),
        _ => Err(bad()),
    }
}
