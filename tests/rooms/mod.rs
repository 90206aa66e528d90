//! Small test scenes, the quadrant statistics by which renders are compared, a scene parsed
//! and rendered whole, and a whole frame rendered under a schedule: shared by the tests of the
//! world (`world*.rs`), of bidirectional path tracing (`bidir.rs`) and of manifold samples
//! (`manifold.rs`), so that none keeps its own copy.
#![allow(dead_code)]

use std::sync::Arc;

use raypool::scenes::format::SceneFile;
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{self, Rendered, Schedule};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::Vec3;
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::scene::Scene;
use raypool::tracer::tile::Tile;

/// `scene` rendered whole by `schedule` on `threads` threads, per-sample streams.
pub fn render_frame(scene: &Scene, settings: RenderSettings, schedule: Schedule, threads: usize) -> Rendered {
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    let frame =
        Arc::new(Frame::new(RenderJob::new(scene.clone(), settings), rng, threads, 8, Arc::new(|_| {})));
    modes::render(&frame, &schedule)
}

/// `scene` under `settings` rendered serially on one thread, then under every schedule on 2
/// and on 5 threads: each must cast the same rays and make the same image (`what` names the
/// case when one does not). Returns the serial render.
pub fn assert_every_schedule_renders_alike(scene: &Scene, settings: RenderSettings, what: &str) -> Rendered {
    let serial = render_frame(scene, settings, Schedule::Serial, 1);
    for schedule in Schedule::ALL {
        for threads in [2, 5] {
            let other = render_frame(scene, settings, schedule, threads);
            assert_eq!(other.rays, serial.rays, "{what}: {schedule:?} × {threads} cast other rays");
            assert!(other.image == serial.image, "{what}: {schedule:?} × {threads} changed the image");
        }
    }
    serial
}

/// A camera at the origin looking down −z with a 60° view, its focus 1 away.
pub const CAMERA: &str = r#"
[camera]
lookfrom = [0.0, 0.0, 0.0]
lookat = [0.0, 0.0, -1.0]
vup = [0.0, 1.0, 0.0]
vfov = 60.0
focus_dist = 1.0
aspect = 1.0
"#;

