//! The lights a path aims at (`world/lights.rs`): the density `Lights::pdf` gives a direction
//! is the density with which `Lights::sample` draws it. Checked by Monte Carlo with answers
//! known otherwise: a density integrates to 1 over the sphere of directions, and the mean of
//! `1/pdf` over sampled directions is the solid angle the lights cover.

use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::tracer::geometry::quad::Quad;
use raypool::tracer::geometry::sphere::Sphere;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::sampling::warp::random_unit_vector;
use raypool::tracer::shading::material::Material;
use raypool::tracer::world::lights::Lights;
use raypool::tracer::world::object::Object;

/// A lamp quad facing down, a bright sphere beside it, a quad seen from behind, and a
/// non-emitting sphere (not a light): from the origin, the three lights fill about 0.9 sr.
fn lights() -> (Lights, Vec<Object>) {
    let materials = [
        Material::DiffuseLight { emit: Vec3::splat(4.0), albedo: 0.0 },
        Material::DiffuseLight { emit: Vec3::new(20.0, 10.0, 5.0), albedo: 0.0 },
        Material::Lambertian { albedo: Vec3::splat(0.5) },
    ];
    let lamp = Quad::new(Vec3::new(-0.5, 2.0, -0.5), Vec3::Z, Vec3::X, 0).unwrap();
    let behind = Quad::new(Vec3::new(-2.0, -1.0, 1.5), Vec3::X * 0.5, Vec3::Y, 0).unwrap();
    let ball = Sphere { center: Vec3::new(2.0, 0.5, -1.0), radius: 0.4, material: 1 };
    let plain = Sphere { center: Vec3::new(0.0, -2.0, 0.0), radius: 0.5, material: 2 };
    let objects = vec![Object::Quad(lamp), Object::Quad(behind), Object::Sphere(ball), Object::Sphere(plain)];
    (Lights::new(&objects, &materials), objects)
}

#[test]
fn a_lights_density_integrates_to_one_over_all_directions() {
    let (lights, _) = lights();
    assert_eq!(lights.len(), 3, "two quads and the emitting sphere");
    let mut rng = SmallRng::seed_from_u64(1);
    let n = 1_000_000;
    let values: Vec<f64> = (0..n)
        .map(|_| f64::from(lights.pdf(Vec3::ZERO, random_unit_vector(&mut rng))) * 4.0 * std::f64::consts::PI)
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let spread = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
    let error = spread / (n as f64).sqrt();
    assert!((mean - 1.0).abs() < 5.0 * error, "∫ pdf dω = {mean} ± {error}");
}

#[test]
fn sampled_directions_are_drawn_with_the_density_pdf_gives_them() {
    // E[1/pdf] over sampled directions is the solid angle the lights cover; so is the share of
    // uniformly drawn directions that meet a light, times 4π.
    let (lights, objects) = lights();
    let lit = |dir: Vec3| {
        let ray = Ray::new(Vec3::ZERO, dir);
        objects[..3].iter().any(|o| o.hit(&ray, Real::INFINITY, &Default::default()).is_some())
    };
    let mut rng = SmallRng::seed_from_u64(2);
    let n = 400_000;
    let (mut inverse, mut grazing) = (Vec::with_capacity(n), 0);
    for _ in 0..n {
        let sample = lights.sample(Vec3::ZERO, &mut rng).expect("the origin is outside every light");
        let pdf = lights.pdf(Vec3::ZERO, sample.dir);
        assert!(pdf > 0.0, "a sampled direction must have a density: {sample:?}");
        // At the very edge of a sphere's cone a ray test may round to a miss.
        grazing += usize::from(!lit(sample.dir));
        inverse.push(1.0 / f64::from(pdf));
    }
    assert!(grazing <= n / 10_000, "{grazing} of {n} sampled directions miss every light");
    let sampled = inverse.iter().sum::<f64>() / n as f64;
    let uniform = (0..4 * n).filter(|_| lit(random_unit_vector(&mut rng))).count() as f64 / (4 * n) as f64;
    let covered = uniform * 4.0 * std::f64::consts::PI;
    // Binomial error of the uniform estimate dominates; 5 of its standard errors.
    let error = 4.0 * std::f64::consts::PI * (uniform * (1.0 - uniform) / (4 * n) as f64).sqrt();
    assert!(
        (sampled - covered).abs() < 5.0 * error + 1e-3 * covered,
        "E[1/pdf] {sampled}, covered {covered} ± {error}"
    );
}
