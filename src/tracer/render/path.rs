//! One pixel sample's path: the book's `ray_color`, as a loop, with the second book's
//! emission, time and media, and the third book's ways of finding the lights
//! (`--light-sampling`, `lighting/`). [`super::accumulate_tile`] calls it once per sample.
//!
//! [`trace`] is the loop (pbrt-v4's `PathIntegrator::Li`); what a path carries from one ray to
//! the next is a `Path`, and each event of a ray is one of its methods, in the order they
//! happen: the light the ray's hit emits (`emission_met`), the light glass mirrors (`glint`),
//! the bounce followed through a glass ball (`follow`), the light samples at a diffuse hit
//! (`sample_lights`, pbrt-v4's `SampleLd`), the bounce (`bounce`) and Russian roulette
//! (`roulette`); or the sky, where the ray escapes (`escaped`). In a guided pass
//! (`guiding/`), a diffuse-like bounce may be drawn by the guide instead, and a learning
//! pass notes each such bounce on the path's trail.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::guiding::bounce::{guided_bounce, guides};
use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::trail::Trail;
use crate::tracer::lighting::manifold::{self, Passing, manifold_event};
use crate::tracer::lighting::{
    Odds, glint, lobe_pdf, mixture_bounce, next_event, power_heuristic, shadow_chance,
};
use crate::tracer::lights::LightSampling;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::render::{ROULETTE_AFTER, RenderSettings};
use crate::tracer::sampling::independent::mix;
use crate::tracer::sampling::keys::SHADOW_KEY;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::{Lobe, Material, Scatter};
use crate::tracer::world::object::Probe;

/// A sample's camera ray, its time and media seed, and whether its path counts the light
/// that the ray's first hit emits (if not, the caller counts what the camera sees directly,
/// by [`Edges`](crate::tracer::lighting::edges::Edges)' points).
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    /// The ray.
    pub ray: Ray,
    /// The ray's time and media seed, which the whole path keeps.
    pub start: Probe,
    /// Whether the path counts its first hit's light.
    pub first_light: bool,
}

/// What a path of a guided pass has of the guide: the guide its bounces draw from, and the
/// trail its bounces are noted on to be learnt from when it ends (each `None` where the
/// pass has none; both `None` outside guided renders).
#[derive(Debug, Default)]
pub struct Guided<'a> {
    /// The guide.
    pub guide: Option<&'a Guide>,
    /// The trail.
    pub trail: Option<&'a mut Trail>,
}

/// The radiance arriving along the camera ray: the book's `ray_color`, as a loop. A path casts
/// at most `settings.max_depth` rays; one still bouncing after that contributes black. Adds the
/// number of rays cast to `rays`. Forced inline into the render loop: left to the compiler,
/// `final` took more instructions (`results/perf.md`).
///
/// Without `WORLD` (a first-book scene), each ray's closest hit is found by `closest_hit` (the
/// scene's sphere search, `|ray| scene.hit(ray, Real::INFINITY)`, except in the Embree
/// benchmark), and nothing emits. With `WORLD`, the scene's world is searched with a
/// [`Probe`] carrying `time` (and, in a scene with media, a seed drawn for each ray), and every
/// surface hit adds what it emits, weighted by the path's throughput.
#[inline(always)]
pub fn trace<R: SampleRng + ?Sized, const WORLD: bool>(
    scene: &Scene,
    closest_hit: &impl Fn(&Ray) -> Option<Hit>,
    camera: CameraRay,
    settings: &RenderSettings,
    guided: Guided<'_>,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let CameraRay { mut ray, start, first_light } = camera;
    let mut path = Path::<WORLD>::new(scene, settings, start);
    let Guided { guide, mut trail } = guided;
    let guiding = WORLD && (guide.is_some() || trail.is_some());
    // A `while`, not `for n in 1..=max_depth`: the inclusive range compiled to more work
    // per ray here.
    let mut n = 0;
    while n < settings.max_depth {
        n += 1;
        *rays += 1;
        let cast = Cast { n, medium_seed: path.medium_seed(n) };
        let found = if WORLD { scene.hit_world(&ray, &path.probe(cast)) } else { closest_hit(&ray) };
        // Borrowed, not moved: a move copied the record in 16-byte pieces right after the
        // search had written it field by field, and such a load waits for the stores it spans.
        let Some(hit) = &found else { return path.escaped(ray.dir) };
        rng.bounce(n - 1);
        let material = scene.material(hit);
        if WORLD {
            let counted = n > 1 || first_light;
            path.emission_met(hit, if counted { material.emitted(hit) } else { Vec3::ZERO });
        }
        let Some(mut scatter) = material.scatter(ray.dir, hit, &scene.textures, rng) else {
            return path.radiance;
        };
        path.weighed = None;
        // Not on a path's last ray: the reflection could not have met a light either.
        if path.aiming == LightSampling::Mis && n < settings.max_depth {
            path.glint(hit, material, ray.dir, scatter.direction, cast, rays);
        }
        // Tested first, so that a first-book scene (always `Bsdf`) has no further work here.
        let lobe = if path.aiming == LightSampling::Bsdf && !guiding { None } else { material.lobe() };
        if path.caustics {
            path.follow(hit, lobe, scatter.direction);
        }
        if let Some(lobe) = lobe {
            // A guided bounce is drawn before the light samples, which weigh its direction
            // (and count the light they find with the material's own attenuation).
            let drawn = (guiding && guides(n, path.aiming))
                .then(|| guided_bounce(guide, hit, lobe, &mut scatter.direction, rng));
            // The light's numbers only where lights are aimed at: under `bsdf` a pass that
            // learns (and so has a lobe) must draw what one that does not draws.
            if path.aiming != LightSampling::Bsdf {
                rng.light(n - 1);
            }
            match path.aiming {
                LightSampling::Mis if n < settings.max_depth => {
                    path.sample_lights(hit, lobe, &scatter, cast, rng, rays);
                }
                LightSampling::Mixture => {
                    let goes_on = mixture_bounce(scene.lights(), hit, start.time, lobe, &mut scatter, rng);
                    if !goes_on {
                        return path.radiance;
                    }
                }
                _ => {}
            }
            if let Some(drawn) = drawn {
                scatter.attenuation *= drawn.weight;
                if let Some(trail) = trail.as_deref_mut() {
                    let throughput = path.throughput * scatter.attenuation;
                    trail.push(hit, lobe, scatter.direction, drawn.pdf, throughput, path.radiance);
                }
            }
        }
        if !path.bounce(scatter.attenuation) || !path.roulette(n, rng) {
            return path.radiance;
        }
        ray = hit.spawn(scatter.direction);
    }
    path.radiance
}

