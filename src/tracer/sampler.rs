//! Random numbers: one stream per pixel sample, independent or low-discrepancy, and the few
//! warps the book needs.
//!
//! An image must be bit-identical whatever the scheduler and thread count. So no random
//! generator is shared, global or thread-local: sample `s` of pixel `p` draws from its own
//! stream, made from `(render seed, p, s)`. Which thread renders the sample, and in what order,
//! cannot change a single number it draws.
//!
//! Two samplers make those streams ([`Sampler`], `--sampler`): [`PerSample`], independent
//! numbers from SplitMix64 started at a hash of the three keys; and [`SobolStreams`], an
//! Owen-scrambled Sobol sequence (the `sobol_burley` crate, after Burley's "Practical
//! Hash-based Owen Scrambling"), scrambled per pixel and indexed by the sample number, so a
//! pixel's samples fill each 4-dimensional use evenly instead of by chance.

use std::cell::Cell;
use std::sync::Arc;

use rand::rngs::SmallRng;
use rand::{Rng, RngExt, SeedableRng};
use rand_xoshiro::SplitMix64;
use sobol_burley::parts::{self, Int4};

use crate::tracer::real::{Real, Vec3};
use crate::tracer::turn::sin_cos_turn;

/// Which numbers pixel samples draw (`--sampler`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Sampler {
    /// Independent numbers: [`PerSample`].
    #[default]
    Independent,
    /// An Owen-scrambled Sobol sequence per pixel: [`SobolStreams`].
    Sobol,
}

impl Sampler {
    /// The `--sampler` name.
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Independent => "independent",
            Sampler::Sobol => "sobol",
        }
    }
}

/// A pixel sample's generator, told when a new bounce begins, so that a low-discrepancy
/// sampler can give each use of random numbers its own dimensions. Independent generators
/// ignore it.
pub trait SampleRng: Rng {
    /// The next numbers are for bounce `bounce` (0 for the camera ray's first scatter). Until
    /// the first call, they are the camera's: pixel jitter (2), then lens (2).
    fn bounce(&mut self, bounce: u32) {
        let _ = bounce;
    }
}

impl SampleRng for SmallRng {}
impl SampleRng for SplitMix64 {}

/// Where the random numbers of each pixel sample come from.
///
/// [`PerSample`] and [`SobolStreams`] are the renderer's real sources. The trait also lets an
/// ablation (the paper's single shared `rand()`) be plugged into the same render loop.
///
/// It has two levels because a pixel's samples share work: the render loop asks once per pixel
/// for its [`PixelStreams`] (for Sobol, the scramble keys of the pixel's dimension sets), then
/// for one stream per sample. What a stream draws still depends only on `(seed, pixel, sample)`.
///
/// ```
/// use raypool::tracer::sampler::{PerSample, PixelStreams, RandomStreams, uniform};
/// let streams = PerSample { seed: 1 };
/// let pixel = streams.pixel(42);
/// // The same sample of the same pixel draws the same numbers, however it is reached.
/// assert_eq!(uniform(&mut pixel.stream(3)), uniform(&mut streams.pixel(42).stream(3)));
/// ```
pub trait RandomStreams: Sync {
    /// What the samples of one pixel share.
    type Pixel<'a>: PixelStreams
    where
        Self: 'a;
    /// The streams of pixel `pixel` (row-major index).
    fn pixel(&self, pixel: u64) -> Self::Pixel<'_>;
}

/// The random streams of one pixel's samples (see [`RandomStreams`]).
pub trait PixelStreams {
    /// The generator type handed to one pixel sample.
    type Stream<'a>: SampleRng
    where
        Self: 'a;
    /// The stream of sample `sample` of this pixel.
    fn stream(&self, sample: u64) -> Self::Stream<'_>;
}

/// Independent streams seeded from `(seed, pixel, sample)`: deterministic under any schedule.
#[derive(Clone, Copy, Debug)]
pub struct PerSample {
    /// The render seed (`--seed`).
    pub seed: u64,
}

impl RandomStreams for PerSample {
    type Pixel<'a> = PerSamplePixel;

    fn pixel(&self, pixel: u64) -> PerSamplePixel {
        PerSamplePixel { key: mix(mix(self.seed) ^ pixel) }
    }
}

/// One pixel's independent streams: the render seed and the pixel, already mixed.
#[derive(Clone, Copy, Debug)]
pub struct PerSamplePixel {
    key: u64,
}

impl PixelStreams for PerSamplePixel {
    type Stream<'a> = SplitMix64;

