//! Manifold next-event estimation (`lighting/manifold.rs`, `lighting/passage.rs`): the solve
//! finds the passages rays through a glass ball take, `mis` lights the caustic beside
//! cornell's ball as bounces alone do (and with less noise), the weights keep an emitting
//! furnace with a glass ball exact, and the images keep their bits under every schedule.

mod deadline;
mod rooms;

use deadline::within;
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::scenes::builtin::builtin_scene;
use raypool::schedule::modes::Schedule;
use raypool::tracer::geometry::sphere::Sphere;
use raypool::tracer::lighting::passage::{may_pass, solve};
use raypool::tracer::lights::LightSampling;
use raypool::tracer::lights::casters::{Ball, Lamps};
use raypool::tracer::math::real::{Vec3, to_f64};
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::sampling::warp::{random_unit_vector, uniform};
use raypool::tracer::scene::Scene;
use raypool::tracer::tile::Tile;
use rooms::{CAMERA, assert_every_schedule_renders_alike, inward_cube, parse, render_frame};

fn cornell() -> Scene {
    parse(&builtin_scene("cornell", 0).unwrap().to_toml())
}

#[test]
fn the_solve_finds_the_passage_a_ray_through_the_ball_takes_and_only_true_passages() {
    // Rays from a floor beside a ball resting on it (cornell's geometry, scaled to 1), drawn
    // by the cosine law, through the ball to a ceiling 5 radii up: the solve from the ray's
    // start to where it lands must find that passage (3,973 of 4,000: the fold search finds
    // pairs closer than its step, which the changes of side alone missed, 92% found then), and
    // everything it finds must be a passage from the start that lands on the target. The 97%
    // floor is a regression guard, not a proof: set from the measured 3,973 at ed73e9f.
    let ball = Ball::new(Sphere { center: Vec3::new(0.0, 1.0, 0.0), radius: 1.0, material: 0 }, 1.5);
    let mut rng = SmallRng::seed_from_u64(5);
    let (mut taken, mut found, mut solved) = (0, 0, 0);
    while taken < 4000 {
        let from = Vec3::new(2.2 * (uniform(&mut rng) - 0.5), 1e-4, 2.2 * (uniform(&mut rng) - 0.5));
        let dir = (Vec3::Y + random_unit_vector(&mut rng)).normalize();
        let Some(passage) = ball.pass(from, dir) else { continue };
        if passage.out.y <= 0.0 {
            continue;
        }
        let to = passage.exit + ((6.0 - passage.exit.y) / passage.out.y) * passage.out;
        taken += 1;
        let mut this = false;
        solve(&ball, from, to, |other| {
            solved += 1;
            this |= (other.entry - passage.entry).length() <= 1e-3;
            let aim = (to - other.exit).normalize().dot(other.out);
            assert!(aim > 1.0 - 1e-5, "a solved passage from {from} misses {to}: cos {aim}");
            let again = ball.pass(from, (other.entry - from).normalize()).expect("a passage from the start");
            assert!(
                (again.exit - other.exit).length() < 1e-3,
                "the passage is the ray's own: {again:?}, {other:?}"
            );
        });
        found += usize::from(this);
    }
    assert!(found * 100 >= taken * 97, "the solve found {found} of {taken} passages ({solved} in all)");
}

/// Cornell's caustic window beside the ball's foot, in an 80 × 80 image.
const CAUSTIC: Tile = Tile { x: 44, y: 68, width: 14, height: 8 };

/// Where cornell's ball mirrors the lamp, near its top, in an 80 × 80 image.
const GLINT: Tile = Tile { x: 44, y: 50, width: 8, height: 5 };

/// The pixels of `window` of an 80 × 80 image (grey: the channels' mean), rendered alone
/// under `light_sampling`, seed `seed`.
fn window(scene: &Scene, window: Tile, light_sampling: LightSampling, spp: u32, seed: u64) -> Vec<f64> {
    let settings = RenderSettings { width: 80, height: 80, spp, seed, light_sampling, ..Default::default() };
    let job = RenderJob::new(scene.clone(), settings);
    let pixels = render_tile(&job, &SobolStreams::new(seed), window).pixels;
    pixels.iter().map(|p| to_f64(p.x + p.y + p.z) / 3.0).collect()
}

