//! **Manifold next-event estimation** (Hanika, Droske and Fascione 2015; Cycles' "shadow
//! caustics"): at a diffuse hit under `mis`, a second light sample aimed *through* a glass
//! ball. A shadow ray cannot reach a light through glass, so without this the bright spot a
//! ball focuses on the floor is found only by bounces that happen to cross the ball and then
//! meet the small lamp: fireflies for thousands of samples (`results/caustics.md`).
//!
//! [`manifold_event`] draws a caster and a point on a light by area (as a light path starts,
//! `lights/emission.rs`), solves for the passage that joins the hit to that point
//! (`passage.rs`), and checks the three straight pieces with shadow rays. Its density is
//! the point's, per unit area; a bounce that found the same path has density
//! [`bounce_density`] there, and each is weighted by the power heuristic against the other.
//! [`Passing`] follows a bounce on its way, so that a light it meets after crossing a caster
//! gets that weight.
//!
//! Most manifold samples find nothing: most end at once (`may_focus`: one product per caster
//! says no light can reach the hit through it) or before a light point is drawn ([`may_pass`]
//! for the caster drawn), and many of the solves left end at their bound (how many, on
//! `cornell`: `results/mnee.md`). A path meets many diffuse hits in a
//! closed room, most of them carrying little light: so a hit takes a manifold sample with the
//! chance `min(1, 2 × the path's throughput after it)` (every hit of a path's first bounces,
//! fewer later), and the sample is divided by that chance and its density multiplied by it
//! (what that trades, measured: `results/mnee.md`).
//!
//! Invariant: a path is weighed against the solve only if the solve, run from the same two
//! points, finds that very passage; otherwise the bounce alone could make it and it keeps
//! weight 1. So the weights of every path sum to 1 even where the solve misses passages, and
//! the estimate stays unbiased: the solve decides only how much noise is left.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::lighting::passage::{bounce_density, may_pass, solve};
use crate::tracer::lighting::{Odds, power_heuristic};
use crate::tracer::lights::casters::{Ball, Lamps, Passage};
use crate::tracer::lights::emission::Emission;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::keys::PIECE_KEY;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::scene::Scene;
use crate::tracer::world::object::Probe;

/// Rays a manifold sample spends beyond a shadow ray's one: the path from the hit to a light
/// through a ball is three straight pieces, so it needs three rays of a path's budget.
pub const RAYS: u32 = 3;

/// Light points a manifold sample at bounce `bounce` aims at, each with its own caster and
/// Sobol set, their estimates averaged: two at a path's first hit (the one the camera sees,
/// where a caustic's noise shows), eight there if the hit is `near` a ball's focus (where its
/// caustic is brightest, and most of the light points drawn find no passage), one after
/// (where `near` is not asked). Two at the first hit only did as well on `cornell` as two at
/// every hit, which on `next-week` cost time for no less error (`results/mnee.md`).
pub fn points(bounce: u32, near: bool) -> u32 {
    match (bounce, near) {
        (0, true) => FIRST_POINTS,
        (0, false) => 2,
        _ => 1,
    }
}

/// The most light points a path's first hit aims at; the aims of later bounces are numbered
/// after them.
const FIRST_POINTS: u32 = 8;

/// Light arriving at a diffuse `hit` of bounce `bounce` through one of the scene's casters,
/// per unit albedo (as [`super::next_event`]'s), taken by `odds` (whose coin is the one the
/// shadow ray's chance is drawn against) and divided by its chance; then [`points`] aims,
/// each with four draws in its own dimensions (the caster, the light, a point on it),
/// numbered along the path. Counts its shadow rays in `rays`.
pub fn manifold_event<R: SampleRng + ?Sized>(
    scene: &Scene,
    hit: &Hit,
    bounce: u32,
    odds: Odds,
    probe: Probe,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let Odds { coin, chance } = odds;
    if coin >= chance || !may_focus(scene, hit.departure()) {
        return Vec3::ZERO;
    }
    // Aims are numbered along the path: the first hit's, then one per bounce.
    let near = bounce == 0 && scene.casters().near_focus(hit.departure());
    let (first, aims) = (if bounce == 0 { 0 } else { FIRST_POINTS + bounce - 1 }, points(bounce, near));
    let (mut focused, mut allowed) = (Vec3::ZERO, Allowed::default());
    for aim in first..first + aims {
        rng.light_through_glass(aim);
        focused += aim_once(scene, hit, &mut allowed, chance * aims as Real, probe, rng, rays);
    }
    focused
}

