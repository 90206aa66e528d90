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
use sobol_burley::parts;
use wide::u16x8;

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

/// Owen-scrambled Sobol streams: sample `s` of pixel `p` takes point `s` of a Sobol sequence
/// (in the camera's dimensions; in the others, point `s` of the index shuffled per set, below)
/// scrambled by a seed made from `(render seed, p)`.
///
/// Each use of random numbers gets its own dimensions of a 4-dimensional set: the camera all
/// four of the first (pixel jitter, lens); bounces `2m` and `2m + 1` two each of set `m + 1`
/// (a scattered direction takes two, the glass choice one). Sets are "padded" as Burley
/// recommends: the same four best Sobol dimensions, decorrelated by a different scramble seed
/// per set, so bounces do not correlate with the camera or with bounces of other sets, and the
/// two bounces of one set are stratified jointly, as four dimensions of one sequence. As in
/// Burley's paper, each set also shuffles the sample index (a nested scramble, so a pixel's
/// first 2ᵏ samples still take an aligned block of 2ᵏ points, a net as the first 2ᵏ are; which
/// block depends on the set's key): all but the camera's set, which needs none, since the
/// others' shuffles, each independent, already decorrelate them from it; unshuffled, it takes
/// the first block, and its index is read without reversing its bits. (Which block changes
/// nothing on its own: Sobol points are linear over XOR, so another block is the first one
/// XORed with a constant point, and the pixel's Owen scramble of the values absorbs such a
/// shift.)
///
/// Sets are the sampler's main cost, so they are made two at a time, in the eight 16-bit lanes
/// of one SSE2 register (`SobolTable`): the camera's with that of bounces 0 and 1 when a sample
/// starts, sets 2 and 3 (bounces 2 to 5) when a path gets that far. A set took 290
/// instructions before `SobolTable`, 190 with it, 105 once its scramble keys were made once per
/// pixel ([`SobolPixel`]); a pair of sets about 100, and the first pair about 75 once the
/// camera's set was left unshuffled (`results/perf.md`, ninth and tenth passes). Past a use's
/// dimensions (Russian roulette's draw after a direction), or past the sequence's 2¹⁶ samples,
/// the stream falls back to independent numbers seeded like [`PerSample`]'s, so any draw count
/// and any spp work.
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
    /// scrambled by `scramble`: `sobol_burley::sample_4d(index, 0, scramble)` to 2⁻¹⁶, the
    /// sequence's own resolution, computed faster, with its own offset below (see
    /// `SobolTable`).
    ///
    /// ```
    /// use raypool::tracer::sampler::SobolStreams;
    /// let streams = SobolStreams::new(1);
    /// let cell = |x: f32| (x * 65536.0) as u32;
    /// assert_eq!(streams.sample_4d(5, 77).map(cell), sobol_burley::sample_4d(5, 0, 77).map(cell));
    /// ```
    pub fn sample_4d(&self, index: u32, scramble: u32) -> [f32; 4] {
        let pair = self.table.pair(index.reverse_bits(), &PairKeys::new([scramble; 2]));
        std::array::from_fn(|d| (pair[d] >> 9) as f32 * (1.0 / (1u32 << 23) as f32))
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
            made: Cell::new(0),
        }
    }
}

/// How many pairs of a pixel's dimension sets keep their keys for the pixel's next samples:
/// sets 0 to 3, the camera's and those of bounces 0 to 5, more than almost every path uses.
const KEPT_PAIRS: usize = 2;

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
    keys: [Cell<PairKeys>; KEPT_PAIRS],
    /// Bit `k` set: `keys[k]` is made.
    made: Cell<u8>,
}

impl SobolPixel<'_> {
    /// The points of bit-reversed index `index_rev` in dimension sets `2 pair` and
    /// `2 pair + 1`, for a pair after the first (the first pair is [`Self::first_pair`]'s).
    #[inline]
    fn pair(&self, index_rev: u32, pair: u32) -> [u32; 8] {
        self.table.pair(index_rev, &self.keys(pair))
    }

    /// Sample `sample`'s camera set and that of bounces 0 and 1, and its bit-reversed index.
    #[inline]
    fn first_pair(&self, sample: u32) -> ([u32; 8], u32) {
        self.table.first_pair(sample, &self.keys(0))
    }

    /// The keys of dimension sets `2 pair` and `2 pair + 1`, kept from an earlier sample if
    /// they are among the first.
    #[inline]
    fn keys(&self, pair: u32) -> PairKeys {
        let make = || PairKeys::new([0, 1].map(|k| mix(self.seed ^ u64::from(2 * pair + k)) as u32));
        let Some(kept) = self.keys.get(pair as usize) else { return make() };
        let bit = 1 << pair;
        if self.made.get() & bit == 0 {
            kept.set(make());
            self.made.set(self.made.get() | bit);
        }
        // Read back from where they are kept, so each group of eight lanes is one load.
        kept.get()
    }
}

