//! Independent numbers: each pixel sample its own SplitMix64 stream, started at a hash of
//! `(render seed, pixel, sample)`. The sampler every other is measured against, and the one
//! the Sobol streams fall back to past their dimensions.

use rand::SeedableRng;
use rand_xoshiro::SplitMix64;

use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams};

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

/// SplitMix64's finaliser: a bijection on u64 with full avalanche.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
