//! What a search needs besides the ray ([`Probe`]): kept apart from the objects it is handed
//! to, which re-export it (`world::object::Probe`).

use crate::tracer::accel::isa::Isa;
use crate::tracer::math::real::Real;
use crate::tracer::sampling::independent::mix;
use crate::tracer::sampling::keys::MEDIUM_KEY;

/// What a search needs besides the ray: the time the camera ray sampled (for moving shapes),
/// the random seed media draw their scattering distances from, and the vector instructions
/// meshes are searched with.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Probe {
    /// In `[0, 1)`: where in the shutter interval the path was sampled.
    pub time: Real,
    /// Drawn once per ray (only in scenes with media). Each medium turns it into its own
    /// number with its own id ([`Probe::uniform`]), so what a medium draws does not depend on
    /// the order in which a tree visits objects: `--accel` changes no pixel.
    pub medium_seed: u64,
    /// The widest vector instructions a mesh's search may use (the same hits at every level).
    pub isa: Isa,
}

impl Probe {
    /// A number in `(0, 1]` for medium `id`, independent of every other medium's.
    pub fn uniform(&self, id: u32) -> Real {
        let bits = mix(self.medium_seed ^ u64::from(id).wrapping_mul(MEDIUM_KEY));
        ((bits >> 40) + 1) as Real * (1.0 / (1u64 << 24) as Real)
    }
}
