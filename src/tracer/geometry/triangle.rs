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
//! The test is written once, for four triangles at a time ([`Triangles4`], each step one SIMD
//! operation on four lanes, as Embree tests its leaves): a mesh (`world/mesh.rs`) keeps its
//! vertices shared and indexed for shading, and a copy of each leaf's corners lane by lane for
//! the search; [`intersect`], one triangle, is the same test with it in every lane.

use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Real4, Vec3};

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

/// The hit of `ray` on the triangle `p` in `(0, t_max)`, if any (the four-lane test of
/// [`Triangles4`] with one triangle in every lane: the same numbers, so the same hits).
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
    let hits = Triangles4::new(&[p]).intersect(&RayFrame::new(ray), t_max);
    hits.lanes().next().map(|lane| hits.hit(lane))
}

/// The ray's own frame, the part of the test that depends on the ray alone: computed once
/// per ray by a mesh's search, then shared by every triangle it tests.
#[derive(Clone, Copy, Debug)]
pub struct RayFrame {
    /// The axes that become x, y and z (z: the direction's largest component).
    k: [usize; 3],
    /// The ray's origin, its axes so permuted.
    origin: [Real; 3],
    /// The shear: `x += sx·z`, `y += sy·z`, then `z·sz`.
    sx: Real,
    sy: Real,
    sz: Real,
}

impl RayFrame {
    /// The frame of `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> RayFrame {
        // Arrays, not vectors, indexed: a vector's index is a three-way branch.
        let d = ray.dir.to_array();
        let kz = ray.dir.abs().max_position();
        let (kx, ky) = ([1, 2, 0][kz], [2, 0, 1][kz]);
        let (dx, dy, dz) = (d[kx], d[ky], d[kz]);
        let o = ray.origin.to_array();
        RayFrame { k: [kx, ky, kz], origin: [o[kx], o[ky], o[kz]], sx: -dx / dz, sy: -dy / dz, sz: 1.0 / dz }
    }
}

/// Triangles per [`Triangles4`]: one per SIMD lane of f32.
pub const LANES: usize = 4;

/// Up to four triangles with their corners stored lane by lane (Embree's `Triangle4v`), so
/// that one pass of the test checks all four: every step below is one operation on a
/// [`Real4`], four numbers in one SIMD register. A mesh keeps one per leaf of its tree. A
/// leaf of fewer than four leaves its spare lanes NaN, which no comparison of the test
/// accepts: a spare lane never hits, and costs the lanes beside it nothing.
///
/// ```
/// use raypool::tracer::geometry::triangle::{RayFrame, Triangles4};
/// use raypool::tracer::math::{ray::Ray, real::Vec3};
/// let at = |z: f32| [Vec3::new(-1.0, -1.0, z), Vec3::new(1.0, -1.0, z), Vec3::new(0.0, 1.0, z)];
/// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
/// let hits = Triangles4::new(&[at(-3.0), at(2.0), at(-2.0)]).intersect(&RayFrame::new(&ray), f32::INFINITY);
/// assert_eq!(hits.lanes().collect::<Vec<_>>(), [0, 2], "the one behind is missed; lane 3 is spare");
/// assert_eq!((hits.t(0), hits.t(2)), (3.0, 2.0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Triangles4 {
    /// `corner[vertex][axis]`, a lane per triangle.
    corner: [[Real4; 3]; 3],
}

/// What [`Triangles4::intersect`] found: which lanes hit, where, and the edge functions from
/// which a hit's barycentric coordinates follow.
#[derive(Clone, Copy, Debug)]
pub struct Hits4 {
    /// Bit `k` set when lane `k` hit in `(0, t_max)`.
    mask: u32,
    t: Real4,
    /// The three edge functions, whose sum is `det`.
    e: [Real4; 3],
    /// `1 / det`: the barycentric coordinates are `e · (1 / det)`.
    inv_det: Real4,
}

impl Triangles4 {
    /// The triangles `p` (one to four), NaN in the lanes left over.
    pub fn new(p: &[[Vec3; 3]]) -> Triangles4 {
        assert!((1..=LANES).contains(&p.len()), "{} triangles for four lanes", p.len());
        let value = |l: usize, vertex: usize, axis: usize| p.get(l).map_or(Real::NAN, |t| t[vertex][axis]);
        let corner = std::array::from_fn(|vertex| {
            std::array::from_fn(|axis| Real4::from_array(std::array::from_fn(|l| value(l, vertex, axis))))
        });
        Triangles4 { corner }
    }

