//! The edge-avoiding à-trous wavelet filter (Dammertz, Sewtz, Hanika and Lensch 2010), the
//! spatial filter of SVGF (Schied et al. 2017).
//!
//! Each pass replaces every pixel by a weighted mean of a 3 × 3 grid of pixels around it,
//! `step` pixels apart; the steps double from pass to pass (1, 2, 4, …: "à trous", with
//! holes), so three passes of 9 taps reach 15 pixels across, as one pass of 225 taps would.
//! A neighbour's weight is the B-spline kernel's (1/4, 1/2, 1/4 per axis; Dammertz's paper
//! uses the 5 × 5 B3 spline) times how alike its guide is to the pixel's. Both choices were
//! measured: the 3 × 3 kernel removes as much error inside surfaces as the 5 × 5 in a third
//! of the time, and three passes leave less error than four or five, which blur the shadows
//! more (`results/denoise.md`; the kernels' figures: `results/history/comment-figures.md`).
//!
//! - **normal**: `max(0, n_p·n_q)^64`, so a surface that turns away stops the blur;
//! - **plane**: `exp(−|n_p·(x_q − x_p)| / (σ · distance · pixel angle))`, the neighbour's
//!   height above the pixel's tangent plane against the size of a pixel there, so a sphere in
//!   front of a floor does not blend into it, while a floor seen at a grazing angle (points
//!   far apart in depth, all on one plane) blurs along itself; a curved surface bends away
//!   from its tangent plane slowly enough (`s²/2r` at `s` from the pixel) to blur along itself
//!   too;
//! - **albedo**: `exp(−|a_p − a_q|² / σ_a²)`, so objects of different colour stay apart;
//! - the sky blends only with the sky.
//!
//! What is filtered is the light, not the colour: the image divided by the guide's albedo
//! (plus a small ε, so black divides safely), multiplied back after the last pass, which
//! keeps a texture's detail and the sky exact.
//!
//! Invariant: the pixel itself always has a positive weight (its own kernel weight, 1/4),
//! so the mean is always defined; every pixel's result depends only on the inputs, never on
//! the bands the passes are split into.

use crate::denoise::guide::{Guide, Guides};
use crate::denoise::in_row_bands;
use crate::tracer::math::real::{Real, Vec3};

/// The 3 × 3 B-spline kernel, one axis.
const KERNEL: [Real; 3] = [0.25, 0.5, 0.25];

/// The normals' likeness is `(n_p·n_q)^64` (SVGF's σ_n = 64): six squarings.
const NORMAL_SQUARINGS: u32 = 6;

/// Added to the albedo before dividing by it, so a black surface (or a black sky) divides
/// safely and multiplies back to exactly what it was.
const EPSILON: Real = 1e-3;

/// The filter's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    /// Passes (steps 1, 2, 4, …).
    pub passes: u32,
    /// How many pixel sizes off the tangent plane halve a neighbour's weight, about.
    pub plane_sigma: Real,
    /// Albedo difference scale.
    pub albedo_sigma: Real,
}

impl Default for Filter {
    fn default() -> Filter {
        Filter { passes: 3, plane_sigma: 1.0, albedo_sigma: 0.1 }
    }
}

