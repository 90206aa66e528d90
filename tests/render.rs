//! Whole renders: energy conservation (white furnace) and bit-identical images under every
//! schedule and thread count.

use std::sync::Arc;

use raypool::files::output::{Format, encode};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::{Frame, RngSource};
use raypool::schedule::modes::{Rendered, Schedule, render};
use raypool::tracer::real::Real;
use raypool::tracer::render::{Adaptive, RenderJob, RenderSettings};
use raypool::tracer::sampler::PerSample;
use raypool::tracer::scene::Scene;

fn frame(scene: Scene, settings: RenderSettings, threads: usize) -> Arc<Frame> {
    let rng = RngSource::PerSample(PerSample { seed: settings.seed });
    Arc::new(Frame::new(RenderJob::new(scene, settings), rng, threads, 16, Arc::new(|_| {})))
}

fn render_builtin(name: &str, settings: RenderSettings, schedule: Schedule, threads: usize) -> Rendered {
    let scene = builtin_scene(name, DEFAULT_SCENE_SEED).unwrap().to_scene();
    render(&frame(scene, settings, threads), &schedule)
}

fn pfm_bytes(r: &Rendered) -> Vec<u8> {
    let mut bytes = Vec::new();
    encode(&r.image, Format::Pfm, &mut bytes).unwrap();
    bytes
}

#[test]
fn furnace_sphere_renders_its_albedo_and_the_sky_renders_white() {
    let settings =
        RenderSettings { width: 48, height: 48, spp: 16, max_depth: 50, seed: 9, ..Default::default() };
    let scene = builtin_scene("furnace", 0).unwrap().to_scene();
    let frame = frame(scene.clone(), settings, 1);
    let out = render(&frame, &Schedule::Serial);
    let sphere = scene.spheres()[0];
    let (mut inside, mut outside) = (0, 0);
    for j in 0..48 {
        for i in 0..48 {
            // Classify the pixel by a 5 × 5 grid of points across it, corners included.
            let hits = (0..25)
                .filter(|k| {
                    let (x, y) = (i as Real + (k % 5) as Real / 4.0, j as Real + (k / 5) as Real / 4.0);
                    let ray = frame.job().camera.center_ray(x, y);
                    sphere.intersect(&ray, Real::INFINITY).is_some()
                })
                .count();
            let p = out.image.pixels[j * 48 + i];
            let expected = match hits {
                25 => 0.5,
                0 => 1.0,
                _ => continue, // the silhouette: a mix of both
            };
            if hits == 25 {
                inside += 1
            } else {
                outside += 1
            }
            for c in p.to_array() {
                assert!((c - expected).abs() <= 1e-4, "pixel ({i}, {j}) = {p:?}, expected {expected}");
            }
        }
    }
    assert!(inside > 500 && outside > 200, "the view must show both: {inside} inside, {outside} outside");
}

#[test]
fn every_schedule_and_thread_count_gives_identical_bytes() {
    let settings =
        RenderSettings { width: 64, height: 43, spp: 4, max_depth: 10, seed: 5, ..Default::default() };
    let reference = render_builtin("final", settings, Schedule::Serial, 1);
    let bytes = pfm_bytes(&reference);
    for schedule in Schedule::ALL {
        for threads in [2, 7] {
            let other = render_builtin("final", settings, schedule, threads);
            assert_eq!(
                other.rays, reference.rays,
                "{schedule:?} × {threads} cast a different number of rays"
            );
            assert!(pfm_bytes(&other) == bytes, "{schedule:?} with {threads} threads differs from serial");
        }
    }
}

#[test]
fn the_seed_changes_the_image_and_nothing_else_does() {
    let settings =
        RenderSettings { width: 32, height: 21, spp: 2, max_depth: 8, seed: 1, ..Default::default() };
    let a = pfm_bytes(&render_builtin("paper1", settings, Schedule::Serial, 1));
    let again = pfm_bytes(&render_builtin("paper1", settings, Schedule::StaticBlocks, 3));
    let reseeded =
        pfm_bytes(&render_builtin("paper1", RenderSettings { seed: 2, ..settings }, Schedule::Serial, 1));
    assert!(a == again);
    assert!(a != reseeded, "a different seed must give different noise");
}

#[test]
fn every_builtin_renders_finite_pixels_and_counts_rays() {
    let settings =
        RenderSettings { width: 24, height: 16, spp: 2, max_depth: 50, seed: 3, ..Default::default() };
    for b in raypool::scenes::builtin::BUILTINS {
        let out = render_builtin(b.name, settings, Schedule::StaticBlocks, 2);
        assert!(out.image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{}", b.name);
        // At least one camera ray per sample; at most max_depth rays per sample.
        let samples = 24 * 16 * 2;
        assert!(out.rays >= samples && out.rays <= samples * 50, "{}: {} rays", b.name, out.rays);
    }
}

fn adaptive(target_error: Real, min_spp: u32, max_spp: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 32,
        spp: max_spp,
        max_depth: 20,
        seed: 4,
        adaptive: Some(Adaptive { target_error, min_spp }),
        ..Default::default()
    }
}