/// The mean of `values` and the variance of one value about it.
fn mean_and_variance(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (mean, values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0))
}

/// The window's mean over 8 seeds, its standard error, and the mean over its pixels of each
/// pixel's variance across the seeds.
fn window_statistics(scene: &Scene, tile: Tile, light_sampling: LightSampling) -> (f64, f64, f64) {
    let runs: Vec<Vec<f64>> = (1..=8).map(|seed| window(scene, tile, light_sampling, 256, seed)).collect();
    let means: Vec<f64> = runs.iter().map(|run| run.iter().sum::<f64>() / run.len() as f64).collect();
    let (mean, variance) = mean_and_variance(&means);
    let pixels = runs[0].len();
    let per_pixel = (0..pixels)
        .map(|k| mean_and_variance(&runs.iter().map(|run| run[k]).collect::<Vec<_>>()).1)
        .sum::<f64>()
        / pixels as f64;
    (mean, (variance / 8.0).sqrt(), per_pixel)
}

/// `mis` against `bsdf` in cornell's `window` (named `name`), 8 seeds of 256 spp each: the
/// same mean, within 5 standard errors, and less than `share` of `bsdf`'s variance per pixel.
/// Smallest bias caught: 8.7% of the caustic window's mean, 11.9% of the glint's (measured in
/// issue #55's review, before 227b8c9; not re-measured). Each `share` is a regression guard,
/// not a proof: set from the share measured (each test says which, and at which commit).
fn assert_mis_agrees_with_less_noise(name: &str, tile: Tile, share: f64) {
    let what = format!("the renders of cornell's {name} window to finish");
    let name = name.to_owned();
    within(&what, move || {
        let scene = cornell();
        let (bsdf, bsdf_error, bsdf_noise) = window_statistics(&scene, tile, LightSampling::Bsdf);
        let (mis, mis_error, mis_noise) = window_statistics(&scene, tile, LightSampling::Mis);
        let error = bsdf_error.hypot(mis_error);
        assert!((mis - bsdf).abs() <= 5.0 * error, "the {name} window: mis {mis}, bsdf {bsdf} (± {error})");
        assert!(
            mis_noise < share * bsdf_noise,
            "{name}, variance per pixel: mis {mis_noise}, bsdf {bsdf_noise}"
        );
    });
}

#[test]
fn mis_lights_the_caustic_beside_the_ball_as_bounces_do_with_less_noise() {
    // The same samples, less noise: the solve aims at the light through the ball. Measured
    // per pixel at 256 spp (ed73e9f): 0.087 of bsdf's variance; 0.153 with two light points
    // near the ball's focus instead of eight (0.15 before the fold search and the glints too),
    // 0.23 with one light point per manifold sample, 0.62 without manifold samples. The bound
    // 0.12 was set from the 0.087 at 62e0a6c: a regression guard, not a proof.
    assert_mis_agrees_with_less_noise("caustic", CAUSTIC, 0.12);
}

#[test]
fn mis_shows_the_lamp_mirrored_in_the_ball_as_bounces_do_with_less_noise() {
    // The reflection's light counted R times every sample (`lighting::glint`) instead of in
    // full by the few samples the Fresnel coin sends into it: the same mean, and per pixel at
    // 256 spp 0.042 of bsdf's variance (measured at ed73e9f). The bound 0.2 is a regression
    // guard set from it, not a proof.
    assert_mis_agrees_with_less_noise("glint", GLINT, 0.2);
}

