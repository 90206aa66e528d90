//! The disc as a light (`lights/disc.rs`): its points are drawn uniformly by area with the
//! density the other flat lights' points have, checked against answers known in closed form
//! (the solid angle a disc fills seen from its axis, the spread of points over its area); and
//! a room lit only by discs renders the same mean image under every `--light-sampling`.

mod chi_squared;
mod deadline;
mod rooms;

use deadline::within;
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::tracer::geometry::disc::Disc;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::lights::power::Lights;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::math::transform::Transform;
use raypool::tracer::render::RenderSettings;
use raypool::tracer::sampling::warp::random_unit_vector;
use raypool::tracer::shading::material::Material;
use raypool::tracer::world::object::{Group, Instance, Object, Probe};
use rooms::{
    CAMERA, assert_every_schedule_renders_alike, assert_within_five_errors, inward_cube, parse,
    quadrant_means,
};

/// Three discs about the origin, each on its axis seen from there: `(distance, radius, luminance
/// of its emission)`, in order: above, facing down (grey, 4); along +x, facing the origin, placed
/// by an instance (turned 30° and moved; orange, luminance 11.765); beyond −z, facing away (its
/// back seen: grey, 4).
const DISCS: [(f64, f64, f64); 3] = [(2.0, 1.0, 4.0), (3.0, 0.8, 11.765), (2.5, 0.6, 4.0)];

/// The lights of the three [`DISCS`], and the objects.
fn discs() -> (Lights, Vec<Object>) {
    let materials = [
        Material::DiffuseLight { emit: Vec3::splat(4.0), albedo: 0.0 },
        Material::DiffuseLight { emit: Vec3::new(20.0, 10.0, 5.0), albedo: 0.0 },
    ];
    let above = Disc::new(Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 1.0, 0).unwrap();
    let place = Transform::rotate_y(30.0).then_translate(Vec3::new(3.0, 0.0, 0.0));
    let turned = Disc::new(Vec3::ZERO, place.inverse_vector(-Vec3::X), 0.8, 1).unwrap();
    let placed = Instance::new(place, Group::new(vec![Object::shape(turned)]));
    let away = Disc::new(Vec3::new(0.0, 0.0, -2.5), -Vec3::Z, 0.6, 0).unwrap();
    let objects = vec![Object::shape(above), Object::Instance(Box::new(placed)), Object::shape(away)];
    (Lights::new(&objects, &materials), objects)
}

/// The solid angle of a disc of radius `r` seen from `h` along its axis.
fn solid_angle(h: f64, r: f64) -> f64 {
    2.0 * std::f64::consts::PI * (1.0 - h / (h * h + r * r).sqrt())
}

