//! Making Sobol points fast: `sobol_burley::sample_4d`'s points, to its top 16 bits, two
//! 4-dimensional sets at a time in the eight 16-bit lanes of one SSE2 register. The streams
//! that hand these points to a sample are in [`super::sobol`].

use sobol_burley::parts;
use wide::u16x8;

/// The most samples per pixel the Sobol sequence holds; later samples draw independent numbers.
pub const SOBOL_SAMPLES: u64 = 1 << 16;

/// The scramble keys of two dimension sets: each set's index shuffle, and per dimension the
/// Owen hash's two keys and the key of the offset within a cell, in eight lanes (the first
/// set's four dimensions, then the second's). They derive from `sobol_burley::sample_4d`'s own
/// keys for each set's seed, made as it makes them; of the hash's keys only the low 16 bits
/// are kept, all that reaches a point's top 16 bits (see `SobolTable`).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PairKeys {
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
    pub(super) fn new(seeds: [u32; 2]) -> PairKeys {
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
pub(super) struct SobolTable {
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
    pub(super) fn new() -> SobolTable {
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
    pub(super) fn pair(&self, index_rev: u32, keys: &PairKeys) -> [u32; 8] {
        Self::scramble(keys.shuffle.map(|shuffle| self.shuffled_row(index_rev, shuffle)), keys)
    }

    /// The first pair of sample `sample` (below [`SOBOL_SAMPLES`]): as [`Self::pair`], but the
    /// first set, the camera's, takes the sample's own index, unshuffled (see
    /// [`SobolStreams`]); with the index bit-reversed, which later pairs need.
    #[inline]
    pub(super) fn first_pair(&self, sample: u32, keys: &PairKeys) -> ([u32; 8], u32) {
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