    /// Chains the three keys through a strong 64-bit mixer, so that neighbouring pixels and
    /// samples start at unrelated points, and starts SplitMix64 there. SplitMix64 (Vigna's,
    /// as `rand_xoshiro` has it) needs no seeding beyond its one 64-bit word, where
    /// xoshiro256++ (`SmallRng`, used until issue #10) spent four more mixes filling its
    /// state for every sample; a sample draws about ten numbers, each one mix either way.
    /// Two samples' streams overlap only if their start points are within a few draws of
    /// each other on SplitMix64's one cycle of 2⁶⁴: for hashed start points, never in practice.
    fn stream(&self, sample: u64) -> SplitMix64 {
        SplitMix64::seed_from_u64(mix(self.key ^ sample))
    }
}

/// Owen-scrambled Sobol streams: sample `s` of pixel `p` is point `s` of a Sobol sequence
/// scrambled by a seed made from `(render seed, p)`.
///
/// Each use of random numbers gets its own dimensions of a 4-dimensional set: the camera all
/// four of the first (pixel jitter, lens); bounces `2m` and `2m + 1` two each of set `m + 1`
/// (a scattered direction takes two, the glass choice one). Sets are "padded" as Burley
/// recommends: the same four best Sobol dimensions, decorrelated by a different scramble seed
/// per set, so bounces do not correlate with the camera or with bounces of other sets, and the
/// two bounces of one set are stratified jointly, as four dimensions of one sequence. A set is
/// the sampler's main cost: about 105 instructions now that its scramble keys are made once
/// per pixel ([`SobolPixel`]), 190 when they were made per sample, 290 before `SobolTable`;
/// sharing one between two bounces made Sobol renders of `final` 1.07× faster
/// (`results/perf.md`). Past a use's dimensions (Russian roulette's draw after a direction),
/// or past the sequence's 2¹⁶ samples, the stream falls back to independent numbers seeded
/// like [`PerSample`]'s, so any draw count and any spp work.
///
/// ```
/// use raypool::tracer::sampler::{PixelStreams, RandomStreams, SobolStreams, uniform};
/// let streams = SobolStreams::new(1);
/// // The first 16 samples of a pixel put exactly one jitter x in each sixteenth of [0, 1).
/// let mut strata: Vec<usize> = (0..16).map(|s| (uniform(&mut streams.pixel(42).stream(s)) * 16.0) as usize).collect();
/// strata.sort();
/// assert_eq!(strata, (0..16).collect::<Vec<_>>());
/// ```
#[derive(Clone, Debug)]
pub struct SobolStreams {
    /// The render seed (`--seed`).
    seed: u64,
    /// The render seed mixed, the first step of every pixel's seed.
    seed_key: u64,
    table: Arc<SobolTable>,
}

/// The most samples per pixel the Sobol sequence holds; later samples draw independent numbers.
pub const SOBOL_SAMPLES: u64 = 1 << 16;

impl SobolStreams {
    /// The streams of render seed `seed` (`--seed`).
    pub fn new(seed: u64) -> SobolStreams {
        SobolStreams { seed, seed_key: mix(seed ^ 0x536F_626F_6C00_0000), table: Arc::new(SobolTable::new()) }
    }

    /// Point `index` (below [`SOBOL_SAMPLES`]) of the four dimensions every set uses, Owen
    /// scrambled by `scramble`: exactly `sobol_burley::sample_4d(index, 0, scramble)`, computed
    /// faster (see `SobolTable`).
    ///
    /// ```
    /// use raypool::tracer::sampler::SobolStreams;
    /// let streams = SobolStreams::new(1);
    /// assert_eq!(streams.sample_4d(5, 77), sobol_burley::sample_4d(5, 0, 77));
    /// ```
    pub fn sample_4d(&self, index: u32, scramble: u32) -> [f32; 4] {
        let bits = self.table.sample_4d(index.reverse_bits(), &SetKeys::new(scramble));
        // The crate's `to_f32_norm`: the top 23 bits, exactly.
        bits.map(|x| (x >> 9) as f32 * (1.0 / (1u32 << 23) as f32))
    }
}

impl RandomStreams for SobolStreams {
    type Pixel<'a> = SobolPixel<'a>;

    fn pixel(&self, pixel: u64) -> SobolPixel<'_> {
        SobolPixel {
            table: &self.table,
            seed: mix(self.seed_key ^ pixel),
            fallback: (PerSample { seed: self.seed }, pixel),
            keys: Default::default(),
        }
    }
}

/// How many of a pixel's dimension sets keep their keys for the pixel's next samples: the
/// camera's and those of bounces 0 to 5, more than almost every path uses.
const KEPT_SETS: usize = 4;