    /// The hits of the ray of `frame` on the four triangles in `(0, t_max)`: in each lane,
    /// pbrt's scalar test's arithmetic in its order (so each lane's hit is bit for bit the
    /// scalar test's, as the mesh's per-triangle test before these lanes found), with no early
    /// exit.
    #[inline(always)]
    pub fn intersect(&self, frame: &RayFrame, t_max: Real) -> Hits4 {
        let [kx, ky, kz] = frame.k;
        let [ox, oy, oz] = frame.origin.map(Real4::splat);
        let (sx, sy, sz) = (frame.sx, frame.sy, frame.sz);
        // The corners moved to the ray's origin, permuted and sheared: `q[vertex][axis]`.
        let q: [[Real4; 3]; 3] = std::array::from_fn(|vertex| {
            let c = &self.corner[vertex];
            let z = c[kz] - oz;
            [(c[kx] - ox) + sx * z, (c[ky] - oy) + sy * z, z]
        });
        let edge = |a: usize, b: usize| q[a][0] * q[b][1] - q[a][1] * q[b][0];
        let mut e = [edge(1, 2), edge(2, 0), edge(0, 1)];
        let zero = Real4::ZERO;
        if (e[0].cmpeq(zero) | e[1].cmpeq(zero) | e[2].cmpeq(zero)).any() {
            recompute_zero_edges(&q, &mut e);
        }
        let det = e[0] + e[1] + e[2];
        let z = q.map(|v| v[2] * sz);
        let t_scaled = e[0] * z[0] + e[1] * z[1] + e[2] * z[2];
        let inv_det = Real4::ONE / det;
        let t = t_scaled * inv_det;
        let outside = (e[0].cmplt(zero) | e[1].cmplt(zero) | e[2].cmplt(zero))
            & (e[0].cmpgt(zero) | e[1].cmpgt(zero) | e[2].cmpgt(zero));
        // t = t_scaled / det must lie in (0, t_max): compared before dividing, sign by sign.
        let bound = t_max * det;
        let negative = det.cmplt(zero);
        let behind_or_beyond = (negative & (t_scaled.cmpge(zero) | t_scaled.cmplt(bound)))
            | (!negative & (t_scaled.cmple(zero) | t_scaled.cmpgt(bound)));
        let kept = !outside & det.cmpne(zero) & !behind_or_beyond & t.cmplt(Real4::splat(t_max));
        let candidates = kept.bitmask();
        // The rounding bound only where a lane may hit: about a third of the leaves a ray
        // visits on `mesh` (callgrind), each lane's bound in its own lane, as for the test.
        let mask = if candidates == 0 {
            0
        } else {
            candidates & t.cmpgt(rounding_bound(&q, sz, &e, inv_det)).bitmask()
        };
        Hits4 { mask, t, e, inv_det }
    }
}

impl Hits4 {
    /// The lanes that hit, in increasing order.
    #[inline(always)]
    pub fn lanes(&self) -> impl Iterator<Item = usize> + use<> {
        let mut mask = self.mask;
        std::iter::from_fn(move || {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask.wrapping_sub(1);
            (lane < LANES).then_some(lane)
        })
    }

    /// Whether any lane hit.
    #[inline(always)]
    pub fn any(&self) -> bool {
        self.mask != 0
    }

    /// Lane `lane`'s distance (a lane that [`Hits4::lanes`] names).
    #[inline(always)]
    pub fn t(&self, lane: usize) -> Real {
        self.t[lane]
    }

    /// Lane `lane`'s hit (a lane that [`Hits4::lanes`] names).
    #[inline(always)]
    pub fn hit(&self, lane: usize) -> TriangleHit {
        let barycentric = [0, 1, 2].map(|k| self.e[k][lane] * self.inv_det[lane]);
        TriangleHit { t: self.t[lane], barycentric }
    }
}

/// An edge function of exactly zero may be rounding's: in each lane that has one, all three
/// are recomputed in f64, as pbrt does, so that a ray that truly misses an edge is not taken
/// for one on it.
#[cold]
#[allow(clippy::unnecessary_cast)] // a no-op in the f64 build
fn recompute_zero_edges(q: &[[Real4; 3]; 3], e: &mut [Real4; 3]) {
    for lane in 0..LANES {
        if (0..3).any(|k| e[k][lane] == 0.0) {
            for (k, (a, b)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
                let (ax, ay) = (q[a][0][lane] as f64, q[a][1][lane] as f64);
                let (bx, by) = (q[b][0][lane] as f64, q[b][1][lane] as f64);
                e[k][lane] = (ax * by - ay * bx) as Real;
            }
        }
    }
}

/// pbrt's bound on the rounding error of the computed `t` (`deltaT`), lane by lane: a hit no
/// farther than this might really lie behind the ray's origin. Each lane's arithmetic is
/// pbrt's scalar expression in its order, so each lane's bound is the scalar one's bits.
#[inline(always)]
fn rounding_bound(q: &[[Real4; 3]; 3], sz: Real, e: &[Real4; 3], inv_det: Real4) -> Real4 {
    let max3 = |f: &dyn Fn(usize) -> Real4| f(0).abs().max(f(1).abs()).max(f(2).abs());
    let max_z = max3(&|v| q[v][2] * sz);
    let delta_z = gamma(3.0) * max_z;
    let max_x = max3(&|v| q[v][0]);
    let max_y = max3(&|v| q[v][1]);
    let delta_x = gamma(5.0) * (max_x + max_z);
    let delta_y = gamma(5.0) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = max3(&|k| e[k]);
    3.0 * (gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs()
}
