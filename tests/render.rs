//! Whole renders: energy conservation (white furnace) and bit-identical images under every
//! schedule and thread count.

mod deadline;

use std::sync::Arc;

use deadline::within;
use raypool::files::output::{Format, encode};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Rendered, Schedule, render};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::math::real::Real;
use raypool::tracer::render::{Adaptive, RenderJob, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::scene::Scene;

fn frame(scene: Scene, settings: RenderSettings, threads: usize) -> Arc<Frame> {
    let rng = RngSource::new(&settings, RngChoice::PerSample);
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
    within("the furnace render to finish", move || {
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
    });
}

#[test]
fn every_schedule_and_thread_count_gives_identical_bytes() {
    within("the renders of final under every schedule on 2 and 7 threads to finish", move || {
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
                assert!(
                    pfm_bytes(&other) == bytes,
                    "{schedule:?} with {threads} threads differs from serial"
                );
            }
        }
    });
}

#[test]
fn the_seed_changes_the_image_and_nothing_else_does() {
    within("the three renders of paper1 to finish", move || {
        let settings =
            RenderSettings { width: 32, height: 21, spp: 2, max_depth: 8, seed: 1, ..Default::default() };
        let a = pfm_bytes(&render_builtin("paper1", settings, Schedule::Serial, 1));
        let again = pfm_bytes(&render_builtin("paper1", settings, Schedule::StaticBlocks, 3));
        let reseeded =
            pfm_bytes(&render_builtin("paper1", RenderSettings { seed: 2, ..settings }, Schedule::Serial, 1));
        assert!(a == again);
        assert!(a != reseeded, "a different seed must give different noise");
    });
}

#[test]
fn every_builtin_renders_finite_pixels_and_counts_rays() {
    within("the render of every builtin on 2 threads to finish", move || {
        let settings =
            RenderSettings { width: 24, height: 16, spp: 2, max_depth: 50, seed: 3, ..Default::default() };
        for b in raypool::scenes::builtin::BUILTINS {
            let out = render_builtin(b.name, settings, Schedule::StaticBlocks, 2);
            assert!(out.image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{}", b.name);
            // At least one camera ray per sample; at most max_depth rays per sample.
            let samples = 24 * 16 * 2;
            assert!(out.rays >= samples && out.rays <= samples * 50, "{}: {} rays", b.name, out.rays);
        }
    });
}

fn adaptive(target_error: Real, min_spp: u32, max_spp: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 32,
        spp: max_spp,
        max_depth: 20,
        seed: 4,
        adaptive: Some(Adaptive { target_error, min_spp }),
        sampler: Sampler::Independent,
        ..Default::default()
    }
}

#[test]
fn adaptive_sampling_is_identical_under_every_schedule() {
    within("the adaptive renders of final under every schedule to finish", move || {
        let settings = adaptive(0.05, 8, 128);
        let reference = render_builtin("final", settings, Schedule::Serial, 1);
        for schedule in Schedule::ALL {
            let other = render_builtin("final", settings, schedule, 3);
            assert_eq!((other.samples, other.rays), (reference.samples, reference.rays), "{schedule:?}");
            assert!(pfm_bytes(&other) == pfm_bytes(&reference), "{schedule:?} differs from serial");
        }
    });
}