#[test]
fn an_emitting_furnace_with_a_glass_ball_stays_exact_in_the_mean() {
    // Walls that emit Le and reflect a, and a ball of lossless glass: radiance is Le/(1 − a)
    // everywhere. Manifold samples reach the walls through the ball and bounces meet them
    // there: only weights that sum to 1 keep that mean. Held to 5 standard errors of the
    // pixels' spread + 0.01%: that catches a bias of 0.48% of the mean (printed; measured at
    // 0db8597).
    within("the renders of the furnace with a glass ball to finish", || {
        let (le, a) = (0.75, 0.5);
        let material = format!("{{ kind = \"diffuse_light\", emit = [{le}, {le}, {le}], albedo = {a} }}");
        let ball = "[[sphere]]\ncenter = [0.2, -0.4, -0.45]\nradius = 0.55\nmaterial = { kind = \"dielectric\", ior = 1.5 }\n";
        let text = format!("{CAMERA}[background]\nkind = \"black\"\n{}{ball}", inward_cube(&material));
        let scene = parse(&text);
        assert_eq!(scene.casters().len(), 1, "the ball is a caster");
        let expected = le / (1.0 - a);
        let settings = RenderSettings {
            width: 16,
            height: 16,
            spp: 16,
            max_depth: 120,
            light_sampling: LightSampling::Mis,
            ..Default::default()
        };
        let job = RenderJob::new(scene, settings);
        let whole = Tile { x: 0, y: 0, width: 16, height: 16 };
        let pixels = render_tile(&job, &SobolStreams::new(7), whole).pixels;
        let values: Vec<f64> = pixels.iter().flat_map(|p| p.to_array().map(to_f64)).collect();
        let (mean, variance) = mean_and_variance(&values);
        let error = (variance / values.len() as f64).sqrt();
        eprintln!("catches a bias of {:.2}%", 100.0 * (5.0 * error + 1e-4 * expected) / expected);
        assert!(
            (mean - expected).abs() <= 5.0 * error + 1e-4 * expected,
            "mean {mean} against {expected} (± {error})"
        );
    });
}

#[test]
fn the_solve_finds_both_passages_of_a_fold_closer_than_its_step() {
    // A floor point of cornell's beside the ball's foot, 1.02 radii from its centre, and a
    // lamp point: two passages join them, entering 0.0015 radii apart (a twelfth of the
    // solve's step between tries), where the caustic folds. Neither is found by a change of side
    // between tries; the search for the turning point between them finds both.
    let ball = Ball::new(Sphere { center: Vec3::new(190.0, 90.0, 190.0), radius: 90.0, material: 0 }, 1.5);
    let (from, to) = (Vec3::new(202.6359, 0.0, 175.29427), Vec3::new(274.11914, 554.0, 239.743));
    let mut found = Vec::new();
    solve(&ball, from, to, |passage| found.push(passage));
    assert_eq!(found.len(), 2, "two passages: {found:?}");
    for passage in &found {
        let aim = (to - passage.exit).normalize().dot(passage.out);
        assert!(aim > 1.0 - 1e-5, "a solved passage misses the lamp point: cos {aim}");
    }
    let apart = (found[0].entry - found[1].entry).length() / ball.sphere.radius;
    assert!(apart > 1e-3 && apart < 0.01, "two passages close together, {apart} radii apart");
}

#[test]
fn manifold_samples_keep_the_image_the_same_bits_under_every_schedule_and_thread_count() {
    within("the mis renders of cornell under every schedule to finish", || {
        // And with the exact Fresnel equations, which the scatter, the glints and the
        // casters' passages all take (its image must differ from Schlick's).
        let text = builtin_scene("cornell", 0).unwrap().to_toml();
        let exact = text.replace("ior = 1.5", "ior = 1.5\nfresnel = \"exact\"");
        assert_ne!(exact, text, "cornell's glass is written as expected");
        let settings = RenderSettings { width: 24, height: 24, spp: 4, seed: 3, ..Default::default() };
        let (schlick, exact) = (cornell(), parse(&exact));
        let image = |scene: &Scene| render_frame(scene, settings, Schedule::Serial, 1).image;
        assert!(image(&schlick) != image(&exact), "fresnel = \"exact\" changed nothing");
        for (scene, sampler) in
            [(&schlick, Sampler::Sobol), (&schlick, Sampler::Independent), (&exact, Sampler::Sobol)]
        {
            let settings = RenderSettings { sampler, ..settings };
            assert_every_schedule_renders_alike(scene, settings, sampler.name());
        }
    });
}

