//! Path guiding (`--guiding on`, `src/tracer/guiding/`): the guide draws directions by the
//! density it states and the guided bounce by the mixture's (χ² tests, as `sampling.rs`'s:
//! each also rejects the stated density tilted by ±5% across the sphere, the power it
//! asserts; measured when written, each rejected a tilt of ±2.25%); the statistics sum to the same guide whatever order and threads add them; a
//! guided image is the same bits under every scheduler, thread count and tile size; and a
//! scene without lights renders as without guiding. Whether a guided render agrees with
//! `bsdf` is `agreement.rs`'s; whether its shards merge into it, `shard.rs`'s.

mod chi_squared;
mod deadline;

use std::ops::Range;
use std::sync::Arc;

use chi_squared::{Cone, assert_fits, front_hit};
use deadline::within;
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::files::image::Image;
use raypool::scenes::builtin::builtin_scene;
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, Scheduler, render};
use raypool::schedule::progressive::{Pass, Sums};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::guiding::bounce::{GUIDED_SHARE, guided_bounce};
use raypool::tracer::guiding::guide::Guide;
use raypool::tracer::guiding::learning::Learning;
use raypool::tracer::guiding::spatial::facing;
use raypool::tracer::guiding::{Guiding, bounds};
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::aabb::Aabb;
use raypool::tracer::math::real::{Real, Vec3, to_f64};
use raypool::tracer::render::{RenderJob, RenderSettings};
use raypool::tracer::sampling::warp::{random_unit_vector, uniform};
use raypool::tracer::shading::material::Lobe;

const Z_BINS: usize = 16;
const PHI_BINS: usize = 32;
const SAMPLES: usize = 200_000;
/// The significance each χ² test rejects at: 1%, split over the two (Bonferroni).
const ALPHA: f64 = 0.01 / 2.0;

/// Where the tests' guide learns: the middle of a unit box.
const POINT: Vec3 = Vec3::splat(0.5);

/// A floor's normal, and the facing it has.
const UP: Vec3 = Vec3::Y;

/// The light the tests' guide learns at a surface facing up: a bright lamp about a tilted
/// axis, a dimmer patch beside it, a little everywhere else above, nothing below.
fn light(d: Vec3) -> Real {
    let lamp = Vec3::new(0.3, 0.9, -0.2).normalize();
    let patch = Vec3::new(-0.8, 0.4, 0.4).normalize();
    match d.y {
        y if y <= 0.0 => 0.0,
        _ if d.dot(lamp) > 0.97 => 20.0,
        _ if d.dot(patch) > 0.8 => 2.0,
        _ => 0.2,
    }
}

/// A guide learnt from `light` at [`POINT`] on a surface facing up, in three passes of
/// 200,000 directions each, each pass drawing half its directions from the last pass's guide
/// (so the quadtree is cut deep where the lamp is, as a render's is).
fn trained() -> Guide {
    let mut rng = SmallRng::seed_from_u64(17);
    let up = facing(Some(UP));
    let mut learning = Learning::new(Aabb { min: Vec3::ZERO, max: Vec3::ONE }, 1);
    let mut guide: Option<Guide> = None;
    for _ in 0..3 {
        for _ in 0..200_000 {
            let sphere = 0.25 / std::f64::consts::PI as Real;
            let directions = guide.as_ref().map(|g| g.directions(POINT, up)).filter(|d| d.total() > 0.0);
            let (dir, pdf) = match directions {
                Some(d) => {
                    let u = [uniform(&mut rng), uniform(&mut rng)];
                    let dir = if uniform(&mut rng) < 0.5 {
                        d.sample(u).unwrap().0
                    } else {
                        random_unit_vector(&mut rng)
                    };
                    (dir, 0.5 * d.pdf(dir) + 0.5 * sphere)
                }
                None => (random_unit_vector(&mut rng), sphere),
            };
            learning.record(POINT, up, dir, light(dir) / pdf);
        }
        let learnt = learning.finish();
        learning = Learning::after(&learnt, 1);
        guide = Some(learnt);
    }
    guide.unwrap()
}

