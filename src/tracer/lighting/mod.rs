//! **Lighting**: how a path at a diffuse surface finds the scene's lights (`--light-sampling`),
//! the third book's importance sampling and pbrt's multiple importance sampling: the
//! estimators, where the `lights` room holds what they aim at (the lights, and the density
//! with which each point and direction is drawn towards them). The render loop (`render.rs`)
//! calls these at each diffuse hit, and [`edges`] where a pixel may see a light directly.
//!
//! - `bsdf`: the material's bounce only; a light counts when a bounce happens to hit it.
//! - `mixture`: the bounce drawn half the time towards a light ([`mixture_bounce`]) and
//!   weighted by the mixture's density `½·p_light + ½·cos/π`, so the estimate stays unbiased.
//! - `mis`: a shadow ray to a light at every diffuse hit and every scattering in fog
//!   ([`next_event`]; where the path carries little, by a chance, [`shadow_chance`]), and
//!   the material's bounce as well; each of the two ways of finding a light is weighted by
//!   the power heuristic ([`power_heuristic`]) against the other's density, so a light found
//!   both ways is counted once, and never with more noise than the better of the two (Veach 1997).
//!   In a scene with glass balls, a diffuse hit also aims at a light *through* a ball
//!   ([`manifold`]: manifold next-event estimation, solved in [`passage`]), weighed the same
//!   way against the bounce that crosses the ball and meets the light.
//! - every setting but `bdpt`: where a pixel may see a light, extra points of the pixel for
//!   the light it sees directly ([`edges`]).
//!
//! Invariant: a light's point reached by a shadow ray and the same point met by a bounce are
//! weighed by the same density ([`Lights::pdf_of_point`]), and a path's last ray gets no
//! shadow ray (it could not have met a light by bouncing either), so the three settings
//! estimate the same image at every `max_depth`.
//!
//! [`Lights::pdf_of_point`]: crate::tracer::lights::power::Lights::pdf_of_point

pub mod manifold;
pub mod passage;
pub mod edges;

use crate::tracer::geometry::hit::Hit;
use crate::tracer::lights::power::Lights;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::keys::GLINT_KEY;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::{Lobe, Material, Scatter};
use crate::tracer::world::object::Probe;

/// The power heuristic's weight (β = 2) for a sample drawn with density `chosen` that the
/// other strategy would have drawn with density `other`.
#[inline]
pub fn power_heuristic(chosen: Real, other: Real) -> Real {
    let (a, b) = (chosen * chosen, other * other);
    if a + b > 0.0 { a / (a + b) } else { 0.0 }
}

/// The density with which a material of `lobe` scatters into the unit direction `dir` at a
/// hit with normal `normal`; for both lobes also the scattered light's factor per unit albedo
/// (a Lambertian's `cos/π`, the phase function's `1/4π`).
#[inline]
pub fn lobe_pdf(lobe: Lobe, dir: Vec3, normal: Vec3) -> Real {
    match lobe {
        Lobe::Cosine => dir.dot(normal).max(0.0) / PI,
        Lobe::Sphere => 0.25 / PI,
    }
}

/// The chance that a hit whose light reaches the camera multiplied by `carried` (the path's
/// throughput times the hit's albedo) casts its shadow ray: 1 while the brightest channel
/// carries at least 1/8, less below. Deep in a path a shadow ray costs as much as near the
/// camera and adds little; on `cornell`, skipping them so (and counting those cast `1/chance`
/// times) saves time at the same squared error (`results/lights.md`).
#[inline]
pub fn shadow_chance(carried: Vec3) -> Real {
    (8.0 * carried.max_element()).min(1.0)
}

/// A sample taken by chance: where `coin`, uniform in `[0, 1)`, falls below `chance`, and then
/// counted `1/chance` times (Russian roulette on a sample: Arvo and Kirk 1990).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Odds {
    /// The number drawn.
    pub coin: Real,
    /// The chance that the sample is taken.
    pub chance: Real,
}