/// Six quads facing into the cube `[-1, 1]³`, all of `material`.
pub fn inward_cube(material: &str) -> String {
    let faces = [
        ([-1.0, -1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]), // back wall, facing +z
        ([-1.0, -1.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]),  // front wall, facing −z
        ([-1.0, -1.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]), // left, facing +x
        ([1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0]),  // right, facing −x
        ([-1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [2.0, 0.0, 0.0]), // floor, facing +y
        ([-1.0, 1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),  // ceiling, facing −y
    ];
    faces
        .iter()
        .map(|(q, u, v)| format!("[[quad]]\nq = {q:?}\nu = {u:?}\nv = {v:?}\nmaterial = {material}\n"))
        .collect()
}

/// A white room lit by a quad and a triangle inside a turned, moved group, a triangle at the
/// top level and a sphere that moves during the shutter.
pub fn lit_room() -> String {
    let lamp = "{ kind = \"diffuse_light\", emit = [3.0, 3.0, 3.0] }";
    format!(
        "{CAMERA}[background]\nkind = \"black\"\n{room}\
         [[triangle]]\nvertices = [[-0.8, -0.8, -0.95], [-0.4, -0.8, -0.95], [-0.6, -0.4, -0.95]]\nmaterial = {lamp}\n\
         [[sphere]]\ncenter = [0.5, -0.6, -0.5]\ncenter1 = [0.7, -0.6, -0.3]\nradius = 0.15\nmaterial = {lamp}\n\
         [[group]]\n[group.transform]\nrotate_y = 30.0\ntranslate = [0.0, 0.9, -0.3]\n\
         [[group.quad]]\nq = [-0.3, 0.0, -0.3]\nu = [0.6, 0.0, 0.0]\nv = [0.0, 0.0, 0.6]\nmaterial = {lamp}\n\
         [[group.triangle]]\nvertices = [[0.5, -0.5, -0.2], [0.5, -0.5, 0.2], [0.5, -0.1, 0.0]]\nmaterial = {lamp}\n",
        room = inward_cube("{ kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }"),
    )
}

/// The mean colour of each quadrant of a `side × side` image (row-major `pixels`), per channel,
/// then the whole image's: 15 numbers, quadrant by quadrant, the whole image last (a bias
/// spread over the image shows there at half a quadrant's standard error).
pub fn quadrant_sums(pixels: &[raypool::tracer::math::real::Vec3], side: u32) -> Vec<f64> {
    let mut sums = vec![0.0; 15];
    for (k, p) in pixels.iter().enumerate() {
        let (i, j) = (k as u32 % side, k as u32 / side);
        let quadrant = (2 * (j / (side / 2)) + i / (side / 2)) as usize;
        for (c, v) in p.to_array().iter().enumerate() {
            let v = raypool::tracer::math::real::to_f64(*v) / (side * side / 4) as f64;
            sums[3 * quadrant + c] += v;
            sums[12 + c] += v / 4.0;
        }
    }
    sums
}

/// Over independent `runs` of the same numbers, each number's mean and its standard error.
pub fn mean_and_error(runs: &[Vec<f64>]) -> Vec<(f64, f64)> {
    let n = runs.len() as f64;
    (0..runs[0].len())
        .map(|k| {
            let mean = runs.iter().map(|r| r[k]).sum::<f64>() / n;
            let variance = runs.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (variance / n).sqrt())
        })
        .collect()
}

/// Asserts that each of `ours` (mean, standard error) lies within 5 combined standard errors of
/// `theirs` (quadrant by quadrant, channel by channel, then the whole image, as
/// [`quadrant_sums`] orders them; or any other list of numbers), and prints the smallest bias
/// that catches: 5 combined standard errors as a share of each number's mean.
pub fn assert_within_five_errors(what: &str, theirs: (&str, &[(f64, f64)]), ours: (&str, &[(f64, f64)])) {
    let caught: Vec<f64> =
        theirs.1.iter().zip(ours.1).map(|((a, sa), (_, sb))| 5.0 * sa.hypot(*sb) / a.abs()).collect();
    let span = |share: &[f64]| {
        let mut share = share.to_vec();
        share.sort_by(f64::total_cmp);
        let percent = |x: f64| 100.0 * x;
        format!(
            "{:.1}–{:.1}% (median {:.1}%)",
            percent(share[0]),
            percent(share[share.len() - 1]),
            percent(share[share.len() / 2])
        )
    };
    if caught.len() == 15 {
        let (quadrants, whole) = caught.split_at(12);
        eprintln!(
            "{what}: catches a bias of {} of a quadrant, {} of the image",
            span(quadrants),
            span(whole)
        );
    } else {
        eprintln!("{what}: catches a bias of {} of a number", span(&caught));
    }
    for (k, ((a, sa), (b, sb))) in theirs.1.iter().zip(ours.1).enumerate() {
        assert!(
            (a - b).abs() <= 5.0 * (sa * sa + sb * sb).sqrt(),
            "{what}, number {k} (quadrant {}, 4 the whole image; channel {}): {} {a} ± {sa}, {} {b} ± {sb}",
            k / 3,
            k % 3,
            theirs.0,
            ours.0
        );
    }
}

/// The scene of `text`, which must parse (its error is the panic's message).
pub fn parse(text: &str) -> Scene {
    SceneFile::parse(text, "test.toml").unwrap_or_else(|e| panic!("{e}")).to_scene()
}

/// `scene` rendered whole, as one tile, with Sobol streams.
pub fn render_scene(scene: &Scene, settings: RenderSettings) -> Vec<Vec3> {
    let job = RenderJob::new(scene.clone(), settings);
    let whole = Tile { x: 0, y: 0, width: settings.width, height: settings.height };
    render_tile(&job, &SobolStreams::new(settings.seed), whole).pixels
}

/// The scene of `text` rendered whole ([`parse`], then [`render_scene`]).
pub fn render(text: &str, settings: RenderSettings) -> Vec<Vec3> {
    render_scene(&parse(text), settings)
}

/// The mean image of `scene` under `light_sampling` at `spp` over 8 seeds, per quadrant and
/// channel: the mean of the 8 and its standard error (from the 8, not guessed).
pub fn quadrant_means(scene: &Scene, light_sampling: LightSampling, spp: u32) -> Vec<(f64, f64)> {
    let side = 16;
    let runs: Vec<Vec<f64>> = (1..=8)
        .map(|seed| {
            let settings =
                RenderSettings { width: side, height: side, spp, seed, light_sampling, ..Default::default() };
            quadrant_sums(&render_frame(scene, settings, Schedule::Stealing, 2).image.pixels, side)
        })
        .collect();
    mean_and_error(&runs)
}

/// Each quadrant's mean colour and the whole image's under `mixture` and `mis` against
/// `bsdf`'s, within 5 standard errors from 8 renders of each. The smallest bias caught
/// (printed; measured at 0db8597), mixture's then mis's: on cornell 6.9–34% and 5.5–33% of a
/// quadrant's mean (medians 23% and 19%), 5.2–7.6% and 4.6–6.4% of the image's; cornell-smoke
/// 2.0–12.7% and 1.8–9.9%, 1.8–2.4% and 1.6–1.8%; the lit room 5.2–8.8% and 3.5–5.5%, 3.3%
/// and 1.8%; the lamp on a smooth ball (`world_smooth.rs`) 19–165% and 10–151% of a quadrant
/// (medians 101% and 105%: its quadrants are mostly black), 9.6% and 7.2% of the image: it
/// would not see the 2.6% it was written for. `tests/agreement.rs` is the sharp test.
pub fn assert_the_three_light_samplings_agree(name: &str, scene: &Scene) {
    let reference = quadrant_means(scene, LightSampling::Bsdf, 64);
    for light_sampling in [LightSampling::Mixture, LightSampling::Mis] {
        let other = quadrant_means(scene, light_sampling, 64);
        assert_within_five_errors(name, ("bsdf", &reference), (light_sampling.name(), &other));
    }
}