/// Counts `SAMPLES` directions from `draw` in bins of equal solid angle, against `pdf` and
/// `pdf` tilted by ±5%.
fn assert_draws_follow(name: &str, mut draw: impl FnMut(&mut SmallRng) -> Vec3, pdf: &dyn Fn(Vec3) -> f64) {
    let mut rng = SmallRng::seed_from_u64(name.len() as u64 * 7919);
    let sphere = Cone::sphere(Z_BINS, PHI_BINS);
    let mut observed = vec![0usize; sphere.len()];
    for _ in 0..SAMPLES {
        observed[sphere.bin(draw(&mut rng)).expect("the whole sphere")] += 1;
    }
    let tilted = |d: Vec3| pdf(d) * (1.0 + 0.05 * sphere.side(d));
    let expected = sphere.expected(pdf, SAMPLES, 64);
    let wrong = sphere.expected(&tilted, SAMPLES, 64);
    // Absolute counts: the densities integrate to 1 (no degree of freedom is fitted).
    assert_fits(name, &observed, (&expected, &wrong), 0, ALPHA);
}

/// The learnt quadtree draws by `Directions::pdf` (and `sample` returns that density with
/// each direction). Its cut is deep at the lamp, so the midpoint rule integrates it on 64 × 64
/// points per bin.
#[test]
fn the_guide_draws_directions_by_the_density_it_states() {
    let guide = trained();
    let directions = guide.directions(POINT, facing(Some(UP)));
    assert!(directions.shape().len() > 20, "a cut deeper than a few levels: {}", directions.shape().len());
    let draw = |rng: &mut SmallRng| {
        let (dir, pdf) = directions.sample([uniform(rng), uniform(rng)]).expect("a learnt guide");
        assert!(
            (pdf - directions.pdf(dir)).abs() <= 1e-3 * pdf,
            "{dir}: drawn with {pdf}, stated {}",
            directions.pdf(dir)
        );
        dir
    };
    assert_draws_follow("the guide's quadtree", draw, &|d| f64::from(directions.pdf(d)));
}

/// The guided bounce at a floor point: the material's cosine draw, replaced by the guide's
/// with chance `GUIDED_SHARE`, follows the mixture `share · p_guide + (1 − share) · cos/π`,
/// the density it returns and weighs the bounce by.
#[test]
fn the_guided_bounce_draws_the_mixture_of_the_guide_and_the_material() {
    let guide = trained();
    let hit = front_hit(POINT, UP);
    let directions = guide.directions(POINT, facing(Some(UP)));
    let share = f64::from(GUIDED_SHARE);
    let mixture = move |d: Vec3| {
        share * f64::from(directions.pdf(d)) + (1.0 - share) * f64::from(d.y.max(0.0)) / std::f64::consts::PI
    };
    let draw = |rng: &mut SmallRng| {
        let mut dir = (UP + random_unit_vector(rng)).normalize();
        let drawn = guided_bounce(Some(&guide), &hit, Lobe::Cosine, &mut dir, rng);
        let stated = mixture(dir);
        assert!((f64::from(drawn.pdf) - stated).abs() <= 1e-3 * stated, "{dir}: {drawn:?} against {stated}");
        dir
    };
    assert_draws_follow("the guided bounce", draw, &mixture);
}

/// The statistics are integers added atomically: the same records, added in another order by
/// four threads at once, make the same guide, bit for bit.
#[test]
fn the_statistics_make_the_same_guide_in_any_order_from_any_threads() {
    let mut rng = SmallRng::seed_from_u64(3);
    let bounds = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
    let records: Vec<(Vec3, usize, Vec3, Real)> = (0..100_000)
        .map(|k| {
            let point = Vec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng));
            let dir = random_unit_vector(&mut rng);
            (point, k % 7, dir, light(dir) * uniform(&mut rng) * 3.7)
        })
        .collect();
    // Cut into a few cells first, so the records spread over cells and quadtrees.
    let first = Learning::new(bounds, 1);
    records.iter().for_each(|&(p, f, d, e)| first.record(p, f, d, e));
    let cut = first.finish();
    let in_order = Learning::after(&cut, 1);
    records.iter().for_each(|&(p, f, d, e)| in_order.record(p, f, d, e));
    let shuffled = Learning::after(&cut, 1);
    within("four threads to add the records", move || {
        std::thread::scope(|scope| {
            for t in 0..4 {
                let (records, shuffled) = (&records, &shuffled);
                scope.spawn(move || {
                    records
                        .iter()
                        .rev()
                        .skip(t)
                        .step_by(4)
                        .for_each(|&(p, f, d, e)| shuffled.record(p, f, d, e))
                });
            }
        });
        assert!(shuffled.finish() == in_order.finish(), "the guide depends on the order of the records");
    });
}

