//! What a light sample is: a point drawn on a light for a shadow ray, the direction towards
//! it and the density with which it was drawn, and the by-area form that every flat light's
//! sample takes (pbrt's `LightLiSample`).

use crate::tracer::math::real::{Real, Vec3};

/// A point on a light drawn by [`Lights::sample`], and the direction towards it.
///
/// [`Lights::sample`]: crate::tracer::lights::power::Lights::sample
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point.
    pub dir: Vec3,
    /// Distance along `dir` to the light's surface.
    pub distance: Real,
    /// The density, per unit solid angle, with which this direction was drawn (the light's
    /// choice included), > 0 and finite.
    pub pdf: Real,
    /// The point on the light.
    pub point: Vec3,
    /// The light's unit geometric normal there.
    pub normal: Vec3,
    /// What the point gives off towards the shading point (zero from behind: a light emits
    /// from its front only).
    pub emitted: Vec3,
    /// Which light it was drawn on.
    pub light: usize,
}

/// The light a sample was drawn on: which, the chance it had of being chosen, and what it
/// gives off from its front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    /// Its index among the scene's lights.
    pub light: usize,
    /// The chance it was chosen.
    pub chance: Real,
    /// What it gives off from its front.
    pub emit: Vec3,
}

/// The sample of the point `point` (unit normal `normal`) of a flat light of area `area`,
/// drawn uniformly by area, seen from `from`: density `chance · d² / (|cos θ| · area)` per unit
/// solid angle. `None` where that is not a positive finite number.
#[inline(always)]
pub fn toward_area(from: Vec3, point: Vec3, normal: Vec3, area: Real, chosen: Chosen) -> Option<LightSample> {
    let to = point - from;
    let distance = to.length();
    let dir = to / distance;
    let cos = dir.dot(normal);
    let pdf = chosen.chance * distance * distance / (cos.abs() * area);
    // From its front (the direction against the normal), as `Quad::hit_at` decides.
    let emitted = if cos < 0.0 { chosen.emit } else { Vec3::ZERO };
    let sample = LightSample { dir, distance, pdf, point, normal, emitted, light: chosen.light };
    (distance > 0.0 && pdf > 0.0 && pdf.is_finite()).then_some(sample)
}

/// The density per unit solid angle with which a flat light of area `area` and unit normal
/// `normal`, drawn by area, is drawn along the unit `dir` that meets it `t` away.
#[inline]
pub fn density_by_area(dir: Vec3, t: Real, normal: Vec3, area: Real) -> Real {
    t * t / (dir.dot(normal).abs() * area)
}

/// A point on a light and its unit normal on the emitting side: where a light path starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    /// The point.
    pub point: Vec3,
    /// The unit normal on its emitting side (outwards, on a sphere).
    pub normal: Vec3,
}
