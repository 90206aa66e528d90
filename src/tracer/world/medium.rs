//! A participating medium of constant density (the second book's `constant_medium`): fog or
//! smoke filling a closed boundary. A ray crossing `L` of it scatters with probability
//! `1 − e^(−density·L)`, at a distance drawn from that exponential law, into a direction
//! drawn by the isotropic phase function (`Material::Isotropic`).
//!
//! The boundary is any closed group. Where the ray is decides the interval: if the boundary's
//! first hit is a front face, the ray enters there and leaves at the next hit; if it is a back
//! face, the ray starts inside (a camera in global fog, a path that scattered in the smoke)
//! and leaves there.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::world::group::Group;
use crate::tracer::world::object::Probe;

/// Fog or smoke inside `boundary`.
#[derive(Clone, Debug)]
pub struct Medium {
    /// The closed surface the medium fills (its front faces outwards).
    pub boundary: Group,
    /// Scattering events per unit length, ≥ 0 (0: the medium is not there).
    pub density: Real,
    /// Index of its isotropic material in the scene's table.
    pub material: u32,
    /// Which medium this is: its own random number per ray ([`Probe::uniform`]).
    pub id: u32,
}

impl Medium {
    /// Where the ray scatters in the medium before `t_max`, if it does.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        if self.density.is_nan() || self.density <= 0.0 {
            return None;
        }
        let first = self.boundary.hit(ray, Real::INFINITY, probe)?;
        let (enter, exit) = if first.front_face {
            // Cross into the boundary, then find where the ray leaves it.
            let inside = first.spawn(ray.dir);
            let last = self.boundary.hit(&inside, Real::INFINITY, probe)?;
            (first.t, (last.point - ray.origin).dot(ray.dir))
        } else {
            (0.0, first.t)
        };
        if enter >= t_max {
            return None;
        }
        let length = exit.min(t_max) - enter;
        let distance = -probe.uniform(self.id).ln() / self.density;
        if distance.is_nan() || distance >= length {
            return None;
        }
        let t = enter + distance;
        Some(Hit {
            t,
            point: ray.at(t),
            // Any unit vector: the phase function ignores it, and a ray leaves from right
            // here (no offset: there is no surface to clear).
            normal: Vec3::X,
            front_face: true,
            material: self.material,
            offset: 0.0,
            u: 0.0,
            v: 0.0,
        })
    }
}
