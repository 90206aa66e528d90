//! A scene ready to render: flat arrays of spheres and materials, a background, a camera.
//!
//! Built from a [`SceneFile`](crate::scene_file::SceneFile), which is what users write;
//! this is what the tracer reads. Everything is plain data (`Sync` for free), shared by
//! reference between render threads.

use crate::background::Background;
use crate::bvh::{BVH_MIN_SPHERES, Bvh};
use crate::camera::CameraSettings;
use crate::material::Material;
use crate::ray::Ray;
use crate::real::Real;
use crate::sphere::{Hit, Sphere};

/// Geometry, materials, background and camera of one scene.
#[derive(Clone, Debug)]
pub struct Scene {
    spheres: Vec<Sphere>,
    materials: Vec<Material>,
    /// Built only for scenes of at least [`BVH_MIN_SPHERES`] spheres.
    bvh: Option<Bvh>,
    /// Light for rays that escape.
    pub background: Background,
    /// Camera parameters (the image size is chosen at render time).
    pub camera: CameraSettings,
}

impl Scene {
    /// A scene of these spheres (each `material` indexing `materials`). Large scenes get a
    /// [`Bvh`], which reorders the spheres (never the image).
    ///
    /// # Panics
    /// If a sphere's material index is out of range.
    pub fn new(
        mut spheres: Vec<Sphere>,
        materials: Vec<Material>,
        background: Background,
        camera: CameraSettings,
    ) -> Scene {
        assert!(
            spheres.iter().all(|s| (s.material as usize) < materials.len()),
            "material index out of range"
        );
        let bvh = (spheres.len() >= BVH_MIN_SPHERES).then(|| Bvh::build(&mut spheres));
        Scene { spheres, materials, bvh, background, camera }
    }

    /// The spheres, in the order the hierarchy (if any) stored them.
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }

    /// The material table.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Whether intersection goes through a bounding volume hierarchy.
    pub fn has_bvh(&self) -> bool {
        self.bvh.is_some()
    }

    /// The closest hit along `ray` closer than `t_max`.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        let (index, t) = match &self.bvh {
            Some(bvh) => bvh.hit(&self.spheres, ray, t_max)?,
            None => self.hit_all(ray, t_max)?,
        };
        Some(self.spheres[index].hit_at(ray, t))
    }

    /// Tests every sphere: the fastest way for a handful of them.
    #[inline]
    fn hit_all(&self, ray: &Ray, t_max: Real) -> Option<(usize, Real)> {
        let mut closest = t_max;
        let mut found = None;
        for (i, sphere) in self.spheres.iter().enumerate() {
            if let Some(t) = sphere.intersect(ray, closest) {
                closest = t;
                found = Some(i);
            }
        }
        found.map(|i| (i, closest))
    }

    /// The material of a hit.
    #[inline]
    pub fn material(&self, hit: &Hit) -> &Material {
        &self.materials[hit.material as usize]
    }
}
