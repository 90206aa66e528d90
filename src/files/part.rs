//! Part files (`.rpart`): one shard of an image, rendered by one process, waiting to be merged
//! with the others (`raypool render --shard K/N --out part-K.rpart`, then `raypool merge`).
//!
//! A part says what it is a part *of* (the scene's digest and every setting that changes a
//! pixel), which shard it is, and holds its tiles' linear pixels exactly as rendered, so the
//! merged image is the one-process image byte for byte. Reading a part checks everything a
//! copy between machines can break: a truncated or corrupt file, a foreign file, a part of a
//! newer format, or one rendered with the other precision; [`merge`] then checks that the parts
//! belong together and cover every tile once. Every failure is one line naming the file.
//!
//! A part also holds the light its light paths carried to any pixel of the image
//! (`--light-sampling bdpt`'s splats), in fixed point: the merge sums every part's and adds it
//! once, as the one-process render does, so the bits agree.
//!
//! The format, version 2 (all integers little-endian):
//!
//! ```text
//! raypool-part 2\n                       magic and version
//! <H>\n                                  the header's length in bytes, decimal
//! <H bytes of TOML>                      PartHeader: scene digest, settings, shard, totals,
//!                                        data length and SHA-256
//! per tile, in the shard's order:
//!   x, y, width, height                  4 × u32
//!   width × height × (r, g, b)           f64 each, row-major, linear light
//! per pixel that received splats, in pixel order:
//!   pixel, r, g, b                       u32 (row-major index), 3 × u64 (fixed point)
//! ```
//!
//! Values are stored as f64 whatever the build, which holds an f32 exactly.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::Error;
use crate::files::image::Image;
use crate::tracer::math::real::{Real, Vec3, to_f64};
use crate::tracer::render::{RenderSettings, TileOutput};
use crate::tracer::splats::Splats;
use crate::tracer::tile::{Shard, Tile};

/// The first line of every part file.
const MAGIC: &str = "raypool-part";
/// The format version this code writes and reads.
const VERSION: u32 = 2;
/// A header longer than this is not a part's.
const MAX_HEADER_BYTES: usize = 1 << 20;
/// Bytes per tile record before its pixels.
const TILE_RECORD_BYTES: usize = 16;
/// Tiles with their pixels, as a part holds them.
type TilePixels = Vec<(Tile, Vec<Vec3>)>;

/// Bytes per splat record: a pixel index and three fixed-point sums.
const SPLAT_RECORD_BYTES: usize = 28;

/// Everything that decides a pixel's value, which every part of one image must share.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartSettings {
    /// The program that rendered it (a different version may render differently).
    pub renderer: String,
    /// `f32` or `f64`: the renderer's precision.
    pub real: String,
    /// SHA-256 of the scene's TOML (see [`scene_digest`]).
    pub scene_digest: String,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Samples per pixel (the most, with adaptive sampling).
    pub spp: u32,
    /// Maximum rays per path.
    pub depth: u32,
    /// Seed of the pixel samples' random streams.
    pub seed: u64,
    /// Russian roulette.
    pub roulette: bool,
    /// Paths with black throughput stopped early.
    pub stop_black_paths: bool,
    /// `independent` or `sobol`.
    pub sampler: String,
    /// `bsdf`, `mixture`, `mis` or `bdpt`.
    pub light_sampling: String,
    /// Edge points per sample where a pixel may see a light.
    pub edge_spots: u32,
    /// Adaptive sampling's target error, if on.
    pub target_error: Option<f64>,
    /// Adaptive sampling's samples per pass, if on.
    pub min_spp: Option<u32>,
    /// Tile side: the grid that shards are dealt from.
    pub tile: u32,
    /// How many shards the image is cut into.
    pub shards: u32,
}

impl PartSettings {
    /// The settings of a render of a scene with digest `scene_digest`, cut into `shards`
    /// shards of `tile`-sized tiles.
    pub fn new(scene_digest: String, settings: &RenderSettings, tile: u32, shards: u32) -> PartSettings {
        PartSettings {
            renderer: concat!("raypool ", env!("CARGO_PKG_VERSION")).to_string(),
            real: real_name().to_string(),
            scene_digest,
            width: settings.width,
            height: settings.height,
            spp: settings.spp,
            depth: settings.max_depth,
            seed: settings.seed,
            roulette: settings.roulette,
            stop_black_paths: settings.stop_black_paths,
            sampler: settings.sampler.name().to_string(),
            light_sampling: settings.light_sampling.name().to_string(),
            edge_spots: settings.edge_spots,
            target_error: settings.adaptive.map(|a| to_f64(a.target_error)),
            min_spp: settings.adaptive.map(|a| a.min_spp),
            tile,
            shards,
        }
    }