#[test]
fn only_solid_still_glass_balls_in_lit_scenes_are_casters() {
    // cornell's glass ball is; a scene without lights has none (nothing to aim at), and
    // neither has a lit scene whose ball is white.
    assert_eq!(cornell().casters().len(), 1);
    let final_scene = raypool::scenes::builtin::builtin_scene("final", 0).unwrap().to_scene();
    assert!(final_scene.casters().is_empty(), "no lights in final: no casters");
    let original = builtin_scene("cornell", 0).unwrap().to_toml();
    let white =
        original.replace("radius = 90.0\nmaterial = \"glass\"", "radius = 90.0\nmaterial = \"white\"");
    assert_ne!(white, original, "the ball was made white");
    assert!(parse(&white).casters().is_empty());
}

#[test]
fn the_solve_finds_passages_from_far_points_and_may_pass_never_rules_them_out() {
    // Starts from 1.05 to 8 radii away in every direction, rays through the ball drawn
    // uniformly over the ball as the start sees it, targets from 1.5 to 10 radii beyond the
    // exit: the bounds that end most solves before their tries must not end these (measured:
    // 3,588 of 4,000 found, 3,576 before the fold search; 3,637 without the bounds, the rest
    // grazing the ball's rim; the 85% floor is a regression guard, not a proof, set from the
    // 3,576 at 339ae2a). And
    // `may_pass` and `Ball::widest`, which rule out a hit for a whole sphere of lights, must
    // never rule out one the solve finds a passage from, to a point anywhere inside that sphere.
    let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.5);
    let mut rng = SmallRng::seed_from_u64(11);
    let (mut taken, mut found) = (0, 0);
    while taken < 4000 {
        let from = (1.05 + 6.95 * uniform(&mut rng)) * random_unit_vector(&mut rng);
        let aim = 0.999 * random_unit_vector(&mut rng);
        let Some(passage) = ball.pass(from, (aim - from).normalize()) else { continue };
        let to = passage.exit + (1.5 + 8.5 * uniform(&mut rng)) * passage.out;
        taken += 1;
        let mut this = false;
        let mut any = false;
        solve(&ball, from, to, |other| {
            any = true;
            this |= (other.entry - passage.entry).length() <= 1e-3;
        });
        found += usize::from(this);
        if any {
            let spread = 2.0 * uniform(&mut rng);
            let lamp = to + spread * uniform(&mut rng) * random_unit_vector(&mut rng);
            let (inward, outward) = (ball.sphere.center - from, lamp - ball.sphere.center);
            let apart = inward.angle_between(outward);
            let widest = ball.widest(Lamps { center: lamp, radius: spread });
            assert!(apart <= widest, "Ball::widest rules out {from} to {to}: {apart} > {widest}");
            assert!(
                may_pass(&ball, from, Lamps { center: lamp, radius: spread }),
                "may_pass rules out {from} to {to} in ({lamp}, {spread})"
            );
        }
    }
    assert!(found * 100 >= taken * 85, "the solve found {found} of {taken} passages");
}

#[test]
fn no_passage_leaves_wider_than_ball_widest() {
    // Every traced passage (starts from just off the surface to 5 radii, rays anywhere across
    // the ball, the rim included) to a target from just past its exit to 3 radii on, inside a
    // sphere of lamps of radius up to 1: seen from the centre, the way in and the way out to
    // the lamps' centre are never further apart than `Ball::widest`, by which
    // `Casters::may_light` rules hits out before any solve. (Loose on purpose, one product
    // per hit: measured, the closest passage stays 0.93 rad inside it.)
    let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.5);
    let mut rng = SmallRng::seed_from_u64(17);
    let mut traced = 0;
    while traced < 20_000 {
        let from = (1.001 + 4.0 * uniform(&mut rng).powi(2)) * random_unit_vector(&mut rng);
        let Some(passage) = ball.pass(from, (random_unit_vector(&mut rng) - from).normalize()) else {
            continue;
        };
        traced += 1;
        let to = passage.exit + (1e-3 + 3.0 * uniform(&mut rng)) * passage.out;
        let spread = uniform(&mut rng);
        let lamp = to + spread * uniform(&mut rng) * random_unit_vector(&mut rng);
        let apart = (ball.sphere.center - from).angle_between(lamp - ball.sphere.center);
        let widest = ball.widest(Lamps { center: lamp, radius: spread });
        assert!(
            apart <= widest,
            "from {from} through the ball to {to} in ({lamp}, {spread}): {apart} > {widest}"
        );
    }
}
