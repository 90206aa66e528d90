//! Warps: uniform numbers turned into the shapes the book draws from (a direction on the
//! sphere, a point in the lens's disk), each by inverting its measure, so a warp takes a fixed
//! number of draws and a low-discrepancy sampler's even spread survives it.

use rand::{Rng, RngExt};

use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::turn::sin_cos_turn;

/// A uniform number in `[0, 1)`.
#[inline]
pub fn uniform<R: Rng + ?Sized>(rng: &mut R) -> Real {
    rng.random::<Real>()
}

/// A direction uniformly distributed on the unit sphere (by inverting the area measure,
/// which needs exactly two draws, unlike the book's rejection loop).
pub fn random_unit_vector<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    let z = 1.0 - 2.0 * uniform(rng);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = sin_cos_turn(uniform(rng));
    Vec3::new(r * cos, r * sin, z)
}

/// A point uniformly distributed in the unit disk, as `(x, y)`.
pub fn random_in_unit_disk<R: Rng + ?Sized>(rng: &mut R) -> (Real, Real) {
    let r = uniform(rng).sqrt();
    let (sin, cos) = sin_cos_turn(uniform(rng));
    (r * cos, r * sin)
}
