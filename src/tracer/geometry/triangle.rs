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
//! The test is written once, for eight triangles at a time ([`Triangles8`], each step one
//! operation on eight lanes of a vector level, [`Lanes8`]: one AVX register where the CPU has
//! it): a mesh (`world/mesh.rs`) keeps its vertices shared and indexed for shading, and a copy
//! of each leaf's corners lane by lane for the search; [`intersect`], one triangle, is the
//! same test at the baseline ([`Baseline8`]) with it in the first lane. Each lane's arithmetic
//! is pbrt's scalar test's in its order, one IEEE operation a step, so a triangle's hit is
//! the same bits in any lane, at any level.

use crate::tracer::math::lanes::{Baseline8, Lanes8};
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

/// The hit of `ray` on the triangle `p` in `(0, t_max)`, if any (the eight-lane test of
/// [`Triangles8`] with it in the first lane: the same numbers, so the same hits).
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
    let hits = Triangles8::new(&[p]).intersect(Baseline8::default(), &RayFrame::new(ray), t_max);
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

/// Triangles per [`Triangles8`]: one per lane of [`Lanes8`].
pub const LANES: usize = 8;

/// Up to eight triangles with their corners stored lane by lane (as Embree's `Triangle4v`
/// keeps four), so that one pass of the test checks all eight: every step below is one
/// [`Lanes8`] operation. A mesh keeps one per leaf of its tree, 32-byte aligned for AVX loads.
/// A leaf of fewer than eight leaves its spare lanes NaN, which no comparison of the test
/// accepts: a spare lane never hits, and costs the lanes beside it nothing.
///
/// ```
/// use raypool::tracer::geometry::triangle::{RayFrame, Triangles8};
/// use raypool::tracer::math::{lanes::Scalar8, ray::Ray, real::Vec3};
/// let at = |z: f32| [Vec3::new(-1.0, -1.0, z), Vec3::new(1.0, -1.0, z), Vec3::new(0.0, 1.0, z)];
/// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
/// let leaf = Triangles8::new(&[at(-3.0), at(2.0), at(-2.0)]);
/// let hits = leaf.intersect(Scalar8, &RayFrame::new(&ray), f32::INFINITY);
/// assert_eq!(hits.lanes().collect::<Vec<_>>(), [0, 2], "the one behind is missed; lanes 3 to 7 are spare");
/// assert_eq!((hits.t(0), hits.t(2)), (3.0, 2.0));
/// ```
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Triangles8 {
    /// `corner[vertex][axis]`, a lane per triangle.
    corner: [[[Real; LANES]; 3]; 3],
}

/// What [`Triangles8::intersect`] found: which lanes hit, where, and the edge functions from
/// which a hit's barycentric coordinates follow.
#[derive(Clone, Copy, Debug)]
pub struct Hits8 {
    /// Bit `k` set when lane `k` hit in `(0, t_max)`.
    mask: u32,
    t: [Real; LANES],
    /// The three edge functions, whose sum is `det`.
    e: [[Real; LANES]; 3],
    /// `1 / det`: the barycentric coordinates are `e · (1 / det)`.
    inv_det: [Real; LANES],
}

impl Triangles8 {
    /// The triangles `p` (one to eight), NaN in the lanes left over.
    pub fn new(p: &[[Vec3; 3]]) -> Triangles8 {
        assert!((1..=LANES).contains(&p.len()), "{} triangles for eight lanes", p.len());
        let value = |l: usize, vertex: usize, axis: usize| p.get(l).map_or(Real::NAN, |t| t[vertex][axis]);
        let corner = std::array::from_fn(|vertex| {
            std::array::from_fn(|axis| std::array::from_fn(|l| value(l, vertex, axis)))
        });
        Triangles8 { corner }
    }

