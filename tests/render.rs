//! Whole renders: energy conservation (white furnace) and bit-identical images under every
//! schedule and thread count.

use std::sync::Arc;

use raypool::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::frame::{Frame, RngSource};
use raypool::output::{Format, encode};
use raypool::real::Real;
use raypool::render::{RenderJob, RenderSettings};
use raypool::sampler::PerSample;
use raypool::scene::Scene;
use raypool::schedule::{Rendered, Schedule, render};

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
    let settings = RenderSettings { width: 48, height: 48, spp: 16, max_depth: 50, seed: 9 };
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
    let settings = RenderSettings { width: 64, height: 43, spp: 4, max_depth: 10, seed: 5 };
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
    let settings = RenderSettings { width: 32, height: 21, spp: 2, max_depth: 8, seed: 1 };
    let a = pfm_bytes(&render_builtin("paper1", settings, Schedule::Serial, 1));
    let again = pfm_bytes(&render_builtin("paper1", settings, Schedule::StaticBlocks, 3));
    let reseeded =
        pfm_bytes(&render_builtin("paper1", RenderSettings { seed: 2, ..settings }, Schedule::Serial, 1));
    assert!(a == again);
    assert!(a != reseeded, "a different seed must give different noise");
}

#[test]
fn every_builtin_renders_finite_pixels_and_counts_rays() {
    let settings = RenderSettings { width: 24, height: 16, spp: 2, max_depth: 50, seed: 3 };
    for b in raypool::builtin::BUILTINS {
        let out = render_builtin(b.name, settings, Schedule::StaticBlocks, 2);
        assert!(out.image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{}", b.name);
        // At least one camera ray per sample; at most max_depth rays per sample.
        let samples = 24 * 16 * 2;
        assert!(out.rays >= samples && out.rays <= samples * 50, "{}: {} rays", b.name, out.rays);
    }
}
