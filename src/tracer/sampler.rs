//! Random numbers: one independent stream per pixel sample, and the few warps the book needs.
//!
//! An image must be bit-identical whatever the scheduler and thread count. So no random
//! generator is shared, global or thread-local: sample `s` of pixel `p` draws from its own
//! small generator seeded from `(render seed, p, s)`. Which thread renders the sample, and in
//! what order, cannot change a single number it draws.

use rand::rngs::SmallRng;
use rand::{Rng, RngExt, SeedableRng};

use crate::tracer::real::{Real, Vec3, consts::TAU};

/// Where the random numbers of each pixel sample come from.
///
/// [`PerSample`] is the renderer's real source. The trait exists so that an ablation (the
/// paper's single shared `rand()`) can be plugged into the same render loop.
pub trait RandomStreams: Sync {
    /// The generator type handed to one pixel sample.
    type Stream<'a>: Rng
    where
        Self: 'a;
    /// The stream for sample `sample` of pixel `pixel` (row-major index).
    fn stream(&self, pixel: u64, sample: u64) -> Self::Stream<'_>;
}

/// Independent streams seeded from `(seed, pixel, sample)`: deterministic under any schedule.
#[derive(Clone, Copy, Debug)]
pub struct PerSample {
    /// The render seed (`--seed`).
    pub seed: u64,
}

impl RandomStreams for PerSample {
    type Stream<'a> = SmallRng;

    fn stream(&self, pixel: u64, sample: u64) -> SmallRng {
        // Chain the three keys through a strong 64-bit mixer so neighbouring pixels and
        // samples get unrelated seeds; SmallRng expands the 64 bits into its full state.
        let key = mix(mix(mix(self.seed) ^ pixel) ^ sample);
        SmallRng::seed_from_u64(key)
    }
}

/// SplitMix64's finaliser: a bijection on u64 with full avalanche.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

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
    let (sin, cos) = (TAU * uniform(rng)).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// A point uniformly distributed in the unit disk, as `(x, y)`.
pub fn random_in_unit_disk<R: Rng + ?Sized>(rng: &mut R) -> (Real, Real) {
    let r = uniform(rng).sqrt();
    let (sin, cos) = (TAU * uniform(rng)).sin_cos();
    (r * cos, r * sin)
}

/// The seed paper's random numbers: one generator shared by every thread, behind a lock (as
/// C's `rand()` is). For the ablation only: every draw takes the lock, so threads queue on
/// it, and which thread gets which number depends on timing, so images are not reproducible.
///
/// The lock is `std::sync::Mutex`, which on Linux, like glibc's lock inside `rand()`, is a
/// futex: a contended acquisition sleeps in the kernel. (`parking_lot`'s adaptive spinning
/// would hide part of the cost the paper ran into.)
#[derive(Debug)]
pub struct SharedRng {
    generator: std::sync::Mutex<SmallRng>,
}

impl SharedRng {
    /// One generator for the whole render, seeded with `seed`.
    pub fn new(seed: u64) -> SharedRng {
        SharedRng { generator: std::sync::Mutex::new(SmallRng::seed_from_u64(seed)) }
    }
}

/// A handle that draws from the [`SharedRng`], taking its lock for every number.
pub struct SharedStream<'a>(&'a SharedRng);

impl SharedStream<'_> {
    fn lock(&self) -> std::sync::MutexGuard<'_, SmallRng> {
        // A draw cannot panic while holding the lock, so it is never poisoned in practice;
        // if it were, the generator's state would still be valid.
        self.0.generator.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl rand::TryRng for SharedStream<'_> {
    type Error = std::convert::Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        Ok(self.lock().next_u32())
    }

    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        Ok(self.lock().next_u64())
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
        self.lock().fill_bytes(dst);
        Ok(())
    }
}

impl RandomStreams for SharedRng {
    type Stream<'a> = SharedStream<'a>;

    fn stream(&self, _pixel: u64, _sample: u64) -> SharedStream<'_> {
        SharedStream(self)
    }
}
