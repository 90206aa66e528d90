//! A scene ready to render: flat arrays of spheres and materials, a background, a camera.
//!
//! Built from a [`SceneFile`](crate::scene_file::SceneFile), which is what users write;
//! this is what the tracer reads. Everything is plain data (`Sync` for free), shared by
//! reference between render threads.

use crate::background::Background;
use crate::camera::CameraSettings;
use crate::material::Material;
use crate::ray::Ray;
use crate::real::Real;
use crate::sphere::{Hit, Sphere};

/// Geometry, materials, background and camera of one scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Every sphere; `Sphere::material` indexes `materials`.
    pub spheres: Vec<Sphere>,
    /// Material table.
    pub materials: Vec<Material>,
    /// Light for rays that escape.
    pub background: Background,
    /// Camera parameters (the image size is chosen at render time).
    pub camera: CameraSettings,
}

impl Scene {
    /// The closest hit along `ray` closer than `t_max`.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        let mut closest = t_max;
        let mut found = None;
        for sphere in &self.spheres {
            if let Some(t) = sphere.intersect(ray, closest) {
                closest = t;
                found = Some(sphere);
            }
        }
        found.map(|sphere| sphere.hit_at(ray, closest))
    }

    /// The material of a hit.
    #[inline]
    pub fn material(&self, hit: &Hit) -> &Material {
        &self.materials[hit.material as usize]
    }
}
