//! An instance: a group placed in the scene by a rigid transform. The ray is moved into the
//! group's frame and the hit moved back (the books' `translate` and `rotate_y`, pbrt's
//! `TransformedPrimitive`), so the geometry exists once however many times it is placed.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::aabb::Bounded;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;
use crate::tracer::math::transform::Transform;
use crate::tracer::world::group::Group;
use crate::tracer::world::object::Probe;

/// A group and where it is placed.
#[derive(Clone, Debug)]
pub struct Instance {
    /// Object frame to world.
    pub transform: Transform,
    /// What is placed.
    pub group: Group,
    bounds: Aabb,
}

impl Instance {
    /// `group` placed by `transform`.
    pub fn new(transform: Transform, group: Group) -> Instance {
        let inner = group.bounds();
        // The placed box is padded by the rounding of placing a point at its magnitude.
        let placed = transform.bounds(&inner);
        let pad = 4.0 * Real::EPSILON * (placed.magnitude() + inner.magnitude());
        Instance { transform, group, bounds: placed.padded(pad) }
    }

    /// The world box.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The nearest hit in `(0, t_max)`: found in the group's frame (a rigid placement keeps
    /// distances), then placed in the world's. The spawn offset grows by the rounding of
    /// placing the point.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        let local = self.transform.inverse_ray(ray);
        let mut hit = self.group.hit(&local, t_max, probe)?;
        hit.point = self.transform.point(hit.point);
        hit.normal = self.transform.vector(hit.normal);
        let magnitude = hit.point.abs().max_element() + self.transform.offset_magnitude();
        hit.offset += 8.0 * Real::EPSILON * magnitude;
        Some(hit)
    }
}