/// Which ray of the path this is: the `n`-th (1 for the camera's), with the seed its media
/// draw from (in a scene with media).
#[derive(Clone, Copy, Debug)]
struct Cast {
    n: u32,
    medium_seed: u64,
}

/// What the last bounce carries forward when it was weighed against a light sample (multiple
/// importance sampling), so that an emitter it meets is weighted by the power heuristic:
/// pbrt-v4's `prevIntrCtx` and `p_b`.
#[derive(Clone, Copy, Debug)]
struct Weighed {
    /// The point the bounce left from.
    from: Vec3,
    /// The material's density for the bounce's direction.
    bsdf_pdf: Real,
    /// The chance the light sample there had of being taken ([`shadow_chance`]).
    chance: Real,
}

/// What a path carries from one ray to the next, and what stays the same along it.
struct Path<'a, const WORLD: bool> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    /// The camera ray's time and media seed.
    start: Probe,
    /// Where the lights are sampled: the settings' way in a second-book scene with lights,
    /// else `bsdf`.
    aiming: LightSampling,
    /// Under `mis`, with glass balls and lights: each diffuse hit also aims at a light through
    /// a ball (`lighting/manifold.rs`), and its bounce is followed through a ball to weigh a
    /// light it meets there against that.
    caustics: bool,
    /// The light gathered so far (pbrt's `L`).
    radiance: Vec3,
    /// What the path multiplies the light it meets by (pbrt's `beta`).
    throughput: Vec3,
    /// How to weigh an emitter the last bounce meets, if it was weighed against a light sample;
    /// otherwise it counts whole.
    weighed: Option<Weighed>,
    /// The last diffuse bounce followed through a glass ball, to weigh a light met after it
    /// against a manifold sample.
    passing: Option<Passing>,
    /// The weight of the light met next: below 1 after glass reflected the path (under `mis`,
    /// [`glint`] counts that light).
    mirrored: Real,
}

impl<'a, const WORLD: bool> Path<'a, WORLD> {
    #[inline(always)]
    fn new(scene: &'a Scene, settings: &'a RenderSettings, start: Probe) -> Self {
        let aiming =
            if WORLD && !scene.lights().is_empty() { settings.light_sampling } else { LightSampling::Bsdf };
        let caustics = WORLD && aiming == LightSampling::Mis && !scene.casters().is_empty();
        Path {
            scene,
            settings,
            start,
            aiming,
            caustics,
            radiance: Vec3::ZERO,
            throughput: Vec3::ONE,
            weighed: None,
            passing: None,
            mirrored: 1.0,
        }
    }

    /// The seed the media of the path's `n`-th ray draw from; 0 in a scene without media.
    #[inline(always)]
    fn medium_seed(&self, n: u32) -> u64 {
        let has_media = WORLD && self.scene.has_media();
        if has_media { mix(self.start.medium_seed ^ u64::from(n)) } else { 0 }
    }

    /// What a search for `cast`'s hit needs besides the ray: the path's time, the ray's media
    /// seed.
    #[inline(always)]
    fn probe(&self, cast: Cast) -> Probe {
        Probe { medium_seed: cast.medium_seed, ..self.start }
    }

