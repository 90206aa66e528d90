//! Small test scenes, the quadrant statistics by which renders are compared, and a whole
//! frame rendered under a schedule, shared by the tests of the world (`world.rs`), of
//! bidirectional path tracing (`bidir.rs`) and of manifold samples (`manifold.rs`).
#![allow(dead_code)]

use std::sync::Arc;

use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Rendered, Schedule, render};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::render::{RenderJob, RenderSettings};
use raypool::tracer::scene::Scene;

/// `scene` rendered whole by `schedule` on `threads` threads, per-sample streams.
pub fn render_frame(scene: &Scene, settings: RenderSettings, schedule: Schedule, threads: usize) -> Rendered {
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    let frame =
        Arc::new(Frame::new(RenderJob::new(scene.clone(), settings), rng, threads, 8, Arc::new(|_| {})));
    render(&frame, &schedule)
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

/// The mean colour of each quadrant of a `side × side` image (row-major `pixels`), per channel:
/// 12 numbers, quadrant by quadrant.
pub fn quadrant_sums(pixels: &[raypool::tracer::math::real::Vec3], side: u32) -> Vec<f64> {
    let mut sums = vec![0.0; 12];
    for (k, p) in pixels.iter().enumerate() {
        let (i, j) = (k as u32 % side, k as u32 / side);
        let quadrant = (2 * (j / (side / 2)) + i / (side / 2)) as usize;
        for (c, v) in p.to_array().iter().enumerate() {
            sums[3 * quadrant + c] += raypool::tracer::math::real::to_f64(*v) / (side * side / 4) as f64;
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
/// `theirs` (quadrant by quadrant, channel by channel, as [`quadrant_sums`] orders them).
pub fn assert_within_five_errors(what: &str, theirs: (&str, &[(f64, f64)]), ours: (&str, &[(f64, f64)])) {
    for (k, ((a, sa), (b, sb))) in theirs.1.iter().zip(ours.1).enumerate() {
        assert!(
            (a - b).abs() <= 5.0 * (sa * sa + sb * sb).sqrt(),
            "{what}, quadrant {} channel {}: {} {a} ± {sa}, {} {b} ± {sb}",
            k / 3,
            k % 3,
            theirs.0,
            ours.0
        );
    }
}
