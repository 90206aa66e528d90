//! The keys that set random streams apart, in one place so that no two can meet. A key is
//! XORed onto a seed (the render seed, a pixel's, a path's or a ray's) to make the seed of
//! another stream; where the code also XORs an index on (an edge ray's point, a connection's
//! vertex counts, a manifold sample's piece), the test below checks the keys with those
//! indices too, and every value with the medium ids XORed on as a ray's media draw them. The
//! values are those the images were made with: changing one changes images.

/// Render seed → each pixel's Sobol scramble seed (`sobol.rs`).
pub const SOBOL_KEY: u64 = 0x536F_626F_6C00_0000;

/// A pixel's Sobol seed → the 2-D sequence of its edge points (`sobol.rs`, `lighting/edges.rs`).
pub const EDGE_KEY: u64 = 0xED6E_0000_0000_0001;

/// Render seed → the seed of a path's media numbers, so they are no pixel stream's
/// (`render.rs`).
pub const MEDIA_KEY: u64 = 0x6D65_6469_6100_0000;

/// Render seed → the light paths' streams of `--light-sampling bdpt` (`render.rs`).
pub const LIGHT_PATHS_KEY: u64 = 0x6C69_6768_7473_0000;

/// A ray's media seed → its shadow ray's (`render/path.rs`).
pub const SHADOW_KEY: u64 = 0x5ad0_0000_0000_0001;

/// A ray's media seed → its glint ray's, the mirror ray glass casts (`lighting/mod.rs`).
pub const GLINT_KEY: u64 = 0x6711_0000_0000_0001;

/// A shadow ray's media seed → piece `k` (1 to 3) of a manifold sample, XORed on as `k ×`
/// this key (`lighting/manifold.rs`). It was [`MEDIUM_KEY`] until the test below covered media
/// ids: piece `k` in medium `m` then drew what piece `m` drew in medium `k`.
pub const PIECE_KEY: u64 = 0x7069_6563_6500_0001;

/// A ray's media seed → the number medium `id` draws, XORed on as `id ×` this key
/// ([`Probe::uniform`]).
///
/// [`Probe::uniform`]: crate::tracer::world::object::Probe::uniform
pub const MEDIUM_KEY: u64 = 0x9E37_79B9_7F4A_7C15;

/// A path's media seed → its edge ray `spot`'s, XORed on with the spot's number
/// (`lighting/edges.rs`).
pub const EDGE_RAY_KEY: u64 = 0xED6E_5000_0000_0001;

/// A camera path's media seed → its light path's (`bidir/connect.rs`).
pub const LIGHT_KEY: u64 = 0x6c69_6768_7400_0000;

/// A path's media seed → the shadow ray joining vertex `s` of the light path to vertex `t`
/// of the camera path, XORed on with `s << 32 | t` (`bidir/connect.rs`).
pub const CONNECT_KEY: u64 = 0x636f_6e6e_0000_0000;

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;

    /// Media ids the test gives each stream: a scene's first 64 media.
    const MEDIA: u64 = 64;

    #[test]
    fn no_two_streams_share_a_seed() {
        // Every value the code XORs onto a seed, by the key it comes from; 0 stands for the
        // seed itself (a path's own rays).
        let spots = (0..1u64 << 16).map(|spot| EDGE_RAY_KEY ^ spot);
        let vertices = (0..64u64).flat_map(|s| (0..64u64).map(move |t| CONNECT_KEY ^ (s << 32 | t)));
        let pieces = (1..=3u64).map(|k| SHADOW_KEY ^ k.wrapping_mul(PIECE_KEY));
        let derived: [(&str, Vec<u64>); 11] = [
            ("the seed itself", vec![0]),
            ("SOBOL_KEY", vec![SOBOL_KEY]),
            ("EDGE_KEY", vec![EDGE_KEY]),
            ("MEDIA_KEY", vec![MEDIA_KEY]),
            ("LIGHT_PATHS_KEY", vec![LIGHT_PATHS_KEY]),
            ("SHADOW_KEY", vec![SHADOW_KEY]),
            ("GLINT_KEY", vec![GLINT_KEY]),
            ("PIECE_KEY", pieces.collect()),
            ("EDGE_RAY_KEY", spots.collect()),
            ("LIGHT_KEY", vec![LIGHT_KEY]),
            ("CONNECT_KEY", vertices.collect()),
        ];
        let mut seen = HashMap::new();
        for (name, values) in &derived {
            for &value in values {
                if let Some(other) = seen.insert(value, *name) {
                    assert_eq!(other, *name, "{other} and {name} both make {value:#x}");
                }
            }
        }
        // What medium `m` draws on each stream: no two (stream, medium) pairs may meet, within
        // one key's family too (piece 1 in medium 2 against piece 2 in medium 1).
        let mut drawn: Vec<(u64, &str, usize, u64)> = derived
            .iter()
            .flat_map(|(name, values)| values.iter().enumerate().map(move |(k, &value)| (value, *name, k)))
            .flat_map(|(value, name, k)| {
                (0..MEDIA).map(move |m| (value ^ m.wrapping_mul(MEDIUM_KEY), name, k, m))
            })
            .collect();
        drawn.sort_unstable();
        for pair in drawn.windows(2) {
            let [(value, name, k, m), (other, name2, k2, m2)] = [pair[0], pair[1]];
            assert_ne!(
                value, other,
                "{name}[{k}] in medium {m} and {name2}[{k2}] in medium {m2} draw the same"
            );
        }
    }
}
