//! Owen-scrambled Sobol streams (`--sampler sobol`, the default): a pixel's samples fill each
//! 4-dimensional use of random numbers evenly instead of by chance. The sequence is the
//! `sobol_burley` crate's, after Burley's "Practical Hash-based Owen Scrambling"; how its points
//! are made two sets at a time is `sobol_table.rs`'s business, how a sample's draws walk
//! through them is this file's.

use std::cell::Cell;
use std::sync::Arc;

use rand::Rng;
use rand_xoshiro::SplitMix64;

use crate::tracer::math::real::Real;
use crate::tracer::sampling::independent::{PerSample, mix};
use crate::tracer::sampling::keys::{EDGE_KEY, SOBOL_KEY};
use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams, SampleRng};
use crate::tracer::sampling::sobol_table::{PairKeys, SobolTable};
use crate::tracer::sampling::warp::uniform;

pub use crate::tracer::sampling::sobol_table::SOBOL_SAMPLES;

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
/// use raypool::tracer::sampling::sampler::{PixelStreams, RandomStreams};
/// use raypool::tracer::sampling::sobol::SobolStreams;
/// use raypool::tracer::sampling::warp::uniform;
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

impl SobolStreams {
    /// The streams of render seed `seed` (`--seed`).
    pub fn new(seed: u64) -> SobolStreams {
        SobolStreams { seed, seed_key: mix(seed ^ SOBOL_KEY), table: Arc::new(SobolTable::new()) }
    }

    /// Point `index` (below [`SOBOL_SAMPLES`]) of the four dimensions every set uses, Owen
    /// scrambled by `scramble`: `sobol_burley::sample_4d(index, 0, scramble)` to 2⁻¹⁶, the
    /// sequence's own resolution, computed faster, with its own offset below (see
    /// `SobolTable`).
    ///
    /// ```
    /// use raypool::tracer::sampling::sobol::SobolStreams;
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
/// (Keeping the first light samples' and aims' keys too gained on `cornell` less than it
/// cost `paper1`, whose pixels take few short samples: `results/history/comment-figures.md`.)
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
        let empty = ([0; 8], NO_PAIR);
        SobolStream {
            pixel: self,
            index_rev,
            slots: [(numbers, 0), empty, empty],
            slot: BOUNCES,
            next: 0,
            end: if index_rev.is_some() { 4 } else { 0 },
            fallback: Fallback { sample, rng: None },
        }
    }
}

/// One pixel sample's numbers from [`SobolStreams`].
#[derive(Clone, Debug)]
pub struct SobolStream<'a> {
    pixel: &'a SobolPixel<'a>,
    /// The sample's index in the sequence, bits reversed; `None` past [`SOBOL_SAMPLES`].
    index_rev: Option<u32>,
    /// The pair of 4-dimensional sets each kind of use last needed, and its number (from the
    /// start, pair 0 in the bounces' slot: the camera's set and that of bounces 0 and 1). A
    /// path that aims at lights switches between its bounce's pair, its light sample's and its
    /// aims through glass at every hit: a slot each, so none recomputes another's.
    slots: [([u32; 8], u32); SLOTS],
    /// The slot the current use reads, its next lane, and the end of its lanes.
    slot: usize,
    next: usize,
    end: usize,
    fallback: Fallback,
}

/// The kinds of use, each with its slot of [`SobolStream::slots`]: bounces (and the camera),
/// light samples, aims through glass.
const SLOTS: usize = 3;
const BOUNCES: usize = 0;
const LIGHTS: usize = 1;
const AIMS: usize = 2;

/// The independent numbers a Sobol stream falls back to, seeded only if it ever needs them
/// (most samples never do).
#[derive(Clone, Debug)]
struct Fallback {
    sample: u64,
    rng: Option<SplitMix64>,
}

impl SobolStream<'_> {
    /// The next numbers are `dimensions` of 4-dimensional set `set`, read from `slot`, whose
    /// pair of sets is computed first if it is not `set`'s. Past the sequence's samples, they
    /// are independent numbers.
    #[inline(always)]
    fn use_dimensions(&mut self, slot: usize, set: u32, dimensions: std::ops::Range<usize>) {
        let Some(index_rev) = self.index_rev else { return };
        if self.slots[slot].1 != set / 2 {
            self.load(index_rev, slot, set / 2);
        }
        let lane = 4 * (set % 2) as usize;
        (self.slot, self.next, self.end) = (slot, lane + dimensions.start, lane + dimensions.end);
    }

    /// Computes the pair of sets `pair` into `slot`. Out of line, so that a use whose pair is
    /// already there (a bounce but for 2, 6, 10, …) pays for a comparison, not for saving the
    /// registers this needs.
    #[inline(never)]
    fn load(&mut self, index_rev: u32, slot: usize, pair: u32) {
        self.slots[slot] = (self.pixel.pair(index_rev, pair), pair);
    }

    fn fallback(&mut self) -> &mut SplitMix64 {
        let ((streams, pixel), sample) = (self.pixel.fallback, self.fallback.sample);
        self.fallback.rng.get_or_insert_with(|| streams.pixel(pixel).stream(sample))
    }
}

/// No pair of sets (a slot before its first use).
const NO_PAIR: u32 = u32::MAX;

/// The first dimension set of the light samples: bounce `b` aims at a light with the four
/// dimensions of set `LIGHT_SETS + b`, far from every bounce's set (`1 + b/2`), so the choice
/// of a light and the point on it are spread evenly over a pixel's samples and correlate with
/// nothing else the path draws. Light samples keep their pair in a slot of their own
/// ([`SobolStream::slots`]), computed every other bounce (about 100 instructions), only in
/// scenes with lights.
const LIGHT_SETS: u32 = 1 << 16;

/// The first dimension set of the light samples through a glass ball: a path's aim `a` takes
/// set `GLASS_LIGHT_SETS + a`, as far from the light samples' sets as those are from the
/// bounces'.
const GLASS_LIGHT_SETS: u32 = 1 << 17;

impl SampleRng for SobolStream<'_> {
    fn bounce(&mut self, bounce: u32) {
        let first = 2 * (bounce % 2) as usize;
        self.use_dimensions(BOUNCES, 1 + bounce / 2, first..first + 2);
    }

    fn light(&mut self, bounce: u32) {
        self.use_dimensions(LIGHTS, LIGHT_SETS + bounce, 0..4);
    }

    fn light_through_glass(&mut self, aim: u32) {
        self.use_dimensions(AIMS, GLASS_LIGHT_SETS + aim, 0..4);
    }

    /// Point `sample × of + k` of a 2-dimensional Owen-scrambled Sobol sequence of the
    /// pixel's own (`sobol_burley`'s two first dimensions, its seed the pixel's keyed apart);
    /// independent numbers past the sequence's 2¹⁶ points.
    fn pixel_point(&mut self, k: u32, of: u32) -> [Real; 2] {
        let index = self.fallback.sample * u64::from(of) + u64::from(k);
        if index >= SOBOL_SAMPLES {
            return [uniform(self.fallback()), uniform(self.fallback())];
        }
        let seed = mix(self.pixel.seed ^ EDGE_KEY) as u32;
        [0, 1].map(|d| sobol_burley::sample(index as u32, d, seed) as Real)
    }
}

impl rand::TryRng for SobolStream<'_> {
    type Error = std::convert::Infallible;

    /// The current use's next Sobol number (23 bits, what an `f32` holds: see `SobolTable`),
    /// or an independent one once they are used up.
    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        if self.next < self.end {
            let v = self.slots[self.slot].0[self.next];
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
