//! A ray: `origin + t · dir`, with `dir` always of unit length.
//!
//! Keeping directions normalised makes `t` a distance, lets the sphere test drop the `a`
//! coefficient of the quadratic, and keeps the stable form of that test exact (see
//! `geometry/sphere.rs`).

use crate::tracer::math::real::{Real, Vec3};

/// How many ulps of its target's size [`Ray::towards`] stops short of it: more than any
/// surface's spawn offset (8 to 32 ulps) and the rounding of its hit test.
pub const REACH_ULPS: Real = 64.0;

/// A half-line from `origin` along the unit vector `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Unit direction of travel.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` towards `dir`, which is normalised here.
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray { origin, dir: dir.normalize() }
    }

    /// A shadow ray from `from`, a point already off its own surface (where [`Hit::spawn`]
    /// starts rays), to `to`, a point on another surface, and the distance it may search:
    /// aimed from where it really starts (pbrt's `SpawnRayTo`), and stopping short of `to` by
    /// a thousandth of the way or by [`REACH_ULPS`] ulps of `to`'s size, whichever is more,
    /// so that it never meets the surface it aims at. (Measured from the surface point
    /// instead, a start lifted towards a surface close by ran into it: the floor under a
    /// glass ball's foot found its passages blocked by the ball, `tests/agreement.rs`.)
    ///
    /// ```
    /// use raypool::tracer::math::ray::Ray;
    /// use raypool::tracer::math::real::Vec3;
    /// let (ray, reach) = Ray::towards(Vec3::new(0.0, 0.001, 0.0), Vec3::new(0.0, 0.02, 0.0));
    /// assert_eq!(ray.dir, Vec3::Y);
    /// assert!(reach < 0.019 && reach > 0.018);
    /// ```
    ///
    /// [`Hit::spawn`]: crate::tracer::geometry::hit::Hit::spawn
    pub fn towards(from: Vec3, to: Vec3) -> (Ray, Real) {
        let way = to - from;
        let distance = way.length();
        let short = (1e-3 * distance).max(REACH_ULPS * Real::EPSILON * to.abs().max_element());
        (Ray { origin: from, dir: way / distance }, distance - short)
    }

    /// The point at distance `t` along the ray.
    pub fn at(&self, t: Real) -> Vec3 {
        self.origin + t * self.dir
    }
}
