//! A quad that emits (the second and third books' lamp): a point drawn on it uniformly by
//! area, for a shadow ray and for a light path alike.

use rand::Rng;

use crate::tracer::geometry::quad::Quad;
use crate::tracer::lights::sample::{Chosen, LightPoint, LightSample, density_by_area, toward_area};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::warp::uniform;

/// An emitting quad, in world space.
#[derive(Clone, Debug)]
pub struct QuadLight(Quad);

impl QuadLight {
    /// `quad` placed by `place`; `None` if placing leaves it degenerate.
    pub fn placed(quad: &Quad, place: &Transform) -> Option<QuadLight> {
        Quad::new(place.point(quad.q), place.vector(quad.u), place.vector(quad.v), quad.material)
            .map(QuadLight)
    }

    /// Its power where each unit of its area gives off `glow` (a luminance).
    pub fn power(&self, glow: Real) -> Real {
        glow * self.0.area()
    }

    /// A point drawn uniformly by area with the numbers `[a, b]`, seen from `from`.
    #[inline(always)]
    pub fn sample(&self, from: Vec3, [a, b]: [Real; 2], chosen: Chosen) -> Option<LightSample> {
        let quad = &self.0;
        toward_area(from, quad.q + a * quad.u + b * quad.v, quad.normal(), quad.area(), chosen)
    }

    /// The density, per unit solid angle, with which [`QuadLight::sample`] draws along `ray`.
    #[inline]
    pub fn density_along(&self, ray: &Ray) -> Real {
        let quad = &self.0;
        quad.intersect(ray, Real::INFINITY)
            .map_or(0.0, |(t, _, _)| density_by_area(ray.dir, t, quad.normal(), quad.area()))
    }

    /// Where a light path starts on it: two numbers, uniformly by area.
    pub fn emission<R: Rng + ?Sized>(&self, rng: &mut R) -> LightPoint {
        let quad = &self.0;
        let (a, b) = (uniform(rng), uniform(rng));
        LightPoint { point: quad.q + a * quad.u + b * quad.v, normal: quad.normal() }
    }

    /// Its size (its area's square root), so that a light path leaves a big quad far from the
    /// origin as safely as one near it.
    pub fn size(&self) -> Real {
        self.0.area().sqrt()
    }

    /// Its box.
    pub fn bounds(&self) -> Aabb {
        self.0.bounds()
    }
}
