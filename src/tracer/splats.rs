//! Light a light path carries straight to the camera lands in whatever pixel it reaches, not
//! in the pixel whose sample made it: a *splat*. Threads finish their tiles in any order, so
//! splats are summed in fixed point (integers add the same in any order), 2⁻³² a unit: the
//! image stays bit-identical whatever the schedule and thread count.
//!
//! Invariant: a splat is rounded once, when it is made; sums saturate at `u64::MAX` (of
//! non-negative numbers, also the same in any order), which no real image reaches: a pixel
//! holds 4·10⁹ units of light before it would.

use std::collections::HashMap;

use glam::DVec3;

use crate::tracer::math::real::{Vec3, to_dvec3};

/// One unit of light is this many counts.
const SCALE: f64 = 4_294_967_296.0;

/// Splats summed per pixel (row-major index), in fixed point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Splats {
    sums: HashMap<u32, [u64; 3]>,
}

impl Splats {
    /// Adds `value` (non-negative; anything else adds nothing) to pixel `pixel`.
    ///
    /// ```
    /// use raypool::tracer::splats::Splats;
    /// use raypool::tracer::math::real::Vec3;
    /// let (mut a, mut b) = (Splats::default(), Splats::default());
    /// a.add(7, Vec3::new(0.1, 0.2, 0.3));
    /// a.add(7, Vec3::new(0.7, 0.0, 1e-3));
    /// b.add(7, Vec3::new(0.7, 0.0, 1e-3));
    /// b.add(7, Vec3::new(0.1, 0.2, 0.3));
    /// assert_eq!(a, b); // the order of the adds does not matter
    /// ```
    pub fn add(&mut self, pixel: u32, value: Vec3) {
        self.add_counts(pixel, to_dvec3(value).to_array().map(to_counts));
    }

    /// Adds every splat of `other`.
    pub fn merge(&mut self, other: &Splats) {
        for (&pixel, &counts) in &other.sums {
            self.add_counts(pixel, counts);
        }
    }

    /// Adds `counts` (fixed point, as [`Splats::counts`] gives them) to pixel `pixel`: how a
    /// part file's splats are read back.
    pub fn add_counts(&mut self, pixel: u32, counts: [u64; 3]) {
        let sum = self.sums.entry(pixel).or_default();
        for (s, c) in sum.iter_mut().zip(counts) {
            *s = s.saturating_add(c);
        }
    }

    /// Every pixel that received light, in pixel order, with its sums in fixed point: what a
    /// part file stores (in order, so the same splats are the same bytes).
    ///
    /// ```
    /// use raypool::tracer::splats::Splats;
    /// use raypool::tracer::math::real::Vec3;
    /// let mut a = Splats::default();
    /// a.add(9, Vec3::new(1.0, 0.0, 0.5));
    /// a.add(2, Vec3::new(0.25, 0.0, 0.0));
    /// let mut b = Splats::default();
    /// for (pixel, counts) in a.counts() {
    ///     b.add_counts(pixel, counts);
    /// }
    /// assert_eq!(a, b);
    /// assert_eq!(a.counts().next(), Some((2, [1 << 30, 0, 0])));
    /// ```
    pub fn counts(&self) -> impl Iterator<Item = (u32, [u64; 3])> + '_ {
        let mut pixels: Vec<u32> = self.sums.keys().copied().collect();
        pixels.sort_unstable();
        pixels.into_iter().map(|pixel| (pixel, self.sums[&pixel]))
    }

    /// How many pixels received light.
    pub fn len(&self) -> usize {
        self.sums.len()
    }

    /// Whether no splat has landed.
    pub fn is_empty(&self) -> bool {
        self.sums.is_empty()
    }

    /// Each pixel that received light, with the light's sum divided by `paths` (the number of
    /// light paths per pixel: the image's samples per pixel).
    pub fn per_pixel(&self, paths: u32) -> impl Iterator<Item = (usize, DVec3)> + '_ {
        let scale = 1.0 / (SCALE * f64::from(paths.max(1)));
        self.sums.iter().map(move |(&pixel, c)| {
            (pixel as usize, DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * scale)
        })
    }
}

/// A non-negative amount of light in counts, rounded to the nearest; 0 for anything else.
fn to_counts(value: f64) -> u64 {
    if value > 0.0 { (value * SCALE).round().min(u64::MAX as f64) as u64 } else { 0 }
}
