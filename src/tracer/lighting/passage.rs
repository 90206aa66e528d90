//! Joining two points through a glass ball: the passage from a diffuse point `x` that enters
//! the ball, crosses it and leaves towards a point `y` on a light ([`solve`]), and the density
//! with which a bounce from `x` would have found that same path ([`bounce_density`]).
//!
//! The solve is a manifold walk (Hanika et al. 2015) made one-dimensional by the ball's
//! symmetry: a ray's passage stays in the plane of its start, its direction and the ball's
//! centre, so a path from `x` to `y` lies in the plane through `x`, `y` and the centre, and is
//! fixed by one number, the angle at which it enters. Several angles can join the same two
//! points (two or three beside cornell's ball, where the caustic folds), so the solve tries
//! angles evenly across the ball as `x` sees it, four at a time in SIMD lanes, and closes in on
//! every one between two tries where the ray leaving passes from one side of `y` to the other
//! (regula falsi). Two passages closer than a step leave no such change of side: where the ray
//! leaving turns back towards `y` between three tries, the solve seeks that turning point, and
//! if the ray there passes `y`, closes in on each side of it (on `cornell`, the floor round the
//! ball's foot, where bounces had found passages the solve missed). A cheap bound ends most
//! solves first ([`may_pass`], asked before a manifold sample draws its light point, for a hit
//! and every light at once; then `within_reach`, in the solve, for `x` and `y`): the ball
//! turns a ray by at most [`Ball::turn`] at the outermost try, so `y` must lie within that
//! reach. The solve is deterministic: the same `x` and `y`
//! give the same passages, which is how a bounce that found a passage by chance knows whether
//! the solve would have found it too (it still misses a few, grazing the rim).
//!
//! The density: the bounce leaves `x` in direction `ω` with density `p(ω)` per unit solid
//! angle and refracts twice with chance `T`, so it lands near `y` with density
//! `p(ω)·T / J` per unit area, where `J = dA/dω` is how widely the ball spreads a cone of
//! directions over the light's plane (small where it focuses), measured by forward
//! differences as `bidir/chain.rs` measures its chains (here without casting rays: the
//! passage has a closed form, [`Ball::pass`]).

use glam::DVec3;

use crate::tracer::lights::casters::{Ball, Crossing, Lamps, Passage};
use crate::tracer::math::real::{Real, Real4, Vec3, to_dvec3, to_f64};

/// The angle by which a direction is turned to measure the spread of its passage.
const STEP: Real = 1e-3;

/// The entry angles tried first, evenly across those the start point sees: a passage is
/// found between two neighbours where the ray leaving passes from one side of the target to
/// the other. Two passages closer than a step are both missed (a bounce still finds them).
const TRIES: usize = 24;
const _: () = assert!(TRIES % 4 == 0 && TRIES <= 64, "tries come in fours and fit a u64's bits");

/// The most steps that close in on one passage.
const STEPS: u32 = 24;

/// How closely (radians) the ray that leaves must point at its target to count as found.
const AIM: Real = 1e-5;