#[test]
fn adaptive_sampling_spends_fewer_samples_where_the_image_is_smooth() {
    within("the adaptive renders of three-spheres and furnace to finish", move || {
        let (width, height, max_spp) = (48u64, 32u64, 128u64);
        let uniform = render_builtin(
            "three-spheres",
            RenderSettings { adaptive: None, ..adaptive(0.2, 8, 128) },
            Schedule::Serial,
            1,
        );
        assert_eq!(uniform.samples, width * height * max_spp);
        let adapted = render_builtin("three-spheres", adaptive(0.2, 8, 128), Schedule::Serial, 1);
        // Every pixel took at least min_spp and at most max_spp samples; in all, far fewer.
        assert!(adapted.samples >= width * height * 8, "{}", adapted.samples);
        assert!(adapted.samples * 2 < uniform.samples, "{} of {}", adapted.samples, uniform.samples);
        // A target so loose every pixel stops after its first pass: exactly min_spp each.
        let loose = render_builtin("three-spheres", adaptive(10.0, 8, 128), Schedule::Serial, 1);
        assert_eq!(loose.samples, width * height * 8);
        // In the furnace every sample of a pixel wholly on the sphere (0.5) or the sky (1.0) is
        // the same: its two halves agree exactly, and a pixel whose neighbours are all such keeps
        // its pilot. Only next to the silhouette do halves differ: a band a few pixels wide around
        // a circle inside the image, so fewer than 5 perimeters' worth of pixels take more,
        // however small the target.
        let furnace = render_builtin("furnace", adaptive(1e-6, 8, 128), Schedule::Serial, 1);
        let extra = furnace.samples - width * height * 8;
        assert!(extra > 0 && extra < 5 * 2 * (width + height) * (max_spp - 8), "{extra} extra samples");
    });
}

/// The mean pixel value of `name` rendered with `settings`.
fn image_mean(name: &str, settings: RenderSettings) -> f64 {
    render_builtin(name, settings, Schedule::StaticBlocks, 2).image.mean()
}

#[test]
fn russian_roulette_keeps_the_mean_image() {
    within("the renders of final with and without roulette to finish", move || {
        // Paired renders: for each seed, the image with and without roulette. They share every
        // random number until a path reaches its fourth ray, so their difference has far less
        // noise than either image: a sharp test. The mean difference over seeds must be within
        // 4 standard errors of zero. Measured at 2276efe: 0.001 of one; a biased roulette
        // (without the 1/p weight) darkens `final` by 1.0% and lands 68 standard errors away,
        // so the smallest bias caught is about 0.06% of the image's mean (not re-measured).
        let settings = RenderSettings {
            width: 40,
            height: 27,
            spp: 16,
            max_depth: 50,
            sampler: Sampler::Independent,
            ..Default::default()
        };
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
        assert!(
            mean.abs() < 4.0 * standard_error,
            "mean difference {mean:e}, standard error {standard_error:e}"
        );
        // And it does end paths early: fewer rays for the same samples.
        let rays = |s| render_builtin("final", s, Schedule::Serial, 1).rays;
        assert!(rays(roulette) < rays(settings));
    });
}