    /// The light of the sky, where a ray escapes: the path's last event.
    #[inline(always)]
    fn escaped(&self, dir: Vec3) -> Vec3 {
        let sky = self.throughput * self.scene.background.radiance(dir);
        if WORLD { self.radiance + sky } else { sky }
    }

    /// The light `emitted` at `hit`, met by the last bounce: weighed against the light sample
    /// that could have found the same point (by the power heuristic), or against the manifold
    /// sample if the bounce crossed a glass ball; whole otherwise.
    #[inline(always)]
    fn emission_met(&mut self, hit: &Hit, emitted: Vec3) {
        let weight = match (self.weighed, self.passing) {
            _ if emitted == Vec3::ZERO => 1.0,
            (Some(Weighed { from, bsdf_pdf, chance }), _) => power_heuristic(
                bsdf_pdf,
                chance * self.scene.lights().pdf_of_hit(from, hit, emitted, self.start.time),
            ),
            (None, Some(passing)) => passing.weight(self.scene, hit, emitted),
            (None, None) => 1.0,
        };
        self.radiance += self.throughput * emitted * (weight * self.mirrored);
        self.mirrored = 1.0;
    }

    /// The light glass at `hit` shows by reflection, found by a mirror ray of its own
    /// ([`glint`]), for a path that arrived along `incoming` and goes on along `onward`; and
    /// the weight of the light the path meets next.
    #[inline(always)]
    fn glint(
        &mut self,
        hit: &Hit,
        material: &Material,
        incoming: Vec3,
        onward: Vec3,
        cast: Cast,
        rays: &mut u64,
    ) {
        let (shown, next) = glint(self.scene, hit, material, incoming, onward, self.probe(cast), rays);
        self.radiance += self.throughput * shown;
        self.mirrored = next;
    }

    /// The bounce from `hit` along `onward`, followed through a glass ball while it crosses one
    /// (`lobe`: the hit's, if it scatters diffusely, which ends the crossing).
    #[inline(always)]
    fn follow(&mut self, hit: &Hit, lobe: Option<Lobe>, onward: Vec3) {
        self.passing =
            if lobe.is_some() { None } else { self.passing.and_then(|p| p.next(self.scene, hit, onward)) };
    }

    /// The light samples at a diffuse `hit` of the ray `cast` (`mis`; pbrt-v4's
    /// `SampleLd`): a shadow ray to a point on a light and, with glass balls, a manifold sample
    /// through one, each weighed against the bounce `scatter`, which then remembers how to
    /// weigh the light it meets.
    #[inline(always)]
    fn sample_lights<R: SampleRng + ?Sized>(
        &mut self,
        hit: &Hit,
        lobe: Lobe,
        scatter: &Scatter,
        cast: Cast,
        rng: &mut R,
        rays: &mut u64,
    ) {
        let shadow = Probe { medium_seed: cast.medium_seed ^ SHADOW_KEY, ..self.start };
        let carried = self.throughput * scatter.attenuation;
        // One coin, the light sample's first number, for the shadow ray and the aims through
        // glass: each is taken where it falls below its own chance.
        let (coin, aim) = (uniform(rng), shadow_chance(carried));
        let direct = next_event(self.scene, hit, lobe, shadow, Odds { coin, chance: aim }, rng, rays);
        self.radiance += carried * direct;
        let bsdf_pdf = lobe_pdf(lobe, scatter.direction, hit.normal);
        self.weighed = Some(Weighed { from: hit.departure(), bsdf_pdf, chance: aim });
        if self.caustics && lobe == Lobe::Cosine && cast.n + manifold::RAYS <= self.settings.max_depth {
            // Fewer solves where the path carries little (`lighting/manifold.rs`).
            let chance = (2.0 * carried.max_element()).min(1.0);
            let odds = Odds { coin, chance };
            let focused = manifold_event(self.scene, hit, cast.n - 1, odds, shadow, rng, rays);
            self.radiance += carried * focused;
            let (from, dir) = (hit.departure(), scatter.direction);
            self.passing = Some(Passing::leave(self.scene, from, dir, bsdf_pdf, cast.n - 1, chance));
        }
    }

    /// The bounce: the throughput takes its `attenuation`. `false` ends a path that carries
    /// nothing any more (where black paths stop: nothing it meets could add light).
    #[inline(always)]
    fn bounce(&mut self, attenuation: Vec3) -> bool {
        self.throughput *= attenuation;
        !(self.settings.stop_black_paths && self.throughput == Vec3::ZERO)
    }

    /// Russian roulette after the path's `n`-th ray, if asked for: the path survives with its
    /// brightest channel's throughput (at most 0.95) and is weighted by its inverse. `false`
    /// ends it.
    #[inline(always)]
    fn roulette<R: SampleRng + ?Sized>(&mut self, n: u32, rng: &mut R) -> bool {
        if self.settings.roulette && n >= ROULETTE_AFTER {
            let survive = self.throughput.max_element().min(0.95);
            if uniform(rng) >= survive {
                return false;
            }
            self.throughput /= survive;
        }
        true
    }
}
