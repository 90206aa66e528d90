//! **The guided bounce**: one-sample multiple importance sampling between the guide and the
//! material (Veach 1997, §9.2.4; Müller et al. 2017, §5). At a diffuse-like hit (a
//! Lambertian surface, a light that reflects, fog's phase function) whose distribution (its
//! cell's, for its facing) has learnt anything, a coin chooses who draws the direction: the
//! guide, with chance [`GUIDED_SHARE`], else the material (the draw it has already made).
//! Whoever drew it, the bounce is weighed as one sample of the mixture: its attenuation is
//! the material's `f·cos` over the mixture's density `share · p_guide + (1 − share) ·
//! p_material`. Glass and metal keep their own bounce.
//!
//! The light samples at the hit (`mis`) still weigh themselves against the material's
//! density, not the mixture's, and the bounce that meets a light is weighed so too: any
//! weights that sum to 1 keep MIS unbiased, and the manifold samples through glass
//! (`lighting/manifold.rs`) know only the material's density.
//!
//! Invariants: the mixture's density is positive wherever the material's is (the material
//! keeps half the draws), so every direction the material could take is still taken and the
//! estimate stays unbiased whatever the guide learnt, even a wrong guide; and a bounce's
//! weight is at most twice the material's own (`f·cos / ((1 − share) · p_material)`), so a
//! poor guide costs at most that much noise. Where the guide's cell learnt nothing, the
//! bounce is the material's and draws no numbers.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::spatial::facing;
use crate::tracer::lighting::lobe_pdf;
use crate::tracer::lights::LightSampling;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::shading::material::Lobe;

/// The share of a guided hit's bounces that the guide draws (a fixed weight: Müller et al.'s
/// first version's 0.5).
pub const GUIDED_SHARE: Real = 0.5;

/// Where the lights are sampled too (`mis`), the hits up to this ray of a path are guided,
/// the later ones not: their light samples already find the lamps, and what is left for a
/// bounce to find there is dim indirect light, which cost more to guide than it gained (on
/// `cornell`: `results/guiding.md`).
pub const GUIDED_RAYS_WITH_LIGHT_SAMPLES: u32 = 3;

/// Whether the hit of a path's `n`-th ray is guided, the path finding the lights by
/// `aiming`: under `mis`, up to [`GUIDED_RAYS_WITH_LIGHT_SAMPLES`]; else every one.
#[inline]
pub fn guides(n: u32, aiming: LightSampling) -> bool {
    aiming != LightSampling::Mis || n <= GUIDED_RAYS_WITH_LIGHT_SAMPLES
}

/// How a bounce's direction was drawn: the density it was drawn with, and the factor its
/// attenuation takes (the material's density over that one; 1 for the material's own draw).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drawn {
    /// The density of the direction taken.
    pub pdf: Real,
    /// What the material's attenuation is multiplied by.
    pub weight: Real,
}

/// The bounce at `hit` of a material that scatters by `lobe`, `direction` holding the
/// material's own draw: replaced by the guide's with chance [`GUIDED_SHARE`] where the
/// guide's cell has learnt anything (three more numbers: the coin, then the guide's two),
/// and weighed as a draw of the mixture. Without a guide (a pass that only learns), the
/// material's draw as it is.
#[inline]
pub fn guided_bounce<R: SampleRng + ?Sized>(
    guide: Option<&Guide>,
    hit: &Hit,
    lobe: Lobe,
    direction: &mut Vec3,
    rng: &mut R,
) -> Drawn {
    let facing = facing((lobe == Lobe::Cosine).then_some(hit.normal));
    let directions = guide.map(|g| g.directions(hit.departure(), facing)).filter(|d| d.total() > 0.0);
    let Some(directions) = directions else {
        return Drawn { pdf: lobe_pdf(lobe, *direction, hit.normal), weight: 1.0 };
    };
    let share = GUIDED_SHARE;
    let guided = if uniform(rng) < share { directions.sample([uniform(rng), uniform(rng)]) } else { None };
    let guide_pdf = match guided {
        Some((dir, pdf)) => {
            *direction = dir;
            pdf
        }
        None => directions.pdf(*direction),
    };
    let material = lobe_pdf(lobe, *direction, hit.normal);
    let mixture = share * guide_pdf + (1.0 - share) * material;
    // `lobe_pdf` is also the lobe's `f·cos` per unit albedo, which the attenuation holds.
    let weight = if mixture > 0.0 { material / mixture } else { 0.0 };
    Drawn { pdf: mixture, weight }
}