    /// The first setting in which `self` and `other` differ, as "name a vs b".
    fn first_difference(&self, other: &PartSettings) -> Option<String> {
        let (a, b) = (toml::Table::try_from(self).ok()?, toml::Table::try_from(other).ok()?);
        let names = a.keys().chain(b.keys().filter(|k| !a.contains_key(*k)));
        names.into_iter().find_map(|name| {
            let (x, y) = (a.get(name), b.get(name));
            let show = |v: Option<&toml::Value>| v.map_or("none".to_string(), toml::Value::to_string);
            (x != y).then(|| format!("{name} {} vs {}", show(x), show(y)))
        })
    }
}

/// A part file's header: what it is part of, which part, and what it cost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartHeader {
    /// Which shard: `0..settings.shards`.
    pub shard: u32,
    /// Number of tiles in the data.
    pub tiles: u32,
    /// Number of pixels with splats in the data, after the tiles.
    pub splat_pixels: u64,
    /// Rays cast rendering it.
    pub rays: u64,
    /// Camera samples taken rendering it.
    pub samples: u64,
    /// Seconds the render took.
    pub seconds: f64,
    /// The machine that rendered it (for the merge's summary).
    pub host: String,
    /// Length of the data after the header, bytes.
    pub data_bytes: u64,
    /// SHA-256 of the data, hex.
    pub data_sha256: String,
    /// What the part belongs to.
    pub settings: PartSettings,
}

/// One shard of an image: its header and its tiles' pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The header.
    pub header: PartHeader,
    /// The shard's tiles and their pixels (row-major, linear RGB), in grid order.
    pub tiles: Vec<(Tile, Vec<Vec3>)>,
    /// The light the shard's light paths splatted, anywhere in the image.
    pub splats: Splats,
}

/// SHA-256 of `text` (a scene's TOML), hex: what tells two parts' scenes apart.
pub fn scene_digest(text: &str) -> String {
    hex(&Sha256::digest(text.as_bytes()))
}

