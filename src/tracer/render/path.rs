//! One pixel sample's path: the book's `ray_color`, as a loop, with the second book's
//! emission, time and media, and the third book's ways of finding the lights
//! (`--light-sampling`, `lighting/`). [`super::accumulate_tile`] calls it once per sample.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::lighting::manifold::{self, Passing, manifold_event};
use crate::tracer::lighting::{glint, lobe_pdf, mixture_bounce, next_event, power_heuristic, shadow_chance};
use crate::tracer::lights::LightSampling;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::render::{ROULETTE_AFTER, RenderSettings};
use crate::tracer::sampling::independent::mix;
use crate::tracer::sampling::keys::SHADOW_KEY;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::Lobe;
use crate::tracer::world::object::Probe;

/// The radiance arriving along `ray`: the book's `ray_color`, as a loop. A path casts at most
/// `settings.max_depth` rays; one still bouncing after that contributes black. Adds the number
/// of rays cast to `rays`. Forced inline into the render loop: left to the compiler, `final`
/// took 1.8% more instructions (`results/perf.md`).
///
/// Without `WORLD` (a first-book scene), each ray's closest hit is found by `closest_hit` (the
/// scene's sphere search, `|ray| scene.hit(ray, Real::INFINITY)`, except in the Embree
/// benchmark), and nothing emits. With `WORLD`, the scene's world is searched with a
/// [`Probe`] carrying `time` (and, in a scene with media, a seed drawn for each ray), and every
/// surface hit adds what it emits, weighted by the path's throughput: the first hit too if
/// `first_light`, else the caller counts what the camera sees directly (by
/// [`Edges`](crate::tracer::lighting::edges::Edges)' points).
#[inline(always)]
pub fn trace<R: SampleRng + ?Sized, const WORLD: bool>(
    scene: &Scene,
    closest_hit: &impl Fn(&Ray) -> Option<Hit>,
    (mut ray, first_light): (Ray, bool),
    start: Probe,
    settings: &RenderSettings,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    // Where the lights are sampled (a second-book scene with lights, and not `bsdf`).
    let aiming =
        if WORLD && !scene.lights().is_empty() { settings.light_sampling } else { LightSampling::Bsdf };
    // The previous hit's point, its material's density for the bounce that led here and the
    // chance its shadow ray had, if that bounce was weighed against a light sample (MIS): an
    // emitter it reaches is then weighted by the power heuristic. Otherwise it counts whole.
    let mut weighed: Option<(Vec3, Real, Real)> = None;
    // Under `mis`, with glass balls and lights: each diffuse hit also aims at a light through
    // a ball (`lighting/manifold.rs`), and its bounce is followed through a ball to weigh a
    // light it meets there against that.
    let caustics = WORLD && aiming == LightSampling::Mis && !scene.casters().is_empty();
    let mut passing: Option<Passing> = None;
    // The weight of the light met next: below 1 after glass reflected the path (under `mis`,
    // `lighting::glint` counts that light).
    let mut mirrored = 1.0;
    for cast in 1..=settings.max_depth {
        *rays += 1;
        let medium_seed =
            if WORLD && scene.has_media() { mix(start.medium_seed ^ u64::from(cast)) } else { 0 };
        let found =
            if WORLD { scene.hit_world(&ray, &Probe { medium_seed, ..start }) } else { closest_hit(&ray) };
        let Some(hit) = found else {
            let sky = throughput * scene.background.radiance(ray.dir);
            return if WORLD { radiance + sky } else { sky };
        };
        rng.bounce(cast - 1);
        let material = scene.material(&hit);
        if WORLD {
            let emitted = if cast > 1 || first_light { material.emitted(&hit) } else { Vec3::ZERO };
            let weight = match (weighed, passing) {
                _ if emitted == Vec3::ZERO => 1.0,
                (Some((from, bsdf_pdf, chance)), _) => power_heuristic(
                    bsdf_pdf,
                    chance * scene.lights().pdf_of_hit(from, &hit, emitted, start.time),
                ),
                (None, Some(passing)) => passing.weight(scene, &hit, emitted),
                (None, None) => 1.0,
            };
            radiance += throughput * emitted * (weight * mirrored);
            mirrored = 1.0;
        }
        let Some(mut scatter) = material.scatter(ray.dir, &hit, &scene.textures, rng) else {
            return radiance;
        };
        weighed = None;
        // Not on a path's last ray: the reflection could not have met a light either.
        if aiming == LightSampling::Mis && cast < settings.max_depth {
            let probe = Probe { medium_seed, ..start };
            let (shown, next) = glint(scene, (&hit, material), (ray.dir, scatter.direction), probe, rays);
            (radiance, mirrored) = (radiance + throughput * shown, next);
        }
        // Tested first, so that a first-book scene (always `Bsdf`) has no further work here.
        let lobe = if aiming == LightSampling::Bsdf { None } else { material.lobe() };
        if caustics {
            passing = if lobe.is_some() {
                None
            } else {
                passing.and_then(|p| p.next(scene, &hit, scatter.direction))
            };
        }
        if let Some(lobe) = lobe {
            rng.light(cast - 1);
            match aiming {
                LightSampling::Mis if cast < settings.max_depth => {
                    let shadow = Probe { medium_seed: medium_seed ^ SHADOW_KEY, ..start };
                    let carried = throughput * scatter.attenuation;
                    // One coin, the light sample's first number, for the shadow ray and the
                    // aims through glass: each is taken where it falls below its own chance.
                    let (coin, aim) = (uniform(rng), shadow_chance(carried));
                    let direct = next_event(scene, &hit, lobe, shadow, (coin, aim), rng, rays);
                    radiance += carried * direct;
                    let bsdf_pdf = lobe_pdf(lobe, scatter.direction, hit.normal);
                    weighed = Some((hit.departure(), bsdf_pdf, aim));
                    if caustics && lobe == Lobe::Cosine && cast + manifold::RAYS <= settings.max_depth {
                        // Fewer solves where the path carries little (`lighting/manifold.rs`).
                        let chance = (2.0 * carried.max_element()).min(1.0);
                        let focused =
                            manifold_event(scene, &hit, (cast - 1, coin, chance), shadow, rng, rays);
                        radiance += carried * focused;
                        let taken = (cast - 1, chance);
                        passing =
                            Some(Passing::leave(scene, hit.departure(), scatter.direction, bsdf_pdf, taken));
                    }
                }
                LightSampling::Mixture => {
                    let goes_on = mixture_bounce(scene.lights(), &hit, start.time, lobe, &mut scatter, rng);
                    if !goes_on {
                        return radiance;
                    }
                }
                _ => {}
            }
        }
        throughput *= scatter.attenuation;
        if settings.stop_black_paths && throughput == Vec3::ZERO {
            return radiance;
        }
        if settings.roulette && cast >= ROULETTE_AFTER {
            let survive = throughput.max_element().min(0.95);
            if uniform(rng) >= survive {
                return radiance;
            }
            throughput /= survive;
        }
        ray = hit.spawn(scatter.direction);
    }
    radiance
}