    /// The hits of the ray of `frame` on the eight triangles in `(0, t_max)`, in `lanes`: in
    /// each lane, pbrt's scalar test's arithmetic in its order, with no early exit. Every
    /// step is a plain function call inlined into the caller (no closures, which the compiler
    /// may leave out of line, compiled for the baseline), so it runs in the caller's level.
    #[inline(always)]
    pub fn intersect<L: Lanes8>(&self, lanes: L, frame: &RayFrame, t_max: Real) -> Hits8 {
        let o = [lanes.splat(frame.origin[0]), lanes.splat(frame.origin[1]), lanes.splat(frame.origin[2])];
        let shear = [lanes.splat(frame.sx), lanes.splat(frame.sy)];
        let sz = lanes.splat(frame.sz);
        let q = [
            moved(lanes, &self.corner[0], frame.k, o, shear),
            moved(lanes, &self.corner[1], frame.k, o, shear),
            moved(lanes, &self.corner[2], frame.k, o, shear),
        ];
        let mut e = [edge(lanes, q[1], q[2]), edge(lanes, q[2], q[0]), edge(lanes, q[0], q[1])];
        let zero = lanes.splat(0.0);
        if (lanes.eq_mask(e[0], zero) | lanes.eq_mask(e[1], zero) | lanes.eq_mask(e[2], zero)) != 0 {
            let qa = [store3(lanes, q[0]), store3(lanes, q[1]), store3(lanes, q[2])];
            let mut ea = store3(lanes, e);
            recompute_zero_edges(&qa, &mut ea);
            e = [lanes.load(&ea[0]), lanes.load(&ea[1]), lanes.load(&ea[2])];
        }
        // A triangle's determinant, distance and bound, each lane's in pbrt's order.
        let det = lanes.add(lanes.add(e[0], e[1]), e[2]);
        let z = [lanes.mul(q[0][2], sz), lanes.mul(q[1][2], sz), lanes.mul(q[2][2], sz)];
        let t_scaled =
            lanes.add(lanes.add(lanes.mul(e[0], z[0]), lanes.mul(e[1], z[1])), lanes.mul(e[2], z[2]));
        let inv_det = lanes.div(lanes.splat(1.0), det);
        let t = lanes.mul(t_scaled, inv_det);
        let outside = (lanes.lt_mask(e[0], zero) | lanes.lt_mask(e[1], zero) | lanes.lt_mask(e[2], zero))
            & (lanes.lt_mask(zero, e[0]) | lanes.lt_mask(zero, e[1]) | lanes.lt_mask(zero, e[2]));
        // t = t_scaled / det must lie in (0, t_max): compared before dividing, sign by sign.
        let bound = lanes.mul(lanes.splat(t_max), det);
        let negative = lanes.lt_mask(det, zero);
        let behind_or_beyond = (negative & (lanes.le_mask(zero, t_scaled) | lanes.lt_mask(t_scaled, bound)))
            | (!negative & (lanes.le_mask(t_scaled, zero) | lanes.lt_mask(bound, t_scaled)));
        let kept =
            !outside & !lanes.eq_mask(det, zero) & !behind_or_beyond & lanes.lt_mask(t, lanes.splat(t_max));
        // The rounding bound only when some lane may hit (many leaves a ray visits have no
        // such lane), each lane's bound in its own lane.
        let mask =
            if kept == 0 { 0 } else { kept & lanes.lt_mask(rounding_bound(lanes, &q, sz, &e, inv_det), t) };
        Hits8 { mask, t: lanes.store(t), e: store3(lanes, e), inv_det: lanes.store(inv_det) }
    }
}

/// A triangle corner per lane moved to the ray's origin, permuted and sheared: `[x, y, z]`.
#[inline(always)]
fn moved<L: Lanes8>(
    lanes: L,
    c: &[[Real; LANES]; 3],
    k: [usize; 3],
    o: [L::V; 3],
    shear: [L::V; 2],
) -> [L::V; 3] {
    let z = lanes.sub(lanes.load(&c[k[2]]), o[2]);
    [
        lanes.add(lanes.sub(lanes.load(&c[k[0]]), o[0]), lanes.mul(shear[0], z)),
        lanes.add(lanes.sub(lanes.load(&c[k[1]]), o[1]), lanes.mul(shear[1], z)),
        z,
    ]
}

/// The edge function of the edge from `a` to `b`.
#[inline(always)]
fn edge<L: Lanes8>(lanes: L, a: [L::V; 3], b: [L::V; 3]) -> L::V {
    lanes.sub(lanes.mul(a[0], b[1]), lanes.mul(a[1], b[0]))
}

/// Three registers as arrays.
#[inline(always)]
fn store3<L: Lanes8>(lanes: L, v: [L::V; 3]) -> [[Real; LANES]; 3] {
    [lanes.store(v[0]), lanes.store(v[1]), lanes.store(v[2])]
}

/// `max(|f₀|, |f₁|, |f₂|)` per lane.
#[inline(always)]
fn max_abs3<L: Lanes8>(lanes: L, f: [L::V; 3]) -> L::V {
    lanes.max(lanes.max(lanes.abs(f[0]), lanes.abs(f[1])), lanes.abs(f[2]))
}

impl Hits8 {
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

    /// Lane `lane`'s distance (a lane that [`Hits8::lanes`] names).
    #[inline(always)]
    pub fn t(&self, lane: usize) -> Real {
        self.t[lane]
    }

    /// Lane `lane`'s hit (a lane that [`Hits8::lanes`] names).
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
fn recompute_zero_edges(q: &[[[Real; LANES]; 3]; 3], e: &mut [[Real; LANES]; 3]) {
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
fn rounding_bound<L: Lanes8>(l: L, q: &[[L::V; 3]; 3], sz: L::V, e: &[L::V; 3], inv_det: L::V) -> L::V {
    let max_z = max_abs3(l, [l.mul(q[0][2], sz), l.mul(q[1][2], sz), l.mul(q[2][2], sz)]);
    let delta_z = l.mul(l.splat(gamma(3.0)), max_z);
    let max_x = max_abs3(l, [q[0][0], q[1][0], q[2][0]]);
    let max_y = max_abs3(l, [q[0][1], q[1][1], q[2][1]]);
    let delta_x = l.mul(l.splat(gamma(5.0)), l.add(max_x, max_z));
    let delta_y = l.mul(l.splat(gamma(5.0)), l.add(max_y, max_z));
    // 2 · (γ₂ · max_x · max_y + δy · max_x + δx · max_y)
    let xy = l.mul(l.mul(l.splat(gamma(2.0)), max_x), max_y);
    let delta_e = l.mul(l.splat(2.0), l.add(l.add(xy, l.mul(delta_y, max_x)), l.mul(delta_x, max_y)));
    let max_e = max_abs3(l, *e);
    // 3 · (γ₃ · max_e · max_z + δe · max_z + δz · max_e) · |1 / det|
    let ez = l.mul(l.mul(l.splat(gamma(3.0)), max_e), max_z);
    let sum = l.add(l.add(ez, l.mul(delta_e, max_z)), l.mul(delta_z, max_e));
    l.mul(l.mul(l.splat(3.0), sum), l.abs(inv_det))
}
