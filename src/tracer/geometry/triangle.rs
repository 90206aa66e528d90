//! Triangles: pbrt's watertight ray–triangle test (Woop, Benthin and Wald 2013; pbrt-v4's
//! `Triangle::Intersect`), which never lets a ray slip between two triangles that share an
//! edge or a vertex.
//!
//! The ray is made the +z axis of its own frame: the vertices are moved to the ray's origin,
//! the axes permuted so the ray's largest direction component is z, and the frame sheared so
//! the ray points straight along it. The hit is then a 2-D question, answered by three edge
//! functions `e = a.x·b.y − a.y·b.x`, one per edge. Two triangles sharing an edge compute its
//! edge function from the same two transformed vertices, in the same order up to a swap, which
//! exactly negates the result: a ray is inside one or the other (or on the edge, `e = 0`,
//! where both accept it), never in neither. An `e` of exactly zero is recomputed in f64, as
//! pbrt does, so that a ray that truly misses an edge is not taken for one on it. The hit's
//! distance is kept only if it is positive beyond the test's own rounding bound (pbrt's
//! `deltaT`), so a ray leaving a triangle never meets it again.
//!
//! A triangle here is only three points: meshes (`world/mesh.rs`) keep their vertices shared
//! and indexed, and hand the three of a triangle to [`intersect`].

use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// pbrt's `γ(n) = nε / (1 − nε)`, with ε half an ulp of 1: a bound on `n` roundings.
const fn gamma(n: Real) -> Real {
    let e = Real::EPSILON * 0.5;
    n * e / (1.0 - n * e)
}

/// A hit on a triangle: its distance and barycentric coordinates (weights of the three
/// vertices, summing to 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray.
    pub t: Real,
    /// Weights of vertices 0, 1, 2.
    pub barycentric: [Real; 3],
}

/// Whether the triangle `p` has no area (it is then never hit; scene files refuse it).
pub fn degenerate(p: [Vec3; 3]) -> bool {
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let area2 = n.length_squared();
    !n.is_finite() || !area2.is_finite() || area2 <= 0.0
}

/// The hit of `ray` on the triangle `p` in `(0, t_max)`, if any.
///
/// ```
/// use raypool::tracer::geometry::triangle::intersect;
/// use raypool::tracer::math::{ray::Ray, real::Vec3};
/// let triangle = [Vec3::new(-1.0, -1.0, -2.0), Vec3::new(1.0, -1.0, -2.0), Vec3::new(0.0, 1.0, -2.0)];
/// let hit = intersect(triangle, &Ray::new(Vec3::ZERO, -Vec3::Z), f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 2.0);
/// assert!(intersect(triangle, &Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY).is_none());
/// ```
#[inline]
pub fn intersect(p: [Vec3; 3], ray: &Ray, t_max: Real) -> Option<TriangleHit> {
    intersect_in(&RayFrame::new(ray), p, ray, t_max)
}

/// The ray's own frame, the part of the test that depends on the ray alone: computed once
/// per ray by a mesh's search, then shared by every triangle it tests (the same numbers as
/// [`intersect`] computes for itself, so the same hits).
#[derive(Clone, Copy, Debug)]
pub struct RayFrame {
    /// The axes that become x, y and z (z: the direction's largest component).
    k: [usize; 3],
    /// The shear: `x += sx·z`, `y += sy·z`, then `z·sz`.
    sx: Real,
    sy: Real,
    sz: Real,
}

impl RayFrame {
    /// The frame of `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> RayFrame {
        let d = ray.dir;
        let kz = d.abs().max_position();
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        let (dx, dy, dz) = (d[kx], d[ky], d[kz]);
        RayFrame { k: [kx, ky, kz], sx: -dx / dz, sy: -dy / dz, sz: 1.0 / dz }
    }
}

/// [`intersect`] with the ray's frame already made (`frame` must be `RayFrame::new(ray)`).
#[inline(always)]
pub fn intersect_in(frame: &RayFrame, p: [Vec3; 3], ray: &Ray, t_max: Real) -> Option<TriangleHit> {
    let [kx, ky, kz] = frame.k;
    let permute = |v: Vec3| Vec3::new(v[kx], v[ky], v[kz]);
    let (sx, sy, sz) = (frame.sx, frame.sy, frame.sz);
    let mut q = p.map(|v| permute(v - ray.origin));
    for v in &mut q {
        v.x += sx * v.z;
        v.y += sy * v.z;
    }
    let mut e = [edge(q[1], q[2]), edge(q[2], q[0]), edge(q[0], q[1])];
    if e.contains(&0.0) {
        e = [edge_f64(q[1], q[2]), edge_f64(q[2], q[0]), edge_f64(q[0], q[1])];
    }
    if (e[0] < 0.0 || e[1] < 0.0 || e[2] < 0.0) && (e[0] > 0.0 || e[1] > 0.0 || e[2] > 0.0) {
        return None;
    }
    let det = e[0] + e[1] + e[2];
    if det == 0.0 {
        return None;
    }
    let z = q.map(|v| v.z * sz);
    let t_scaled = e[0] * z[0] + e[1] * z[1] + e[2] * z[2];
    // t = t_scaled / det must lie in (0, t_max): compared before dividing, sign by sign.
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if t.is_nan() || t >= t_max || t <= rounding_bound(&q, &z, &e, inv_det) {
        return None;
    }
    Some(TriangleHit { t, barycentric: e.map(|x| x * inv_det) })
}

/// The edge function of the transformed vertices `a`, `b`: twice the signed area of the
/// triangle they make with the ray (the origin of the sheared frame).
#[inline(always)]
fn edge(a: Vec3, b: Vec3) -> Real {
    a.x * b.y - a.y * b.x
}

/// [`edge`] in f64, for the rare exact zero that f32 rounding may have produced.
#[cold]
#[allow(clippy::unnecessary_cast)] // a no-op in the f64 build
fn edge_f64(a: Vec3, b: Vec3) -> Real {
    let (ax, ay, bx, by) = (a.x as f64, a.y as f64, b.x as f64, b.y as f64);
    (ax * by - ay * bx) as Real
}

/// pbrt's bound on the rounding error of the computed `t` (`deltaT`): a hit no farther than
/// this might really lie behind the ray's origin.
#[inline(always)]
fn rounding_bound(q: &[Vec3; 3], z: &[Real; 3], e: &[Real; 3], inv_det: Real) -> Real {
    let max_z = z[0].abs().max(z[1].abs()).max(z[2].abs());
    let delta_z = gamma(3.0) * max_z;
    let max_x = q[0].x.abs().max(q[1].x.abs()).max(q[2].x.abs());
    let max_y = q[0].y.abs().max(q[1].y.abs()).max(q[2].y.abs());
    let delta_x = gamma(5.0) * (max_x + max_z);
    let delta_y = gamma(5.0) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e[0].abs().max(e[1].abs()).max(e[2].abs());
    3.0 * (gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs()
}