impl Filter {
    /// `color` (one value per pixel of `guides`, row-major) filtered, on `threads` threads.
    ///
    /// ```
    /// use raypool::denoise::atrous::Filter;
    /// use raypool::denoise::guide::{Guide, Guides};
    /// use glam::Vec3A as Vec3;
    /// // Two walls facing the camera side by side, red and white, lit alike; noisy light.
    /// let (w, h) = (16, 8);
    /// let wall = |x: u32, y: u32| Guide {
    ///     albedo: if x < 8 { Vec3::new(0.8, 0.1, 0.1) } else { Vec3::splat(0.8) },
    ///     normal: Vec3::Z, point: Vec3::new(x as f32, y as f32, 0.0), distance: 10.0 };
    /// let pixels: Vec<Guide> = (0..w * h).map(|k| wall(k % w, k / w)).collect();
    /// let guides = Guides { width: w, height: h, pixel_angle: 0.1, pixels };
    /// let noisy: Vec<Vec3> = (0..w * h).map(|k| guides.pixels[k as usize].albedo * (0.5 + 0.4 * ((k * 7919 % 13) as f32 / 12.0 - 0.5))).collect();
    /// let smooth = Filter::default().apply(&noisy, &guides, 1);
    /// // The edge stays sharp: no red leaks into the white wall's first column.
    /// let white = smooth[8];
    /// assert!((white.x - white.y).abs() < 1e-3 * white.x, "{white:?}");
    /// ```
    pub fn apply(&self, color: &[Vec3], guides: &Guides, threads: usize) -> Vec<Vec3> {
        assert_eq!(color.len(), guides.pixels.len(), "one colour per guide");
        let mut light: Vec<Vec3> =
            color.iter().zip(&guides.pixels).map(|(&c, g)| c / (g.albedo + EPSILON)).collect();
        let mut next = vec![Vec3::ZERO; light.len()];
        for pass in 0..self.passes {
            let step = 1usize << pass;
            in_row_bands(&mut next, guides.width as usize, threads, |first_row, band| {
                self.pass_rows(&light, guides, step, first_row, band)
            });
            std::mem::swap(&mut light, &mut next);
        }
        light.iter().zip(&guides.pixels).map(|(&l, g)| l * (g.albedo + EPSILON)).collect()
    }

    /// One pass at `step` over the rows from `first_row` that `out` holds.
    fn pass_rows(&self, light: &[Vec3], guides: &Guides, step: usize, first_row: usize, out: &mut [Vec3]) {
        let (width, height) = (guides.width as usize, guides.height as usize);
        let inv_albedo = 1.0 / (self.albedo_sigma * self.albedo_sigma);
        for (k, result) in out.iter_mut().enumerate() {
            let (x, y) = (k % width, first_row + k / width);
            let p = &guides.pixels[y * width + x];
            let inv_pixel = 1.0 / (p.distance * guides.pixel_angle * self.plane_sigma);
            // The taps inside the image: rows `dys`, columns `dxs` of the 3 × 3 grid.
            let inside =
                |c: usize, size: usize| (1usize.saturating_sub(c / step))..(2 + (size - 1 - c) / step).min(3);
            let (dys, dxs) = (inside(y, height), inside(x, width));
            let (mut sum, mut total) = (Vec3::ZERO, 0.0);
            for dy in dys {
                let row = (y + dy * step - step) * width;
                for dx in dxs.clone() {
                    let q = row + x + dx * step - step;
                    let weight = KERNEL[dy]
                        * KERNEL[dx]
                        * if p.is_sky() {
                            Real::from(u8::from(guides.pixels[q].is_sky()))
                        } else {
                            self.likeness(p, &guides.pixels[q], inv_pixel, inv_albedo)
                        };
                    sum += weight * light[q];
                    total += weight;
                }
            }
            *result = sum / total;
        }
    }

    /// How alike neighbour `q`'s guide is to the pixel `p`'s (not the sky), in `[0, 1]` (1 for
    /// the pixel itself); `inv_pixel` is 1 / (σ × the size of a pixel on `p`'s surface). A sky
    /// `q` has no normal, so `facing` is 0 for it.
    #[inline(always)]
    fn likeness(&self, p: &Guide, q: &Guide, inv_pixel: Real, inv_albedo: Real) -> Real {
        let facing = p.normal.dot(q.normal);
        if facing <= 0.0 {
            return 0.0;
        }
        let off_plane = p.normal.dot(q.point - p.point).abs() * inv_pixel;
        let albedo = (p.albedo - q.albedo).length_squared() * inv_albedo;
        // facing^64 as six squarings (`powi` is a call, not inlined).
        let aligned = (0..NORMAL_SQUARINGS).fold(facing, |f, _| f * f);
        aligned * (-(off_plane + albedo)).exp()
    }
}
