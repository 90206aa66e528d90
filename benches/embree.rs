//! `cargo bench --bench embree --features embree`: raypool's closest-hit search against Intel
//! Embree 3's, the library production CPU renderers use, tracing the same rays.
//!
//! One path tracer (raypool's render loop, materials, camera and random numbers) finds its
//! hits three ways: raypool's own (the four-wide tree, the default for `final`), Embree's
//! sphere primitive in Embree's tree, and Embree's tree calling raypool's sphere test
//! (`embree/library.rs`). One thread, the book's `final` scene, 16 × 16 tiles in order.
//! Each round renders all three, in an order that rotates every round so that a slow spell
//! of the machine hits each alike; the table gives each one's median time and rays per second
//! and the median over rounds of its time paired with raypool's in the same round.
//!
//! It also checks that they trace the same rays: the ray counts, and the image against
//! raypool's, next to how far two raypool images of different seeds are apart (the noise).
//! Where they disagree the bench fails rather than report a speed.
//!
//! Needs Debian's `libembree-dev` (Embree 3). Writes `results/embree.md` (or `$RAYPOOL_RESULTS/embree.md`, or `--out FILE`).
//! `--quick`: 300 × 200 at 4 spp, 5 rounds; by default 600 × 400 at 16 spp, 7 rounds.
//! Then the triangle table (`embree/triangles.rs`): the `mesh` scene's mesh, the hit search alone
//! over a fixed ray set, and the quad tables (`embree/quads.rs`): the second book's quads and
//! an instance, likewise; `--triangles-only` reruns those alone, keeping the file's sphere table.

#[path = "embree/library.rs"]
mod library;
#[path = "embree/quads.rs"]
mod quads;
#[path = "embree/triangles.rs"]
mod triangles;

use std::path::PathBuf;
use std::time::Instant;

use library::{EmbreeSpheres, Variant};
use raypool::files::image::Image;
use raypool::measure::compare::metrics;
use raypool::measure::machine::{Machine, results_dir};
use raypool::measure::speedup::median;
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, to_f32};
use raypool::tracer::render::{RenderJob, RenderSettings, TileOutput, render_tile_with};
use raypool::tracer::sampling::independent::PerSample;
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::tile::Tile;

/// One render: its pixels (row-major linear RGB), rays cast and seconds.
struct Rendered {
    pixels: Vec<[f32; 3]>,
    rays: u64,
    seconds: f64,
}

/// Renders `job`'s whole image on this thread, tile after tile, finding hits with `closest_hit`.
fn render(job: &RenderJob, closest_hit: impl Fn(&Ray) -> Option<Hit> + Copy) -> Rendered {
    let (width, height) = (job.settings.width, job.settings.height);
    let streams = PerSample { seed: job.settings.seed };
    let start = Instant::now();
    let tiles: Vec<TileOutput> = Tile::grid(width, height, 16)
        .into_iter()
        .map(|tile| render_tile_with(job, &streams, tile, closest_hit))
        .collect();
    let seconds = start.elapsed().as_secs_f64();
    let image = Image::from_tiles(width, height, &tiles).expect("the grid covers the image once");
    let pixels = image.pixels.iter().map(|p| [to_f32(p.x), to_f32(p.y), to_f32(p.z)]).collect();
    Rendered { pixels, rays: tiles.iter().map(|t| t.rays).sum(), seconds }
}

/// The median of `values` (`speedup::median` sorts its argument: a copy here).
fn median_of(values: &[f64]) -> f64 {
    median(&mut values.to_vec())
}

struct Options {
    width: u32,
    height: u32,
    spp: u32,
    rounds: usize,
    quick: bool,
    out: PathBuf,
    /// `--triangles-only`: rerun the triangle table alone, keeping the file's sphere table.
    triangles_only: bool,
}

