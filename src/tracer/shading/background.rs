//! What a ray that escapes the scene sees.

use crate::tracer::math::real::{Real, Vec3};

/// The light arriving from infinitely far away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// The book's sky: `lerp(horizon, zenith, ½(dir.y + 1))`.
    Gradient {
        /// Colour looking straight down (and, blended, at the horizon).
        horizon: Vec3,
        /// Colour looking straight up.
        zenith: Vec3,
    },
    /// The same light from every direction (a "white furnace" when it is 1).
    Constant {
        /// Radiance, linear RGB.
        color: Vec3,
    },
}

impl Background {
    /// Radiance seen along the unit direction `dir`.
    #[inline]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match *self {
            Background::Gradient { horizon, zenith } => {
                let t: Real = 0.5 * (dir.y + 1.0);
                horizon.lerp(zenith, t)
            }
            Background::Constant { color } => color,
        }
    }
}