impl PixelStreams for SobolPixel<'_> {
    type Stream<'a>
        = SobolStream<'a>
    where
        Self: 'a;

    #[inline]
    fn stream(&self, sample: u64) -> SobolStream<'_> {
        // The camera's set and bounces 0 and 1's, computed here in line: every sample needs
        // the first, almost every one the second.
        let (numbers, index_rev) = if sample < SOBOL_SAMPLES {
            let (numbers, index_rev) = self.first_pair(sample as u32);
            (numbers, Some(index_rev))
        } else {
            (Default::default(), None)
        };
        SobolStream {
            pixel: self,
            index_rev,
            numbers,
            loaded: 0,
            next: 0,
            end: if index_rev.is_some() { 4 } else { 0 },
            fallback: Fallback { sample, rng: None },
        }
    }
}

/// The scramble keys of two dimension sets: each set's index shuffle, and per dimension the
/// Owen hash's two keys and the key of the offset within a cell, in eight lanes (the first
/// set's four dimensions, then the second's). They derive from `sobol_burley::sample_4d`'s own
/// keys for each set's seed, made as it makes them; of the hash's keys only the low 16 bits
/// are kept, all that reaches a point's top 16 bits (see `SobolTable`).
#[derive(Clone, Copy, Debug, Default)]
struct PairKeys {
    /// Each set's index shuffle (the camera's, in the first pair, unused: it is not shuffled).
    shuffle: [u32; 2],
    add: u16x8,
    multiply: u16x8,
    cell_offset: u16x8,
}

impl PairKeys {
    /// The keys `sample_4d(_, 0, seed)` uses for each of the two `seeds` (its seed multiplier
    /// and per-dimension offsets for dimension set 0), so the top 16 bits match the crate's.
    /// Made once per pixel and pair, so kept out of line: inlined, its registers would crowd
    /// the per-sample code.
    #[inline(never)]
    fn new(seeds: [u32; 2]) -> PairKeys {
        let offsets: [u32; 4] = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
        // Each set's four dimension hashes by the crate's four-lane hash (as `sample_4d` makes
        // them): 114 instructions a pair, against 168 by eight calls of its one-lane `hash`.
        let halves: [[u32; 4]; 2] = seeds.map(|seed| {
            let dimension_seed = seed.wrapping_mul(0x9c8f_2d3b);
            parts::hash_int4(offsets.map(|offset| dimension_seed ^ offset).into()).into()
        });
        let hashes: [u32; 8] = bytemuck::cast(halves);
        // The crate's hash adds its key, then multiplies by the key's top half, made odd.
        let lanes = |f: fn(u32) -> u16| u16x8::new(hashes.map(f));
        PairKeys {
            shuffle: seeds.map(|seed| parts::hash(seed ^ 0x79c6_8e4a)),
            add: lanes(|h| h as u16),
            multiply: lanes(|h| (h >> 16) as u16 | 1),
            cell_offset: lanes(|h| (h.wrapping_mul(0x9e37_79b9) >> 16) as u16),
        }
    }
}

/// `sobol_burley::sample_4d`'s points, the same top 16 bits, two dimension sets at a time in
/// fewer instructions than the crate spends on one.
///
/// The crate multiplies the (shuffled, bit-reversed) index by the generator matrices one set
/// bit at a time, a loop whose exit the CPU mispredicts; the product is linear over XOR, so it
/// is the XOR of the products of the index's two bytes, 256 of each kept here (made once per
/// render from the crate's own `parts::sobol_int4_rev`).
///
/// The crate then Owen-scrambles each dimension with a hash of 32-bit multiplies, which
/// baseline x86-64 (SSE2) has no instruction for on several lanes. But the sequence has 2¹⁶
/// points, so a point's coordinates have 16 significant bits, and every step of that hash
/// (multiply, add, XOR with a multiple) carries only upwards in the bit-reversed word: its low
/// 16 bits, the point's top 16 once reversed back, depend only on the low 16 bits of what goes
/// in. So the hash runs on 16-bit lanes, eight in one SSE2 register, two sets' four dimensions
/// for one `pmullw` per step, and gives the crate's top 16 bits exactly (`tests/sampler.rs`
/// checks every index). Below them the crate's bits are a hash of the point's cell and seed;
/// here they are too, a cheaper one: the cell XOR a key per pixel and dimension, times an odd
/// constant, its top 7 bits (for a random key, a uniform offset within the cell: no bias).
#[derive(Debug)]
struct SobolTable {
    /// `bytes[k][b]`: the low 16 bits of the four dimensions' product (dimension `d` in lane
    /// `d` of four) for byte `b` at bits `24 − 8k ..` of the bit-reversed index (only its top
    /// 16 bits count).
    bytes: [[u64; 256]; 2],
    /// The same rows indexed by the sample's own bytes: `by_sample[k][b]` is `bytes[k]` at `b`
    /// reversed, for byte `k` of an index that is not shuffled (the camera's set's), so that
    /// it is read without reversing the index.
    by_sample: [[u64; 256]; 2],
    /// `reversed[k][b]`: byte `k` of a sample index, `b`, with its bits reversed into bits
    /// `24 − 8k ..`: the index reversed in two loads, where the CPU has no instruction for it
    /// (bit tricks took 17).
    reversed: [[u32; 256]; 2],
}

