//! What a search for the nearest surface keeps ([`Closest`]) and returns ([`Hit`]): shape-
//! independent, so every shape's test and every tree of `accel` speak the same two types.

use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// What a ray hit: where, which way the surface faces, and how to leave it safely.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the ray.
    pub t: Real,
    /// The hit point.
    pub point: Vec3,
    /// Unit surface normal, turned to face against the incoming ray.
    pub normal: Vec3,
    /// True when the ray arrived from the side the geometric normal points to (outside,
    /// for a positive radius).
    pub front_face: bool,
    /// Index into the scene's material table.
    pub material: u32,
    /// How far off the surface a new ray must start to never re-hit it by rounding error.
    pub offset: Real,
    /// How much higher, along `normal`, paths leave on the normal's side ([`Hit::departure`]):
    /// the height of the smooth surface a mesh's vertex normals describe above its flat
    /// triangle (`world/mesh.rs`); 0 for every other shape.
    pub lift: Real,
    /// Surface coordinates for textures, each in `[0, 1]` (0 where no texture can look: the
    /// sphere-only scenes never compute them).
    pub u: Real,
    /// See [`Hit::u`].
    pub v: Real,
}

/// The closest hit found so far: distance and sphere index. Ties in distance go to the
/// lower index, so the answer does not depend on the order in which spheres are tested.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Distance of the best hit (the search bound while none is found).
    pub t: Real,
    /// Index of the sphere hit, `u32::MAX` while none is.
    pub index: u32,
    /// The bound for sphere tests: `t` while nothing is found, else the next number above
    /// `t`, so that a tie is reported and [`Closest::offer`] can decide it. Kept, not
    /// computed per test: it changes only when a hit is kept, which is rare.
    bound: Real,
}

impl Closest {
    /// Nothing found yet, searching up to `t_max` (exclusive).
    pub fn none(t_max: Real) -> Closest {
        Closest { t: t_max, index: u32::MAX, bound: t_max }
    }

    /// The bound a sphere test must use so that a hit at exactly `t` (a tie) is reported.
    #[inline]
    pub fn bound(&self) -> Real {
        self.bound
    }

    /// Keeps the hit `(t, index)` if it is closer, or as close with a lower index.
    #[inline]
    pub fn offer(&mut self, t: Real, index: u32) {
        if t < self.t || (t == self.t && index < self.index) {
            // A hit distance is positive and finite, so the next number above it is one bit
            // pattern up (cheaper than the general `next_up`, which this is on the hot path).
            *self = Closest { t, index, bound: Real::from_bits(t.to_bits() + 1) };
        }
    }

    /// Rules out everything a search has left (an any-hit search that found its answer): no
    /// box is entered before a negative distance.
    #[inline]
    pub fn rule_out_rest(&mut self) {
        *self = Closest { t: -1.0, index: self.index, bound: -1.0 };
    }

    /// `(index, t)` of the hit, if any.
    pub fn found(&self) -> Option<(usize, Real)> {
        (self.index != u32::MAX).then_some((self.index as usize, self.t))
    }
}

impl Hit {
    /// A scattering event at distance `t` along `ray` inside a medium of `material`: its normal
    /// is any unit vector (the phase function ignores it), and a ray leaves from right there
    /// (no offset: there is no surface to clear).
    #[inline]
    pub fn in_medium(ray: &Ray, t: Real, material: u32) -> Hit {
        let point = ray.at(t);
        Hit { t, point, normal: Vec3::X, front_face: true, material, offset: 0.0, lift: 0.0, u: 0.0, v: 0.0 }
    }

    /// Where paths leave this hit on the normal's side, and the point light is gathered at:
    /// `point` raised by [`Hit::lift`] (so a light sample, its shadow ray, its density and
    /// the bounce all start from one point). An emitter's own point stays `point`.
    #[inline]
    pub fn departure(&self) -> Vec3 {
        // Tested, not added: `point + 0·normal` could turn a −0 coordinate into +0.
        if self.lift > 0.0 { self.point + self.lift * self.normal } else { self.point }
    }

    /// A new ray leaving this hit in the unit direction `dir` (a scattered direction is
    /// one: `shading/material.rs`), started off the surface on the side `dir` points to (outwards
    /// for reflection, from [`Hit::departure`]; inwards for refraction).
    #[inline]
    pub fn spawn(&self, dir: Vec3) -> Ray {
        debug_assert!((dir.length_squared() - 1.0).abs() < 1e-4, "a unit direction");
        let origin = if dir.dot(self.normal) >= 0.0 {
            self.departure() + self.offset * self.normal
        } else {
            self.point + (-self.offset) * self.normal
        };
        // Not normalised again: a square root and a division on every bounce's critical
        // path, for a vector already unit to within rounding.
        Ray { origin, dir }
    }
}
