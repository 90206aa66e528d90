//! A scene ready to render: flat arrays of spheres and materials, a background, a camera.
//!
//! Built from a [`SceneFile`](crate::scenes::format::SceneFile), which is what users write;
//! this is what the tracer reads. Everything is plain data (`Sync` for free), shared by
//! reference between render threads.

use crate::tracer::background::Background;
use crate::tracer::bvh::{BVH_MIN_SPHERES, Bvh};
use crate::tracer::camera::CameraSettings;
use crate::tracer::material::Material;
use crate::tracer::ray::Ray;
use crate::tracer::real::Real;
use crate::tracer::sphere::{Hit, Intersection, Sphere};

/// Geometry, materials, background and camera of one scene.
#[derive(Clone, Debug)]
pub struct Scene {
    spheres: Vec<Sphere>,
    materials: Vec<Material>,
    /// Built only for scenes of at least [`BVH_MIN_SPHERES`] spheres.
    bvh: Option<Bvh>,
    /// How rays meet spheres: robust unless a comparison asks for the book's method.
    intersection: Intersection,
    /// Light for rays that escape.
    pub background: Background,
    /// Camera parameters (the image size is chosen at render time).
    pub camera: CameraSettings,
}

impl Scene {
    /// A scene of these spheres (each `material` indexing `materials`). Large scenes get a
    /// [`Bvh`], which reorders the spheres.
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
        Scene { spheres, materials, bvh, intersection: Intersection::Robust, background, camera }
    }

    /// The same scene traced by testing every sphere (for the ablation table: the same hits
    /// but for exact ties, only slower for large scenes).
    pub fn without_bvh(mut self) -> Scene {
        self.bvh = None;
        self
    }

    /// The same scene traced with another intersection method (for comparisons).
    pub fn with_intersection(mut self, intersection: Intersection) -> Scene {
        self.intersection = intersection;
        self
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
    ///
    /// One branch per ray picks the method; each arm is its own monomorphised traversal, so
    /// the robust default pays nothing for the textbook alternative.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        match self.intersection {
            Intersection::Robust => {
                let (index, t) = self.closest(ray, t_max, Sphere::intersect)?;
                Some(self.spheres[index].hit_at(ray, t))
            }
            Intersection::Textbook => {
                let (index, t) = self.closest(ray, t_max, Sphere::intersect_textbook)?;
                Some(self.spheres[index].hit_at_textbook(ray, t))
            }
        }
    }

    /// The closest sphere `test` finds: through the hierarchy, or for a handful of spheres
    /// (the fastest way then) by testing every one.
    #[inline]
    fn closest(
        &self,
        ray: &Ray,
        t_max: Real,
        test: impl Fn(&Sphere, &Ray, Real) -> Option<Real>,
    ) -> Option<(usize, Real)> {
        if let Some(bvh) = &self.bvh {
            return bvh.hit(&self.spheres, ray, t_max, test);
        }
        let mut closest = t_max;
        let mut found = None;
        for (i, sphere) in self.spheres.iter().enumerate() {
            if let Some(t) = test(sphere, ray, closest) {
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