/// Which casters [`may_pass`] allows from one hit, each asked once: a hit's aims draw their
/// casters again and again (cornell's eight all draw its one ball).
#[derive(Default)]
struct Allowed {
    /// Bit `k`: caster `k` was asked (casters from 64 on are asked every time).
    asked: u64,
    /// Bit `k`: it allows the hit.
    allows: u64,
}

impl Allowed {
    /// Whether caster `k`, `ball`, may let light from `lamps` through to `from`.
    fn ask(&mut self, k: usize, ball: &Ball, from: Vec3, lamps: Lamps) -> bool {
        let Some(bit) = 1u64.checked_shl(k as u32) else { return may_pass(ball, from, lamps) };
        if self.asked & bit == 0 {
            self.asked |= bit;
            self.allows |= if may_pass(ball, from, lamps) { bit } else { 0 };
        }
        self.allows & bit != 0
    }
}

/// One of [`manifold_event`]'s aims: a caster and a point on a light drawn, every passage
/// between the hit and the point found, each weighed against the bounce as the sample's
/// `aims` (its points times its chance) would weigh it.
fn aim_once<R: SampleRng + ?Sized>(
    scene: &Scene,
    hit: &Hit,
    allowed: &mut Allowed,
    aims: Real,
    probe: Probe,
    rng: &mut R,
    rays: &mut u64,
) -> Vec3 {
    let casters = scene.casters();
    let pick = ((uniform(rng) * casters.len() as Real) as usize).min(casters.len() - 1);
    let ball = casters.ball(pick);
    if !allowed.ask(pick, ball, hit.departure(), casters.lamps()) {
        return Vec3::ZERO;
    }
    let Some(light) = scene.lights().sample_emission(probe.time, rng) else { return Vec3::ZERO };
    let target = Target { light, chosen: aimed_density(aims, light.pdf, casters.len()) };
    let mut gathered = 0.0;
    solve(ball, hit.departure(), light.point, |passage| {
        gathered += through(scene, hit, ball, &passage, &target, probe, rays);
    });
    light.emitted * (gathered / target.chosen)
}

/// A point drawn on a light for one aim, and the density per unit area with which the aim
/// drew it ([`aimed_density`]).
#[derive(Clone, Copy, Debug)]
struct Target {
    light: Emission,
    chosen: Real,
}

/// The density per unit area with which a manifold sample that makes `aims` aims (its points
/// times the chance it was taken) draws a light point of density `pdf` through one of
/// `casters` (each point's estimate is divided by it, so their sum is their mean).
fn aimed_density(aims: Real, pdf: Real, casters: usize) -> Real {
    aims * pdf / casters as Real
}

/// Whether a manifold sample at `from` may find anything: whether some caster may let light
/// from the lamps through to it ([`Casters::may_light`], one product each); each aim then asks
/// [`may_pass`] of the caster it drew. Where neither allows it, the solve would find nothing,
/// so nothing is drawn, and a bounce that crosses that ball to a light keeps weight 1, as
/// [`Passing::weight`] would give it there.
///
/// [`Casters::may_light`]: crate::tracer::lights::casters::Casters::may_light
fn may_focus(scene: &Scene, from: Vec3) -> bool {
    let casters = scene.casters();
    (0..casters.len()).any(|k| casters.may_light(k, from))
}

