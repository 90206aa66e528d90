//! Four spheres tested at once: spheres stored as structure of arrays (all centres' x, then
//! all y, …), so one pass of the stable ray–sphere test runs in the four lanes of a SIMD
//! register.
//!
//! The lanes are plain `[Real; 4]` arrays written as loops over the lanes, which the compiler
//! vectorises for baseline x86-64 SSE (`Scene::hit` in the release binary holds `sqrtps` and
//! `divps`: `objdump -d target/release/raypool`), with no `unsafe` and no CPU-specific build;
//! elsewhere the same loops compile to that CPU's vector or scalar code. Every lane performs exactly
//! the arithmetic of [`Sphere::intersect`], in the same order, so a packet finds bit for bit
//! the distances that testing the spheres one by one finds (`tests/bvh.rs`); the scalar test's
//! early exits (a negative discriminant, a sphere behind the ray) only skip work whose answer
//! is "no hit", which a lane computes and finds too.
//!
//! Invariant: unused lanes hold NaN centres and radii and index [`Packet::EMPTY`]; every
//! comparison with NaN is false, so they never report a hit.

use crate::tracer::geometry::hit::Closest;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;

/// Spheres per packet: one SSE register of f32.
pub const LANES: usize = 4;

/// One value per lane.
pub type Lanes = [Real; LANES];

/// Up to [`LANES`] spheres, structure of arrays.
#[derive(Clone, Copy, Debug)]
pub struct Packet {
    center: [Lanes; 3],
    radius: Lanes,
    /// Each lane's index in the scene's sphere array (for tie-breaking and the hit record).
    index: [u32; LANES],
}

impl Packet {
    /// The index of an unused lane.
    pub const EMPTY: u32 = u32::MAX;

    /// Packs `spheres` (at most [`LANES`]), which sit at `first`, `first + 1`, … in the
    /// scene's array.
    ///
    /// ```
    /// use raypool::tracer::accel::packet::Packet;
    /// use raypool::tracer::geometry::{hit::Closest, sphere::Sphere};
    /// use raypool::tracer::math::{ray::Ray, real::{Real, Vec3}};
    /// let ball = |x: Real| Sphere { center: Vec3::new(x, 0.0, -5.0), radius: 1.0, material: 0 };
    /// let packet = Packet::new(&[ball(0.0), ball(0.5)], 7);
    /// let mut closest = Closest::none(Real::INFINITY);
    /// packet.intersect(&Ray::new(Vec3::ZERO, -Vec3::Z), &mut closest);
    /// assert_eq!(closest.found(), Some((7, 4.0)), "the first sphere, 4 units away");
    /// ```
    pub fn new(spheres: &[Sphere], first: usize) -> Packet {
        assert!(spheres.len() <= LANES, "a packet holds at most {LANES} spheres");
        let mut packet = Packet {
            center: [[Real::NAN; LANES]; 3],
            radius: [Real::NAN; LANES],
            index: [Packet::EMPTY; LANES],
        };
        for (lane, sphere) in spheres.iter().enumerate() {
            for axis in 0..3 {
                packet.center[axis][lane] = sphere.center[axis];
            }
            packet.radius[lane] = sphere.radius;
            packet.index[lane] = (first + lane) as u32;
        }
        packet
    }

    /// Offers every lane's hit to `closest`: the stable test of [`Sphere::intersect`], lane
    /// by lane, bounded by [`Closest::bound`].
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, closest: &mut Closest) {
        let distances = self.distances(ray, closest.bound());
        for (&t, &index) in distances.iter().zip(&self.index) {
            // A lane without a hit has t = infinity; an empty lane never gets here with a
            // finite t (NaN fails every comparison of `distances`).
            if t < Real::INFINITY {
                closest.offer(t, index);
            }
        }
    }

    /// Each lane's nearest hit in `(0, t_max)`, or infinity. The arithmetic is
    /// [`Sphere::intersect`]'s, operation for operation (`dot` sums as glam does,
    /// `(x + y) + z`); each step is one whole-register operation over the lanes, with no
    /// branch, which is the shape the compiler vectorises.
    #[inline(always)]
    fn distances(&self, ray: &Ray, t_max: Real) -> Lanes {
        let (o, d) = (ray.origin, ray.dir);
        let [cx, cy, cz] = &self.center;
        let fx = lanes(|l| o.x - cx[l]);
        let fy = lanes(|l| o.y - cy[l]);
        let fz = lanes(|l| o.z - cz[l]);
        let r2 = lanes(|l| self.radius[l] * self.radius[l]);
        let b = lanes(|l| (fx[l] * d.x + fy[l] * d.y) + fz[l] * d.z);
        let px = lanes(|l| fx[l] - b[l] * d.x);
        let py = lanes(|l| fy[l] - b[l] * d.y);
        let pz = lanes(|l| fz[l] - b[l] * d.z);
        let discriminant = lanes(|l| r2[l] - ((px[l] * px[l] + py[l] * py[l]) + pz[l] * pz[l]));
        if discriminant.iter().all(|d| d.is_nan() || *d < 0.0) {
            // Every lane misses (or is empty): skip the square root and the division, the
            // slowest part of the test.
            return [Real::INFINITY; LANES];
        }
        let q = lanes(|l| -b[l] - discriminant[l].sqrt().copysign(b[l]));
        let c = lanes(|l| ((fx[l] * fx[l] + fy[l] * fy[l]) + fz[l] * fz[l]) - r2[l]);
        let t0 = lanes(|l| c[l] / q[l]);
        let near = lanes(|l| if t0[l] <= q[l] { t0[l] } else { q[l] });
        let far = lanes(|l| if t0[l] <= q[l] { q[l] } else { t0[l] });
        // A negative discriminant makes everything after it NaN, and NaN fails every test
        // below: no hit. q == 0 (a tangent ray starting on its tangent point) is refused
        // as the scalar test refuses it.
        let ok = lanes(|l| if discriminant[l] >= 0.0 && q[l] != 0.0 { t_max } else { 0.0 });
        let far = lanes(|l| if far[l] > 0.0 && far[l] < ok[l] { far[l] } else { Real::INFINITY });
        lanes(|l| if near[l] > 0.0 && near[l] < ok[l] { near[l] } else { far[l] })
    }
}

/// One value per lane, computed lane by lane (straight-line code the compiler vectorises).
#[inline(always)]
fn lanes(value: impl Fn(usize) -> Real) -> Lanes {
    std::array::from_fn(value)
}