impl SobolTable {
    fn new() -> SobolTable {
        let mut bytes = [[0; 256]; 2];
        for (k, products) in bytes.iter_mut().enumerate() {
            for (b, product) in products.iter_mut().enumerate() {
                let full: [u32; 4] = parts::sobol_int4_rev((b as u32) << (24 - 8 * k), 0).into();
                // Four 16-bit lanes in one word, as they lie in memory (any byte order), so that
                // two words XOR as lanes and are cast to eight lanes without moving any.
                *product = bytemuck::cast(full.map(|x| x as u16));
            }
        }
        let reverse = |b: usize| usize::from((b as u8).reverse_bits());
        SobolTable {
            by_sample: std::array::from_fn(|k| std::array::from_fn(|b| bytes[k][reverse(b)])),
            reversed: std::array::from_fn(|k| std::array::from_fn(|b| (reverse(b) as u32) << (24 - 8 * k))),
            bytes,
        }
    }

    /// The four dimensions of each of two sets for the point of bit-reversed index `index_rev`,
    /// scrambled by `keys`, as 32-bit fractions with 23 significant bits (what an `f32` holds).
    #[inline]
    fn pair(&self, index_rev: u32, keys: &PairKeys) -> [u32; 8] {
        Self::scramble(keys.shuffle.map(|shuffle| self.shuffled_row(index_rev, shuffle)), keys)
    }

    /// The first pair of sample `sample` (below [`SOBOL_SAMPLES`]): as [`Self::pair`], but the
    /// first set, the camera's, takes the sample's own index, unshuffled (see
    /// [`SobolStreams`]); with the index bit-reversed, which later pairs need.
    #[inline]
    fn first_pair(&self, sample: u32, keys: &PairKeys) -> ([u32; 8], u32) {
        debug_assert!(u64::from(sample) < SOBOL_SAMPLES, "sample {sample} is past the sequence");
        let bytes = [sample & 0xff, sample >> 8 & 0xff].map(|b| b as usize);
        let index_rev = self.reversed[0][bytes[0]] | self.reversed[1][bytes[1]];
        let camera = self.by_sample[0][bytes[0]] ^ self.by_sample[1][bytes[1]];
        (Self::scramble([camera, self.shuffled_row(index_rev, keys.shuffle[1])], keys), index_rev)
    }

    /// One set's four dimensions, unscrambled, at the index `index_rev` shuffled by `shuffle`.
    #[inline]
    fn shuffled_row(&self, index_rev: u32, shuffle: u32) -> u64 {
        let shuffled = parts::owen_scramble_rev(index_rev, shuffle);
        self.bytes[0][(shuffled >> 24) as usize] ^ self.bytes[1][(shuffled >> 16 & 0xff) as usize]
    }

    /// Two sets' rows (four lanes each), Owen scrambled by `keys`, with the offsets below.
    #[inline]
    fn scramble(rows: [u64; 2], keys: &PairKeys) -> [u32; 8] {
        // `parts::owen_scramble_rev`'s steps on all eight lanes, with its constants' low 16 bits.
        let mut x: u16x8 = bytemuck::cast(rows);
        x ^= x * u16x8::splat(0xadea);
        x = (x + keys.add) * keys.multiply;
        x ^= x * u16x8::splat(0x6c56);
        x ^= x * u16x8::splat(0x2864);
        let top = reverse_bits(x);
        // The product's top 7 bits, in place: bits 9 to 15 of the fraction's low half.
        let below = (((top ^ keys.cell_offset) * u16x8::splat(0x9e37)) & u16x8::splat(0xfe00)).to_array();
        let top = top.to_array();
        std::array::from_fn(|l| u32::from(top[l]) << 16 | u32::from(below[l]))
    }
}