/// Calls `each` with every passage the solve finds from `from` through `ball` that leaves
/// straight towards `to` (none if either point is inside the ball, or they lie in a line
/// with its centre).
///
/// ```
/// use raypool::tracer::geometry::sphere::Sphere;
/// use raypool::tracer::lighting::passage::solve;
/// use raypool::tracer::math::real::Vec3;
/// use raypool::tracer::lights::casters::Ball;
/// let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.5);
/// let (from, to) = (Vec3::new(0.3, 0.0, 4.0), Vec3::new(-0.2, 0.5, -3.0));
/// let mut found = Vec::new();
/// solve(&ball, from, to, |passage| found.push(passage));
/// assert_eq!(found.len(), 1);
/// assert!((to - found[0].exit).normalize().dot(found[0].out) > 1.0 - 1e-6);
/// ```
pub fn solve(ball: &Ball, from: Vec3, to: Vec3, mut each: impl FnMut(Passage)) {
    // The start, the target and the plane's axes in double precision, and the tries' angles
    // from the start's gap from the glass: a start near the glass sees the ball only within
    // thousandths of a radian of its tangents, closer than `f32` differences place them. The
    // tries then run in `f32` (`Plane::sides`).
    let (center, radius) = (to_dvec3(ball.sphere.center), to_f64(ball.sphere.radius));
    let (from, to) = (to_dvec3(from), to_dvec3(to));
    let reach = from - center;
    let (distance, far) = (reach.length(), (to - center).length());
    if distance <= radius || far <= radius {
        return;
    }
    let target = to - center;
    // The plane's axes: `e1` towards `from`, `e2` towards `to`'s side of it.
    let e1 = reach / distance;
    let Some(e2) = (target - target.dot(e1) * e1).try_normalize() else { return };
    let apart = ((-reach.dot(target) / (distance * far)) as Real).clamp(-1.0, 1.0).acos();
    let target = (target.dot(e1) as Real, target.dot(e2) as Real);
    let gap = (distance - radius) as Real;
    let (distance, far, radius) = (distance as Real, far as Real, radius as Real);
    // `from` sees the entry angles up to `limit = acos(r / d) = 2 asin √(gap / 2d)` either way
    // (the two tangents, where the glass would meet the ray edge-on, never pass; the second
    // form keeps its digits near the glass): tried at `TRIES` angles from `-limit` up, four at
    // a time, each turned from the one before by a rotation (so the tries take one arc sine,
    // one sine and one cosine between them, however many), from `sin limit = √(gap (d + r)) / d`.
    let limit = 2.0 * (gap / (2.0 * distance)).sqrt().asin();
    let step = 2.0 * limit / (TRIES - 1) as Real;
    let angle = |k: usize| -limit + step * k as Real;
    let turn = Turn::by(step);
    let mut lanes = [Turn { sin: -(gap * (distance + radius)).sqrt() / distance, cos: radius / distance }; 4];
    for k in 1..4 {
        lanes[k] = turn.apply(lanes[k - 1]);
    }
    if !within_reach(ball, distance, far, lanes[1], apart) {
        return;
    }
    let ior = ball.ior;
    let plane = Plane { radius, inverse_radius: 1.0 / radius, gap, ior, target };
    let (mut sin, mut cos) = (Real4::from(lanes.map(|l| l.sin)), Real4::from(lanes.map(|l| l.cos)));
    let four = turn.twice().twice();
    let miss = |angle: Real| {
        let (sin, cos) = angle.sin_cos();
        let (across, along) = plane.sides(Real4::splat(cos), Real4::splat(sin));
        (along.x > 0.0).then(|| across.x / along.x)
    };
    // Every try first (independent blocks of arithmetic, which the processor overlaps), as
    // two bit sets: the tries whose ray leaves towards the target's side of the ball, and
    // those that pass it on the negative side; then only the neighbours that change side.
    let (mut seen, mut negative) = (0u64, 0u64);
    let mut misses = [0.0; TRIES];
    for block in 0..TRIES / 4 {
        let (across, along) = plane.sides(cos, sin);
        seen |= u64::from(along.cmpgt(Real4::ZERO).bitmask()) << (4 * block);
        negative |= u64::from(across.cmplt(Real4::ZERO).bitmask()) << (4 * block);
        misses[4 * block..4 * block + 4].copy_from_slice(&(across / along).to_array());
        (sin, cos) = (sin * four.cos + cos * four.sin, cos * four.cos - sin * four.sin);
    }
    // Only passages between the first and last tries inside the tangents are looked for,
    // the ones `within_reach` allows for.
    seen &= !(1 | 1 << (TRIES - 1));
    // Bit k: tries k and k + 1 are both seen and on opposite sides.
    let mut changes = seen & (seen >> 1) & (negative ^ (negative >> 1)) & ((1u64 << (TRIES - 1)) - 1);
    let entry = |a: f64| {
        let (sin, cos) = a.sin_cos();
        center + to_f64(radius) * (cos * e1 + sin * e2)
    };
    let mut pass = |found: Option<Real>| {
        if let Some(crossing) = found.and_then(|a| ball.cross(from, entry(to_f64(a)))) {
            each(crossing.rounded());
        }
    };
    while changes != 0 {
        let k = changes.trailing_zeros() as usize;
        changes &= changes - 1;
        let bracket = |k: usize| Some(Try { angle: angle(k), miss: miss(angle(k))? });
        pass(bracket(k).zip(bracket(k + 1)).and_then(|(low, high)| close_in(&miss, low, high)));
    }
    // A fold: where the ray leaving turns back towards the target and away again between
    // three tries on one side of it, two passages may lie between the outer two, closer than
    // a step. The turning point is sought; if the ray there passes the target, each half
    // holds one passage.
    let mut dips =
        seen & (seen >> 1) & (seen << 1) & !(negative ^ (negative >> 1)) & !(negative ^ (negative << 1));
    while dips != 0 {
        let k = dips.trailing_zeros() as usize;
        dips &= dips - 1;
        let side = misses[k].signum();
        let (middle, outer) = (side * misses[k], (side * misses[k - 1]).min(side * misses[k + 1]));
        if middle > FOLD_DEPTH * outer {
            continue;
        }
        let Some(fold) = turning_point(&miss, angle(k - 1), angle(k + 1), side) else { continue };
        pass(close_in(&miss, Try { angle: angle(k - 1), miss: misses[k - 1] }, fold));
        pass(close_in(&miss, fold, Try { angle: angle(k + 1), miss: misses[k + 1] }));
    }
}

