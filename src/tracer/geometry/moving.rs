//! A moving sphere, for motion blur: its centre travels in a straight line from `center0` at
//! time 0 to `center1` at time 1 while the shutter is open, and each camera ray carries the
//! time it samples (the second book's chapter 2). At a given time it is an ordinary sphere,
//! tested with the same robust test.

use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::real::{Real, Vec3};

/// A sphere whose centre moves from `center0` (time 0) to `center1` (time 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingSphere {
    /// Centre at time 0.
    pub center0: Vec3,
    /// Centre at time 1.
    pub center1: Vec3,
    /// Radius; negative for an inward-facing shell, as for [`Sphere`].
    pub radius: Real,
    /// Index into the scene's material table.
    pub material: u32,
}

impl MovingSphere {
    /// The sphere where it is at `time` (0 to 1). With equal end points it is exactly the
    /// static sphere, whatever the time.
    #[inline]
    pub fn at(&self, time: Real) -> Sphere {
        let center = if self.center0 == self.center1 {
            self.center0
        } else {
            self.center0 + time * (self.center1 - self.center0)
        };
        Sphere { center, radius: self.radius, material: self.material }
    }
}

impl Bounded for MovingSphere {
    /// Both end positions' boxes: every position between lies inside their union.
    fn bounds(&self) -> Aabb {
        self.at(0.0).bounds().union(self.at(1.0).bounds())
    }

    fn centroid(&self) -> Vec3 {
        0.5 * (self.center0 + self.center1)
    }
}
