//! Error falls as 1/√spp: the slope that `cargo bench --bench error` checks on every scene,
//! checked here on one small scene.

mod deadline;

use deadline::within;
use raypool::measure::convergence::{Reference, log_log_fit, timed_render};
use raypool::scenes::builtin::builtin_scene;
use raypool::tracer::render::RenderSettings;
use raypool::tracer::sampling::sampler::Sampler;

/// The settings both tests render three-spheres at: small, and independent numbers, whose
/// error falls as spp^-0.5.
fn independent_48_by_32() -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 32,
        max_depth: 50,
        seed: 1,
        sampler: Sampler::Independent,
        ..Default::default()
    }
}

#[test]
fn error_falls_as_one_over_root_spp_on_three_spheres() {
    within("the reference and the renders of three-spheres to finish", move || {
        let scene = builtin_scene("three-spheres", 0).unwrap().to_scene();
        let base = independent_48_by_32();
        let reference = Reference::render(&scene, base, 1024, 2);
        assert!(reference.noise > 0.0, "two independent halves differ");
        let points: Vec<(f64, f64)> = [1, 2, 4, 8, 16, 32, 64]
            .iter()
            .map(|&spp| {
                let (out, _) = timed_render(scene.clone(), RenderSettings { spp, ..base }, 2);
                (spp as f64, reference.error_of(&out.image))
            })
            .collect();
        let (slope, _) = log_log_fit(&points);
        assert!((slope + 0.5).abs() <= 0.05, "slope {slope}, points {points:?}");
    });
}

#[test]
fn a_biased_render_is_caught_by_the_slope() {
    within("the reference and the depth-2 renders of three-spheres to finish", move || {
        // Depth 2 against a depth-50 reference: the error stops falling at the bias, so the
        // slope flattens far beyond the tolerance. This is what the check is for.
        let scene = builtin_scene("three-spheres", 0).unwrap().to_scene();
        let base = independent_48_by_32();
        let reference = Reference::render(&scene, base, 512, 2);
        let points: Vec<(f64, f64)> = [1, 4, 16, 64]
            .iter()
            .map(|&spp| {
                let (out, _) = timed_render(scene.clone(), RenderSettings { spp, max_depth: 2, ..base }, 2);
                (spp as f64, reference.error_of(&out.image))
            })
            .collect();
        let (slope, _) = log_log_fit(&points);
        assert!(slope > -0.4, "slope {slope}: the bias should flatten it, points {points:?}");
    });
}