/// A small guided cornell: 24 × 24, depth 10, 8 samples (passes of 1, 1, 2 and 4).
fn guided(mode: Schedule, threads: usize, tile: u32, guiding: Option<Guiding>) -> Image {
    let scene = builtin_scene("cornell", 0).unwrap().to_scene();
    let settings =
        RenderSettings { width: 24, height: 24, spp: 8, max_depth: 10, guiding, ..Default::default() };
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, threads, tile, Arc::new(|_| {})));
    render(&frame, &mode).image
}

fn bits(image: &Image) -> Vec<[u64; 3]> {
    image.pixels.iter().map(|p| [p.x, p.y, p.z].map(|c| to_f64(c).to_bits())).collect()
}

/// Every scheduler, at 1 and 3 threads, in tiles of 5 and 16 pixels: the same bits. The
/// threads add to the same statistics in a different order every run; the guide they make,
/// and so every pixel, cannot tell.
#[test]
fn a_guided_render_is_the_same_bits_under_every_scheduler_thread_count_and_tile_size() {
    within("the guided renders to finish", || {
        let guiding = Some(Guiding { pilot: 4 });
        let first = bits(&guided(Schedule::Serial, 1, 16, guiding));
        assert!(first != bits(&guided(Schedule::Serial, 1, 16, None)), "guiding changed nothing");
        for mode in Schedule::ALL {
            for (threads, tile) in [(1, 5), (3, 5), (3, 16)] {
                let image = guided(mode, threads, tile, guiding);
                assert!(
                    bits(&image) == first,
                    "{} at {threads} threads, tiles of {tile}: other bits",
                    mode.name()
                );
            }
        }
    });
}

/// `final` has no lights: it takes no guide, and renders as without guiding.
#[test]
fn a_scene_without_lights_renders_as_without_guiding() {
    within("final to render", || {
        let scene = builtin_scene("final", 1).unwrap().to_scene();
        let at = |guiding| {
            let settings = RenderSettings { width: 32, height: 20, spp: 4, guiding, ..Default::default() };
            let rng = RngSource::new(&settings, RngChoice::PerSample);
            let frame = Frame::new(RenderJob::new(scene.clone(), settings), rng, 2, 16, Arc::new(|_| {}));
            bits(&render(&Arc::new(frame), &Schedule::Stealing).image)
        };
        assert!(at(Some(Guiding { pilot: 2 })) == at(None), "final changed under --guiding on");
    });
}

/// A pass draws the same numbers whether it learns or not: learning only records what the
/// paths found, so samples 0..4 of cornell, with no guide and then with one learnt from
/// sample 0, are the same bits with statistics gathered or not (under `bsdf` with roulette,
/// a learning pass once switched to the light's numbers before the roulette's draw; the
/// viewer's passes learn where `render`'s last pass does not).
#[test]
fn a_pass_draws_the_same_numbers_whether_it_learns_or_not() {
    within("the passes to render", || {
        let scene = builtin_scene("cornell", 0).unwrap().to_scene();
        for (light_sampling, roulette) in [(LightSampling::Bsdf, true), (LightSampling::Mis, true)] {
            let settings = RenderSettings {
                width: 24,
                height: 24,
                spp: 4,
                max_depth: 10,
                light_sampling,
                roulette,
                ..Default::default()
            };
            let rng = RngSource::new(&settings, RngChoice::PerSample);
            let frame = Frame::new(RenderJob::new(scene.clone(), settings), rng, 2, 8, Arc::new(|_| {}));
            let pass = |samples: Range<u32>, guide: Option<Arc<Guide>>, learning: Option<Arc<Learning>>| {
                let job = frame.job().guided(guide, learning);
                let pass = Pass { samples, sums: Sums::default(), counts: None };
                let frame = Arc::new(frame.clone().with_job(job).with_pass(pass));
                bits(&frame.assemble(&Schedule::Stealing.render(&frame)).expect("every tile"))
            };
            let learning = Arc::new(Learning::new(bounds(&scene), 1));
            let learns = pass(0..1, None, Some(Arc::clone(&learning)));
            assert!(learns == pass(0..1, None, None), "{light_sampling:?}: learning changed the first pass");
            let guide = Arc::new(learning.finish());
            let learning = Some(Arc::new(Learning::after(&guide, 3)));
            let learns = pass(1..4, Some(Arc::clone(&guide)), learning);
            assert!(
                learns == pass(1..4, Some(guide), None),
                "{light_sampling:?}: learning changed a guided pass"
            );
        }
    });
}