/// This build's precision: `f32`, or `f64` with the `f64` feature.
fn real_name() -> &'static str {
    if size_of::<Real>() == 4 { "f32" } else { "f64" }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl Part {
    /// The part of shard `shard` cut from `image` (a render of that shard, other pixels
    /// black): the pixels of `tiles`, which are the shard's tiles in grid order, and the
    /// shard's `splats` (see [`Rendered::splats`](crate::schedule::modes::Rendered::splats)).
    pub fn new(settings: PartSettings, shard: Shard, tiles: &[Tile], image: &Image, splats: Splats) -> Part {
        let header = PartHeader {
            shard: shard.index,
            tiles: tiles.len() as u32,
            splat_pixels: 0,
            rays: 0,
            samples: 0,
            seconds: 0.0,
            host: String::new(),
            data_bytes: 0,
            data_sha256: String::new(),
            settings,
        };
        Part { header, tiles: tiles.iter().map(|&t| (t, image.crop(t))).collect(), splats }
    }

    /// The part as bytes: magic line, header length, header, data (see the module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut bytes = Vec::new();
        self.write_to(&mut bytes).expect("writing to a Vec cannot fail");
        bytes
    }

    /// Writes the part to `out` without holding its data in memory: one pass over the tiles
    /// hashes the data (the header, which comes first, holds its length and SHA-256), a
    /// second writes it. (A 4-Mpixel shard's data is 100 MB as f64; buffered, it and its copy
    /// were 48 of the 82 bytes per pixel a part render peaked at.)
    pub fn write_to(&self, out: &mut impl std::io::Write) -> std::io::Result<()> {
        let mut hash = Sha256::new();
        let mut data_bytes = 0;
        self.each_record(|record| {
            hash.update(record);
            data_bytes += record.len() as u64;
            Ok(())
        })?;
        let mut header = self.header.clone();
        header.tiles = self.tiles.len() as u32;
        header.splat_pixels = self.splats.len() as u64;
        header.data_bytes = data_bytes;
        header.data_sha256 = hex(&hash.finalize());
        let text = toml::to_string(&header).expect("a part header is plain TOML");
        write!(out, "{MAGIC} {VERSION}\n{}\n{text}", text.len())?;
        self.each_record(|record| out.write_all(record))
    }

    /// Calls `each` with every tile's record (its rectangle, then its pixels as f64), in order,
    /// then with every splat's (its pixel, then its sums).
    fn each_record(&self, mut each: impl FnMut(&[u8]) -> std::io::Result<()>) -> std::io::Result<()> {
        let mut record = Vec::new();
        for (tile, pixels) in &self.tiles {
            record.clear();
            for n in [tile.x, tile.y, tile.width, tile.height] {
                record.extend_from_slice(&n.to_le_bytes());
            }
            for value in pixels.iter().flat_map(|p| p.to_array()) {
                record.extend_from_slice(&to_f64(value).to_le_bytes());
            }
            each(&record)?;
        }
        for (pixel, counts) in self.splats.counts() {
            record.clear();
            record.extend_from_slice(&pixel.to_le_bytes());
            counts.iter().for_each(|c| record.extend_from_slice(&c.to_le_bytes()));
            each(&record)?;
        }
        Ok(())
    }

    /// Reads a part from its bytes; the error says what is wrong (the caller names the file).
    pub fn from_bytes(bytes: &[u8]) -> Result<Part, String> {
        let (magic, rest) = split_line(bytes).ok_or("not a raypool part file (no first line)")?;
        let version = magic
            .strip_prefix(MAGIC.as_bytes())
            .and_then(|v| std::str::from_utf8(v).ok())
            .and_then(|v| v.trim().parse::<u32>().ok())
            .ok_or("not a raypool part file")?;
        if version != VERSION {
            return Err(format!("part format version {version}; this raypool reads version {VERSION}"));
        }
        let (length, rest) = split_line(rest).ok_or("truncated header")?;
        let length = std::str::from_utf8(length)
            .ok()
            .and_then(|l| l.parse::<usize>().ok())
            .filter(|&l| l <= MAX_HEADER_BYTES)
            .ok_or("bad header length")?;
        let text = rest.get(..length).ok_or("truncated header")?;
        let text = std::str::from_utf8(text).map_err(|_| "header is not UTF-8")?;
        let header: PartHeader = toml::from_str(text)
            .map_err(|e| format!("bad header: {}", e.message().lines().next().unwrap_or("not valid TOML")))?;
        let data = &rest[length..];
        if (data.len() as u64) < header.data_bytes {
            return Err(format!("truncated: {} of its {} data bytes", data.len(), header.data_bytes));
        }
        if data.len() as u64 > header.data_bytes {
            return Err(format!("{} bytes past its data", data.len() as u64 - header.data_bytes));
        }
        if hex(&Sha256::digest(data)) != header.data_sha256 {
            return Err("corrupt: its data does not match the header's SHA-256".into());
        }
        if header.settings.real != real_name() {
            return Err(format!(
                "rendered in {}; this raypool renders in {}",
                header.settings.real,
                real_name()
            ));
        }
        let (tiles, rest) = read_tiles(data, &header)?;
        let splats = read_splats(rest, &header)?;
        Ok(Part { header, tiles, splats })
    }
}

/// `(line without its '\n', the rest)`.
fn split_line(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let end = bytes.iter().take(MAX_HEADER_BYTES).position(|&b| b == b'\n')?;
    Some((&bytes[..end], &bytes[end + 1..]))
}

/// The header's number of tile records at the start of `data`, checked against the image's
/// size, and the bytes after them.
fn read_tiles<'a>(data: &'a [u8], header: &PartHeader) -> Result<(TilePixels, &'a [u8]), String> {
    let (width, height) = (header.settings.width, header.settings.height);
    let mut tiles = Vec::new();
    let mut at = data;
    while tiles.len() < header.tiles as usize {
        let record = at
            .get(..TILE_RECORD_BYTES)
            .ok_or_else(|| format!("holds {} tiles; its header says {}", tiles.len(), header.tiles))?;
        let tile = Tile {
            x: u32_at(record, 0),
            y: u32_at(record, 4),
            width: u32_at(record, 8),
            height: u32_at(record, 12),
        };
        let fits = tile.x as u64 + tile.width as u64 <= width as u64
            && tile.y as u64 + tile.height as u64 <= height as u64;
        if !fits {
            return Err(format!("tile {tile:?} does not fit the {width}x{height} image"));
        }
        let values =
            at.get(TILE_RECORD_BYTES..TILE_RECORD_BYTES + tile.area() * 24).ok_or("a tile is cut short")?;
        let pixels = values
            .chunks_exact(24)
            .map(|p| {
                let c = |k: usize| f64::from_bits(u64_at(p, k)) as Real;
                Vec3::new(c(0), c(8), c(16))
            })
            .collect();
        tiles.push((tile, pixels));
        at = &at[TILE_RECORD_BYTES + tile.area() * 24..];
    }
    Ok((tiles, at))
}

