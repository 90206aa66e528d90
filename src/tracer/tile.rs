//! Tiles and shards: how an image is cut into rectangles of pixels, and how those are dealt
//! out to separate processes.
//!
//! A [`Tile`] is any rectangle of pixels; [`Tile::grid`] cuts an image into square tiles in
//! row-major order, the order every scheduler and every shard counts them in. A [`Shard`]
//! `K/N` is the grid tiles whose index is `K mod N`: dealt round-robin, so each shard gets
//! its share of sky and of ground and the shards take about equally long. A pixel's value does
//! not depend on which tile or shard it is rendered in, so the shards of an image, rendered by
//! `N` processes on any machines, merge into the image one process renders, byte for byte.
//! [`PixelSums`] are a tile's running sums, which the render loop adds its samples to.

use std::fmt;
use std::str::FromStr;

use glam::DVec3;

use crate::tracer::math::real::{Vec3, from_dvec3};
use crate::tracer::splats::Splats;

/// A rectangle of pixels: columns `x..x + width`, rows `y..y + height` (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tile {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Tile {
    /// The tile of whole rows `rows.start..rows.end` of an image `width` wide.
    pub fn rows(width: u32, rows: std::ops::Range<u32>) -> Tile {
        Tile { x: 0, y: rows.start, width, height: rows.end - rows.start }
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Square tiles of side `size` covering a `width × height` image (smaller at the right
    /// and bottom edges), in row-major order: left to right, then top to bottom.
    ///
    /// ```
    /// use raypool::tracer::tile::Tile;
    /// let grid = Tile::grid(40, 20, 16);
    /// assert_eq!(grid.len(), 3 * 2);
    /// assert_eq!(grid[2], Tile { x: 32, y: 0, width: 8, height: 16 });
    /// assert_eq!(grid.iter().map(Tile::area).sum::<usize>(), 40 * 20);
    /// ```
    pub fn grid(width: u32, height: u32, size: u32) -> Vec<Tile> {
        let s = size.max(1);
        (0..height.div_ceil(s))
            .flat_map(|ty| (0..width.div_ceil(s)).map(move |tx| (tx, ty)))
            .map(|(tx, ty)| Tile {
                x: tx * s,
                y: ty * s,
                width: s.min(width - tx * s),
                height: s.min(height - ty * s),
            })
            .collect()
    }
}

/// Shard `index` of `count`: the grid tiles whose row-major index is `index` mod `count`.
///
/// ```
/// use raypool::tracer::tile::{Shard, Tile};
/// let shard: Shard = "1/3".parse().unwrap();
/// let grid = Tile::grid(64, 32, 16); // 4 × 2 tiles
/// assert_eq!(shard.tiles(&grid), vec![grid[1], grid[4], grid[7]]);
/// assert_eq!(Shard::WHOLE.tiles(&grid), grid);
/// assert!("3/3".parse::<Shard>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Shard {
    /// Which shard, `0..count`.
    pub index: u32,
    /// How many shards the image is cut into.
    pub count: u32,
}

/// The most shards an image may be cut into.
pub const MAX_SHARDS: u32 = 65_536;

impl Shard {
    /// The whole image: shard 0 of 1.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Whether grid tile number `tile_index` belongs to this shard.
    pub fn takes(&self, tile_index: usize) -> bool {
        tile_index % self.count as usize == self.index as usize
    }

    /// The tiles of `grid` that belong to this shard, in grid order.
    pub fn tiles(&self, grid: &[Tile]) -> Vec<Tile> {
        grid.iter().enumerate().filter(|&(k, _)| self.takes(k)).map(|(_, &t)| t).collect()
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// Parses `K/N`: `0 ≤ K < N ≤ 65536`.
    fn from_str(text: &str) -> Result<Shard, String> {
        let (k, n) = text.split_once('/').ok_or("expected K/N, e.g. 2/7")?;
        let number = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{s}' is not a whole number"));
        let (index, count) = (number(k)?, number(n)?);
        if count == 0 || count > MAX_SHARDS {
            return Err(format!("N must be 1 to {MAX_SHARDS}"));
        }
        if index >= count {
            return Err(format!("K must be below N (shards are numbered 0 to {})", count - 1));
        }
        Ok(Shard { index, count })
    }
}

/// The running sums of a tile's pixels: each pixel's sample sum (f64) and sample count.
///
/// The sum is f64, as pbrt's film: in f32 a sum of 2^20 samples near 0.4 is near 4·10⁵, where
/// f32's spacing is 0.03, and every sample added is rounded to it (the error that leaves, measured:
/// `results/accumulation.md`). Samples are always added in sample
/// order, so a pixel's mean after `n` samples is the same bits however many passes added them.
///
/// Odd-numbered samples are also summed apart: the pixel's two half-estimates (even and odd
/// samples) are independent, and their difference is what adaptive sampling judges it by.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelSums {
    sums: Vec<DVec3>,
    odd: Vec<DVec3>,
    counts: Vec<u32>,
    /// What the samples' light paths splatted into any pixel of the image.
    pub splats: Splats,
}

impl PixelSums {
    /// `pixels` pixels with no samples yet.
    pub fn new(pixels: usize) -> PixelSums {
        let zeros = vec![DVec3::ZERO; pixels];
        PixelSums { sums: zeros.clone(), odd: zeros, counts: vec![0; pixels], splats: Splats::default() }
    }

    /// Each pixel's mean (black before its first sample).
    pub fn means(&self) -> Vec<Vec3> {
        self.sums.iter().zip(&self.counts).map(|(&s, &n)| from_dvec3(s / f64::from(n.max(1)))).collect()
    }

    /// Samples taken, all pixels together.
    pub fn samples(&self) -> u64 {
        self.counts.iter().map(|&n| u64::from(n)).sum()
    }

    /// How many pixels it sums.
    pub fn len(&self) -> usize {
        self.counts.len()
    }

    /// Whether it sums no pixel.
    pub fn is_empty(&self) -> bool {
        self.counts.is_empty()
    }

    /// Adds sample number `sample`'s `value` to pixel `k`.
    #[inline]
    pub fn add(&mut self, k: usize, sample: u32, value: DVec3) {
        self.sums[k] += value;
        if sample % 2 == 1 {
            self.odd[k] += value;
        }
        self.counts[k] += 1;
    }

    /// Pixel `k`'s (sum of all samples, sum of its odd-numbered samples, sample count).
    pub fn pixel(&self, k: usize) -> (DVec3, DVec3, u32) {
        (self.sums[k], self.odd[k], self.counts[k])
    }
}
