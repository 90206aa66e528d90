//! Textures: a colour that varies over a surface. Solid, the second book's spatial checker, its
//! marble of Perlin turbulence, and images looked up at the hit's `(u, v)`. Kept in the
//! scene's [`Textures`] table, so a material names one by index and stays small and `Copy`.

use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::shading::perlin::Perlin;

/// One texture of a scene's table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texture {
    /// The same colour everywhere.
    Solid {
        /// Linear RGB.
        color: Vec3,
    },
    /// The book's 3-D checker: cells of side `scale`, alternately `even` and `odd`.
    Checker {
        /// `1 / cell side`.
        inv_scale: Real,
        /// Colour of cells whose integer coordinates sum to an even number.
        even: Vec3,
        /// The other cells' colour.
        odd: Vec3,
    },
    /// The book's marble: `½(1 + sin(scale·z + 10·turbulence(p)))` grey.
    Marble {
        /// Stripes per unit length, ×2π.
        scale: Real,
    },
    /// An image, indexed in the table's images.
    Image {
        /// Which image.
        image: u32,
    },
}

/// An image for textures: linear RGB pixels, row 0 at the top (`v = 1`).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// `width × height` linear RGB values, row-major.
    pub pixels: Vec<Vec3>,
}

impl ImageTexture {
    /// The pixel at `(u, v)` (clamped into `[0, 1]`; `v = 1` is the top row), nearest, as the
    /// book.
    pub fn lookup(&self, u: Real, v: Real) -> Vec3 {
        let (u, v) = (u.clamp(0.0, 1.0), 1.0 - v.clamp(0.0, 1.0));
        let i = ((u * self.width as Real) as u32).min(self.width - 1);
        let j = ((v * self.height as Real) as u32).min(self.height - 1);
        self.pixels[(j * self.width + i) as usize]
    }
}

/// A scene's textures, its images and its noise field. Empty (and never read) in a scene
/// without textures.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Textures {
    /// The table materials index.
    pub textures: Vec<Texture>,
    /// The images [`Texture::Image`] indexes.
    pub images: Vec<ImageTexture>,
    /// The noise field of every [`Texture::Marble`] (made only if one exists).
    pub noise: Option<Perlin>,
}

/// The seed of every scene's noise field: the marble is part of the scene, not of the render.
pub const NOISE_SEED: u64 = 0x006E_6F69_7365;

impl Textures {
    /// Texture `index`'s colour at surface point `p` with coordinates `(u, v)`.
    pub fn value(&self, index: u32, u: Real, v: Real, p: Vec3) -> Vec3 {
        match self.textures[index as usize] {
            Texture::Solid { color } => color,
            Texture::Checker { inv_scale, even, odd } => {
                let cell = (p * inv_scale).floor();
                let sum = cell.x as i64 + cell.y as i64 + cell.z as i64;
                if sum.rem_euclid(2) == 0 { even } else { odd }
            }
            Texture::Marble { scale } => {
                let noise = self.noise.as_ref().expect("a marble texture has a noise field");
                Vec3::splat(0.5 * (1.0 + (scale * p.z + 10.0 * noise.turbulence(p, 7)).sin()))
            }
            Texture::Image { image } => self.images[image as usize].lookup(u, v),
        }
    }
}