/// How far below both its neighbours' misses the middle try's must dip for [`solve`] to seek
/// a fold there. Shallower dips rarely hide passages: this depth leaves most dips unsought and
/// keeps nearly all of those that hide one (counted on `cornell`: `results/mnee.md`).
const FOLD_DEPTH: Real = 0.9;

/// The most golden-section steps [`turning_point`] takes: they narrow its interval to 0.07%.
const TURNING_STEPS: u32 = 15;

/// An entry angle between `low` and `high` where the ray leaving passes the target on the
/// other side than `side` (the side of the rays entering at `low`, the middle try and
/// `high`), and its miss; sought by golden section towards the least `side × miss`.
fn turning_point(
    miss: &impl Fn(Real) -> Option<Real>,
    mut low: Real,
    mut high: Real,
    side: Real,
) -> Option<Try> {
    const GOLDEN: Real = 0.618_034;
    let inner = |angle: Real| Some(Try { angle, miss: miss(angle)? });
    let mut left = inner(high - GOLDEN * (high - low))?;
    let mut right = inner(low + GOLDEN * (high - low))?;
    for _ in 0..TURNING_STEPS {
        for probe in [left, right] {
            if side * probe.miss < 0.0 {
                return Some(probe);
            }
        }
        if side * left.miss < side * right.miss {
            high = right.angle;
            right = left;
            left = inner(high - GOLDEN * (high - low))?;
        } else {
            low = left.angle;
            left = right;
            right = inner(low + GOLDEN * (high - low))?;
        }
    }
    None
}

/// An entry angle tried, and its miss: how far, and on which side, the ray leaving passes the
/// target.
#[derive(Clone, Copy)]
struct Try {
    angle: Real,
    miss: Real,
}

/// An angle in the plane, as its sine and cosine: an entry point's, or the rotation by it.
#[derive(Clone, Copy)]
struct Turn {
    sin: Real,
    cos: Real,
}

impl Turn {
    fn by(angle: Real) -> Turn {
        let (sin, cos) = angle.sin_cos();
        Turn { sin, cos }
    }

    /// The rotation by twice the angle.
    fn twice(self) -> Turn {
        Turn { sin: 2.0 * self.sin * self.cos, cos: self.cos * self.cos - self.sin * self.sin }
    }

    /// `angle` turned by this one.
    fn apply(self, angle: Turn) -> Turn {
        let Turn { sin, cos } = angle;
        Turn { sin: sin * self.cos + cos * self.sin, cos: cos * self.cos - sin * self.sin }
    }
}

/// Whether [`solve`] can find a passage through `ball` from `from` to some point of the
/// sphere `lamps` at all: `within_reach` for the whole sphere at once,
/// with the nearest of its distances from the ball's centre and the smallest of its angles
/// from straight on. A hit it rules out needs no manifold sample (its solves would all end
/// at the bound); on `cornell`, most of the hits that take a manifold sample
/// (`results/mnee.md`).
///
/// ```
/// use raypool::tracer::geometry::sphere::Sphere;
/// use raypool::tracer::lighting::passage::may_pass;
/// use raypool::tracer::math::real::Vec3;
/// use raypool::tracer::lights::casters::{Ball, Lamps};
/// let ball = Ball::new(Sphere { center: Vec3::new(0.0, 1.0, 0.0), radius: 1.0, material: 0 }, 1.5);
/// let lamp = Lamps { center: Vec3::new(0.0, 6.0, 0.0), radius: 0.7 };
/// assert!(may_pass(&ball, Vec3::new(0.5, 0.0, 0.0), lamp)); // the floor under it
/// assert!(!may_pass(&ball, Vec3::new(0.5, 6.0, 0.0), lamp)); // the ceiling beside the lamp
/// ```
pub fn may_pass(ball: &Ball, from: Vec3, lamps: Lamps) -> bool {
    let Lamps { center: lamp, radius: spread } = lamps;
    let (center, radius) = (ball.sphere.center, ball.sphere.radius);
    let (reach, toward) = (from - center, lamp - center);
    let (distance, away) = (reach.length(), toward.length());
    if distance <= radius {
        return false;
    }
    if away - spread <= radius {
        return true;
    }
    // The first try inside the tangent, as `solve` places it.
    let first = (radius / distance).acos() * (TRIES - 3) as Real / (TRIES - 1) as Real;
    let apart = (-reach.dot(toward) / (distance * away)).clamp(-1.0, 1.0).acos() - (spread / away).asin();
    within_reach(ball, distance, away - spread, Turn::by(first), apart)
}

