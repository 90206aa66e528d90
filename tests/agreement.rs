//! Do the estimators agree? Every light-transport setting renders the same mean image as the
//! material's bounce alone (`bsdf`), the one estimator with no light sampling to get wrong.
//!
//! - At points: at the floor round a glass ball's foot (cornell's, a smaller one, the two
//!   together), the manifold sample plus the bounce weighed against it equals the bounce
//!   alone (issue #55's bias lived there).
//! - Per 8 × 8 block of a 64 × 64 `cornell`: each setting's mean over independent seeds
//!   (guided renders', `--guiding on`, too) against a committed `bsdf` reference of 256 seeds
//!   × 1,024 spp (`tests/references/cornell-bsdf-64.txt`, written by an ignored test below);
//!   and `cornell-smoke`'s default, `mis`, against its own (`cornell-smoke-bsdf-64.txt`). Standard
//!   errors come from the spread between seeds, never from within one image: the estimators
//!   are heavy-tailed. Each test states the smallest bias it catches, and asserts it.

mod deadline;

use std::fmt::Write as _;

use deadline::{deadline, within, within_for};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::measure::agreement::{Estimate, WHOLE_Z, compare, over_seeds, renders};
use raypool::scenes::builtin::builtin_scene;
use raypool::scenes::format::SceneFile;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::guiding::Guiding;
use raypool::tracer::lighting::Odds;
use raypool::tracer::lighting::manifold::{Passing, manifold_event};
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::render::{Adaptive, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::sampling::warp::random_unit_vector;
use raypool::tracer::scene::Scene;
use raypool::tracer::shading::material::Material;
use raypool::tracer::world::object::Probe;

/// The built-in scene `name`.
fn builtin(name: &str) -> Scene {
    let text = builtin_scene(name, 0).unwrap().to_toml();
    SceneFile::parse(&text, "scene.toml").unwrap_or_else(|e| panic!("{e}")).to_scene()
}

/// Mean and standard error of the mean of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Cornell's room with `spheres` (TOML) in place of its glass ball.
fn cornell_with(spheres: &str) -> Scene {
    let text = include_str!("../src/scenes/cornell.toml");
    let room = &text[..text.find("[[sphere]]").unwrap()];
    SceneFile::parse(&format!("{room}{spheres}"), "cornell.toml").unwrap_or_else(|e| panic!("{e}")).to_scene()
}

/// A glass ball of `radius` resting on cornell's floor at `(x, z)`.
fn ball(x: Real, z: Real, radius: Real) -> String {
    format!("[[sphere]]\ncenter = [{x:?}, {radius:?}, {z:?}]\nradius = {radius:?}\nmaterial = \"glass\"\n")
}

/// Light from the lamp through the scene's glass balls reaching a white floor point `dx`
/// along x from the foot of caster `k`, per unit albedo, green channel, over `n` samples:
/// (bounces alone, manifold sample plus the weighed bounce), each as per-sample values.
fn through_the_ball_at(scene: &Scene, k: usize, dx: Real, n: usize) -> (Vec<f64>, Vec<f64>) {
    let white = Material::Lambertian { albedo: Vec3::splat(0.73) };
    let white = scene.materials().iter().position(|m| *m == white).expect("cornell's white") as u32;
    let sphere = scene.casters().ball(k).sphere;
    let point = sphere.center - sphere.radius * Vec3::Y + dx * Vec3::X;
    let hit = Hit {
        t: 1.0,
        point,
        normal: Vec3::Y,
        front_face: true,
        material: white,
        offset: 1e-3,
        lift: 0.0,
        u: 0.0,
        v: 0.0,
    };
    let probe = Probe { time: 0.0, medium_seed: 0, ..Default::default() };
    let mut rng = SmallRng::seed_from_u64(dx.to_bits() as u64 ^ k as u64);
    let (mut alone, mut weighed, mut rays) = (Vec::new(), Vec::new(), 0);
    for _ in 0..n {
        let manifold =
            manifold_event(scene, &hit, 1, Odds { coin: 0.0, chance: 1.0 }, probe, &mut rng, &mut rays).y;
        let dir = (Vec3::Y + random_unit_vector(&mut rng)).normalize();
        let mut passing =
            Some(Passing::leave(scene, point, dir, dir.y / std::f64::consts::PI as Real, 1, 1.0));
        let (mut ray, mut refractions) = (hit.spawn(dir), 0);
        let (mut light, mut weight) = (0.0, 1.0);
        // Into a ball, out of it, to the lamp: a bounce is followed while it refracts; any
        // other event ends it (those paths are neither estimator's business here).
        while let (Some(found), Some(now)) = (scene.hit_world(&ray, &probe), passing) {
            let material = scene.material(&found);
            let emitted = material.emitted(&found);
            if emitted != Vec3::ZERO {
                if refractions == 2 {
                    (light, weight) = (emitted.y, now.weight(scene, &found, emitted));
                }
                break;
            }
            let scattered = material.scatter(ray.dir, &found, &scene.textures, &mut rng);
            let Some(scatter) = scattered.filter(|_| material.lobe().is_none()) else { break };
            (passing, refractions) = (now.next(scene, &found, scatter.direction), refractions + 1);
            ray = found.spawn(scatter.direction);
        }
        alone.push(f64::from(light));
        weighed.push(f64::from(manifold + light * weight));
    }
    (alone, weighed)
}

/// At floor points 0.5 to 10 units from a glass ball's foot, where the manifold sample
/// gathers most of the light through the ball: cornell's ball, a small ball elsewhere, and
/// the two together (each sample aims through one, drawn at random). Catches a bias of
/// 2.2–3% of that light at any point (4.5 standard errors; the bound below asserts it).
/// Before the fix of issue #55 the sample found its passages blocked by the ball itself and
/// lost 50–94% of it at cornell's ball (z −80 to −185), and with the spread measured in
/// `f32` it gained 5% at 2 units (z +9.6).
#[test]
fn through_the_ball_at_its_foot_the_manifold_sample_and_the_bounce_sum_to_the_bounce_alone() {
    let (big, small) = (ball(190.0, 190.0, 90.0), ball(220.0, 310.0, 25.0));
    // Points out to where the caustic fades (the small ball's is 3.6 times narrower).
    let (near_big, near_small) = ([0.5, 2.0, 5.0, 10.0], [0.5, 1.0, 2.0, 3.0]);
    let scenes = [
        (cornell_with(&big), 0, near_big),
        (cornell_with(&small), 0, near_small),
        (cornell_with(&(big + &small)), 1, near_small),
    ];
    within("the samples at the balls' feet to finish", move || {
        for (scene, k, points) in &scenes {
            for dx in *points {
                let (alone, weighed) = through_the_ball_at(scene, *k, dx, 300_000);
                let ((a, sa), (w, sw)) = (mean_and_error(&alone), mean_and_error(&weighed));
                let error = (sa * sa + sw * sw).sqrt();
                let z = (w - a) / error;
                let at = format!("caster {k} of {}, {dx} from its foot", scene.casters().len());
                assert!(
                    z.abs() <= 4.5,
                    "{at}: bounces alone {a:.4} ± {sa:.4}, mis {w:.4} ± {sw:.4} (z {z:.1})"
                );
                assert!(4.5 * error / a < 0.03, "{at}: only a {:.1}% bias is detectable", 450.0 * error / a);
            }
        }
    });
}

/// The references: `bsdf`, 256 seeds × 1,024 spp, their seeds apart from every test's.
const REFERENCE_SEEDS: u64 = 256;
/// 64 × 64 pixels in 8 × 8 blocks.
const SIDE: u32 = 64;
const BLOCK: u32 = 8;

/// The file of built-in `scene`'s reference.
fn reference_file(scene: &str) -> String {
    format!("tests/references/{scene}-bsdf-64.txt")
}

/// Settings at 64 × 64: depth 50, `spp` samples.
fn at(spp: u32) -> RenderSettings {
    RenderSettings { width: SIDE, height: SIDE, spp, max_depth: 50, ..Default::default() }
}

/// Writes the reference of built-in `scene` (cornell's about 12 minutes on two cores;
/// cornell-smoke's took 17 minutes of CPU).
fn write_reference(scene: &str) {
    let settings = RenderSettings { light_sampling: LightSampling::Bsdf, ..at(1024) };
    let seeds = 1_000_000..1_000_000 + REFERENCE_SEEDS;
    let mut text = format!(
        "# {scene}, 64 x 64, bsdf, 1024 spp, depth 50, seeds {seeds:?}, sobol: per 8 x 8 block\n\
         # (row by row) then the whole image: the grey mean over the seeds and its standard error.\n\
         # Written by: cargo test --release --test agreement -- --ignored write_the_reference\n"
    );
    for estimate in over_seeds(&renders(&builtin(scene), settings, seeds, BLOCK, 2)) {
        writeln!(text, "{:.8e} {:.8e}", estimate.mean, estimate.error).unwrap();
    }
    std::fs::write(reference_file(scene), text).unwrap();
}

/// Writes cornell's reference:
/// `cargo test --release --test agreement -- --ignored write_the_reference_of_cornell --exact`
/// (without `--exact`, cornell-smoke's too).
#[test]
#[ignore = "writes a committed reference; run by hand after a change to cornell or to bsdf"]
fn write_the_reference_of_cornell() {
    write_reference("cornell");
}

/// Writes cornell-smoke's reference (as [`write_the_reference_of_cornell`]).
#[test]
#[ignore = "writes a committed reference; run by hand after a change to cornell-smoke or to bsdf"]
fn write_the_reference_of_cornell_smoke() {
    write_reference("cornell-smoke");
}

/// Built-in `scene`'s committed reference, per block then the whole image.
fn reference(scene: &str) -> Vec<Estimate> {
    let text = std::fs::read_to_string(reference_file(scene)).unwrap();
    let parse = |l: &str| {
        let mut fields = l.split_whitespace().map(|f| f.parse().unwrap());
        Estimate { mean: fields.next().unwrap(), error: fields.next().unwrap() }
    };
    text.lines().filter(|l| !l.starts_with('#')).map(parse).collect()
}

/// Every setting of cornell against `bsdf`, each over 96 independent seeds: every 8 × 8 block
/// within 4.5 standard errors and the whole image within 4. Many seeds of few samples, not few
/// of many: a block's mean over a render is itself heavy-tailed (rare paths through the glass
/// lift a render now and then), and 24 seeds of 128 spp once put a plain block 5 of their
/// standard errors low, a set of renders that happened to hold none of those paths.
///
/// The smallest bias caught in any block (4.5 standard errors, the reference's own included;
/// measured when this test was written, asserted with the bound beside each setting): `mis` 2.2%
/// (256 spp a seed; bound 3%); its switches at 32 spp a seed 3.3–5.0% (bounds 5–6%);
/// `mixture` 8.5% and `bdpt` 7.5% at 64 and 16 spp (bounds 10% and 9%). The weakest blocks
/// are the dim ceiling corners. In the whole image, 0.05–0.2%. Under 3 minutes on two cores.
#[test]
fn every_light_sampling_setting_renders_cornell_as_bsdf_does_block_by_block() {
    let cases: Vec<(&str, RenderSettings, f64)> = vec![
        ("mis", at(256), 0.03),
        ("mis, independent", RenderSettings { sampler: Sampler::Independent, ..at(32) }, 0.06),
        ("mis, no edge points", RenderSettings { edge_spots: 0, ..at(32) }, 0.06),
        ("mis, roulette", RenderSettings { roulette: true, ..at(32) }, 0.06),
        (
            "mis, adaptive",
            RenderSettings { adaptive: Some(Adaptive { target_error: 0.05, min_spp: 16 }), ..at(64) },
            0.05,
        ),
        ("mixture", RenderSettings { light_sampling: LightSampling::Mixture, ..at(64) }, 0.10),
        ("bdpt", RenderSettings { light_sampling: LightSampling::Bdpt, ..at(16) }, 0.09),
    ];
    assert_agree_with_bsdf("cornell", cases);
}

/// Guided renders (`--guiding on`, issue #58) of cornell against `bsdf`, as above: passes of
/// 1, 1, 2, 4 and 8 samples learn the guides (`--guide-pilot 16`), and every pass's samples
/// count. The guide is learnt anew under each seed, so the seeds' renders stay independent.
///
/// The smallest bias caught in any block (measured when this test was written, asserted with
/// the bound beside each setting): `mis`, guided, at 64 spp a seed 2.9% (bound 4%); `bsdf`,
/// guided, at 96 spp 8.8% (bound 10%). In the whole image 0.06% and 0.26% (measured: −0.013%
/// ± 0.016% and +0.013% ± 0.066%). 170 s of two cores' user time.
#[test]
fn guided_settings_render_cornell_as_bsdf_does_block_by_block() {
    let guiding = Some(Guiding { pilot: 16 });
    assert_agree_with_bsdf(
        "cornell",
        vec![
            ("mis, guided", RenderSettings { guiding, ..at(64) }, 0.04),
            ("bsdf, guided", RenderSettings { guiding, light_sampling: LightSampling::Bsdf, ..at(96) }, 0.10),
        ],
    );
}

/// Each of `cases` (a name, its settings, the bias it must be able to see in every block) of
/// built-in `scene` over 96 seeds against its reference: every block within 4.5 standard
/// errors, the whole image within 4, and the power asserted.
fn assert_agree_with_bsdf(scene: &'static str, cases: Vec<(&'static str, RenderSettings, f64)>) {
    let reference = reference(scene);
    // Minutes of rendering, not a wait on threads that may hang: six deadlines' worth.
    let what = format!("the agreement renders of {scene} to finish");
    within_for(deadline() * 6, what, move || {
        let scene = builtin(scene);
        let mut report = String::new();
        for (name, settings, power) in cases {
            let ours = over_seeds(&renders(&scene, settings, 2_000_000..2_000_096, BLOCK, 2));
            let found = compare(&ours, &reference);
            writeln!(report, "{name}: {found:?}").unwrap();
            assert!(found.agrees(), "{name} differs from bsdf on {scene:?}: {found:?}\n{report}");
            assert!(
                found.detectable <= power,
                "{name}: too weak to see a {:.0}% bias: {found:?}",
                100.0 * power
            );
            assert!(found.whole_error * WHOLE_Z <= 0.003, "{name}: the whole image's power: {found:?}");
        }
        eprintln!("{report}");
    });
}

/// cornell-smoke's default setting (`mis`) against its `bsdf` reference, over 96 independent
/// seeds of 64 spp: every 8 × 8 block within 4.5 standard errors and the whole image within 4.
/// The smallest bias caught in any block (4.5 standard errors, the reference's 0.8% included;
/// measured when written, asserted with a bound of 2.5%): 1.7%, in block 35 (2.3% at 32 spp a
/// seed); in the whole image 0.02%. Measured: worst block |z| 2.4, the whole image
/// +0.001% ± 0.005%. 32 s of CPU, 16 s on two idle cores. The other settings of cornell-smoke,
/// and next-week and the lit room, are `benches/accuracy.rs`'s.
#[test]
fn mis_renders_cornell_smoke_as_bsdf_does_block_by_block() {
    assert_agree_with_bsdf("cornell-smoke", vec![("mis", at(64), 0.025)]);
}