/// The splat records that end the data: the header's number of them, each a pixel of the
/// image, in increasing pixel order (so each pixel once).
fn read_splats(data: &[u8], header: &PartHeader) -> Result<Splats, String> {
    let expected = header.splat_pixels.saturating_mul(SPLAT_RECORD_BYTES as u64);
    if data.len() as u64 != expected {
        return Err(format!(
            "{} bytes after its tiles; its header says {} splat records ({expected} bytes)",
            data.len(),
            header.splat_pixels
        ));
    }
    let pixels = u64::from(header.settings.width) * u64::from(header.settings.height);
    let mut splats = Splats::default();
    let mut last = None;
    for record in data.chunks_exact(SPLAT_RECORD_BYTES) {
        let pixel = u32_at(record, 0);
        if u64::from(pixel) >= pixels || last.is_some_and(|l| pixel <= l) {
            return Err(format!("splat pixel {pixel} is outside the image or out of order"));
        }
        splats.add_counts(pixel, [u64_at(record, 4), u64_at(record, 12), u64_at(record, 20)]);
        last = Some(pixel);
    }
    Ok(splats)
}

/// The little-endian `u32` at `bytes[k..k + 4]`.
fn u32_at(bytes: &[u8], k: usize) -> u32 {
    u32::from_le_bytes(bytes[k..k + 4].try_into().expect("4 bytes"))
}

/// The little-endian `u64` at `bytes[k..k + 8]`.
fn u64_at(bytes: &[u8], k: usize) -> u64 {
    u64::from_le_bytes(bytes[k..k + 8].try_into().expect("8 bytes"))
}

/// Checks that `parts` (each with the name of its file) are the whole of one image and
/// assembles it: the same scene and settings, shards `0..N` each exactly once, each holding
/// exactly its shard's tiles of the grid. An error names the offending file.
pub fn merge(parts: &[(String, Part)]) -> Result<Image, Error> {
    let (first_name, first) = parts.first().ok_or_else(|| Error::new("no part files given"))?;
    let settings = &first.header.settings;
    let count = settings.shards;
    let mut owner: Vec<Option<&str>> = vec![None; count as usize];
    for (name, part) in parts {
        if let Some(difference) = part.header.settings.first_difference(settings) {
            return Err(Error::new(format!(
                "{name}: not a part of the same image as {first_name} ({difference})"
            )));
        }
        let k = part.header.shard;
        let slot = owner
            .get_mut(k as usize)
            .ok_or_else(|| Error::new(format!("{name}: shard {k} of {count} does not exist")))?;
        if let Some(other) = slot {
            return Err(Error::new(format!("{name}: shard {k} of {count} again (also in {other})")));
        }
        *slot = Some(name);
    }
    if let Some(k) = owner.iter().position(Option::is_none) {
        return Err(Error::new(format!("shard {k} of {count} is missing (no part file holds it)")));
    }
    let grid = Tile::grid(settings.width, settings.height, settings.tile);
    let mut outputs = Vec::with_capacity(grid.len());
    let mut splats = Splats::default();
    for (name, part) in parts {
        let shard = Shard { index: part.header.shard, count };
        let held: Vec<Tile> = part.tiles.iter().map(|(t, _)| *t).collect();
        if held != shard.tiles(&grid) {
            return Err(Error::new(format!("{name}: its tiles are not shard {shard}'s")));
        }
        outputs.extend(part.tiles.iter().map(|(tile, pixels)| TileOutput {
            tile: *tile,
            pixels: pixels.clone(),
            rays: 0,
            samples: 0,
            splats: Default::default(),
            timing: None,
        }));
        splats.merge(&part.splats);
    }
    let mut image = Image::from_tiles(settings.width, settings.height, &outputs).map_err(Error::new)?;
    image.add_splats(&splats, settings.spp);
    Ok(image)
}
