//! Eight quads tested at once: their corners, normals and dual bases stored as structure of
//! arrays, so one pass of [`Quad::intersect`]'s arithmetic runs in the eight lanes of the
//! scene's vector level ([`Lanes8`]: one AVX register where the CPU has it, two SSE steps at
//! the baseline): the walls of a room and a box's faces in one pass, the ground's boxes of the
//! second book a leaf at a time.
//!
//! Every lane performs exactly the arithmetic of [`Quad::intersect`], in glam's order (a dot
//! product is `(x·x′ + y·y′) + z·z′`, no fused multiply-add), so a packet finds bit for bit
//! the distance and the `(α, β)` that testing the quads one by one finds, at every level;
//! the scalar test's early exit (a plane behind the ray) only skips work whose answer is "no
//! hit", which a lane computes and finds too.
//!
//! Invariant: unused lanes hold NaN, and every comparison with NaN is false, so they never
//! report a hit.

use crate::tracer::geometry::quad::{EDGE, Quad};
use crate::tracer::math::lanes::Lanes8;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;

/// Quads per packet.
pub const LANES: usize = 8;

/// One value per lane.
type Wide = [Real; LANES];

/// Up to [`LANES`] quads, structure of arrays: per vector, its x, y and z lanes.
#[derive(Clone, Copy, Debug)]
pub struct QuadPacket {
    q: [Wide; 3],
    normal: [Wide; 3],
    /// [`Quad::dual_basis`]: `α`'s vector, then `β`'s.
    dual: [[Wide; 3]; 2],
}

/// What a packet's test found: each lane's distance and `(α, β)` (meaningful in the lanes
/// hit), and a mask with bit `k` set where lane `k`'s quad is hit in `(0, t_max)`.
#[derive(Clone, Copy, Debug)]
pub struct QuadHits {
    /// The hit's coordinate along the quad's first edge.
    pub alpha: Wide,
    /// Distance along the ray: between `alpha` and `beta`, so that the winning lane's two
    /// coordinates are not 32 bytes apart, which at the avx512 level the compiler read with
    /// one masked 512-bit load, and one such instruction a ray slowed every later instruction
    /// on an Intel Xeon (`results/simd.md`, fifth pass).
    pub t: Wide,
    /// Along its second edge.
    pub beta: Wide,
    /// Bit `k`: lane `k` is hit.
    pub mask: u32,
    /// Bit `k`: the ray meets lane `k`'s front (`n · d < 0`), so the hit record need not find
    /// it again.
    pub front: u32,
}

impl QuadHits {
    /// The lane of the nearest hit, the lowest of equals (the lower index wins a tie, as
    /// [`Closest`](crate::tracer::geometry::hit::Closest) decides), if any lane is hit: a ray
    /// hits one or two of a packet's quads, so the hit lanes are visited one by one.
    #[inline(always)]
    pub fn nearest(&self) -> Option<usize> {
        let mut mask = self.mask;
        let mut best: Option<usize> = None;
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if best.is_none_or(|b| self.t[k] < self.t[b]) {
                best = Some(k);
            }
        }
        best
    }
}

impl QuadPacket {
    /// Lane `k` holds `quads[k]`, or nothing (NaN) where that is `None`.
    ///
    /// ```
    /// use raypool::tracer::geometry::{quad::Quad, quads::QuadPacket};
    /// use raypool::tracer::math::lanes::Baseline8;
    /// use raypool::tracer::math::{ray::Ray, real::{Real, Vec3}};
    /// let wall = |z: Real| Quad::new(Vec3::new(-1.0, -1.0, z), 2.0 * Vec3::X, 2.0 * Vec3::Y, 0).unwrap();
    /// let (near, far) = (wall(-2.0), wall(-5.0));
    /// let packet = QuadPacket::new(&[Some(&far), None, Some(&near)]);
    /// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
    /// let hits = packet.intersect(Baseline8::default(), &ray, Real::INFINITY);
    /// assert_eq!((hits.mask, hits.t[0], hits.t[2], hits.nearest()), (0b101, 5.0, 2.0, Some(2)));
    /// assert_eq!(hits.t[2], near.intersect(&ray, Real::INFINITY).unwrap().0);
    /// ```
    pub fn new(quads: &[Option<&Quad>]) -> QuadPacket {
        assert!(quads.len() <= LANES, "a packet of {} quads", quads.len());
        let lanes = |of: fn(&Quad) -> [Real; 3]| {
            let mut out = [[Real::NAN; LANES]; 3];
            for (k, quad) in quads.iter().enumerate() {
                if let Some(quad) = quad {
                    let value = of(quad);
                    (0..3).for_each(|axis| out[axis][k] = value[axis]);
                }
            }
            out
        };
        QuadPacket {
            q: lanes(|quad| quad.q.to_array()),
            normal: lanes(|quad| quad.normal().to_array()),
            dual: [
                lanes(|quad| quad.dual_basis()[0].to_array()),
                lanes(|quad| quad.dual_basis()[1].to_array()),
            ],
        }
    }

    /// [`Quad::intersect`] in every lane, for hits in `(0, t_max)`, in `lanes`' instructions.
    #[inline(always)]
    pub fn intersect<L: Lanes8>(&self, lanes: L, ray: &Ray, t_max: Real) -> QuadHits {
        let l = lanes;
        let (n, q) = (load3(l, &self.normal), load3(l, &self.q));
        let o = [l.splat(ray.origin.x), l.splat(ray.origin.y), l.splat(ray.origin.z)];
        let d = [l.splat(ray.dir.x), l.splat(ray.dir.y), l.splat(ray.dir.z)];
        let denom = dot3(l, n, d);
        let c = [l.sub(q[0], o[0]), l.sub(q[1], o[1]), l.sub(q[2], o[2])];
        let t = l.div(dot3(l, n, c), denom);
        let (dual_u, dual_v) = (load3(l, &self.dual[0]), load3(l, &self.dual[1]));
        let alpha = l.sub(l.mul(t, dot3(l, d, dual_u)), dot3(l, c, dual_u));
        let beta = l.sub(l.mul(t, dot3(l, d, dual_v)), dot3(l, c, dual_v));
        let (low, high) = (l.splat(-EDGE), l.splat(1.0 + EDGE));
        let mask = l.lt_mask(l.splat(0.0), t)
            & l.lt_mask(t, l.splat(t_max))
            & l.le_mask(low, alpha)
            & l.le_mask(alpha, high)
            & l.le_mask(low, beta)
            & l.le_mask(beta, high);
        let front = l.lt_mask(denom, l.splat(0.0));
        QuadHits { t: l.store(t), alpha: l.store(alpha), beta: l.store(beta), mask, front }
    }
}

// Helpers as functions, not closures: forced inline, so that they are compiled with the
// search's vector level (a closure the compiler left out of line ran at the baseline,
// each lane operation a call).

#[inline(always)]
fn load3<L: Lanes8>(l: L, a: &[Wide; 3]) -> [L::V; 3] {
    [l.load(&a[0]), l.load(&a[1]), l.load(&a[2])]
}

/// `(a·b′ + c·d′) + e·f′`, glam's order, one IEEE operation a step.
#[inline(always)]
fn dot3<L: Lanes8>(l: L, a: [L::V; 3], b: [L::V; 3]) -> L::V {
    l.add(l.add(l.mul(a[0], b[0]), l.mul(a[1], b[1])), l.mul(a[2], b[2]))
}
