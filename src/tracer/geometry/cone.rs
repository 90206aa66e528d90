//! The cone of directions a sphere fills, seen from a point outside it: how a sphere light is
//! aimed at (the third book's and pbrt's way, uniform over the cone, so no sample is spent on
//! its far side), the density of such a direction, and whether a direction lies in it.
//!
//! Small far spheres are where f32 suffers: a cone of half-angle 0.006 rad is a few hundred
//! ulps of its cosine wide. So the cone keeps `sin² θmax` and `1 − cos θmax` computed without
//! cancelling, tests membership by the sine, and builds a drawn point on the sphere from its
//! angle at the centre (pbrt-v4's `Sphere::Sample`) rather than along the ray from the point.
//! Invariant: every direction [`Cone::draw`] returns is one [`Cone::contains`] accepts.

use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};

/// The cone a sphere fills as seen from a point outside it.
///
/// ```
/// use raypool::tracer::geometry::{cone::Cone, sphere::Sphere};
/// use raypool::tracer::math::real::Vec3;
/// let ball = Sphere { center: Vec3::new(0.0, 0.0, -5.0), radius: 0.03, material: 0 };
/// let cone = Cone::of(&ball, Vec3::ZERO).unwrap();
/// let (dir, point) = cone.draw(&ball, 0.999, 0.25);
/// assert!(cone.contains(dir));
/// assert!(((point - ball.center).length() / 0.03 - 1.0).abs() < 1e-5, "on the sphere");
/// assert!(Cone::of(&ball, ball.center).is_none(), "none from inside");
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Cone {
    /// Unit, towards the centre.
    axis: Vec3,
    /// sin² of its half-angle, `r² / d²`.
    sin2_max: Real,
    /// `1 − cos θmax`, as `sin² θmax / (1 + cos θmax)`: the plain form cancels for a small far
    /// sphere in f32 (how far off: `results/history/comment-figures.md`).
    one_minus_cos_max: Real,
}

impl Cone {
    /// The cone `sphere` fills from `from`; `None` from inside or on the sphere.
    pub fn of(sphere: &Sphere, from: Vec3) -> Option<Cone> {
        let to = sphere.center - from;
        let d2 = to.length_squared();
        let sin2_max = sphere.radius * sphere.radius / d2;
        if sin2_max.is_nan() || sin2_max >= 1.0 {
            return None;
        }
        let one_minus_cos_max = sin2_max / (1.0 + (1.0 - sin2_max).sqrt());
        (one_minus_cos_max > 0.0).then(|| Cone { axis: to / d2.sqrt(), sin2_max, one_minus_cos_max })
    }

    /// The density per unit solid angle of a direction drawn uniformly in it, times `chance`
    /// (one expression, so that a sample and a lookup of its point give the same bits).
    pub fn density(&self, chance: Real) -> Real {
        chance / (2.0 * PI * self.one_minus_cos_max)
    }

    /// Whether the unit `dir` lies in it: by the sine, whose f32 resolution stays fine near the
    /// axis where the cosine's does not, with room for a drawn direction's own rounding at the
    /// rim (a few ε in its sine, however small).
    pub fn contains(&self, dir: Vec3) -> bool {
        let sin_max = self.sin2_max.sqrt() + 8.0 * Real::EPSILON;
        dir.dot(self.axis) > 0.0 && dir.cross(self.axis).length_squared() <= sin_max * sin_max
    }

    /// A direction drawn uniformly in the cone of `sphere` (the one it was made for) from two
    /// uniform numbers `a, b` in `[0, 1)`, and the point where it meets the sphere's near side.
    pub fn draw(&self, sphere: &Sphere, a: Real, b: Real) -> (Vec3, Vec3) {
        // θ uniform in cos θ; sin² θ from 1 − cos θ, which does not cancel near the axis as
        // 1 − cos² θ would.
        let one_minus_cos = a * self.one_minus_cos_max;
        let cos = 1.0 - one_minus_cos;
        let sin2 = one_minus_cos * (2.0 - one_minus_cos);
        let (s, c) = (2.0 * PI * b).sin_cos();
        let (t1, t2) = self.axis.any_orthonormal_pair();
        let across = c * t1 + s * t2;
        let dir = (cos * self.axis + sin2.sqrt() * across).normalize();
        // The point, on the sphere at the angle α from the axis that the direction meets:
        // measured from the viewpoint instead, `d cos θ − √(r² − d² sin² θ)` cancels near the
        // rim and left small far spheres' points off their surface; a ray test would miss
        // now and then at the grazing rim.
        let ratio = (sin2 / self.sin2_max).min(1.0);
        let cos_alpha = ratio * self.sin2_max.sqrt() + cos * (1.0 - ratio).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let point = sphere.center + sphere.radius.abs() * (sin_alpha * across - cos_alpha * self.axis);
        (dir, point)
    }
}
