//! A sphere that emits, still or moving: aimed at uniformly over the [`Cone`] it fills from
//! the shading point (the third book's and pbrt's way, so no sample lands on its far side);
//! a light path starts uniformly over its whole surface.

use rand::Rng;

use crate::tracer::geometry::cone::Cone;
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::lights::sample::{Chosen, LightPoint, LightSample};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::warp::random_unit_vector;

/// An emitting sphere, in world space (a still one has equal end points).
#[derive(Clone, Debug)]
pub struct SphereLight(MovingSphere);

impl SphereLight {
    /// `moving` placed by `place`.
    pub fn placed(moving: MovingSphere, place: &Transform) -> SphereLight {
        let (center0, center1) = (place.point(moving.center0), place.point(moving.center1));
        SphereLight(MovingSphere { center0, center1, ..moving })
    }

    /// Its power where each unit of its area gives off `glow` (a luminance).
    pub fn power(&self, glow: Real) -> Real {
        glow * 4.0 * PI * self.0.radius * self.0.radius
    }

    /// A direction drawn uniformly over the cone it fills from `from` at `time`, with the
    /// numbers `[a, b]`. `None` from inside it.
    #[inline(always)]
    pub fn sample(&self, from: Vec3, time: Real, [a, b]: [Real; 2], chosen: Chosen) -> Option<LightSample> {
        let sphere = self.0.at(time);
        let cone = Cone::of(&sphere, from)?;
        let (dir, point) = cone.draw(&sphere, a, b);
        let distance = (point - from).length();
        let pdf = cone.density(chosen.chance);
        let r = sphere.radius;
        let normal = (point - sphere.center) / r;
        // Seen from outside: the front of a sphere, the back of an inward shell.
        let emitted = if r > 0.0 { chosen.emit } else { Vec3::ZERO };
        Some(LightSample { dir, distance, pdf, point, normal, emitted, light: chosen.light })
    }

    /// The density, per unit solid angle, with which [`SphereLight::sample`] at `time` draws
    /// along `ray`.
    #[inline]
    pub fn density_along(&self, ray: &Ray, time: Real) -> Real {
        Cone::of(&self.0.at(time), ray.origin)
            .filter(|cone| cone.contains(ray.dir))
            .map_or(0.0, |cone| cone.density(1.0))
    }

    /// If `point` lies on its surface at `time`, the density with which [`SphereLight::sample`]
    /// from `from` draws it, the light chosen with `chance`.
    #[inline]
    pub fn density_at(&self, from: Vec3, point: Vec3, time: Real, chance: Real) -> Option<Real> {
        let sphere = self.0.at(time);
        let r2 = sphere.radius * sphere.radius;
        (((point - sphere.center).length_squared() - r2).abs() <= 1e-3 * r2)
            .then(|| Cone::of(&sphere, from).map_or(0.0, |cone| cone.density(chance)))
    }

    /// Where a light path starts on it at `time`: uniformly over its surface. `None` on an
    /// inward-facing shell, which sends no light out (a shadow ray never sees its front either).
    pub fn emission<R: Rng + ?Sized>(&self, time: Real, rng: &mut R) -> Option<LightPoint> {
        let sphere = self.0.at(time);
        if sphere.radius <= 0.0 {
            return None;
        }
        let normal = random_unit_vector(rng);
        Some(LightPoint { point: sphere.center + sphere.radius * normal, normal })
    }

    /// Its box: every point it passes while the shutter is open.
    pub fn bounds(&self) -> Aabb {
        self.0.bounds()
    }
}