/// One pixel's Sobol streams: its scramble seed and, made the first time a sample needs them,
/// the keys of its first dimension sets, which every later sample of the pixel reuses. A key
/// is a hash of the pixel and the set, not of the sample: made once per pixel instead of once
/// per sample, it leaves a set only the work that depends on the sample's index.
#[derive(Debug)]
pub struct SobolPixel<'a> {
    table: &'a SobolTable,
    seed: u64,
    /// The independent streams and pixel a sample falls back to (made only if it does).
    fallback: (PerSample, u64),
    keys: [Cell<Option<SetKeys>>; KEPT_SETS],
}

impl SobolPixel<'_> {
    /// The keys of dimension set `set`, kept from an earlier sample if it is one of the first.
    #[inline]
    fn keys(&self, set: u32) -> SetKeys {
        let make = || SetKeys::new(mix(self.seed ^ u64::from(set)) as u32);
        match self.keys.get(set as usize) {
            Some(kept) => kept.get().unwrap_or_else(|| {
                let keys = make();
                kept.set(Some(keys));
                keys
            }),
            None => make(),
        }
    }
}

impl PixelStreams for SobolPixel<'_> {
    type Stream<'a>
        = SobolStream<'a>
    where
        Self: 'a;

    #[inline]
    fn stream(&self, sample: u64) -> SobolStream<'_> {
        let index_rev = (sample < SOBOL_SAMPLES).then(|| (sample as u32).reverse_bits());
        let mut stream = SobolStream {
            pixel: self,
            index_rev,
            set: [0; 4],
            loaded: u32::MAX,
            next: 0,
            end: 0,
            fallback: Fallback { sample, rng: None },
        };
        stream.use_dimensions(0, 0..4);
        stream
    }
}

/// The scramble keys of one dimension set: the index shuffle's and each dimension's. They are
/// `sobol_burley::sample_4d`'s own, derived from its `seed` as it derives them.
#[derive(Clone, Copy, Debug)]
struct SetKeys {
    shuffle: u32,
    dimensions: [u32; 4],
}

impl SetKeys {
    /// The keys `sample_4d(_, 0, seed)` uses (its seed multiplier and per-dimension offsets
    /// for dimension set 0), so the bits match the crate's.
    fn new(seed: u32) -> SetKeys {
        let dimension_seed = seed.wrapping_mul(0x9c8f_2d3b);
        let offsets = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
        SetKeys {
            shuffle: parts::hash(seed ^ 0x79c6_8e4a),
            dimensions: offsets.map(|offset| parts::hash(dimension_seed ^ offset)),
        }
    }
}

/// `sobol_burley::sample_4d`, the same bits, with the Sobol matrix product by table. The crate
/// multiplies the (shuffled, bit-reversed) index by the generator matrices one set bit at a
/// time, a loop of up to 16 rounds whose exit the CPU mispredicts; the product is linear over
/// XOR, so it is the XOR of the products of the index's two bytes, 256 of each kept here
/// (8 KiB, made once per render from the crate's own `parts::sobol_int4_rev`). The scrambles
/// around it are the crate's `parts`, composed as `sample_4d` composes them
/// (`tests/sampler.rs` checks its outputs against the crate's).
#[derive(Debug)]
struct SobolTable {
    /// `bytes[k][b]`: the four dimensions' product for byte `b` at bits `24 − 8k ..` of the
    /// bit-reversed index (only its top 16 bits count: the sequence has 2¹⁶ points).
    bytes: [[[u32; 4]; 256]; 2],
}

impl SobolTable {
    fn new() -> SobolTable {
        let mut bytes = [[[0; 4]; 256]; 2];
        for (k, products) in bytes.iter_mut().enumerate() {
            for (b, product) in products.iter_mut().enumerate() {
                *product = parts::sobol_int4_rev((b as u32) << (24 - 8 * k), 0).into();
            }
        }
        SobolTable { bytes }
    }