/// Whether the solve can find a passage from the start (`distance` from the centre) to the
/// target (`far` from it, `apart` radians from straight on through the centre), given the
/// entry angle of the first try inside the tangent, `entry`. The passages looked for
/// cross the ball at most `b` from its centre, that try's impact. A ray from the start that
/// passes `b` from the centre is `β = asin(b / d)` off the way to it; the ball turns it back
/// across that way by `D =` [`Ball::turn`]`(b / r)`, so it leaves `|D − β|` off, at most the
/// larger of the two, or at most `D − β` at the outermost try where `D − β` grows with `b`
/// (where the turn's slope at the centre, `2(1 − 1/n) / r`, passes the offset's steepest,
/// `1 / √(d² − b²)`: in glass, beyond about 1.8 radii). Leaving on a line `b` from the centre,
/// it meets the target only within `asin(b / |target|)` of that line's direction, seen from
/// the centre. Cheap: on `cornell`, half the solves that [`may_pass`] lets through end here.
fn within_reach(ball: &Ball, distance: Real, far: Real, entry: Turn, apart: Real) -> bool {
    let (radius, Turn { sin, cos }) = (ball.sphere.radius, entry);
    let chord = (distance * distance + radius * radius - 2.0 * distance * radius * cos).sqrt();
    let impact = distance * radius * sin.abs() / chord;
    let (turned, aside) = (ball.turn(impact / radius), (impact / distance).asin());
    let growing = 2.0 * (1.0 - 1.0 / ball.ior) * (distance * distance - impact * impact).sqrt() >= radius;
    let off = if growing { turned - aside } else { turned.max(aside) };
    apart <= off + (impact / far).asin()
}

/// The solve's plane, its coordinates centred on the ball: the start point at
/// `(radius + gap, 0)`, the target at `target`.
struct Plane {
    radius: Real,
    inverse_radius: Real,
    gap: Real,
    ior: Real,
    target: (Real, Real),
}

impl Plane {
    /// Where the rays entering at four points of the ball (at angles `(cos, sin)`) leave
    /// towards, against the target: `(across, along)`, the cross and dot products of the ray
    /// leaving with the way to the target, so it points at the target where `across` is 0 and
    /// `along` positive; `along` is NaN where the start cannot see the point or the glass
    /// reflects it whole. [`Ball::cross`]'s passage in two dimensions: the same two
    /// refractions, the second written with the first's angles (a chord meets the sphere at
    /// equal angles). The way in and its angle to the normal are written with the start's
    /// `gap` from the glass and the sag `r(1 − cos) = r sin² / (1 + cos)` of the entry point,
    /// not as differences of numbers near the radius: from a start near the glass those
    /// differences keep too few digits in `f32` (`tests/sampling_paths.rs`).
    #[inline]
    fn sides(&self, cos: Real4, sin: Real4) -> (Real4, Real4) {
        let (eta, one, gap) = (1.0 / self.ior, Real4::ONE, Real4::splat(self.gap));
        let (ex, ey) = (cos * self.radius, sin * self.radius);
        let sag = sin * sin / (one + cos) * self.radius;
        let fx = -(sag + gap);
        let inverse = (fx * fx + ey * ey).sqrt().recip();
        let (dx, dy) = (fx * inverse, ey * inverse);
        // −(d · normal) = (distance · cos − r) / |e − start|.
        let cos_in = (gap * cos - sag) * inverse;
        // NaN where the glass reflects it whole (a ball of index below 1).
        let cos_inside = (one - (one - cos_in * cos_in) * (eta * eta)).sqrt();
        let bend = cos_in * eta - cos_inside;
        let (ix, iy) = (dx * eta + bend * cos, dy * eta + bend * sin);
        let chord = (ex * ix + ey * iy) * -2.0;
        let (xx, xy) = (ex + chord * ix, ey + chord * iy);
        let (mx, my) = (xx * self.inverse_radius, xy * self.inverse_radius);
        let ox = (ix - cos_inside * mx) * self.ior + cos_in * mx;
        let oy = (iy - cos_inside * my) * self.ior + cos_in * my;
        let (ax, ay) = (Real4::splat(self.target.0) - xx, Real4::splat(self.target.1) - xy);
        let along = ox * ax + oy * ay;
        let seen = cos_in.cmpgt(Real4::ZERO);
        (ox * ay - oy * ax, Real4::select(seen, along, Real4::splat(Real::NAN)))
    }
}

