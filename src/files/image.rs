//! The frame buffer: linear RGB pixels assembled from rendered tiles, and its 8-bit form.

use crate::tracer::real::{Vec3, to_f64};
use crate::tracer::render::TileOutput;

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
        let mut pixels = vec![Vec3::ZERO; width as usize * height as usize];
        let mut written = vec![false; pixels.len()];
        for out in tiles {
            let t = out.tile;
            if t.x + t.width > width || t.y + t.height > height || out.pixels.len() != t.area() {
                return Err(format!("tile {t:?} does not fit the {width}x{height} image"));
            }
            for (row, chunk) in out.pixels.chunks_exact(t.width as usize).enumerate() {
                let start = (t.y as usize + row) * width as usize + t.x as usize;
                pixels[start..start + chunk.len()].copy_from_slice(chunk);
                if let Some(k) = written[start..start + chunk.len()].iter().position(|&w| w) {
                    return Err(format!(
                        "pixel ({}, {}) rendered twice",
                        t.x as usize + k,
                        t.y as usize + row
                    ));
                }
                written[start..start + chunk.len()].fill(true);
            }
        }
        match written.iter().position(|&w| !w) {
            Some(k) => Err(format!("pixel ({}, {}) never rendered", k % width as usize, k / width as usize)),
            None => Ok(Image { width, height, pixels }),
        }
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
