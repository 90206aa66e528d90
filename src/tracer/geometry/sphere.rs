//! Spheres: a numerically stable ray test and a self-intersection-free hit.
//!
//! Two things make f32 spheres robust where the textbook code shows acne or misses:
//!
//! 1. **The stable quadratic** (Ray Tracing Gems, ch. 7). The discriminant is computed from
//!    the perpendicular distance of the centre to the ray, `r² − |f − (f·d)d|²`, instead of
//!    `b² − c`, which cancels catastrophically when the sphere is huge or far away; and the
//!    roots come from `q = −b − sign(b)·√Δ` as `q` and `c/q`, so neither subtracts two
//!    nearly equal numbers.
//! 2. **Spawning off the surface.** A new ray starts at the hit point pushed along the normal,
//!    to the side it leaves towards, by a distance scaled to the sphere's own magnitude
//!    ([`Sphere::spawn_offset`]). This replaces the book's fixed `t_min = 0.001`, which is too
//!    large for tiny scenes and too small for a ground sphere of radius 10⁴ in f32.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, consts};

/// How rays meet spheres. Only [`Intersection::Robust`] is used for images; the book's
/// method is kept so that `results/stability.md` and the ablation table can show what the
/// robust one buys.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Intersection {
    /// The stable quadratic ([`Sphere::intersect`]), hit points re-projected onto the
    /// surface, new rays spawned off it by [`Sphere::spawn_offset`].
    #[default]
    Robust,
    /// The book's: the textbook quadratic ([`Sphere::intersect_textbook`]), hits nearer than
    /// [`TEXTBOOK_T_MIN`] ignored, new rays starting exactly at the computed hit point.
    Textbook,
}

/// The book's fixed minimum hit distance, which hides most self-intersections at the scale
/// of its scenes (and only there).
pub const TEXTBOOK_T_MIN: Real = 0.001;

/// A sphere. A negative radius makes a hollow shell: same surface, normals pointing inwards
/// (the book's trick for a glass bubble).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world units.
    pub center: Vec3,
    /// Radius, world units; negative for an inward-facing shell; never zero.
    pub radius: Real,
    /// Index into the scene's material table.
    pub material: u32,
}