/// Each lane's 16 bits in reverse order (SSE2 has no instruction for it): swap the bytes, then
/// the nibbles, the pairs and the bits of each.
#[inline]
fn reverse_bits(x: u16x8) -> u16x8 {
    let swap = |x: u16x8, shift: u32, mask: u16| {
        let mask = u16x8::splat(mask);
        (x >> shift & mask) | (x & mask) << shift
    };
    swap(swap(swap(x >> 8 | x << 8, 4, 0x0f0f), 2, 0x3333), 1, 0x5555)
}

/// One pixel sample's numbers from [`SobolStreams`].
#[derive(Clone, Debug)]
pub struct SobolStream<'a> {
    pixel: &'a SobolPixel<'a>,
    /// The sample's index in the sequence, bits reversed; `None` past [`SOBOL_SAMPLES`].
    index_rev: Option<u32>,
    /// The numbers of the pair of 4-dimensional sets `loaded` (from the start, pair 0: the
    /// camera's set and that of bounces 0 and 1).
    numbers: [u32; 8],
    loaded: u32,
    /// The current use's next lane in `numbers`, and the end of its lanes.
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
    /// The next numbers are `dimensions` of 4-dimensional set `set`, computed with the other
    /// set of its pair if that pair is not the one loaded. Past the sequence's samples, they
    /// are independent numbers.
    #[inline(always)]
    fn use_dimensions(&mut self, set: u32, dimensions: std::ops::Range<usize>) {
        let Some(index_rev) = self.index_rev else { return };
        if self.loaded != set / 2 {
            self.load(index_rev, set / 2);
        }
        let lane = 4 * (set % 2) as usize;
        (self.next, self.end) = (lane + dimensions.start, lane + dimensions.end);
    }

    /// Computes the pair of sets `pair`. Out of line, so that a bounce whose set is already
    /// loaded (every bounce but 2, 6, 10, …) pays for a comparison, not for saving the
    /// registers this needs.
    #[inline(never)]
    fn load(&mut self, index_rev: u32, pair: u32) {
        self.numbers = self.pixel.pair(index_rev, pair);
        self.loaded = pair;
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

    /// The current use's next Sobol number (23 bits, what an `f32` holds: see `SobolTable`),
    /// or an independent one once they are used up.
    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        if self.next < self.end {
            let v = self.numbers[self.next];
            self.next += 1;
            Ok(v)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sample index of the sequence, each with its own seeds for a pair's two sets.
    fn cases() -> impl Iterator<Item = ([u32; 2], u32)> {
        (0..SOBOL_SAMPLES as u32).map(|index| {
            let k = index.wrapping_mul(0x2C1B_3C6D);
            ([k.wrapping_mul(0x9E37_79B9), k.wrapping_mul(0x85EB_CA6B) ^ 0x2545_F491], index)
        })
    }

    /// The cells (top 16 bits) of half `half` of a pair.
    fn cells(pair: [u32; 8], half: usize) -> [u32; 4] {
        std::array::from_fn(|d| pair[4 * half + d] >> 16)
    }

    /// The cells of the crate's point `index` of dimension set 0 under `seed` (index shuffled).
    fn crate_cells(index: u32, seed: u32) -> [u32; 4] {
        sobol_burley::sample_4d(index, 0, seed).map(|x| (x * 65536.0) as u32)
    }

    #[test]
    fn each_half_of_a_pair_is_its_own_seeds_point() {
        // `tests/sampler.rs` checks the first half against the crate through `sample_4d`; here
        // the two halves under different seeds, so a lane taking the other set's key shows.
        let table = SobolTable::new();
        for (seeds, index) in cases() {
            let pair = table.pair(index.reverse_bits(), &PairKeys::new(seeds));
            for (half, seed) in seeds.into_iter().enumerate() {
                assert_eq!(cells(pair, half), crate_cells(index, seed), "index {index}, half {half}");
            }
        }
    }

    #[test]
    fn the_first_pair_leaves_the_camera_set_unshuffled_and_shuffles_the_second() {
        // The crate always shuffles the index; its parts give the unshuffled point.
        let table = SobolTable::new();
        for (seeds, sample) in cases() {
            let (pair, index_rev) = table.first_pair(sample, &PairKeys::new(seeds));
            assert_eq!(index_rev, sample.reverse_bits());
            let dimension_seed = seeds[0].wrapping_mul(0x9c8f_2d3b);
            let keys =
                [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8].map(|offset| dimension_seed ^ offset);
            let point = parts::owen_scramble_int4_rev(
                parts::sobol_int4_rev(index_rev, 0),
                parts::hash_int4(keys.into()),
            );
            let camera: [u32; 4] = point.reverse_bits().into();
            assert_eq!(cells(pair, 0), camera.map(|x| x >> 16), "sample {sample}, the camera's set");
            assert_eq!(cells(pair, 1), crate_cells(sample, seeds[1]), "sample {sample}, the second set");
        }
    }
}