/// The passage between entry angles `low` and `high` (each with its signed miss, of opposite
/// signs), by regula falsi with the Illinois rule (a side kept twice has its miss halved, so
/// the bracket closes from both ends).
fn close_in(miss: &impl Fn(Real) -> Option<Real>, mut low: Try, mut high: Try) -> Option<Real> {
    if low.miss.signum() == high.miss.signum() {
        return None;
    }
    let mut kept = 0i8;
    for _ in 0..STEPS {
        let angle = (low.angle * high.miss - high.angle * low.miss) / (high.miss - low.miss);
        let off = miss(angle)?;
        if off.abs() < AIM {
            return Some(angle);
        }
        if off.signum() == low.miss.signum() {
            low = Try { angle, miss: off };
            high.miss *= if kept > 0 { 0.5 } else { 1.0 };
            kept = kept.max(0) + 1;
        } else {
            high = Try { angle, miss: off };
            low.miss *= if kept < 0 { 0.5 } else { 1.0 };
            kept = kept.min(0) - 1;
        }
    }
    None
}

/// The density per unit area at `at` (a point of a light whose surface has unit normal
/// `normal` there) of a bounce that leaves `from` in the unit direction `dir` with density
/// `pdf` per unit solid angle, refracts into `ball` and out again: `pdf · T / J` (see the
/// module's opening). 0 if the passage or its spread cannot be followed.
///
/// ```
/// use raypool::tracer::geometry::sphere::Sphere;
/// use raypool::tracer::lighting::passage::bounce_density;
/// use raypool::tracer::math::real::Vec3;
/// use raypool::tracer::lights::casters::Ball;
/// // A ball of index 1 bends nothing: the density is the plain `pdf · cos θ / d²`.
/// let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.0);
/// let (from, at) = (Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.0, 0.0, -5.0));
/// let density = bounce_density(&ball, from, Vec3::new(0.0, 0.0, -1.0), 1.0, at, Vec3::Z);
/// assert!((density - 1.0 / 64.0).abs() < 1e-3 / 64.0);
/// ```
pub fn bounce_density(ball: &Ball, from: Vec3, dir: Vec3, pdf: Real, at: Vec3, normal: Vec3) -> Real {
    // In double precision: from a point near the glass (the floor round the ball's foot) a
    // turn of a thousandth moves the entry by less than an `f32` resolves at the scene's
    // size, and the spread came out wrong (`tests/agreement.rs`).
    let (from, dir, at, normal) = (to_dvec3(from), to_dvec3(dir).normalize(), to_dvec3(at), to_dvec3(normal));
    let Some(taken) = ball.crossing(from, dir) else { return 0.0 };
    let land = |dir: DVec3| land(ball, from, dir, at, normal);
    let (u, v) = dir.any_orthonormal_pair();
    let turned = |a: f64, b: f64| land((dir + a * u + b * v).normalize());
    let step = f64::from(STEP);
    let (Some(centre), Some(along_u), Some(along_v)) =
        (onto(&taken, at, normal), turned(step, 0.0), turned(0.0, step))
    else {
        return 0.0;
    };
    let spread = (along_u - centre).cross(along_v - centre).length() / (step * step);
    let density = pdf * taken.transmitted / spread as Real;
    if density.is_finite() { density } else { 0.0 }
}

/// Where the ray from `from` along the unit `dir` lands on the plane through `at` with unit
/// `normal` after passing through `ball` ([`Ball::crossing`], in double precision, for
/// [`bounce_density`]'s differences; public for `tests/sampling_paths.rs`, which needs the
/// landing point as precisely).
pub fn land(ball: &Ball, from: DVec3, dir: DVec3, at: DVec3, normal: DVec3) -> Option<DVec3> {
    onto(&ball.crossing(from, dir)?, at, normal)
}

/// Where `crossing` lands on the plane through `at` with unit `normal`.
fn onto(crossing: &Crossing, at: DVec3, normal: DVec3) -> Option<DVec3> {
    let t = (at - crossing.exit).dot(normal) / crossing.out.dot(normal);
    (t > 0.0 && t.is_finite()).then(|| crossing.exit + t * crossing.out)
}