/// Mean and standard error of `values`.
fn mean_and_spread(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// `E[1/pdf]` over 10⁶ samples from the origin against the three discs' solid angles in
/// closed form, within 5 standard errors: that catches an error of 0.40% of the whole (printed;
/// measured at this file's commit). Each sample's point is where the ray towards it
/// meets a disc, it gives off light exactly when that is a front face, and the density `pdf`
/// and `pdf_of_point` give it are the sample's own: exact checks, no statistics.
#[test]
fn a_disc_is_drawn_with_the_density_that_covers_its_solid_angle() {
    let (lights, objects) = discs();
    assert_eq!(lights.len(), 3, "every glowing disc is a light, the placed one too");
    let probe = Probe::default();
    let mut rng = SmallRng::seed_from_u64(1);
    let (mut inverse, mut fronts) = (Vec::new(), 0);
    for _ in 0..1_000_000 {
        let sample = lights.sample(Vec3::ZERO, 0.0, &mut rng).expect("the origin sees every disc");
        inverse.push(1.0 / f64::from(sample.pdf));
        if inverse.len() > 4_000 {
            continue;
        }
        let ray = Ray::new(Vec3::ZERO, sample.dir);
        let hits = objects.iter().filter_map(|o| o.hit(&ray, Real::INFINITY, &probe));
        let hit = hits.min_by(|a, b| a.t.total_cmp(&b.t)).expect("the ray meets the disc drawn");
        assert!((hit.point - sample.point).length() < 1e-4, "met {:?}, drew {:?}", hit.point, sample.point);
        assert_eq!(sample.emitted != Vec3::ZERO, hit.front_face, "front only: {sample:?}");
        let along = lights.pdf(Vec3::ZERO, sample.dir, 0.0);
        let emitted = if hit.front_face { sample.emitted } else { Vec3::ZERO };
        let at = lights.pdf_of_point(Vec3::ZERO, hit.point, hit.normal, emitted, 0.0);
        assert!((along / sample.pdf - 1.0).abs() < 1e-3, "pdf {along}, sample {}", sample.pdf);
        // The back of a disc gives off nothing, so `pdf_of_point` counts it as no light's.
        if hit.front_face {
            assert!((at / sample.pdf - 1.0).abs() < 2e-3, "pdf_of_point {at}, sample {}", sample.pdf);
        }
        fronts += usize::from(hit.front_face);
    }
    assert!((2_000..3_900).contains(&fronts), "{fronts} of 4,000 on a front: the back one tried too");
    let covered: f64 = DISCS.iter().map(|&(h, r, _)| solid_angle(h, r)).sum();
    let (mean, error) = mean_and_spread(&inverse);
    eprintln!("E[1/pdf] = {mean:.5} sr of {covered:.5}: catches an error of {:.2}%", 500.0 * error / covered);
    assert!((mean - covered).abs() < 5.0 * error, "E[1/pdf] {mean} ± {error}, covered {covered}");
}

/// χ² goodness of fit, as `tests/sampling.rs` checks the other lights: from the origin (on the
/// first disc's axis) and from a point that sees every disc at a slant, the directions a light
/// sample draws, counted in 16 × 32 bins of equal solid angle, follow `Lights::pdf`; and the
/// same counts reject that density tilted by ±5% across the sphere (the power the test states;
/// the smallest tilt rejected is printed).
#[test]
fn a_disc_lights_directions_follow_the_density_it_states() {
    let (lights, _) = discs();
    for from in [Vec3::ZERO, Vec3::new(0.4, -0.3, 0.5)] {
        let pdf = |d: Vec3| f64::from(lights.pdf(from, d, 0.0));
        chi_squared::assert_draws_follow(
            &format!("disc lights from {from}"),
            |rng| lights.sample(from, 0.0, rng).map(|s| s.dir),
            &pdf,
            0.01 / 2.0,
        );
    }
}

/// `∫ pdf dω = 1` over 4·10⁶ uniform directions, within 5 standard errors: that catches an
/// error of 1.2% (printed; measured at this file's commit).
#[test]
fn a_discs_density_integrates_to_one_over_all_directions() {
    let (lights, _) = discs();
    let mut rng = SmallRng::seed_from_u64(2);
    let values: Vec<f64> = (0..4_000_000)
        .map(|_| {
            f64::from(lights.pdf(Vec3::ZERO, random_unit_vector(&mut rng), 0.0)) * 4.0 * std::f64::consts::PI
        })
        .collect();
    let (mean, error) = mean_and_spread(&values);
    eprintln!("∫ pdf dω = {mean:.4}: catches an error of {:.1}%", 500.0 * error);
    assert!((mean - 1.0).abs() < 5.0 * error, "∫ pdf dω = {mean} ± {error}");
}

/// Where light paths start (bdpt): on each disc as often as its share of the power, in its
/// plane, within its radius, uniformly by area (the mean squared distance from the centre half
/// the radius squared), facing its front, with the density every flat light's point has. The
/// shares and the mean within 5 standard errors of 10⁶ starts: that catches an error of
/// 0.4–1.4% in a share and 0.4–0.9% in the mean (printed; measured at this file's commit).
#[test]
fn light_paths_start_uniformly_by_area_on_each_disc_in_proportion_to_its_power() {
    let (lights, _) = discs();
    let centres = [Vec3::new(0.0, 2.0, 0.0), Vec3::new(3.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -2.5)];
    let normals = [-Vec3::Y, -Vec3::X, -Vec3::Z];
    let power = DISCS.map(|(_, r, glow)| glow * std::f64::consts::PI * r * r);
    let total: f64 = power.iter().sum();
    let mut rng = SmallRng::seed_from_u64(3);
    let n = 1_000_000;
    let (mut on, mut spread) = ([0usize; 3], [const { Vec::new() }; 3]);
    for _ in 0..n {
        let start = lights.sample_emission(0.0, &mut rng).expect("three lights");
        let k = normals.iter().position(|&m| (start.normal - m).length() < 1e-5).expect("a disc's front");
        let (offset, r) = (start.point - centres[k], DISCS[k].1);
        assert!(offset.dot(normals[k]).abs() < 1e-5 && f64::from(offset.length()) <= r * (1.0 + 1e-5));
        let glow = DISCS[k].2;
        assert!((f64::from(start.pdf) * total / glow - 1.0).abs() < 1e-4, "density {}", start.pdf);
        on[k] += 1;
        spread[k].push(f64::from(offset.length_squared()) / (r * r));
    }
    for k in 0..3 {
        let (share, expected) = (on[k] as f64 / n as f64, power[k] / total);
        let error = (expected * (1.0 - expected) / n as f64).sqrt();
        let (mean, spread_error) = mean_and_spread(&spread[k]);
        eprintln!(
            "disc {k}: share {share:.4} of {expected:.4}, mean d²/r² {mean:.4}: catches {:.1}% and {:.1}%",
            500.0 * error / expected,
            500.0 * spread_error / 0.5
        );
        assert!((share - expected).abs() < 5.0 * error, "disc {k}: share {share}, expected {expected}");
        assert!((mean - 0.5).abs() < 5.0 * spread_error, "disc {k}: mean d²/r² {mean} ± {spread_error}");
    }
}

/// A white room lit only by discs: a grey one under the ceiling facing down and an orange one
/// in a turned, moved group, tilted so that part of its light goes to the wall behind it.
fn disc_room() -> String {
    let grey = "{ kind = \"diffuse_light\", emit = [4.0, 4.0, 4.0] }";
    let orange = "{ kind = \"diffuse_light\", emit = [6.0, 3.0, 1.0] }";
    format!(
        "{CAMERA}[background]\nkind = \"black\"\n{room}\
         [[disc]]\ncenter = [0.0, 0.98, -0.3]\nnormal = [0.0, -1.0, 0.0]\nradius = 0.35\nmaterial = {grey}\n\
         [[group]]\n[group.transform]\nrotate_y = 30.0\ntranslate = [-0.6, -0.5, -0.5]\n\
         [[group.disc]]\ncenter = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.5, 0.0]\nradius = 0.25\nmaterial = {orange}\n",
        room = inward_cube("{ kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }"),
    )
}

/// Each quadrant's mean colour and the whole image's under `mixture`, `mis` and `bdpt` against
/// `bsdf`'s (which draws no light, so has no disc density to get wrong), within 5 combined
/// standard errors from 8 renders of each (256 spp, 16 × 16). The smallest bias caught
/// (printed; measured at this file's commit): 1.6–4.0% of a quadrant's mean (medians 2.0–2.4%)
/// and 1.0–1.5% of the image's. Each setting's bias in the image's green is printed too.
#[test]
fn a_room_lit_by_discs_renders_the_same_image_under_every_light_sampling() {
    within("the disc room under four light samplings", || {
        let scene = parse(&disc_room());
        assert_eq!(scene.lights().len(), 2, "both discs are lights");
        let reference = quadrant_means(&scene, LightSampling::Bsdf, 256);
        let whole = |means: &[(f64, f64)]| means[13];
        for light_sampling in [LightSampling::Mixture, LightSampling::Mis, LightSampling::Bdpt] {
            let other = quadrant_means(&scene, light_sampling, 256);
            let ((a, sa), (b, sb)) = (whole(&reference), whole(&other));
            eprintln!(
                "{}: image green {b:.5} vs bsdf {a:.5}: bias {:+.2}% ± {:.2}%",
                light_sampling.name(),
                100.0 * (b - a) / a,
                100.0 * sa.hypot(sb) / a
            );
            assert_within_five_errors("disc room", ("bsdf", &reference), (light_sampling.name(), &other));
        }
    });
}

/// The disc room renders the same bits under every schedule and thread count, under `mis`
/// (shadow rays to the discs) and `bdpt` (light paths from them, splatted to other pixels).
#[test]
fn the_disc_room_is_the_same_image_under_every_schedule() {
    within("the disc room under every schedule", || {
        let scene = parse(&disc_room());
        for light_sampling in [LightSampling::Mis, LightSampling::Bdpt] {
            let settings = RenderSettings {
                width: 24,
                height: 24,
                spp: 4,
                seed: 5,
                light_sampling,
                ..Default::default()
            };
            let serial = assert_every_schedule_renders_alike(&scene, settings, light_sampling.name());
            assert!(serial.image.pixels.iter().any(|p| p.max_element() > 0.0), "the discs light the room");
        }
    });
}
