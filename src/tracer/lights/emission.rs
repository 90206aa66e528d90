//! Light leaving the lights: where a *light path* (bidirectional path tracing, `bidir/`)
//! starts. The light is chosen in proportion to its power, as a shadow ray chooses it
//! (`power.rs`), then a point uniformly by area on it (on a whole sphere too) and a direction
//! from its front by the cosine law, which is how a diffuse emitter sends its light out.
//!
//! Invariant: every light's power is `luminance(emit) × area`, so a point on any light is
//! drawn with the same density per unit area, `luminance(emit) / total power`
//! ([`Lights::origin_pdf`]): a path that meets an emitter knows the density with which a light
//! path would have started there without knowing which light it met.

use rand::Rng;

use crate::tracer::lights::luminance;
use crate::tracer::lights::power::Lights;
use crate::tracer::lights::sample::LightPoint;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::warp::{random_unit_vector, uniform};

/// A point drawn on a light, where a light path starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    /// The point.
    pub point: Vec3,
    /// The light's unit normal on its emitting side (outwards, on a sphere).
    pub normal: Vec3,
    /// The radiance it gives off from that side.
    pub emitted: Vec3,
    /// The density per unit area with which the point was drawn (the light's choice
    /// included): [`Lights::origin_pdf`] of `emitted`.
    pub pdf: Real,
    /// How far off the light a ray leaving it must start (a few ulps of the point's size).
    pub offset: Real,
}

impl Lights {
    /// A point on a light at `time` from which a light path starts: the choice and two
    /// numbers for the point. `None` without lights, or on an inward-facing sphere (which
    /// sends no light out: a shadow ray never sees its front either).
    pub fn sample_emission<R: Rng + ?Sized>(&self, time: Real, rng: &mut R) -> Option<Emission> {
        let pick = uniform(rng);
        let k = self.running.partition_point(|&r| r <= pick).min(self.lights.len().checked_sub(1)?);
        let LightPoint { point, normal } = self.lights[k].emission(time, rng)?;
        let emitted = self.emit[k];
        let pdf = self.origin_pdf(emitted);
        let offset = 32.0 * Real::EPSILON * point.abs().max_element().max(self.lights[k].size());
        (pdf > 0.0).then_some(Emission { point, normal, emitted, pdf, offset })
    }

    /// The density per unit area with which [`Lights::sample_emission`] draws a point of an
    /// emitter that gives off `emitted` (the same on every light: see the module's opening).
    #[inline]
    pub fn origin_pdf(&self, emitted: Vec3) -> Real {
        let pdf = luminance(emitted) / self.total;
        if pdf.is_finite() { pdf } else { 0.0 }
    }
}

/// A direction from a light's front by the cosine law about its unit `normal` (density
/// `cos θ / π`), as a Lambertian surface scatters: two numbers.
pub fn emitted_direction<R: Rng + ?Sized>(normal: Vec3, rng: &mut R) -> Vec3 {
    (normal + random_unit_vector(rng)).try_normalize().unwrap_or(normal)
}