fn options() -> Options {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let out = args.iter().position(|a| a == "--out").and_then(|i| args.get(i + 1).map(PathBuf::from));
    let (width, height, spp, rounds) = if quick { (300, 200, 4, 5) } else { (600, 400, 16, 7) };
    let out = out.unwrap_or_else(|| results_dir().join("embree.md"));
    let triangles_only = args.iter().any(|a| a == "--triangles-only");
    Options { width, height, spp, rounds, quick, out, triangles_only }
}

fn main() {
    let options = options();
    let spheres = if options.triangles_only {
        let old = std::fs::read_to_string(&options.out).unwrap_or_else(|e| {
            panic!("--triangles-only keeps {}'s sphere table: {e}", options.out.display())
        });
        old.split(TRIANGLES).next().unwrap_or_default().to_owned()
    } else {
        spheres(&options)
    };
    let flags: Vec<&str> = [(options.quick, " --quick"), (options.triangles_only, " --triangles-only")]
        .into_iter()
        .filter_map(|(on, flag)| on.then_some(flag))
        .collect();
    let command = format!(
        "cargo bench --bench embree --features embree{}{}",
        if flags.is_empty() { "" } else { " --" },
        flags.concat()
    );
    // The scene's mesh, then the same terrain at 768 × 768 cells (1,179,648 triangles; 384 ×
    // 384 quick): a tree far larger than the caches.
    let larger = if options.quick { 384 } else { 768 };
    let triangles = [None, Some(larger)]
        .map(|cells| {
            triangles::section(
                options.quick,
                &command,
                &Machine::current().describe(),
                &embree_version(),
                cells,
            )
        })
        .join("\n");
    // The second book's quads: its ground of boxes, and the Cornell box's room and turned box.
    let quads = ["next-week", "cornell"]
        .map(|scene| {
            quads::section(options.quick, scene, &command, &Machine::current().describe(), &embree_version())
        })
        .join("\n");
    let report = format!("{spheres}\n{triangles}\n{quads}");
    std::fs::write(&options.out, &report)
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", options.out.display()));
    print!("{report}");
}

/// Where the triangle section starts in the results file.
const TRIANGLES: &str = "\n## Triangles";

