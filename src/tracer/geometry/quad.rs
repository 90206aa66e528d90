//! The second book's parallelogram ("quad"): a corner `q` and two edge vectors `u` and `v`.
//! Boxes are six of them.
//!
//! The test is the book's (the plane, then the hit's coordinates `α`, `β` along `u` and `v`),
//! made robust the way the sphere's is:
//!
//! - the distance is `n·(q − o) / n·d`, the difference taken first, so a ray leaving a quad
//!   far from the origin does not lose its digits to `n·q − n·o` (two large, nearly equal
//!   numbers);
//! - the hit point is re-projected onto the quad, `q + α·u + β·v`, and new rays start a few
//!   ulps of the quad's own magnitude off it ([`Quad::spawn_offset`]);
//! - `α` and `β` are accepted a few ulps past `[0, 1]` ([`EDGE`]), so a ray aimed exactly at
//!   the edge two faces of a box share is caught by at least one of them.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, from_dvec3, to_dvec3};

/// How far past its edges, in units of the edge vectors, a quad still counts a hit: a few
/// roundings of `α` and `β`, so that neighbours overlap by a hair instead of leaving a crack.
pub const EDGE: Real = 16.0 * Real::EPSILON;

/// A parallelogram `q + α·u + β·v`, `α, β ∈ [0, 1]`; its front faces `u × v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// A corner.
    pub q: Vec3,
    /// First edge vector, from `q`.
    pub u: Vec3,
    /// Second edge vector, from `q`.
    pub v: Vec3,
    /// [`dual_basis`]`(u, v)`: a point `p` of the plane (from `q`) has `α = p · dual[0]`
    /// and `β = p · dual[1]`.
    dual: [Vec3; 2],
    /// Unit normal, `u × v` normalised.
    normal: Vec3,
    /// Index into the scene's material table.
    pub material: u32,
}

impl Quad {
    /// The quad at corner `q` with edges `u` and `v`; `None` when it is degenerate (an edge of
    /// length zero, parallel edges, or numbers that are not finite).
    ///
    /// ```
    /// use raypool::tracer::geometry::quad::Quad;
    /// use raypool::tracer::math::real::Vec3;
    /// assert!(Quad::new(Vec3::ZERO, Vec3::X, Vec3::X, 0).is_none(), "parallel edges");
    /// let square = Quad::new(Vec3::ZERO, Vec3::X, Vec3::Y, 0).unwrap();
    /// assert_eq!(square.normal(), Vec3::Z);
    /// ```
    pub fn new(q: Vec3, u: Vec3, v: Vec3, material: u32) -> Option<Quad> {
        let n = u.cross(v);
        let finite = q.is_finite() && u.is_finite() && v.is_finite() && n.is_finite();
        let area2 = n.length_squared();
        if !finite || !area2.is_finite() || area2 <= 0.0 {
            return None;
        }
        Some(Quad { q, u, v, dual: dual_basis(u, v), normal: n / area2.sqrt(), material })
    }

    /// The unit normal the quad's front faces.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The vectors whose dot products with a point of the plane (from `q`) are its `(α, β)`.
    pub fn dual_basis(&self) -> [Vec3; 2] {
        self.dual
    }

    /// Its area.
    pub fn area(&self) -> Real {
        self.u.cross(self.v).length()
    }