/// The share of [`manifold_event`]'s estimate that `passage` through `ball` gives `target`,
/// per unit emission and before the division by the target's density: the bounce's density
/// there, weighted by the power heuristic, if the passage leaves from above the hit, reaches
/// the light's front, and its three straight pieces are clear.
fn through(
    scene: &Scene,
    hit: &Hit,
    ball: &Ball,
    passage: &Passage,
    target: &Target,
    probe: Probe,
    rays: &mut u64,
) -> Real {
    let Target { light, chosen } = *target;
    let from = hit.departure();
    let dir = passage.dir;
    let cosine = dir.dot(hit.normal);
    if cosine <= 0.0 || (light.point - passage.exit).dot(light.normal) >= 0.0 {
        return 0.0;
    }
    let bounce = bounce_density(ball, from, dir, cosine / PI, light.point, light.normal);
    if bounce <= 0.0 {
        return 0.0;
    }
    // The three pieces, each from just off the surface it leaves to just short of the one it
    // meets (the ball's own surface ends the first two, the light the third); each a
    // medium's own numbers.
    let offset = ball.sphere.spawn_offset();
    let center = ball.sphere.center;
    let pieces = [
        Ray::towards(hit.spawn(dir).origin, passage.entry),
        Ray::towards(passage.entry + offset * (center - passage.entry).normalize(), passage.exit),
        Ray::towards(passage.exit + offset * (passage.exit - center).normalize(), light.point),
    ];
    for (key, (ray, reach)) in (1u64..).zip(pieces) {
        *rays += 1;
        let own = Probe { medium_seed: probe.medium_seed ^ key.wrapping_mul(PIECE_KEY), ..probe };
        if scene.occluded(&ray, reach, &own) {
            return 0.0;
        }
    }
    // The bounce's density is its estimate's integrand over the light's emission: the
    // cosine over π, the passage's chance T, and the spread 1/J (the module's opening).
    bounce * power_heuristic(chosen, bounce)
}

/// How far a bounce from a diffuse hit has come on its way through a caster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    /// It left the diffuse hit.
    Left,
    /// It refracted into caster `k`.
    Entered(usize),
    /// It refracted out of caster `k` again: a light met next is a manifold sample's too.
    Crossed(usize),
}

/// A bounce from a diffuse hit (where a manifold sample was taken) followed through its next
/// hits while they are the passage through a caster that [`manifold_event`] would solve for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passing {
    /// The diffuse hit's departure point.
    from: Vec3,
    /// The bounce's unit direction.
    dir: Vec3,
    /// Its density per unit solid angle.
    pdf: Real,
    /// The aims a manifold sample made at the diffuse hit: its points times the chance it was
    /// taken.
    aims: Real,
    stage: Stage,
}

impl Passing {
    /// A bounce leaving `from` along `dir`, drawn with density `pdf`, from bounce `bounce`'s
    /// hit, where a manifold sample was taken with `chance`.
    pub fn leave(scene: &Scene, from: Vec3, dir: Vec3, pdf: Real, bounce: u32, chance: Real) -> Passing {
        let near = bounce == 0 && scene.casters().near_focus(from);
        Passing { from, dir, pdf, aims: chance * points(bounce, near) as Real, stage: Stage::Left }
    }

    /// The bounce after its next `hit`, where it scattered into `out`: still on its way if it
    /// refracted into a caster, or out of the one it entered.
    pub fn next(self, scene: &Scene, hit: &Hit, out: Vec3) -> Option<Passing> {
        let casters = scene.casters();
        // Refracted: `hit.normal` faces the arriving ray, so the ray went on through.
        let refracted = out.dot(hit.normal) < 0.0;
        let stage = match self.stage {
            Stage::Left if refracted && hit.front_face => {
                Stage::Entered(casters.holding(hit.point, hit.material)?)
            }
            Stage::Entered(k) if refracted && !hit.front_face => {
                let ball = casters.ball(k);
                (ball.sphere.material == hit.material && ball.holds(hit.point))
                    .then_some(Stage::Crossed(k))?
            }
            _ => return None,
        };
        Some(Passing { stage, ..self })
    }

    /// The weight of the light `emitted` at `hit`, met next: against a manifold sample's
    /// density if the solve finds this very passage, else 1.
    pub fn weight(&self, scene: &Scene, hit: &Hit, emitted: Vec3) -> Real {
        let Stage::Crossed(k) = self.stage else { return 1.0 };
        let casters = scene.casters();
        let ball = casters.ball(k);
        let Some(taken) = ball.pass(self.from, self.dir) else { return 1.0 };
        let mut found = false;
        solve(ball, self.from, hit.point, |passage| {
            found |= (passage.entry - taken.entry).length() <= 1e-3 * ball.sphere.radius;
        });
        if !found {
            return 1.0;
        }
        let bounce = bounce_density(ball, self.from, self.dir, self.pdf, hit.point, hit.normal);
        if bounce <= 0.0 {
            // The manifold sample gives such a path nothing either.
            return 1.0;
        }
        let chosen = aimed_density(self.aims, scene.lights().origin_pdf(emitted), casters.len());
        power_heuristic(bounce, chosen)
    }
}
