//! The denoiser (`src/denoise/`, `raypool render --denoise`): it brings a 1-sample image of
//! `final` closer to the converged one (by a factor set from a measured one: a regression guard),
//! it keeps an edge between two surfaces sharp whatever lies across it, and like every other
//! path that renders pixels it gives the same bytes whatever the threads and the mode.

mod deadline;

use deadline::{ok, raypool, scratch, within};
use raypool::denoise::atrous::Filter;
use raypool::denoise::guide::{Guide, Guides};
use raypool::files::output::read_pfm;
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::math::real::{Real, Vec3};
use raypool::{RenderJob, RenderSettings};

/// `raypool render --scene final --width 160 FLAGS` as linear pixels.
fn render(dir: &std::path::Path, file: &str, flags: &[&str]) -> Vec<[f32; 3]> {
    let args = [&["render", "--scene", "final", "--width", "160", "--out", file][..], flags].concat();
    ok(raypool(&args, dir));
    read_pfm(&std::fs::read(dir.join(file)).unwrap()).unwrap().2
}

fn rmse(a: &[[f32; 3]], b: &[[f32; 3]], pixels: &[usize]) -> f64 {
    let squares: f64 =
        pixels.iter().map(|&k| (0..3).map(|c| f64::from(a[k][c] - b[k][c]).powi(2)).sum::<f64>()).sum();
    (squares / (3 * pixels.len()) as f64).sqrt()
}

#[test]
fn denoising_one_sample_of_final_brings_it_closer_to_the_converged_image() {
    let dir = scratch("final");
    let reference = render(&dir, "reference.pfm", &["--spp", "256", "--seed", "99"]);
    let scene = builtin_scene("final", DEFAULT_SCENE_SEED).unwrap().to_scene();
    // Measured at 29153fc (160 × 107, seeds 1–4, against 256 spp; in no committed file):
    // 1.40–1.43 over the whole image, 3.54–3.65 inside surfaces. results/denoise.md measures
    // 400 × 267: 1.62–1.64 and 5.64–5.82. The bounds 1.3 and 3.0 are regression guards set
    // from the 160 × 107 figures, with room for other seeds: not a proof.
    for seed in ["1", "2"] {
        let noisy = render(&dir, "noisy.pfm", &["--spp", "1", "--seed", seed]);
        let denoised = render(&dir, "denoised.pfm", &["--spp", "1", "--seed", seed, "--denoise"]);
        let settings =
            RenderSettings { width: 160, height: 107, seed: seed.parse().unwrap(), ..Default::default() };
        let job = RenderJob::new(scene.clone(), settings);
        let guides = within("the guides of final on 2 threads", move || Guides::of(&job, 2));
        let all: Vec<usize> = (0..reference.len()).collect();
        let inside = guides.inside_surfaces();
        assert!(inside.len() > all.len() / 4, "{} of {} pixels inside surfaces", inside.len(), all.len());
        for (pixels, what, at_least) in [(&all, "the whole image", 1.3), (&inside, "inside surfaces", 3.0)] {
            let (before, after) = (rmse(&noisy, &reference, pixels), rmse(&denoised, &reference, pixels));
            assert!(
                before / after >= at_least,
                "seed {seed}, {what}: RMSE {before:.4} at 1 spp, {after:.4} denoised: {:.2}× less, not {at_least}×",
                before / after
            );
        }
    }
}

/// Pixel `(x, y)`'s point on a wall facing the camera (a pixel is 1 unit there).
fn at(x: u32, y: u32) -> Vec3 {
    Vec3::new(Real::from(x as u16), Real::from(y as u16), 0.0)
}

/// Two surfaces side by side on a 32 × 16 image, and noisy light on both.
fn two_surfaces(right: impl Fn(u32, u32) -> Guide) -> (Guides, Vec<Vec3>) {
    let (w, h) = (32, 16);
    let left = |x: u32, y: u32| Guide {
        albedo: Vec3::splat(0.6),
        normal: Vec3::Z,
        point: at(x, y),
        distance: 100.0,
    };
    let pixels: Vec<Guide> =
        (0..w * h).map(|k| if k % w < w / 2 { left(k % w, k / w) } else { right(k % w, k / w) }).collect();
    let noise = |k: u32| 0.5 + 0.4 * (Real::from(((k * 7919) % 101) as u16) / 100.0 - 0.5);
    let light = pixels.iter().enumerate().map(|(k, g)| g.albedo * noise(k as u32)).collect();
    (Guides { width: w, height: h, pixel_angle: 0.01, pixels }, light)
}