    /// The four dimensions of the point of bit-reversed index `index_rev`, scrambled by `keys`,
    /// as 32-bit fractions.
    #[inline]
    fn sample_4d(&self, index_rev: u32, keys: &SetKeys) -> [u32; 4] {
        let shuffled = parts::owen_scramble_rev(index_rev, keys.shuffle);
        let [high, low] = [(shuffled >> 24) as usize, (shuffled >> 16 & 0xff) as usize];
        // The four lanes' scrambles written one lane at a time, not with the crate's `Int4`: the
        // build targets baseline x86-64, which has no 4 × 32-bit multiply (SSE4.1), and the
        // compiler vectorises these four lanes into fewer instructions than `Int4`'s emulation
        // of that multiply (callgrind, the same bits: `Int4` here costs 2.0% more on `final`
        // and 4.4% more on paper1).
        let (by_high, by_low) = (self.bytes[0][high], self.bytes[1][low]);
        let scrambled: [u32; 4] =
            std::array::from_fn(|d| parts::owen_scramble_rev(by_high[d] ^ by_low[d], keys.dimensions[d]));
        Int4::from(scrambled).reverse_bits().into()
    }
}

/// One pixel sample's numbers from [`SobolStreams`].
#[derive(Clone, Debug)]
pub struct SobolStream<'a> {
    pixel: &'a SobolPixel<'a>,
    /// The sample's index in the sequence, bits reversed; `None` past [`SOBOL_SAMPLES`].
    index_rev: Option<u32>,
    /// The numbers of the 4-dimensional set `loaded` (`u32::MAX`: none yet).
    set: [u32; 4],
    loaded: u32,
    /// The current use's next dimension in `set`, and the end of its dimensions.
    next: usize,
    end: usize,
    fallback: Fallback,
}

/// The independent numbers a Sobol stream falls back to, seeded only if it ever needs them
/// (most samples never do).
#[derive(Clone, Debug)]
struct Fallback {
    sample: u64,
    rng: Option<SplitMix64>,
}

impl SobolStream<'_> {
    /// The next numbers are `dimensions` of 4-dimensional set `set`, computed if it is not
    /// the one loaded. Past the sequence's samples, they are independent numbers.
    #[inline]
    fn use_dimensions(&mut self, set: u32, dimensions: std::ops::Range<usize>) {
        let Some(index_rev) = self.index_rev else { return };
        if self.loaded != set {
            self.set = self.pixel.table.sample_4d(index_rev, &self.pixel.keys(set));
            self.loaded = set;
        }
        (self.next, self.end) = (dimensions.start, dimensions.end);
    }

    fn fallback(&mut self) -> &mut SplitMix64 {
        let ((streams, pixel), sample) = (self.pixel.fallback, self.fallback.sample);
        self.fallback.rng.get_or_insert_with(|| streams.pixel(pixel).stream(sample))
    }
}

impl SampleRng for SobolStream<'_> {
    fn bounce(&mut self, bounce: u32) {
        let first = 2 * (bounce % 2) as usize;
        self.use_dimensions(1 + bounce / 2, first..first + 2);
    }
}

impl rand::TryRng for SobolStream<'_> {
    type Error = std::convert::Infallible;

    /// The current use's next Sobol number (its top 23 bits, as `sobol_burley` gives them as
    /// `f32`), or an independent one once they are used up.
    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        if self.next < self.end {
            let v = self.set[self.next];
            self.next += 1;
            Ok(v & !0x1ff)
        } else {
            Ok(self.fallback().next_u32())
        }
    }

    /// A Sobol number's 32 bits on top, independent bits below (for the `f64` build); past
    /// the use's dimensions, the independent stream's own next `u64`, so a sample past the
    /// sequence's 2¹⁶ draws exactly [`PerSample`]'s numbers in both builds. (Within the
    /// sequence the low bits of f64 Sobol draws come from that stream too, so a later
    /// fallback draw is a later number of it.)
    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        if self.next >= self.end {
            return Ok(self.fallback().next_u64());
        }
        let high = self.try_next_u32()?;
        Ok(u64::from(high) << 32 | u64::from(self.fallback().next_u32()))
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
        self.fallback().fill_bytes(dst);
        Ok(())
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
    let (sin, cos) = sin_cos_turn(uniform(rng));
    Vec3::new(r * cos, r * sin, z)
}

/// A point uniformly distributed in the unit disk, as `(x, y)`.
pub fn random_in_unit_disk<R: Rng + ?Sized>(rng: &mut R) -> (Real, Real) {
    let r = uniform(rng).sqrt();
    let (sin, cos) = sin_cos_turn(uniform(rng));
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

impl SampleRng for SharedStream<'_> {}

impl RandomStreams for SharedRng {
    type Pixel<'a> = &'a SharedRng;

    fn pixel(&self, _pixel: u64) -> &SharedRng {
        self
    }
}

impl PixelStreams for &SharedRng {
    type Stream<'a>
        = SharedStream<'a>
    where
        Self: 'a;

    fn stream(&self, _sample: u64) -> SharedStream<'_> {
        SharedStream(self)
    }
}
