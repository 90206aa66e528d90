//! One thing a scene holds, of any kind: an `enum`, so a group of mixed shapes is one flat
//! array its tree indexes, and a search matches on the kind (a predictable branch) instead of
//! calling through a pointer. Composite kinds (meshes, instances, media) hold their parts
//! behind a pointer, which keeps the array's entries small.

use std::sync::Arc;

use crate::tracer::geometry::hit::Hit;
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::independent::mix;
use crate::tracer::world::instance::Instance;
use crate::tracer::world::medium::Medium;
use crate::tracer::world::mesh::Mesh;

/// What a search needs besides the ray: the time the camera ray sampled (for moving shapes)
/// and the random seed media draw their scattering distances from.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Probe {
    /// In `[0, 1)`: where in the shutter interval the path was sampled.
    pub time: Real,
    /// Drawn once per ray (only in scenes with media). Each medium turns it into its own
    /// number with its own id ([`Probe::uniform`]), so what a medium draws does not depend on
    /// the order in which a tree visits objects: `--accel` changes no pixel.
    pub medium_seed: u64,
}

impl Probe {
    /// A number in `(0, 1]` for medium `id`, independent of every other medium's.
    pub fn uniform(&self, id: u32) -> Real {
        let bits = mix(self.medium_seed ^ u64::from(id).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        ((bits >> 40) + 1) as Real * (1.0 / (1u64 << 24) as Real)
    }
}

/// One object of a scene or of a group.
#[derive(Clone, Debug)]
pub enum Object {
    /// A sphere, tested with the robust test of `geometry/sphere.rs`.
    Sphere(Sphere),
    /// A sphere moving during the shutter interval.
    Moving(MovingSphere),
    /// A parallelogram.
    Quad(Quad),
    /// A triangle mesh (shared: one mesh may be placed many times) and its material.
    Mesh(Arc<Mesh>, u32),
    /// A group placed by a rigid transform.
    Instance(Box<Instance>),
    /// Fog or smoke inside a closed boundary.
    Medium(Box<Medium>),
}

impl Object {
    /// The nearest hit in `(0, t_max)`, if any.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        match self {
            Object::Sphere(sphere) => sphere_hit(sphere, ray, t_max),
            Object::Moving(moving) => sphere_hit(&moving.at(probe.time), ray, t_max),
            Object::Quad(quad) => {
                let (t, alpha, beta) = quad.intersect(ray, t_max)?;
                Some(quad.hit_at(ray, t, alpha, beta))
            }
            Object::Mesh(mesh, material) => mesh.hit(ray, t_max, *material),
            Object::Instance(instance) => instance.hit(ray, t_max, probe),
            Object::Medium(medium) => medium.hit(ray, t_max, probe),
        }
    }

    /// The materials this object's surfaces use.
    pub fn materials(&self, out: &mut Vec<u32>) {
        match self {
            Object::Sphere(s) => out.push(s.material),
            Object::Moving(m) => out.push(m.material),
            Object::Quad(q) => out.push(q.material),
            Object::Mesh(_, material) => out.push(*material),
            Object::Instance(instance) => instance.group.objects().iter().for_each(|o| o.materials(out)),
            Object::Medium(medium) => out.push(medium.material),
        }
    }

    /// Whether anything in it moves or is a medium: `(moves, media)`.
    pub fn needs(&self) -> (bool, bool) {
        match self {
            Object::Moving(m) => (m.center0 != m.center1, false),
            Object::Medium(_) => (false, true),
            Object::Instance(instance) => instance.group.needs(),
            _ => (false, false),
        }
    }
}

/// A sphere's hit with its texture coordinates (the world's spheres may be textured).
#[inline]
fn sphere_hit(sphere: &Sphere, ray: &Ray, t_max: Real) -> Option<Hit> {
    let t = sphere.intersect(ray, t_max)?;
    Some(sphere.hit_at_with_uv(ray, t))
}

impl Bounded for Object {
    fn bounds(&self) -> Aabb {
        match self {
            Object::Sphere(s) => s.bounds(),
            Object::Moving(m) => m.bounds(),
            Object::Quad(q) => q.bounds(),
            Object::Mesh(mesh, _) => mesh.bounds(),
            Object::Instance(instance) => instance.bounds(),
            Object::Medium(medium) => medium.boundary.bounds(),
        }
    }

    fn centroid(&self) -> Vec3 {
        match self {
            Object::Sphere(s) => s.center,
            other => {
                let b = other.bounds();
                0.5 * (b.min + b.max)
            }
        }
    }
}