#[test]
fn adaptive_sampling_is_identical_under_every_schedule() {
    let settings = adaptive(0.05, 8, 128);
    let reference = render_builtin("final", settings, Schedule::Serial, 1);
    for schedule in Schedule::ALL {
        let other = render_builtin("final", settings, schedule, 3);
        assert_eq!((other.samples, other.rays), (reference.samples, reference.rays), "{schedule:?}");
        assert!(pfm_bytes(&other) == pfm_bytes(&reference), "{schedule:?} differs from serial");
    }
}

#[test]
fn adaptive_sampling_spends_fewer_samples_where_the_image_is_smooth() {
    let (width, height, max_spp) = (48u64, 32u64, 128u64);
    let uniform = render_builtin(
        "three-spheres",
        RenderSettings { adaptive: None, ..adaptive(0.05, 8, 128) },
        Schedule::Serial,
        1,
    );
    assert_eq!(uniform.samples, width * height * max_spp);
    let adapted = render_builtin("three-spheres", adaptive(0.05, 8, 128), Schedule::Serial, 1);
    // Every pixel took at least min_spp and at most max_spp samples; in all, far fewer.
    assert!(adapted.samples >= width * height * 8, "{}", adapted.samples);
    assert!(adapted.samples * 2 < uniform.samples, "{} of {}", adapted.samples, uniform.samples);
    // A target so loose every pixel stops after its first pass: exactly min_spp each.
    let loose = render_builtin("three-spheres", adaptive(1.0, 8, 128), Schedule::Serial, 1);
    assert!(loose.samples < width * height * 16, "{}", loose.samples);
    // In the furnace every sample of a pixel wholly on the sphere (0.5) or the sky (1.0) is
    // the same: zero error, so even a target of 1e-6 stops them after one pass. Only the
    // silhouette's pixels, which mix the two, go on to max_spp; a circle inside the image
    // crosses fewer pixels than the image's perimeter.
    let furnace = render_builtin("furnace", adaptive(1e-6, 8, 128), Schedule::Serial, 1);
    let silhouette = (furnace.samples - width * height * 8) / (max_spp - 8);
    assert!(silhouette > 0 && silhouette < 2 * (width + height), "{silhouette} pixels ran on");
    assert_eq!(furnace.samples, width * height * 8 + silhouette * (max_spp - 8));
}

/// The mean pixel value of `name` rendered with `settings`.
fn image_mean(name: &str, settings: RenderSettings) -> f64 {
    let out = render_builtin(name, settings, Schedule::StaticBlocks, 2);
    let n = out.image.pixels.len() as f64;
    out.image.pixels.iter().map(|p| f64::from(p.x + p.y + p.z) / 3.0).sum::<f64>() / n
}

#[test]
fn russian_roulette_keeps_the_mean_image() {
    // Paired renders: for each seed, the image with and without roulette. They share every
    // random number until a path reaches its fourth ray, so their difference has far less
    // noise than either image: a sharp test. The mean difference over seeds must be within
    // 4 standard errors of zero. Measured: 0.001 of one; a biased roulette (without
    // the 1/p weight) darkens `final` by 1.0% and lands 68 standard errors away.
    let settings = RenderSettings { width: 40, height: 27, spp: 16, max_depth: 50, ..Default::default() };
    let roulette = RenderSettings { roulette: true, ..settings };
    let runs = 16;
    let differences: Vec<f64> = (0..runs)
        .map(|seed| {
            image_mean("final", RenderSettings { seed, ..roulette })
                - image_mean("final", RenderSettings { seed, ..settings })
        })
        .collect();
    let mean = differences.iter().sum::<f64>() / runs as f64;
    let variance = differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (runs - 1) as f64;
    let standard_error = (variance / runs as f64).sqrt();
    println!("mean difference {mean:e}, {:.2} standard errors", mean / standard_error);
    assert!(standard_error > 0.0, "roulette changed nothing");
    assert!(mean.abs() < 4.0 * standard_error, "mean difference {mean:e}, standard error {standard_error:e}");
    // And it does end paths early: fewer rays for the same samples.
    let rays = |s| render_builtin("final", s, Schedule::Serial, 1).rays;
    assert!(rays(roulette) < rays(settings));
}

#[test]
fn stopping_black_paths_changes_rays_not_pixels() {
    let settings =
        RenderSettings { width: 64, height: 43, spp: 4, max_depth: 50, seed: 5, ..Default::default() };
    let stopped = render_builtin("final", settings, Schedule::Serial, 1);
    let full =
        render_builtin("final", RenderSettings { stop_black_paths: false, ..settings }, Schedule::Serial, 1);
    assert!(pfm_bytes(&stopped) == pfm_bytes(&full));
    assert!(stopped.rays <= full.rays);
}
