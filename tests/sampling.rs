//! χ² goodness-of-fit tests of the sampling routines, as pbrt's and Mitsuba's test theirs:
//! each routine's directions (or points) are counted in bins, and the counts compared with
//! what its stated density predicts there, integrated over each bin. A routine that draws
//! from one density and claims another biases every estimator that divides by the claim.
//!
//! Each test also runs the same statistic against a deliberately wrong density (the stated
//! one tilted by ±5% across the sphere) and asserts that it is rejected: that is the power
//! the test states, measured in the test itself. The machinery is `chi_squared/`, shared with
//! `sampling_paths.rs` (manifold samples and light paths through cornell's glass ball).

mod chi_squared;
mod rooms;

use chi_squared::{assert_fits, front_hit};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::scenes::format::SceneFile;
use raypool::tracer::lights::emission::emitted_direction;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::sampling::warp::random_unit_vector;
use raypool::tracer::shading::material::Material;
use raypool::tracer::shading::texture::Textures;
use rooms::lit_room;

/// Draws for the lamp's points.
const SAMPLES: usize = 200_000;

/// The significance each test rejects at: 1%, split over the seven checks (Bonferroni).
const ALPHA: f64 = 0.01 / 7.0;

/// [`chi_squared::assert_draws_follow`] at this file's significance.
fn assert_draws_follow(
    name: &str,
    draw: impl FnMut(&mut SmallRng) -> Option<Vec3>,
    pdf: &dyn Fn(Vec3) -> f64,
) {
    chi_squared::assert_draws_follow(name, draw, pdf, ALPHA);
}

#[test]
fn the_phase_function_draws_every_direction_alike() {
    let isotropic = |_: Vec3| 0.25 / std::f64::consts::PI;
    assert_draws_follow("phase function", |rng| Some(random_unit_vector(rng)), &isotropic);
}

/// A Lambertian's bounce and a light path's first direction (BDPT) draw by `cos θ / π`.
#[test]
fn the_diffuse_bounce_and_a_light_paths_first_direction_follow_the_cosine() {
    let normal = Vec3::new(0.3, -0.5, 0.81).normalize();
    let cosine = move |d: Vec3| f64::from(d.dot(normal).max(0.0)) / std::f64::consts::PI;
    let hit = front_hit(Vec3::ZERO, normal);
    let white = Material::Lambertian { albedo: Vec3::ONE };
    let textures = Textures::default();
    assert_draws_follow(
        "lambertian bounce",
        |rng| white.scatter(-normal, &hit, &textures, rng).map(|s| s.direction),
        &cosine,
    );
    assert_draws_follow("light path's first direction", |rng| Some(emitted_direction(normal, rng)), &cosine);
}

/// `Lights::sample` from three points of a room lit by a quad and a triangle in a turned group,
/// a triangle and a moving sphere: the directions follow `Lights::pdf` (the density every
/// MIS weight and light sample divides by).
#[test]
fn a_light_sample_draws_directions_by_the_density_it_states() {
    let scene = SceneFile::parse(&lit_room(), "room.toml").unwrap_or_else(|e| panic!("{e}")).to_scene();
    let lights = scene.lights();
    for (k, from) in
        [Vec3::ZERO, Vec3::new(-0.5, -0.7, 0.2), Vec3::new(0.6, 0.4, -0.6)].into_iter().enumerate()
    {
        let time = 0.25 * k as Real;
        let pdf = |d: Vec3| f64::from(lights.pdf(from, d, time));
        assert_draws_follow(
            &format!("light sample from {from}"),
            |rng| lights.sample(from, time, rng).map(|s| s.dir),
            &pdf,
        );
    }
}

/// Where a manifold sample and a light path (BDPT) start: `Lights::sample_emission` draws
/// points uniformly over cornell's lamp (its one light), counted in 16 × 16 cells of it. The
/// same counts must reject a density tilted by ±5% across the lamp.
#[test]
fn light_points_for_manifold_samples_and_light_paths_are_uniform_over_the_lamp() {
    let text = raypool::scenes::builtin::builtin_scene("cornell", 0).unwrap().to_toml();
    let scene = SceneFile::parse(&text, "cornell.toml").unwrap_or_else(|e| panic!("{e}")).to_scene();
    // The lamp: q = (213, 554, 227), u = 130 x̂, v = 105 ẑ (`src/scenes/cornell.toml`).
    let cell = |p: Vec3| {
        let (a, b) = ((p.x - 213.0) / 130.0, (p.z - 227.0) / 105.0);
        assert!((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b) && (p.y - 554.0).abs() < 1e-3, "{p}");
        ((a * 16.0) as usize).min(15) * 16 + ((b * 16.0) as usize).min(15)
    };
    let mut rng = SmallRng::seed_from_u64(5);
    let mut observed = vec![0usize; 256];
    for _ in 0..SAMPLES {
        let emission = scene.lights().sample_emission(0.0, &mut rng).expect("the lamp");
        observed[cell(emission.point)] += 1;
    }
    let uniform = vec![SAMPLES as f64 / 256.0; 256];
    let tilted: Vec<f64> = (0..256).map(|k| uniform[k] * if k < 128 { 1.05 } else { 0.95 }).collect();
    assert_fits("the lamp's points", &observed, (&uniform, &tilted), 1, ALPHA);
}
