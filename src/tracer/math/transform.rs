//! Rigid placements (rotation, then translation) for instances: one copy of the geometry, many
//! placements, the ray moved into the object's frame instead of the object into the world's
//! (the books' `translate` and `rotate_y`; pbrt's `TransformedPrimitive`).
//!
//! Rigid only: lengths are kept, so a ray's unit direction stays unit in the object's frame,
//! a hit's distance is the same number in both frames, and a normal turns like a direction
//! (no inverse transpose). Scaling a mesh is done once, to its vertices, when it is loaded.

use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// `p ↦ R·p + offset`, with `R` a rotation stored as its three rows.
///
/// ```
/// use raypool::tracer::math::{real::Vec3, transform::Transform};
/// let quarter = Transform::rotate_y(90.0).then_translate(Vec3::new(0.0, 2.0, 0.0));
/// let p = quarter.point(Vec3::X);
/// assert!((p - Vec3::new(0.0, 2.0, -1.0)).length() < 1e-6, "{p}");
/// assert!((quarter.inverse_point(p) - Vec3::X).length() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    rows: [Vec3; 3],
    offset: Vec3,
}

impl Transform {
    /// Leaves every point where it is.
    pub const IDENTITY: Transform = Transform { rows: [Vec3::X, Vec3::Y, Vec3::Z], offset: Vec3::ZERO };

    /// A rotation by `degrees` about the y axis (counter-clockwise seen from +y, as the book's
    /// `rotate_y`). Quarter turns are exact.
    pub fn rotate_y(degrees: f64) -> Transform {
        let (sin, cos) = exact_sin_cos(degrees);
        Transform { rows: [Vec3::new(cos, 0.0, sin), Vec3::Y, Vec3::new(-sin, 0.0, cos)], offset: Vec3::ZERO }
    }

    /// A rotation by `degrees` about the x axis.
    pub fn rotate_x(degrees: f64) -> Transform {
        let (sin, cos) = exact_sin_cos(degrees);
        Transform { rows: [Vec3::X, Vec3::new(0.0, cos, -sin), Vec3::new(0.0, sin, cos)], offset: Vec3::ZERO }
    }

    /// A rotation by `degrees` about the z axis.
    pub fn rotate_z(degrees: f64) -> Transform {
        let (sin, cos) = exact_sin_cos(degrees);
        Transform { rows: [Vec3::new(cos, -sin, 0.0), Vec3::new(sin, cos, 0.0), Vec3::Z], offset: Vec3::ZERO }
    }

    /// This placement followed by `other`.
    pub fn then(&self, other: &Transform) -> Transform {
        let column = |k: usize| Vec3::new(self.rows[0][k], self.rows[1][k], self.rows[2][k]);
        let rows =
            other.rows.map(|row| Vec3::new(row.dot(column(0)), row.dot(column(1)), row.dot(column(2))));
        Transform { rows, offset: other.point(self.offset) }
    }

    /// This placement followed by a move of `offset`.
    pub fn then_translate(&self, offset: Vec3) -> Transform {
        Transform { rows: self.rows, offset: self.offset + offset }
    }

    /// Whether this is the identity (nothing to do per ray).
    pub fn is_identity(&self) -> bool {
        *self == Transform::IDENTITY
    }

    /// The world point of object point `p`.
    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.vector(p) + self.offset
    }

    /// The world direction of object direction `v`.
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        Vec3::new(self.rows[0].dot(v), self.rows[1].dot(v), self.rows[2].dot(v))
    }

    /// The object point of world point `p`.
    #[inline]
    pub fn inverse_point(&self, p: Vec3) -> Vec3 {
        self.inverse_vector(p - self.offset)
    }

    /// The object direction of world direction `v` (the rotation's transpose).
    #[inline]
    pub fn inverse_vector(&self, v: Vec3) -> Vec3 {
        self.rows[0] * v.x + self.rows[1] * v.y + self.rows[2] * v.z
    }

    /// The world ray in the object's frame (same distances: the placement is rigid).
    #[inline]
    pub fn inverse_ray(&self, ray: &Ray) -> Ray {
        Ray { origin: self.inverse_point(ray.origin), dir: self.inverse_vector(ray.dir) }
    }

    /// A world box holding the placed object box `b`.
    pub fn bounds(&self, b: &Aabb) -> Aabb {
        b.corners().iter().fold(Aabb::EMPTY, |acc, &c| acc.grow(self.point(c)))
    }

    /// The length of the translation's largest coordinate: a placed point's rounding grows
    /// with it.
    pub fn offset_magnitude(&self) -> Real {
        self.offset.abs().max_element()
    }
}

/// The sine and cosine of `degrees`, exact at multiples of 90° (where libm's are not: `cos(π/2)`
/// is 6·10⁻¹⁷, which would tilt a quarter-turned box).
fn exact_sin_cos(degrees: f64) -> (Real, Real) {
    let quarters = degrees / 90.0;
    if quarters == quarters.round() {
        let k = (quarters.round() as i64).rem_euclid(4);
        return [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][k as usize];
    }
    let (sin, cos) = degrees.to_radians().sin_cos();
    (sin as Real, cos as Real)
}
