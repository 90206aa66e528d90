//! A disc that emits (pbrt's `DiskAreaLight` with its disk whole): a point drawn on it
//! uniformly by area, for a shadow ray and for a light path alike, so that its points have the
//! density per unit area of every flat light (`power.rs`).

use rand::Rng;

use crate::tracer::geometry::disc::Disc;
use crate::tracer::lights::sample::{Chosen, LightPoint, LightSample, density_by_area, toward_area};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::math::turn::sin_cos_turn;
use crate::tracer::sampling::warp::uniform;

/// An emitting disc, in world space, with two unit vectors in its plane to draw points by.
#[derive(Clone, Debug)]
pub struct DiscLight {
    disc: Disc,
    tangent: (Vec3, Vec3),
}

impl DiscLight {
    /// `disc` placed by `place` (a rigid motion: the radius stays); `None` if placing leaves it
    /// degenerate.
    pub fn placed(disc: &Disc, place: &Transform) -> Option<DiscLight> {
        let placed =
            Disc::new(place.point(disc.center), place.vector(disc.normal()), disc.radius, disc.material)?;
        Some(DiscLight { disc: placed, tangent: placed.normal().any_orthonormal_pair() })
    }

    /// Its area.
    fn area(&self) -> Real {
        PI * self.disc.radius * self.disc.radius
    }

    /// Its power where each unit of its area gives off `glow` (a luminance).
    pub fn power(&self, glow: Real) -> Real {
        glow * self.area()
    }

    /// The point at `√a` of the radius and `b` of a turn about the centre: uniform by area for
    /// uniform `a` and `b` (as the lens's disk is drawn).
    #[inline]
    fn at(&self, a: Real, b: Real) -> Vec3 {
        let (sin, cos) = sin_cos_turn(b);
        let r = self.disc.radius * a.sqrt();
        self.disc.center + (r * cos) * self.tangent.0 + (r * sin) * self.tangent.1
    }

    /// A point drawn uniformly by area with the numbers `[a, b]`, seen from `from`.
    #[inline(always)]
    pub fn sample(&self, from: Vec3, [a, b]: [Real; 2], chosen: Chosen) -> Option<LightSample> {
        toward_area(from, self.at(a, b), self.disc.normal(), self.area(), chosen)
    }

    /// The density, per unit solid angle, with which [`DiscLight::sample`] draws along `ray`.
    #[inline]
    pub fn density_along(&self, ray: &Ray) -> Real {
        let disc = &self.disc;
        disc.intersect(ray, Real::INFINITY)
            .map_or(0.0, |(t, _)| density_by_area(ray.dir, t, disc.normal(), self.area()))
    }

    /// Where a light path starts on it: two numbers, uniformly by area.
    pub fn emission<R: Rng + ?Sized>(&self, rng: &mut R) -> LightPoint {
        let (a, b) = (uniform(rng), uniform(rng));
        LightPoint { point: self.at(a, b), normal: self.disc.normal() }
    }

    /// Its size (its radius, which the disc's own offset counts), so that a light path leaves
    /// a point near its centre as safely as one near its rim.
    pub fn size(&self) -> Real {
        self.disc.radius
    }

    /// Its box.
    pub fn bounds(&self) -> Aabb {
        self.disc.bounds()
    }
}