#[test]
fn an_edge_between_surfaces_stops_the_filter() {
    type Surface = Box<dyn Fn(u32, u32) -> Guide>;
    let edges: [(&str, Surface); 3] = [
        (
            "another colour",
            Box::new(|x, y| Guide {
                albedo: Vec3::new(0.6, 0.1, 0.1),
                normal: Vec3::Z,
                point: at(x, y),
                distance: 100.0,
            }),
        ),
        (
            "a corner (another normal)",
            Box::new(|x, y| Guide {
                albedo: Vec3::splat(0.6),
                normal: Vec3::X,
                point: at(x, y),
                distance: 100.0,
            }),
        ),
        (
            "a step in depth (a parallel plane 50 pixel sizes behind)",
            Box::new(|x, y| Guide {
                albedo: Vec3::splat(0.6),
                normal: Vec3::Z,
                point: at(x, y) - Vec3::Z * 50.0,
                distance: 150.0,
            }),
        ),
    ];
    for (what, right) in edges {
        let (guides, light) = two_surfaces(right);
        let (g, l) = (guides.clone(), light.clone());
        let filtered = within("the filter on 2 threads", move || Filter::default().apply(&l, &g, 2));
        // Whatever lies across the edge, the left surface's pixels stay what they were.
        let brighter: Vec<Vec3> =
            light.iter().enumerate().map(|(k, &c)| if k % 32 >= 16 { c * 100.0 } else { c }).collect();
        let g = guides.clone();
        let beside_brighter =
            within("the filter on 2 threads", move || Filter::default().apply(&brighter, &g, 2));
        let left = (0..light.len()).filter(|k| k % 32 < 16);
        for k in left {
            let (a, b) = (filtered[k], beside_brighter[k]);
            assert!(
                (a - b).abs().max_element() <= 1e-4 * a.max_element(),
                "{what}: pixel {k} {a:?} became {b:?}"
            );
        }
        // And the filter did filter: the left surface's spread of values shrank.
        let spread = |v: &[Vec3]| {
            let left: Vec<Real> = (0..v.len()).filter(|k| k % 32 < 16).map(|k| v[k].x).collect();
            left.iter().cloned().fold(Real::MIN, Real::max) - left.iter().cloned().fold(Real::MAX, Real::min)
        };
        assert!(
            spread(&filtered) < 0.5 * spread(&light),
            "{what}: {} → {}",
            spread(&light),
            spread(&filtered)
        );
    }
}

#[test]
fn denoised_images_are_the_same_bytes_whatever_the_threads_and_mode() {
    let dir = scratch("bytes");
    for scene in ["final", "cornell", "next-week"] {
        let runs = [
            ["--mode", "serial", "--threads", "1"],
            ["--mode", "steal", "--threads", "2"],
            ["--mode", "static", "--threads", "3"],
        ];
        let images: Vec<Vec<u8>> = runs
            .iter()
            .map(|run| {
                let args = [
                    &["render", "--scene", scene, "--width", "48", "--spp", "2", "--denoise"][..],
                    run,
                    &["--out", "d.pfm"],
                ]
                .concat();
                ok(raypool(&args, &dir));
                std::fs::read(dir.join("d.pfm")).unwrap()
            })
            .collect();
        assert!(
            images.iter().all(|i| *i == images[0]),
            "{scene}: --denoise gave different bytes across {runs:?}"
        );
    }
}

#[test]
fn a_part_file_is_not_denoised() {
    let dir = scratch("part");
    let out = raypool(&["render", "--width", "16", "--spp", "1", "--denoise", "--out", "p.rpart"], &dir);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--denoise needs the whole image") && stderr.lines().count() == 1, "{stderr}");
    assert!(!dir.join("p.rpart").exists(), "no part file written");
}
