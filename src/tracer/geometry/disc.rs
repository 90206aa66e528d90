//! pbrt's disc (`Disk`): a centre, a unit normal and a radius, met from either side as a quad
//! is.
//!
//! The test is the quad's, made robust the same way:
//!
//! - the distance is `n·(c − o) / n·d`, the difference taken first, so a ray leaving a disc far
//!   from the origin does not lose its digits to `n·c − n·o`;
//! - the hit's offset from the centre is `t·d − (c − o)`, which holds no large `o + t·d`; it is
//!   pressed into the plane and onto the disc, so the point carries only the rounding of the
//!   disc's own numbers, and new rays start a few ulps of its magnitude off it
//!   ([`Disc::spawn_offset`]);
//! - a hit is accepted a few ulps past the rim ([`EDGE`] of the radius), as a quad's past its
//!   edges, and the box is padded by as much.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::geometry::quad::EDGE;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, consts};

/// The points of a plane within `radius` of `center`; its front faces `normal`.
///
/// ```
/// use raypool::tracer::geometry::disc::Disc;
/// use raypool::tracer::math::ray::Ray;
/// use raypool::tracer::math::real::Vec3;
/// assert!(Disc::new(Vec3::ZERO, Vec3::ZERO, 1.0, 0).is_none(), "no normal");
/// let disc = Disc::new(Vec3::ZERO, 2.0 * Vec3::Z, 1.0, 0).unwrap();
/// assert_eq!(disc.normal(), Vec3::Z, "normalised");
/// let down = |x| Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
/// assert_eq!(disc.hit(&down(0.5), 10.0).map(|hit| hit.t), Some(5.0));
/// assert!(disc.hit(&down(1.5), 10.0).is_none(), "outside the radius");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disc {
    /// The centre.
    pub center: Vec3,
    /// The radius, > 0.
    pub radius: Real,
    /// Unit normal.
    normal: Vec3,
    /// Two unit vectors that make a frame with the normal: the texture's angle is measured
    /// from the first towards the second.
    tangent: (Vec3, Vec3),
    /// Index into the scene's material table.
    pub material: u32,
}

impl Disc {
    /// The disc at `center` facing `normal` (of any length, not zero); `None` when degenerate
    /// (a radius not > 0, a zero normal, or numbers that are not finite).
    pub fn new(center: Vec3, normal: Vec3, radius: Real, material: u32) -> Option<Disc> {
        let normal = normal.try_normalize()?;
        if !center.is_finite() || !radius.is_finite() || radius <= 0.0 {
            return None;
        }
        let tangent = normal.any_orthonormal_pair();
        Some(Disc { center, radius, normal, tangent, material })
    }

    /// The unit normal the disc's front faces.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The distance to the hit in `(0, t_max)` and the hit's offset from the centre, if any.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: Real) -> Option<(Real, Vec3)> {
        let to_center = self.center - ray.origin;
        let t = self.normal.dot(to_center) / self.normal.dot(ray.dir);
        // A ray parallel to the plane gives ±∞ or NaN, which fails this test too.
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let offset = t * ray.dir - to_center;
        let rim = self.radius * (1.0 + EDGE);
        (offset.length_squared() <= rim * rim).then_some((t, offset))
    }

    /// The hit in `(0, t_max)`, if any, without its texture coordinates ([`Disc::with_uv`]
    /// adds them to the closest hit of a search).
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        let (t, offset) = self.intersect(ray, t_max)?;
        let in_plane = offset - self.normal.dot(offset) * self.normal;
        let on_disc = in_plane.clamp_length_max(self.radius);
        let front_face = ray.dir.dot(self.normal) < 0.0;
        Some(Hit {
            t,
            point: self.center + on_disc,
            normal: if front_face { self.normal } else { -self.normal },
            front_face,
            material: self.material,
            offset: self.spawn_offset(),
            lift: 0.0,
            u: 0.0,
            v: 0.0,
        })
    }

    /// `hit`, one of [`Disc::hit`]'s, with its texture coordinates: `u` the angle about the
    /// centre over 2π, `v` the distance from it over the radius, both in `[0, 1]`. An arc
    /// tangent: paid for the closest hit only, as a sphere's.
    #[inline]
    pub fn with_uv(&self, mut hit: Hit) -> Hit {
        let offset = hit.point - self.center;
        let (x, y) = (offset.dot(self.tangent.0), offset.dot(self.tangent.1));
        let phi = y.atan2(x);
        let turn = if phi < 0.0 { phi + 2.0 * consts::PI } else { phi };
        hit.u = (turn / (2.0 * consts::PI)).min(1.0);
        hit.v = (offset.length() / self.radius).min(1.0);
        hit
    }

    /// The safe distance off the disc for a new ray's origin: a few ulps of its largest
    /// coordinate, as for spheres and quads.
    #[inline]
    pub fn spawn_offset(&self) -> Real {
        const ULPS: Real = 8.0;
        ULPS * Real::EPSILON * (self.center.abs().max_element() + self.radius)
    }
}

impl Bounded for Disc {
    /// The disc's own box: along axis `i` it reaches `r·√(1 − nᵢ²)` from the centre, written
    /// `r·√(nⱼ² + nₖ²)` so that no nearly-unit `nᵢ²` is subtracted from 1. Padded as a
    /// quad's is: by the box test's rounding, and past the rim by twice what
    /// [`Disc::intersect`] accepts (the rest covers pressing the point into the plane).
    fn bounds(&self) -> Aabb {
        let n2 = self.normal * self.normal;
        let reach = Vec3::new(n2.y + n2.z, n2.x + n2.z, n2.x + n2.y).map(Real::sqrt) * self.radius;
        let pad = 0.25 * self.spawn_offset() + 2.0 * EDGE * self.radius;
        Aabb { min: self.center - reach, max: self.center + reach }.padded(pad)
    }

    fn centroid(&self) -> Vec3 {
        self.center
    }
}
