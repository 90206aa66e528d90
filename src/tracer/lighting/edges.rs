//! **The lights' edges**: extra camera points where a pixel may see a light directly.
//!
//! A pixel that holds the edge of a light sees, sample by sample, either the light (on
//! `cornell`, 15) or the ceiling beside it (under 1): the widest spread of any pixel, and one
//! no light sampling touches (on `cornell`, a large share of `mis`'s squared error:
//! `results/lights.md`). What the pixel sees of the light is cheap to find (a ray and no
//! bounce), so each sample there looks through [`Edges::spots`] more points of the pixel for
//! light alone, and counts their mean instead of what its own first hit emits; the path goes
//! on from its own hit as before. The estimate stays unbiased: every point is uniform in the
//! pixel, so each one's light has the mean of the first hit's.
//!
//! Only pixels whose rays may meet the lights' box take them ([`Camera::pixels_seeing`]), and
//! a point whose ray misses that box casts nothing. With Sobol the points come from a
//! sequence of the pixel's own, `spots` per sample ([`SampleRng::pixel_point`]), so a pixel's
//! first `n` samples place `n × spots` points as evenly as that many samples would.

use std::ops::Range;

use crate::tracer::camera::Camera;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::keys::EDGE_RAY_KEY;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::scene::Scene;
use crate::tracer::world::object::Probe;

/// Which pixels of a camera's image take edge points of a scene, and how many each sample
/// takes.
#[derive(Clone, Debug)]
pub struct Edges<'a> {
    scene: &'a Scene,
    camera: &'a Camera,
    columns: Range<u32>,
    rows: Range<u32>,
    /// Points per sample in those pixels (0: none anywhere).
    pub spots: u32,
}

impl<'a> Edges<'a> {
    /// `spots` points per sample in the pixels of `camera` that may see one of `scene`'s lights
    /// (none in a scene without lights).
    pub fn new(scene: &'a Scene, camera: &'a Camera, spots: u32) -> Edges<'a> {
        let [columns, rows] = if spots == 0 || scene.lights().is_empty() {
            [0..0, 0..0]
        } else {
            camera.pixels_seeing(&scene.lights().bounds)
        };
        Edges { scene, camera, columns, rows, spots }
    }

    /// Whether pixel `(i, j)` takes edge points.
    #[inline]
    pub fn covers(&self, i: u32, j: u32) -> bool {
        self.columns.contains(&i) && self.rows.contains(&j)
    }

    /// The mean light emitted towards the camera at the first hit of [`Edges::spots`] rays
    /// from the lens point `origin` through points of pixel `(i, j)`, at the path's `probe`.
    /// Counts the rays cast in `rays`.
    pub fn light<R: SampleRng + ?Sized>(
        &self,
        origin: Vec3,
        i: u32,
        j: u32,
        probe: Probe,
        rng: &mut R,
        rays: &mut u64,
    ) -> Vec3 {
        let (scene, camera) = (self.scene, self.camera);
        let box_of_lights = &scene.lights().bounds;
        let mut sum = Vec3::ZERO;
        for spot in 0..self.spots {
            let ray = camera.ray_from(origin, i, j, rng.pixel_point(spot, self.spots));
            if !box_of_lights.hit(ray.origin, ray.dir.recip(), Real::INFINITY) {
                continue;
            }
            *rays += 1;
            let probe = Probe { medium_seed: probe.medium_seed ^ EDGE_RAY_KEY ^ u64::from(spot), ..probe };
            if let Some(hit) = scene.hit_world(&ray, &probe) {
                sum += scene.material(&hit).emitted(&hit);
            }
        }
        sum / self.spots as Real
    }
}
