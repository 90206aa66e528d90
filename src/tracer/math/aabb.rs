//! Axis-aligned boxes, and [`Bounded`]: what a tree needs to know of anything it holds.
//!
//! Every shape reports a box that contains every hit point its own test can compute (boxes
//! are padded by the test's rounding), so a tree that skips a box never skips a hit.

use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// An axis-aligned box, `min` to `max` on every axis (inverted, `min > max`, when empty).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Aabb {
    /// The empty box.
    fn default() -> Aabb {
        Aabb::EMPTY
    }
}

/// pbrt's bound on the slab test's own rounding, `1 + 2γ₃`: a slab distance carries three
/// roundings (the reciprocal, the subtraction, the product), so an exit distance scaled up by
/// it never misses a box the ray grazes, and a box entered at a hit's distance times it is
/// never pruned before that hit.
pub const SLAB_ROUNDING: Real = 1.0 + 2.0 * (3.0 * Real::EPSILON / 2.0) / (1.0 - 3.0 * Real::EPSILON / 2.0);

impl Aabb {
    /// The empty box: the union's identity.
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(Real::INFINITY), max: Vec3::splat(Real::NEG_INFINITY) };

    /// The smallest box holding both.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// The smallest box holding this one and `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// Whether the two boxes share a point (touching counts).
    pub fn meets(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// The box grown by `pad` on every side.
    pub fn padded(self, pad: Real) -> Aabb {
        Aabb { min: self.min - Vec3::splat(pad), max: self.max + Vec3::splat(pad) }
    }

    /// Half the surface area: proportional to a random ray's chance of entering the box.
    pub fn half_area(&self) -> Real {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|k| {
            let pick =
                |bit: usize, axis: usize| if k >> bit & 1 == 0 { self.min[axis] } else { self.max[axis] };
            Vec3::new(pick(0, 0), pick(1, 1), pick(2, 2))
        })
    }

    /// The largest absolute coordinate of the box: the scale of its points' rounding errors.
    pub fn magnitude(&self) -> Real {
        self.min.abs().max(self.max.abs()).max_element()
    }

    /// Slab test: does the ray from `origin` with inverse direction `inv_dir` enter the box
    /// before `t_max`?
    ///
    /// The clamps are plain comparisons rather than `f32::max`/`min`, whose NaN handling
    /// costs extra instructions on the hottest line of the renderer (profiled). The results
    /// are the same, NaN included: a NaN `near` becomes 0 and a NaN `far` becomes `t_max`.
    #[inline]
    pub fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: Real) -> bool {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        let near = if near > 0.0 { near } else { 0.0 };
        let far = if far < t_max { far } else { t_max };
        near <= far
    }

    /// Whether `ray` enters the box before `t_max`, never missing a box it grazes: the slab
    /// test of the four-wide trees (`accel/wide.rs`), each exit distance scaled up by pbrt's
    /// bound on the test's own rounding, `1 + 2γ₃`. A NaN distance (a ray along a face, starting
    /// on its plane) is ignored, which only widens the box. Without a branch: which corner the
    /// ray meets first on an axis depends on its direction, which a bounce draws at random.
    #[inline(always)]
    pub fn enters(&self, ray: &Ray, t_max: Real) -> bool {
        self.span(ray, t_max).is_some()
    }

    /// Where `ray` enters and leaves the box within `[0, t_max]`, as [`Aabb::enters`] finds
    /// them (the exit scaled up by its rounding bound, the entry as computed); `None` where
    /// it does not enter before `t_max`.
    #[inline(always)]
    pub fn span(&self, ray: &Ray, t_max: Real) -> Option<(Real, Real)> {
        let inv = ray.dir.recip();
        let (low, high) = ((self.min - ray.origin) * inv, (self.max - ray.origin) * inv);
        let backwards = inv.cmplt(Vec3::ZERO);
        let t_in = Vec3::select(backwards, high, low);
        let t_out = Vec3::select(backwards, low, high) * SLAB_ROUNDING;
        // `if a > b { a } else { b }`: maxss, which keeps `b` where `a` is NaN.
        let later = |a: Real, b: Real| if a > b { a } else { b };
        let sooner = |a: Real, b: Real| if a < b { a } else { b };
        let near = later(t_in.z, later(t_in.y, later(t_in.x, 0.0)));
        let far = sooner(t_out.z, sooner(t_out.y, sooner(t_out.x, t_max)));
        (near <= far).then_some((near, far))
    }
}

/// Anything a bounding volume hierarchy can hold: its padded box, and the point it is sorted
/// by (a sphere's centre, a triangle's box centre).
pub trait Bounded {
    /// A box holding every hit point the item's own test can report.
    fn bounds(&self) -> Aabb;
    /// The point the tree's build sorts the item by.
    fn centroid(&self) -> Vec3;
}
