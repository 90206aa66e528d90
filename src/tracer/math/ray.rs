//! A ray: `origin + t · dir`, with `dir` always of unit length.
//!
//! Keeping directions normalised makes `t` a distance, lets the sphere test drop the `a`
//! coefficient of the quadratic, and keeps the stable form of that test exact (see
//! `geometry/sphere.rs`).

use crate::tracer::math::real::{Real, Vec3};

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

    /// The point at distance `t` along the ray.
    pub fn at(&self, t: Real) -> Vec3 {
        self.origin + t * self.dir
    }
}