/// Next-event estimation: light arriving at `hit` (of a material that scatters by `lobe`)
/// from a light sample, per unit albedo. One shadow ray towards a point drawn on a light's
/// front, cast by `odds` ([`shadow_chance`]); if nothing stands between (no surface, no scattering in a
/// medium on the way), the light's emission times the lobe's factor over the sample's density
/// and the chance, weighted by the power heuristic against the lobe's density. The weight
/// counts the light sample's density times the chance (the bounce that meets the light weighs
/// it so too), so the two weights of a point still sum to 1. Counts the shadow ray in `rays`.
#[inline]
pub fn next_event<R: SampleRng + ?Sized>(
    scene: &Scene,
    hit: &Hit,
    lobe: Lobe,
    probe: Probe,
    odds: Odds,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let Odds { coin, chance } = odds;
    // A skipped shadow ray draws no light point either.
    if coin >= chance {
        return Vec3::ZERO;
    }
    let lights = scene.lights();
    let Some(toward) = lights.sample(hit.departure(), probe.time, rng) else { return Vec3::ZERO };
    let factor = lobe_pdf(lobe, toward.dir, hit.normal);
    if factor <= 0.0 || toward.emitted == Vec3::ZERO {
        return Vec3::ZERO;
    }
    *rays += 1;
    // Visible if nothing stands between, up to just short of the light's point: any
    // blocker will do, so the search ends at the first.
    let (shadow, reach) = Ray::towards(hit.spawn(toward.dir).origin, toward.point);
    if scene.occluded(&shadow, reach, &probe) {
        return Vec3::ZERO;
    }
    // Weighed as a bounce that met this point would weigh it (`render.rs`), so the two
    // weights of the point sum to 1.
    let light_pdf = lights.pdf_of_sample(hit.departure(), &toward, probe.time);
    toward.emitted * (factor / (toward.pdf * chance)) * power_heuristic(chance * light_pdf, factor)
}

/// The light that glass met from outside at `hit` shows by reflection (`mis`), found by a ray
/// of its own, and the weight of the light the path meets next. The Fresnel coin sends a path
/// into the reflection with chance `R`, so a lamp seen in the glass is otherwise a few samples
/// of full brightness among many of none: on `cornell`, the pixels where the ball mirrors the
/// lamp, and the light it throws on the walls by reflection. Instead the reflection's light
/// counts `R` times, every sample: from the mirror ray cast here if the path went `onward`
/// into the glass, else where the path meets it next, weighted `R` instead of 1. Either way
/// the estimate is `R × L`, unbiased. Other hits: nothing, weight 1. Counts the mirror ray in
/// `rays`.
#[inline]
pub fn glint(
    scene: &Scene,
    hit: &Hit,
    material: &Material,
    incoming: Vec3,
    onward: Vec3,
    probe: Probe,
    rays: &mut u64,
) -> (Vec3, Real) {
    let Some((mirror, share)) = material.glint(incoming, hit) else { return (Vec3::ZERO, 1.0) };
    if onward.dot(hit.normal) > 0.0 {
        return (Vec3::ZERO, share);
    }
    // Every emitter lies in the lights' box: a mirror ray that misses it needs no casting.
    let ray = hit.spawn(mirror);
    if !scene.lights().bounds.hit(ray.origin, ray.dir.recip(), Real::INFINITY) {
        return (Vec3::ZERO, 1.0);
    }
    *rays += 1;
    let probe = Probe { medium_seed: probe.medium_seed ^ GLINT_KEY, ..probe };
    let Some(lit) = scene.hit_world(&ray, &probe) else { return (Vec3::ZERO, 1.0) };
    (share * scene.material(&lit).emitted(&lit), 1.0)
}

/// The third book's mixture: with probability ½ the bounce's direction is replaced by one
/// towards a light, and the bounce is weighted by `p_lobe / (½·p_light + ½·p_lobe)` instead
/// of 1 (its attenuation is the material's albedo times that). `false` ends the path: a
/// direction below the surface, or a light that cannot be aimed at from here (inside its
/// sphere; its density is then 0 in `pdf`, so ending the path keeps the estimate unbiased).
#[inline]
pub fn mixture_bounce<R: SampleRng + ?Sized>(
    lights: &Lights,
    hit: &Hit,
    time: Real,
    lobe: Lobe,
    scatter: &mut Scatter,
    rng: &mut R,
) -> bool {
    let light_density = if uniform(rng) < 0.5 {
        let Some(toward) = lights.sample(hit.departure(), time, rng) else { return false };
        scatter.direction = toward.dir;
        lights.pdf_toward(hit.departure(), &toward, time)
    } else {
        lights.pdf(hit.departure(), scatter.direction, time)
    };
    let lobe_density = lobe_pdf(lobe, scatter.direction, hit.normal);
    let mixture = 0.5 * light_density + 0.5 * lobe_density;
    if lobe_density <= 0.0 || mixture <= 0.0 {
        return false;
    }
    scatter.attenuation *= lobe_density / mixture;
    true
}
