//! A triangle that emits (an emitting mesh is one light per triangle): a point drawn on it
//! uniformly by area, for a shadow ray and for a light path alike.

use rand::Rng;

use crate::tracer::geometry::triangle;
use crate::tracer::lights::sample::{Chosen, LightPoint, LightSample, density_by_area, toward_area};
use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::warp::uniform;

/// An emitting triangle, in world space.
#[derive(Clone, Debug)]
pub struct TriangleLight {
    corners: [Vec3; 3],
    /// Its unit geometric normal.
    normal: Vec3,
    area: Real,
}

impl TriangleLight {
    /// The triangle of `corners` placed by `place`.
    pub fn placed(corners: [Vec3; 3], place: &Transform) -> TriangleLight {
        let p = corners.map(|corner| place.point(corner));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let area = 0.5 * n.length();
        TriangleLight { corners: p, normal: n.normalize_or_zero(), area }
    }

    /// Its power where each unit of its area gives off `glow` (a luminance).
    pub fn power(&self, glow: Real) -> Real {
        glow * self.area
    }

    /// The point `r` of the way from the first corner towards the far edge, `b` along it:
    /// uniform by area for `r` the square root of a uniform number (pbrt's
    /// `SampleUniformTriangle`, in its older form).
    #[inline]
    fn at(&self, r: Real, b: Real) -> Vec3 {
        let p = &self.corners;
        p[0] + (r * (1.0 - b)) * (p[1] - p[0]) + (r * b) * (p[2] - p[0])
    }

    /// A point drawn uniformly by area with the numbers `[a, b]`, seen from `from`.
    #[inline(always)]
    pub fn sample(&self, from: Vec3, [a, b]: [Real; 2], chosen: Chosen) -> Option<LightSample> {
        toward_area(from, self.at(a.sqrt(), b), self.normal, self.area, chosen)
    }

    /// The density, per unit solid angle, with which [`TriangleLight::sample`] draws along
    /// `ray`.
    #[inline]
    pub fn density_along(&self, ray: &Ray) -> Real {
        triangle::intersect(self.corners, ray, Real::INFINITY)
            .map_or(0.0, |found| density_by_area(ray.dir, found.t, self.normal, self.area))
    }

    /// Its normal, if the unit `ray` meets it `distance` away (to a thousandth).
    pub fn normal_at(&self, ray: &Ray, distance: Real) -> Option<Vec3> {
        triangle::intersect(self.corners, ray, 1.001 * distance)
            .filter(|found| found.t >= 0.999 * distance)
            .map(|_| self.normal)
    }

    /// Where a light path starts on it: two numbers, uniformly by area.
    pub fn emission<R: Rng + ?Sized>(&self, rng: &mut R) -> LightPoint {
        let (a, b) = (uniform(rng).sqrt(), uniform(rng));
        LightPoint { point: self.at(a, b), normal: self.normal }
    }

    /// Its box, padded by the roundings of a ray's hit on it.
    pub fn bounds(&self) -> Aabb {
        let corners = self.corners.iter().fold(Aabb::EMPTY, |b, &c| b.grow(c));
        corners.padded(8.0 * Real::EPSILON * corners.magnitude())
    }
}