    /// The distance to the hit in `(0, t_max)` and its `(α, β)`, if any.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: Real) -> Option<(Real, Real, Real)> {
        let denom = self.normal.dot(ray.dir);
        let to_corner = self.q - ray.origin;
        let t = self.normal.dot(to_corner) / denom;
        // A ray parallel to the plane gives ±∞ or NaN, which fails this test too.
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        // `(t·d − c) · dual` expanded: the two dot products need not wait for the division.
        let alpha = t * ray.dir.dot(self.dual[0]) - to_corner.dot(self.dual[0]);
        let beta = t * ray.dir.dot(self.dual[1]) - to_corner.dot(self.dual[1]);
        let inside = |x: Real| (-EDGE..=1.0 + EDGE).contains(&x);
        (inside(alpha) && inside(beta)).then_some((t, alpha, beta))
    }

    /// The hit record for an intersection found by [`Quad::intersect`] at distance `t` and
    /// `(α, β)`, met from the front (`front_face`: `n · d < 0`, which a packet's test has
    /// already found).
    #[inline]
    pub fn hit_at(&self, t: Real, alpha: Real, beta: Real, front_face: bool) -> Hit {
        let (u, v) = (alpha.clamp(0.0, 1.0), beta.clamp(0.0, 1.0));
        Hit {
            t,
            point: self.q + u * self.u + v * self.v,
            normal: if front_face { self.normal } else { -self.normal },
            front_face,
            material: self.material,
            offset: self.spawn_offset(),
            lift: 0.0,
            u,
            v,
        }
    }

    /// The safe distance off the quad for a new ray's origin: a few ulps of its largest
    /// coordinate, as for spheres.
    #[inline]
    pub fn spawn_offset(&self) -> Real {
        const ULPS: Real = 8.0;
        ULPS * Real::EPSILON * (self.q.abs() + self.u.abs() + self.v.abs()).max_element()
    }

    /// The four corners.
    pub fn corners(&self) -> [Vec3; 4] {
        [self.q, self.q + self.u, self.q + self.v, self.q + self.u + self.v]
    }
}

/// The vectors `v × w` and `w × u`, with `w = (u × v) / |u × v|²`: the dual basis of
/// `(u, v)` in their plane (`dual[0] · u = 1`, `dual[0] · v = 0`, and the other way round for
/// `dual[1]`). The book finds `α = w · (p × v)` and `β = w · (u × p)` at every ray; the
/// triple products turned round, `p · (v × w)` and `p · (w × u)`, leave one dot product each
/// per ray, and the cross products are taken once, in f64, so each vector is rounded once.
fn dual_basis(u: Vec3, v: Vec3) -> [Vec3; 2] {
    let (u, v) = (to_dvec3(u), to_dvec3(v));
    let n = u.cross(v);
    let w = n / n.length_squared();
    [from_dvec3(v.cross(w)), from_dvec3(w.cross(u))]
}

impl Bounded for Quad {
    /// The corners' box, padded as a sphere's is (a quad in an axis plane has a flat box,
    /// which rounding could otherwise make a ray skip), and by how far past its edges
    /// [`Quad::intersect`] accepts a hit ([`EDGE`] of each side): otherwise a ray that grazes
    /// an edge would hit the quad when tested directly but miss its box in a tree, and
    /// `--accel flat` would change pixels.
    fn bounds(&self) -> Aabb {
        let corners = self.corners().iter().fold(Aabb::EMPTY, |b, &c| b.grow(c));
        let past_edges = EDGE * (self.u.abs() + self.v.abs()).max_element();
        corners.padded(0.25 * self.spawn_offset() + past_edges)
    }

    fn centroid(&self) -> Vec3 {
        self.q + 0.5 * (self.u + self.v)
    }
}

/// The six faces of the box with opposite corners `a` and `b`, each facing outwards (a
/// closed surface: its front faces are its outside, which a medium bounded by it relies on).
pub fn box_faces(a: Vec3, b: Vec3, material: u32) -> Option<[Quad; 6]> {
    let (min, max) = (a.min(b), a.max(b));
    let d = max - min;
    let (dx, dy, dz) = (Vec3::new(d.x, 0.0, 0.0), Vec3::new(0.0, d.y, 0.0), Vec3::new(0.0, 0.0, d.z));
    let faces = [
        Quad::new(Vec3::new(min.x, min.y, max.z), dx, dy, material)?, // front, +z
        Quad::new(Vec3::new(max.x, min.y, max.z), -dz, dy, material)?, // right, +x
        Quad::new(Vec3::new(max.x, min.y, min.z), -dx, dy, material)?, // back, −z
        Quad::new(min, dz, dy, material)?,                            // left, −x
        Quad::new(Vec3::new(min.x, max.y, max.z), dx, -dz, material)?, // top, +y
        Quad::new(min, dx, dz, material)?,                            // bottom, −y
    ];
    Some(faces)
}
