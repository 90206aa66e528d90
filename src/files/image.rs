//! The frame buffer: linear RGB pixels assembled from rendered tiles, and its 8-bit form.

use crate::tracer::math::real::{Vec3, from_dvec3, to_dvec3, to_f64};
use crate::tracer::render::TileOutput;
use crate::tracer::splats::Splats;
use crate::tracer::tile::Tile;

/// A linear-light RGB image, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// `width × height` pixels.
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// Assembles tiles into an image; an error names a pixel that the tiles leave out or
    /// cover twice (a scheduler bug, never bad input).
    pub fn from_tiles(width: u32, height: u32, tiles: &[TileOutput]) -> Result<Image, String> {
        Image::from_tiles_within(width, height, &[Tile::rows(width, 0..height)], tiles)
    }

    /// Assembles tiles that cover exactly the pixels of `region` (a shard's tiles, say) once
    /// each; the pixels outside `region` stay black. An error names the first pixel left out,
    /// covered twice, or outside `region`.
    pub fn from_tiles_within(
        width: u32,
        height: u32,
        region: &[Tile],
        tiles: &[TileOutput],
    ) -> Result<Image, String> {
        let mut wanted = vec![false; width as usize * height as usize];
        for &t in region {
            check_fits(t, width, height)?;
            for (start, len) in spans(t, width) {
                wanted[start..start + len].fill(true);
            }
        }
        let mut pixels = vec![Vec3::ZERO; wanted.len()];
        let mut written = vec![false; wanted.len()];
        let at = |k: usize| (k % width as usize, k / width as usize);
        for out in tiles {
            let t = out.tile;
            check_fits(t, width, height)?;
            if out.pixels.len() != t.area() {
                return Err(format!("tile {t:?} holds {} pixels, not {}", out.pixels.len(), t.area()));
            }
            for ((start, len), chunk) in spans(t, width).zip(out.pixels.chunks_exact(t.width as usize)) {
                if let Some(k) = (start..start + len).find(|&k| written[k] || !wanted[k]) {
                    let (x, y) = at(k);
                    let why = if written[k] { "rendered twice" } else { "outside the frame's tiles" };
                    return Err(format!("pixel ({x}, {y}) {why}"));
                }
                pixels[start..start + len].copy_from_slice(chunk);
                written[start..start + len].fill(true);
            }
        }
        match (0..wanted.len()).find(|&k| wanted[k] && !written[k]) {
            Some(k) => Err(format!("pixel ({}, {}) never rendered", at(k).0, at(k).1)),
            None => Ok(Image { width, height, pixels }),
        }
    }

    /// Adds the light that light paths splatted (`--light-sampling bdpt`), `paths` of them per
    /// pixel, each pixel's sum in f64 and rounded once: the one way a render, a merge of parts
    /// and the viewer add it, so all three give the same bits.
    ///
    /// ```
    /// use raypool::files::image::Image;
    /// use raypool::tracer::math::real::Vec3;
    /// use raypool::tracer::splats::Splats;
    /// let mut image = Image { width: 2, height: 1, pixels: vec![Vec3::ONE; 2] };
    /// let mut splats = Splats::default();
    /// splats.add(1, Vec3::splat(2.0));
    /// image.add_splats(&splats, 4);
    /// assert_eq!(image.pixels, [Vec3::ONE, Vec3::splat(1.5)]);
    /// ```
    pub fn add_splats(&mut self, splats: &Splats, paths: u32) {
        for (k, light) in splats.per_pixel(paths) {
            self.pixels[k] = from_dvec3(to_dvec3(self.pixels[k]) + light);
        }
    }

    /// The pixels of `tile`, row-major.
    ///
    /// # Panics
    /// If `tile` does not fit the image.
    pub fn crop(&self, tile: Tile) -> Vec<Vec3> {
        spans(tile, self.width)
            .flat_map(|(start, len)| self.pixels[start..start + len].iter().copied())
            .collect()
    }

    /// The mean over pixels and channels, summed in f64: the one number by which bias checks
    /// compare whole images.
    ///
    /// ```
    /// use raypool::files::image::Image;
    /// use raypool::tracer::math::real::Vec3;
    /// let image = Image { width: 2, height: 1, pixels: vec![Vec3::new(0.0, 0.0, 3.0), Vec3::ONE] };
    /// assert_eq!(image.mean(), 1.0);
    /// ```
    pub fn mean(&self) -> f64 {
        let sum: f64 = self.pixels.iter().map(|p| to_f64(p.x + p.y + p.z) / 3.0).sum();
        sum / self.pixels.len() as f64
    }

    /// 8-bit sRGB-ish bytes (`RGBRGB…`): the book's gamma 2 (`sqrt`), clamped to [0, 1).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .map(|linear| (256.0 * to_f64(linear.max(0.0)).sqrt().min(0.999)) as u8)
            .collect()
    }
}

/// Whether `t` lies inside a `width × height` image.
fn check_fits(t: Tile, width: u32, height: u32) -> Result<(), String> {
    let fits = t.x as u64 + t.width as u64 <= width as u64 && t.y as u64 + t.height as u64 <= height as u64;
    if fits { Ok(()) } else { Err(format!("tile {t:?} does not fit the {width}x{height} image")) }
}

/// Each row of `t` as (index of its first pixel, length) in a row-major image `width` wide.
fn spans(t: Tile, width: u32) -> impl Iterator<Item = (usize, usize)> {
    (t.y..t.y + t.height).map(move |y| (y as usize * width as usize + t.x as usize, t.width as usize))
}
