//! The command line's flags: clap's definition of every subcommand and its options (except the
//! grader's, `crate::measure::grade::Options`, flattened in here because the course kit's own
//! grade binary parses them too), the choices they offer, and clap's errors as one line. Only the definition lives here; what a
//! set of flags resolves to is in [`crate::cli::settings`]. The viewer parses each request with
//! these same definitions (`src/view/request.rs`), so a request gets the command line's limits
//! and messages.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::measure::grade::{Options, at_least_one};
use crate::scenes::builtin::{BUILTINS, DEFAULT_SCENE_SEED};
use crate::schedule::frame::DEFAULT_TILE;
use crate::schedule::modes::Schedule;
use crate::schedule::random::RngChoice;
use crate::tracer::lights::LightSampling;
use crate::tracer::render::{EDGE_SPOTS, MAX_SIDE};
use crate::tracer::sampling::sampler::Sampler;
use crate::tracer::scene::{Accel, Scene};
use crate::tracer::tile::Shard;

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
    Merge(MergeArgs),
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
    Bench(BenchArgs),
    /// Grade a scheduler or a queue discipline as a course's grader does: the conformance
    /// check, then workloads that each expose one weakness, timed against the reference in
    /// the same run; prints the report and writes it to --out. (A student's own code is
    /// graded by the starter's grade binary: examples/course.)
    Grade(GradeArgs),
    /// Compare two PFM images: RMSE, relative MSE, mean absolute error, largest error, PSNR.
    Compare(CompareArgs),
    /// Print a scene as TOML (e.g. `raypool scene final > final.toml`).
    Scene(SceneArgs),
}

/// What to render and how: the scene, the image size and the sampling (shared by `render`,
/// `simulate` and `view`).
#[derive(Clone, Debug, Args)]
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
    /// same error in less time, results/error.md), or independent numbers
    /// [default: sobol; independent with --rng shared].
    #[arg(long, value_enum)]
    pub sampler: Option<Sampler>,
    /// How paths find a scene's lights: the material's bounce only (bsdf), half the bounces
    /// aimed at a light (mixture), or a shadow ray to a light at every diffuse hit weighed
    /// against the bounce (mis: multiple importance sampling). All give the same mean image.
    #[arg(long, value_enum, default_value_t = LightSampling::Mis)]
    pub light_sampling: LightSampling,
    /// Path guiding: passes of 1, 2, 4, … samples per pixel (up to --guide-pilot) each learn
    /// where light arrives at every place of the scene (an SD-tree), and the next pass draws
    /// half its diffuse bounces from what was learnt, weighed against the material's bounce
    /// (one-sample MIS); every pass's samples count. Unbiased; for scenes lit by light that
    /// bounces. A scene without lights renders as without it.
    #[arg(long, value_enum, default_value_t = Switch::Off)]
    pub guiding: Switch,
    /// With --guiding on: the learning passes' samples per pixel together, rounded down to a
    /// power of two [default: a quarter of --spp].
    #[arg(long, value_name = "SPP", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub guide_pilot: Option<u32>,
    /// Where a pixel may see a light: extra points per sample for the light it sees directly
    /// (the light's edges then converge with the rest of the image); 0 for none.
    #[arg(long, default_value_t = EDGE_SPOTS, value_parser = clap::value_parser!(u32).range(0..=1024))]
    pub edge_spots: u32,
    /// Tile side in pixels, for the tiled modes (pool, steal).
    #[arg(long, default_value_t = DEFAULT_TILE, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub tile: u32,
    /// How rays find the closest hit, for comparisons; all find the same hits. In a scene of
    /// spheres only (the first book's): auto (every sphere below 6, the binary tree below 64,
    /// else the 4-wide tree) or one method. In the second book's scenes (quads, meshes,
    /// media, lights or textures): flat searches the world's objects in runs of eight without
    /// a tree, every other value as auto does.
    #[arg(long, value_enum, default_value_t = AccelChoice::Auto)]
    pub accel: AccelChoice,
}

/// A setting that is off or on (`--guiding on`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Switch {
    /// Off.
    #[default]
    Off,
    /// On.
    On,
}

/// Who renders, and with which random numbers (shared by `render` and `view`).
#[derive(Clone, Debug, Args)]
pub struct WorkerArgs {
    /// Worker threads [default: the number of CPUs].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub threads: Option<u32>,
    /// Scheduler: how the frame's rows or tiles are shared among the threads (the values
    /// are `Schedule`'s own, so a new mode lists itself).
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
    /// Denoise the image before writing it: the edge-avoiding à-trous filter guided by each
    /// pixel's first hit (what the viewer shows while the camera moves). Biased: never for
    /// measurements. Not with a part file (a shard lacks its neighbours' pixels).
    #[arg(long)]
    pub denoise: bool,
    /// Output; the extension picks the format: .png, .ppm (P6), .pfm or .exr (linear float), or
    /// .rpart (a part file of --shard, or of the whole image without it).
    #[arg(long, default_value = "render.png")]
    pub out: PathBuf,
}

