//! `cargo bench --bench trace`: micro-benchmarks of the three innermost operations of the
//! tracer, on inputs drawn once up front so that only the operation is timed. Every result
//! goes through `black_box`: a result left unused lets the optimiser delete the work.
//!
//! - `sphere/*`: the stable ray–sphere test, for rays that hit and rays that miss;
//! - `closest-hit/{camera,bounce}/*`: the closest hit in the book's final scene of camera
//!   rays and of the diffuse bounces leaving their hits, by each [`Accel`]: the binary tree,
//!   the four-wide tree (the default) with scalar or SIMD-packet leaves or the ground kept
//!   apart, and every sphere tested (what a hierarchy saves);
//! - `scatter/*`: one scattering event per material.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use raypool::scenes::builtin::builtin_scene;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::geometry::sphere::Sphere;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::sampling::warp::random_unit_vector;
use raypool::tracer::scene::Accel;
use raypool::tracer::shading::material::Material;
use raypool::tracer::shading::texture::Textures;

const RAYS: usize = 4096;

fn rays_towards(rng: &mut SmallRng, from: Vec3, spread: Real, aim: Vec3) -> Vec<Ray> {
    (0..RAYS).map(|_| Ray::new(from, aim - from + spread * random_unit_vector(rng))).collect()
}

fn sphere_tests(c: &mut Criterion) {
    let mut rng = SmallRng::seed_from_u64(1);
    let sphere = Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 };
    let hits = rays_towards(&mut rng, Vec3::new(0.0, 0.0, 5.0), 0.5, Vec3::ZERO);
    let misses = rays_towards(&mut rng, Vec3::new(0.0, 0.0, 5.0), 0.5, Vec3::new(3.0, 0.0, 0.0));
    let mut group = c.benchmark_group("sphere");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, rays) in [("hit", &hits), ("miss", &misses)] {
        group.bench_function(name, |b| {
            b.iter(|| rays.iter().for_each(|r| _ = black_box(sphere.intersect(black_box(r), Real::INFINITY))))
        });
    }
    group.finish();
}

fn traversal(c: &mut Criterion) {
    let scene = builtin_scene("final", 2026).expect("final builds").to_scene();
    let mut rng = SmallRng::seed_from_u64(2);
    // Camera-like rays from the book's viewpoint into the scene, and the diffuse bounces
    // that leave where they hit (most of a render's rays start on a surface).
    let camera = rays_towards(&mut rng, Vec3::new(13.0, 2.0, 3.0), 4.0, Vec3::ZERO);
    let bounce: Vec<Ray> = camera
        .iter()
        .filter_map(|r| scene.hit(r, Real::INFINITY))
        .map(|hit| hit.spawn((hit.normal + random_unit_vector(&mut rng)).normalize()))
        .collect();
    let accels = [
        ("binary", Accel::Binary),
        ("wide", Accel::Wide),
        ("wide-packets", Accel::WidePackets),
        ("wide-huge-apart", Accel::WideHugeApart),
        ("flat", Accel::Flat),
    ];
    for (kind, rays) in [("camera", &camera), ("bounce", &bounce)] {
        let mut group = c.benchmark_group(format!("closest-hit/{kind}"));
        group.throughput(Throughput::Elements(rays.len() as u64));
        for (name, accel) in accels {
            let scene = scene.clone().with_accel(accel);
            group.bench_function(name, |b| {
                b.iter(|| rays.iter().for_each(|r| _ = black_box(scene.hit(black_box(r), Real::INFINITY))))
            });
        }
        group.finish();
    }
}

fn scattering(c: &mut Criterion) {
    let mut rng = SmallRng::seed_from_u64(3);
    let hit = Hit {
        t: 1.0,
        point: Vec3::ZERO,
        normal: Vec3::Y,
        front_face: true,
        material: 0,
        offset: 1e-6,
        lift: 0.0,
        u: 0.0,
        v: 0.0,
    };
    let incoming: Vec<Vec3> = (0..RAYS)
        .map(|_| (Vec3::new(rng.random::<Real>() - 0.5, -1.0, rng.random::<Real>() - 0.5)).normalize())
        .collect();
    let materials = [
        ("lambertian", Material::Lambertian { albedo: Vec3::splat(0.5) }),
        ("metal", Material::Metal { albedo: Vec3::splat(0.8), fuzz: 0.3 }),
        ("dielectric", Material::glass(1.5)),
    ];
    let mut group = c.benchmark_group("scatter");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, material) in materials {
        group.bench_function(name, |b| {
            b.iter(|| {
                incoming.iter().for_each(|&d| {
                    _ = black_box(material.scatter(black_box(d), &hit, &Textures::default(), &mut rng))
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, sphere_tests, traversal, scattering);
criterion_main!(benches);
