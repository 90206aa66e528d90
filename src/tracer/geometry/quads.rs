//! Four quads tested at once: their corners, normals and edge vectors stored as structure of
//! arrays, so one pass of [`Quad::intersect`]'s arithmetic runs in the four lanes of a SIMD
//! register (the walls of a room, a box's faces, the ground's boxes of the second book).
//!
//! As `accel/packet.rs` does for spheres, the lanes are plain `[Real; 4]` arrays written as
//! loops the compiler vectorises for baseline x86-64, with no `unsafe`. Every lane performs
//! exactly the arithmetic of [`Quad::intersect`], in glam's order (a dot product is
//! `(x·x′ + y·y′) + z·z′`, a cross product's component `a·b′ − a′·b`, no fused multiply-add),
//! so a packet finds bit for bit the distance and the `(α, β)` that testing the quads one by
//! one finds; the scalar test's early exit (a plane behind the ray) only skips work whose
//! answer is "no hit", which a lane computes and finds too.
//!
//! Invariant: unused lanes hold NaN, and every comparison with NaN is false, so they never
//! report a hit.

use crate::tracer::geometry::quad::{EDGE, Quad};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Real4};

/// Quads per packet.
pub const LANES: usize = 4;

/// Up to [`LANES`] quads, structure of arrays: per vector, its x, y and z lanes.
#[derive(Clone, Copy, Debug)]
pub struct QuadPacket {
    q: [Real4; 3],
    normal: [Real4; 3],
    w: [Real4; 3],
    u: [Real4; 3],
    v: [Real4; 3],
}

/// What a packet's test found: each lane's distance (infinity where it is not hit) and
/// `(α, β)`, and a mask with bit `k` set where lane `k`'s quad is hit in `(0, t_max)`.
#[derive(Clone, Copy, Debug)]
pub struct QuadHits {
    /// Distance along the ray; infinity in the lanes not hit.
    pub t: Real4,
    /// The hit's coordinate along the quad's first edge.
    pub alpha: Real4,
    /// Along its second edge.
    pub beta: Real4,
    /// Bit `k`: lane `k` is hit.
    pub mask: u32,
}

impl QuadHits {
    /// The lane of the nearest hit, the lowest of equals (the lower index wins a tie, as
    /// [`Closest`](crate::tracer::geometry::hit::Closest) decides), if any lane is hit. Found
    /// without a branch per lane: how many lanes a ray hits is anyone's guess.
    #[inline(always)]
    pub fn nearest(&self) -> Option<usize> {
        let first = self.t.cmpeq(Real4::splat(self.t.min_element())).bitmask() & self.mask;
        (first != 0).then(|| first.trailing_zeros() as usize)
    }
}

impl QuadPacket {
    /// Lane `k` holds `quads[k]`, or nothing (NaN) where that is `None`.
    ///
    /// ```
    /// use raypool::tracer::geometry::{quad::Quad, quads::QuadPacket};
    /// use raypool::tracer::math::{ray::Ray, real::{Real, Vec3}};
    /// let wall = |z: Real| Quad::new(Vec3::new(-1.0, -1.0, z), 2.0 * Vec3::X, 2.0 * Vec3::Y, 0).unwrap();
    /// let (near, far) = (wall(-2.0), wall(-5.0));
    /// let packet = QuadPacket::new([Some(&far), None, Some(&near), None]);
    /// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
    /// let hits = packet.intersect(&ray, Real::INFINITY);
    /// assert_eq!((hits.mask, hits.t[0], hits.t[2]), (0b101, 5.0, 2.0));
    /// assert_eq!(hits.t[2], near.intersect(&ray, Real::INFINITY).unwrap().0);
    /// ```
    pub fn new(quads: [Option<&Quad>; LANES]) -> QuadPacket {
        let lanes = |of: fn(&Quad) -> [Real; 3]| {
            let mut out = [[Real::NAN; LANES]; 3];
            for (k, quad) in quads.iter().enumerate() {
                if let Some(quad) = quad {
                    let value = of(quad);
                    (0..3).for_each(|axis| out[axis][k] = value[axis]);
                }
            }
            out.map(Real4::from_array)
        };
        QuadPacket {
            q: lanes(|quad| quad.q.to_array()),
            normal: lanes(|quad| quad.normal().to_array()),
            w: lanes(|quad| quad.plane_coordinates().to_array()),
            u: lanes(|quad| quad.u.to_array()),
            v: lanes(|quad| quad.v.to_array()),
        }
    }

    /// [`Quad::intersect`] in every lane, for hits in `(0, t_max)`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: Real) -> QuadHits {
        let splat = Real4::splat;
        let (o, d) = (
            [ray.origin.x, ray.origin.y, ray.origin.z].map(splat),
            [ray.dir.x, ray.dir.y, ray.dir.z].map(splat),
        );
        let (n, q, w, u, v) = (&self.normal, &self.q, &self.w, &self.u, &self.v);
        let denom = (n[0] * d[0] + n[1] * d[1]) + n[2] * d[2];
        let c = [q[0] - o[0], q[1] - o[1], q[2] - o[2]];
        let t = ((n[0] * c[0] + n[1] * c[1]) + n[2] * c[2]) / denom;
        let p = [t * d[0] - c[0], t * d[1] - c[1], t * d[2] - c[2]];
        // α = w·(p × v), β = w·(u × p).
        let pv = [p[1] * v[2] - p[2] * v[1], p[2] * v[0] - p[0] * v[2], p[0] * v[1] - p[1] * v[0]];
        let up = [u[1] * p[2] - u[2] * p[1], u[2] * p[0] - u[0] * p[2], u[0] * p[1] - u[1] * p[0]];
        let alpha = (w[0] * pv[0] + w[1] * pv[1]) + w[2] * pv[2];
        let beta = (w[0] * up[0] + w[1] * up[1]) + w[2] * up[2];
        let (low, high) = (splat(-EDGE), splat(1.0 + EDGE));
        let hit = t.cmpgt(splat(0.0))
            & t.cmplt(splat(t_max))
            & low.cmple(alpha)
            & alpha.cmple(high)
            & low.cmple(beta)
            & beta.cmple(high);
        QuadHits { t: Real4::select(hit, t, splat(Real::INFINITY)), alpha, beta, mask: hit.bitmask() }
    }
}