/// The sphere table: three hit searches under one path tracer.
fn spheres(options: &Options) -> String {
    let scene = builtin_scene("final", DEFAULT_SCENE_SEED).expect("final exists").to_scene();
    let settings = RenderSettings {
        width: options.width,
        height: options.height,
        spp: options.spp,
        max_depth: 50,
        seed: 1,
        sampler: Sampler::Independent,
        ..RenderSettings::default()
    };
    // raypool's own search at each vector level the CPU has (`RAYPOOL_ISA`), the widest
    // first: the ratios are against it, the level a render picks by default.
    let levels: Vec<Isa> = Isa::available().into_iter().rev().collect();
    let jobs: Vec<RenderJob> =
        levels.iter().map(|&isa| RenderJob::new(scene.clone().with_isa(isa), settings)).collect();
    let job = &jobs[0];
    let embree: Vec<EmbreeSpheres> = Variant::ALL
        .iter()
        .map(|&v| EmbreeSpheres::new(job.scene.spheres(), v).unwrap_or_else(|e| panic!("{e}")))
        .collect();

    // names[..levels.len()] are raypool's own search; the others are Embree's, in
    // Variant::ALL's order.
    let mut names: Vec<String> = levels
        .iter()
        .map(|isa| format!("raypool at {} (its 4-wide tree and sphere test)", isa.name()))
        .collect();
    names.extend(Variant::ALL.iter().map(|v| v.name().to_owned()));
    let run = |k: usize| match jobs.get(k) {
        Some(ours) => render(ours, |ray| ours.scene.hit(ray, Real::INFINITY)),
        None => render(job, |ray| embree[k - jobs.len()].closest_hit(ray)),
    };
    let mut seconds = vec![Vec::new(); names.len()];
    let mut last: Vec<Option<Rendered>> = names.iter().map(|_| None).collect();
    for round in 0..options.rounds {
        for step in 0..names.len() {
            let k = (round + step) % names.len();
            let out = run(k);
            eprintln!("round {}/{}: {}: {:.3} s", round + 1, options.rounds, names[k], out.seconds);
            seconds[k].push(out.seconds);
            last[k] = Some(out);
        }
    }
    let last: Vec<Rendered> = last.into_iter().map(|r| r.expect("every contender ran")).collect();

    // The noise: raypool's image at another seed, against raypool's.
    let other_seed = job.with_camera(&job.scene.camera, RenderSettings { seed: 2, ..settings });
    let noise = metrics(
        &render(&other_seed, |ray| other_seed.scene.hit(ray, Real::INFINITY)).pixels,
        &last[0].pixels,
    );

    let mut table = String::new();
    for (k, name) in names.iter().enumerate() {
        let ratios: Vec<f64> =
            seconds[0].iter().zip(&seconds[k]).map(|(ours, theirs)| ours / theirs).collect();
        let error = metrics(&last[k].pixels, &last[0].pixels);
        let ray_ratio = last[k].rays as f64 / last[0].rays as f64;
        let agrees = (ray_ratio - 1.0).abs() < 0.01 && error.rmse < noise.rmse;
        assert!(
            agrees,
            "{name} does not trace the same rays as raypool: {} rays against {} ({ray_ratio:.4}×), \
             image RMSE {:.2e} against the noise of another seed, {:.2e}",
            last[k].rays, last[0].rays, error.rmse, noise.rmse
        );
        let runs: Vec<String> = seconds[k].iter().map(|s| format!("{s:.2}")).collect();
        table += &format!(
            "| {name} | {} | {:.2} | {:.2} | **{:.2}** | {} | {:.1e} |\n",
            runs.join(", "),
            median_of(&seconds[k]),
            last[k].rays as f64 / median_of(&seconds[k]) / 1e6,
            median_of(&ratios),
            last[k].rays,
            error.rmse,
        );
    }
    format!(
        "# raypool's closest-hit search against Intel Embree 3\n\n\
         The same path tracer (raypool's render loop, camera, materials and random numbers) finds\n\
         its hits several ways: raypool's own search at each vector level the CPU has\n\
         (`RAYPOOL_ISA`; the widest, a render's default, first), and Embree's tree with Embree's\n\
         sphere primitive or with raypool's sphere test. The image and ray count must agree,\n\
         only the time differs.\n\
         `final` (486 spheres), {w} × {h}, {spp} spp, depth 50, seed 1, independent sampler, one thread,\n\
         16 × 16 tiles in order; {rounds} rounds, all of them in a rotating order in each.\n\n\
         Machine: {machine}; Embree {embree} (Debian's `libembree-dev`, its own CPU dispatch).\n\
         Command: `cargo bench --bench embree --features embree{quick}`.\n\n\
         | closest hit by | runs (s) | median (s) | Mrays/s | × raypool's rays/s at its widest level (median of paired ratios) | rays | image RMSE against raypool's |\n\
         |---|---|---:|---:|---:|---:|---:|\n\
         {table}\n\
         Two raypool images of seeds 1 and 2 differ by RMSE {noise:.1e} (the noise); every row is\n\
         below it and within 1% of raypool's ray count, or the bench fails instead of writing this.\n\
         Embree's sphere primitive computes its own hit distance (then raypool's hit record\n\
         re-projects the point), so a few paths part ways where the two distances round apart;\n\
         with raypool's sphere test the distances are raypool's own, and only a grazing hit or a\n\
         tie that the two trees decide differently (Embree keeps the first of equal distances,\n\
         raypool the lower sphere index) can part a path.\n",
        w = options.width,
        h = options.height,
        spp = options.spp,
        rounds = options.rounds,
        machine = Machine::current().describe(),
        embree = embree_version(),
        quick = if options.quick { " -- --quick" } else { "" },
        noise = noise.rmse,
    )
}

/// The installed Embree's version, as its package says (or "3").
fn embree_version() -> String {
    std::process::Command::new("dpkg-query")
        .args(["-W", "-f=${Version}", "libembree-dev"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .unwrap_or_else(|| "3".into())
}