/// Options of `raypool view` (and of each render the page asks for).
#[derive(Clone, Debug, Args)]
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

/// Options of `raypool merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Every part, shards 0 to N-1, in any order.
    #[arg(required = true, value_name = "PART")]
    pub parts: Vec<PathBuf>,
    /// The image (.png, .ppm, .pfm or .exr), written only if the parts are complete and agree.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
}

/// Options of `raypool bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Thread counts to measure, e.g. `--threads 1,2,4,8,16` [default: 1, 2, … 2 × CPUs].
    #[arg(long, value_delimiter = ',', value_parser = at_least_one, conflicts_with = "paper")]
    pub threads: Vec<usize>,
    /// Built-in scenes to measure, e.g. `--scenes final,cornell,next-week` [default: final and
    /// the paper's three]; the paper's at its depth 10, the others at the book's 50.
    #[arg(long, value_delimiter = ',', value_parser = builtin_name, conflicts_with = "paper")]
    pub scenes: Vec<&'static str>,
    /// Small images and 3 runs, and the paper table at 2 spp (under 2 minutes on 2 cores),
    /// instead of the full preset.
    #[arg(long, conflicts_with = "paper")]
    pub quick: bool,
    /// Instead: the seed paper's table at 1200 × 800 (paper-table.md). Long: at 500 spp
    /// it is hours of CPU; pass a smaller --spp to estimate.
    #[arg(long)]
    pub paper: bool,
    /// Samples per pixel for --paper.
    #[arg(long, default_value_t = 500, requires = "paper", value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: u32,
    /// Where to write speedup.md, speedup.csv and the plots.
    #[arg(long, default_value = "results", value_name = "DIR")]
    pub out_dir: PathBuf,
}

/// A built-in scene's name, as the scene list spells it.
fn builtin_name(name: &str) -> Result<&'static str, String> {
    let known = || BUILTINS.iter().map(|b| b.name).collect::<Vec<_>>().join(", ");
    BUILTINS
        .iter()
        .find(|b| b.name == name)
        .map(|b| b.name)
        .ok_or_else(|| format!("not a built-in scene (they are: {})", known()))
}

/// A queue discipline by name ([`pool::Discipline::name`]): the names come from the pool's
/// own list, so a new discipline needs no line here.
fn discipline(name: &str) -> Result<pool::Discipline, String> {
    pool::Discipline::named(name).ok_or_else(|| {
        let names: Vec<&str> = pool::Discipline::ALL.iter().map(|d| d.name()).collect();
        format!("not a queue discipline (they are: {})", names.join(", "))
    })
}

/// Options of `raypool grade`.
#[derive(Debug, Args)]
pub struct GradeArgs {
    /// The built-in mode to grade.
    #[arg(long, required_unless_present = "discipline", conflicts_with = "discipline")]
    pub mode: Option<Schedule>,
    /// The built-in queue discipline to grade (a name it does not know is answered with the
    /// list).
    #[arg(long, value_parser = discipline)]
    pub discipline: Option<pool::Discipline>,
    /// Thread counts, rounds, report file.
    #[command(flatten)]
    pub options: Options,
}

/// Options of `raypool compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The image to judge.
    pub image: PathBuf,
    /// The reference.
    pub reference: PathBuf,
    /// Write a false-colour map of each pixel's error (PNG).
    #[arg(long, value_name = "PNG")]
    pub diff: Option<PathBuf>,
}

/// Options of `raypool scene`.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Built-in scene name (see `raypool scenes`).
    pub name: String,
    /// Seed of generated scenes (`final`).
    #[arg(long, default_value_t = DEFAULT_SCENE_SEED)]
    pub scene_seed: u64,
}

/// The `--accel` choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AccelChoice {
    /// The scene's default: every sphere below 6 spheres, the binary tree below 64, else
    /// the 4-wide tree.
    Auto,
    /// Every sphere tested (in the second book's scenes: every object, in runs, no tree).
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

/// Parses a target error: a number in (0, 1].
fn positive_fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(e) if e > 0.0 && e <= 1.0 => Ok(e),
        Ok(_) => Err("must be above 0 and at most 1".to_string()),
        Err(_) => Err("not a number".to_string()),
    }
}