#[test]
fn every_method_keeps_the_mean_image() {
    within("the renders of every sampling method on four scenes to finish", move || {
        // Issue #11: each sampling method's mean image equals independent uniform sampling's within
        // noise. For each seed, the image mean of the method minus that of independent uniform
        // sampling at the same seed; over 24 seeds the mean difference must be within 5 standard
        // errors of zero (24 seeds: a 5-SE miss by chance has odds of about 1 in 25,000 per case).
        // The smallest bias this catches, as a share of each scene's mean (printed; measured at
        // 0db8597): 0.05–0.69%, the weakest final's with sobol + roulette.
        let base = RenderSettings {
            width: 24,
            height: 16,
            spp: 16,
            max_depth: 50,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let adaptive = Some(Adaptive { target_error: 0.1, min_spp: 8 });
        let methods = [
            ("sobol", RenderSettings { sampler: Sampler::Sobol, ..base }),
            ("roulette", RenderSettings { roulette: true, ..base }),
            ("sobol + roulette", RenderSettings { sampler: Sampler::Sobol, roulette: true, ..base }),
            ("adaptive", RenderSettings { spp: 64, adaptive, ..base }),
            ("sobol adaptive", RenderSettings { spp: 64, adaptive, sampler: Sampler::Sobol, ..base }),
        ];
        let seeds = 24;
        for scene in ["final", "paper3", "three-spheres", "furnace"] {
            let uniform: Vec<f64> =
                (0..seeds).map(|seed| image_mean(scene, RenderSettings { seed, ..base })).collect();
            for (method, settings) in methods {
                let differences: Vec<f64> = (0..seeds)
                    .zip(&uniform)
                    .map(|(seed, u)| image_mean(scene, RenderSettings { seed, ..settings }) - u)
                    .collect();
                let n = seeds as f64;
                let mean = differences.iter().sum::<f64>() / n;
                let variance = differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let standard_error = (variance / n).sqrt();
                let caught = 500.0 * standard_error / (uniform.iter().sum::<f64>() / n);
                eprintln!(
                    "{scene}, {method}: {mean:+.2e} ({:+.2} standard errors; catches {caught:.2}%)",
                    mean / standard_error
                );
                if (scene, method) == ("furnace", "roulette") {
                    // Roulette starts at a path's fourth ray; no furnace path gets that far.
                    assert_eq!(standard_error, 0.0, "furnace paths end before roulette starts");
                    continue;
                }
                assert!(standard_error > 0.0, "{scene}, {method}: the same images as uniform sampling");
                assert!(
                    mean.abs() < 5.0 * standard_error,
                    "{scene}, {method}: mean image differs by {mean:e}, standard error {standard_error:e}"
                );
            }
        }
        // The adaptive renders did adapt: more samples than the pilot, fewer than the most.
        let samples = render_builtin("final", methods[3].1, Schedule::Serial, 1).samples;
        assert!(samples > 24 * 16 * 8 && samples < 24 * 16 * 64, "{samples} samples");
    });
}

#[test]
fn stopping_black_paths_changes_rays_not_pixels() {
    within("the two renders of final to finish", move || {
        let settings =
            RenderSettings { width: 64, height: 43, spp: 4, max_depth: 50, seed: 5, ..Default::default() };
        let stopped = render_builtin("final", settings, Schedule::Serial, 1);
        let full = render_builtin(
            "final",
            RenderSettings { stop_black_paths: false, ..settings },
            Schedule::Serial,
            1,
        );
        assert!(pfm_bytes(&stopped) == pfm_bytes(&full));
        assert!(stopped.rays <= full.rays);
    });
}

#[test]
fn adaptive_sampling_keeps_the_mean_image() {
    within("the reference and the adaptive renders of paper1 to finish", move || {
        // Against a converged reference (independent numbers, 2 x 1024 spp), the whole-image mean
        // of adaptive renders over 12 seeds must be within 4 standard errors (estimated across the
        // seeds). Judging pixels by their own samples' spread failed this kind of check by 20
        // standard errors (+0.29%, 21.5 SE over 40 seeds: 32f688f's message): pixels whose first
        // samples agree stop early. It catches a bias of 0.15% of the image's mean (4 standard
        // errors, the reference's included; printed, measured at 0db8597): 32f688f's +0.29%, not
        // the +0.055% its rule then kept.
        let scene = builtin_scene("paper1", DEFAULT_SCENE_SEED).unwrap().to_scene();
        let base = RenderSettings {
            width: 48,
            height: 32,
            max_depth: 20,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let reference = raypool::measure::convergence::Reference::render(&scene, base, 1024, 2);
        let means: Vec<f64> = (1..=12)
            .map(|seed| {
                let settings = RenderSettings { seed, ..adaptive(0.1, 8, 256) };
                render(
                    &frame(scene.clone(), RenderSettings { max_depth: 20, ..settings }, 2),
                    &Schedule::Stealing,
                )
                .image
                .mean()
            })
            .collect();
        let n = means.len() as f64;
        let average = means.iter().sum::<f64>() / n;
        let spread = (means.iter().map(|m| (m - average).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let standard_error =
            (spread.powi(2) / n + (reference.noise / (48.0f64 * 32.0).sqrt()).powi(2)).sqrt();
        let off = (average - reference.image.mean()) / standard_error;
        let caught = 400.0 * standard_error / reference.image.mean();
        eprintln!("adaptive: {off:.2} standard errors from the reference; catches {caught:.2}%");
        assert!(off.abs() < 4.0, "adaptive mean {average} is {off:.1} standard errors from the reference's");
    });
}