impl Sphere {
    /// Distance to the nearest intersection in `(0, t_max)`, if any.
    ///
    /// `ray.dir` must be a unit vector (see [`Ray`]).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: Real) -> Option<Real> {
        let f = ray.origin - self.center;
        let r2 = self.radius * self.radius;
        let b = f.dot(ray.dir); // half the textbook b, with a = 1
        let perp = f - b * ray.dir; // centre-to-line offset, perpendicular to the ray
        let discriminant = r2 - perp.length_squared();
        if discriminant < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        if c > 0.0 && b > 0.0 {
            // Outside and moving away (the roots' product c is positive, their sum −2b
            // negative): both roots are negative, and below they would come out negative too
            // (q < 0, c/q < 0). Decided before the square root and the division, the slowest
            // part of the test: every bounce ray meets the sphere it leaves here.
            return None;
        }
        let q = -b - discriminant.sqrt().copysign(b);
        if q == 0.0 {
            return None; // a tangent ray starting on the tangent point: no hit ahead
        }
        let (near, far) = {
            let (t0, t1) = (c / q, q);
            if t0 <= t1 { (t0, t1) } else { (t1, t0) }
        };
        if near > 0.0 && near < t_max {
            Some(near)
        } else if far > 0.0 && far < t_max {
            Some(far)
        } else {
            None
        }
    }

    /// The book's test, for comparison: `h = d·(c − o)`, `Δ = h² − (|c − o|² − r²)`, roots
    /// `h ∓ √Δ`, accepted in `(TEXTBOOK_T_MIN, t_max)`. Both `h²` and `|c − o|²` are huge for
    /// a big or far sphere, so their difference loses most of its digits in f32.
    #[inline]
    pub fn intersect_textbook(&self, ray: &Ray, t_max: Real) -> Option<Real> {
        let oc = self.center - ray.origin;
        let h = ray.dir.dot(oc);
        let c = oc.length_squared() - self.radius * self.radius;
        let discriminant = h * h - c;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        [h - root, h + root].into_iter().find(|&t| t > TEXTBOOK_T_MIN && t < t_max)
    }

    /// The book's hit record for [`Sphere::intersect_textbook`]: the point is where the ray
    /// says, the normal `(p − c) / r`, and new rays start right there (no offset).
    #[inline]
    pub fn hit_at_textbook(&self, ray: &Ray, t: Real) -> Hit {
        let point = ray.at(t);
        let outward = (point - self.center) / self.radius;
        let front_face = ray.dir.dot(outward) < 0.0;
        let normal = if front_face { outward } else { -outward };
        Hit { t, point, normal, front_face, material: self.material, offset: 0.0, lift: 0.0, u: 0.0, v: 0.0 }
    }

    /// The hit in `(0, t_max)`, if any, without its texture coordinates ([`Sphere::with_uv`]
    /// adds them to the closest hit of a search).
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        let t = self.intersect(ray, t_max)?;
        Some(self.hit_at(ray, t))
    }

    /// The full hit record for an intersection at distance `t` found by [`Sphere::intersect`].
    #[inline]
    pub fn hit_at(&self, ray: &Ray, t: Real) -> Hit {
        // The signed radius's sign turns a hollow shell's normals inwards. One square root
        // and one division: `(p − c) / r` normalised again cost a second vector division.
        let from_center = ray.at(t) - self.center;
        let outward = from_center * ((1.0 as Real).copysign(self.radius) / from_center.length());
        // Re-project onto the surface: `ray.at(t)` carries the rounding error of the ray's
        // origin and length (large for a far camera), this only that of the sphere itself,
        // which is what `spawn_offset` is sized for.
        let point = self.center + self.radius * outward;
        let front_face = ray.dir.dot(outward) < 0.0;
        Hit {
            t,
            point,
            normal: if front_face { outward } else { -outward },
            front_face,
            material: self.material,
            offset: self.spawn_offset(),
            lift: 0.0,
            u: 0.0,
            v: 0.0,
        }
    }

    /// `hit`, one of [`Sphere::hit_at`]'s, with its texture coordinates filled in: `u` the
    /// angle around the y axis from −x, `v` from the bottom pole (the book's `get_sphere_uv`),
    /// both in `[0, 1]`. An arc cosine and an arc tangent: paid for the closest hit only.
    #[inline]
    pub fn with_uv(&self, mut hit: Hit) -> Hit {
        let outward = if hit.front_face == (self.radius > 0.0) { hit.normal } else { -hit.normal };
        let theta = (-outward.y).clamp(-1.0, 1.0).acos();
        let phi = (-outward.z).atan2(outward.x) + consts::PI;
        (hit.u, hit.v) = (phi / (2.0 * consts::PI), theta / consts::PI);
        hit
    }

    /// The safe distance off this sphere's surface for a new ray's origin.
    ///
    /// Rounding puts a computed hit point within a few ulps of the largest coordinate
    /// involved, `|centre| + |radius|`. A few of those ulps clear the surface for every
    /// scale, from a 10⁻³ sphere to paper2's 10⁴ ground, in f32 and f64 alike.
    #[inline]
    pub fn spawn_offset(&self) -> Real {
        const ULPS: Real = 8.0;
        ULPS * Real::EPSILON * (self.center.abs().max_element() + self.radius.abs())
    }
}

impl Bounded for Sphere {
    /// The sphere's box, padded by the sphere test's rounding: its computed hits can lie
    /// outside the exact sphere (the ground of `final`, radius 1000, was once hit above its
    /// box's top, so the box was skipped and a farther sphere reported; `results/perf.md`).
    /// The pad is 2 units of `ε·(|centre| + |radius|)`, far above that hit's distance. New rays start 8 units off the surface ([`Sphere::spawn_offset`]), outside the
    /// pad, so a ray leaving a sphere outwards still misses its box.
    fn bounds(&self) -> Aabb {
        let r = Vec3::splat(self.radius.abs() + 0.25 * self.spawn_offset());
        Aabb { min: self.center - r, max: self.center + r }
    }

    fn centroid(&self) -> Vec3 {
        self.center
    }
}
