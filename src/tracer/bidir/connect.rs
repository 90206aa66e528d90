//! One bidirectional sample: a camera path and a light path, then every connection between
//! them that [`Limits`] uses, each weighted by [`weight`]. What lands in the sample's own pixel
//! is returned; what a light path carries straight to the camera is splatted.
//!
//! The camera path draws from the pixel sample's stream, as the path tracer does (bounce
//! `b`'s scattering from its dimensions, bounce `b`'s shadow ray from its light dimensions);
//! the light path and the lens points it is joined to draw from a second stream of the same
//! sample. Every shadow ray in a medium draws from its own key, so no connection changes a
//! number another draws.

use crate::tracer::bidir::vertex::{Kind, Vertex};
use crate::tracer::bidir::walk::{Direction, Start, walk};
use crate::tracer::bidir::weight::{Ends, Limits, weight};
use crate::tracer::camera::Camera;
use crate::tracer::lights::emission::emitted_direction;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::independent::mix;
use crate::tracer::sampling::keys::{CONNECT_KEY, LIGHT_KEY};
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::scene::Scene;
use crate::tracer::splats::Splats;
use crate::tracer::world::object::Probe;

/// A light path has at most this many vertices (four bounces): enough for light through a
/// glass ball (in, out) onto a wall and one more bounce. Longer paths are left to the camera.
pub const LIGHT_VERTICES: usize = 5;
/// A light path's vertices are joined to the camera path's first this-many-minus-one bounces
/// (the first only): joining them to later bounces too bought no measurable error on `cornell`
/// for more time (`results/bdpt.md`).
pub const CONNECT_VERTICES: usize = 2;

/// Light tracing's density is weighed at this share against the other strategies'. Its light
/// paths draw independent numbers, while the camera's strategies draw Sobol points, whose error
/// falls faster than the densities say: at full share light tracing took nearly all the weight
/// of directly lit walls and `cornell-smoke`'s error per sample was above `mis`'s; at 0.1,
/// below it (`results/bdpt.md`). Any share keeps the weights a partition of 1, so the image unbiased.
pub const LIGHT_TRACING_SHARE: Real = 0.1;

/// What stays the same for every sample of a render.
#[derive(Clone, Copy, Debug)]
pub struct Bidir<'a> {
    /// The scene (with lights).
    pub scene: &'a Scene,
    /// The camera, set up for the image.
    pub camera: &'a Camera,
    /// Rays per path at most (`max_depth`): no strategy makes a longer path.
    pub max_depth: u32,
    /// Image width, pixels (a splat's pixel index is row-major).
    pub width: u32,
}

/// A sample's two streams: the pixel sample's own, which the camera path draws from, and its
/// second, which the light path and the lens points it is joined to draw from.
pub struct Streams<'s, R: ?Sized, L: ?Sized> {
    /// The pixel sample's stream.
    pub camera: &'s mut R,
    /// Its second stream.
    pub light: &'s mut L,
}

/// A connection strategy (Veach's `s` and `t`): the light path's first `s` vertices joined
/// to the camera path's first `t`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Strategy {
    s: usize,
    t: usize,
}

/// The two paths of a sample, kept between samples so their room is allocated once a tile.
#[derive(Clone, Debug, Default)]
pub struct Paths {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
}

impl Bidir<'_> {
    /// The strategies used: [`LIGHT_VERTICES`], [`CONNECT_VERTICES`].
    pub const LIMITS: Limits = Limits {
        light_vertices: LIGHT_VERTICES,
        connect_vertices: CONNECT_VERTICES,
        light_tracing_share: LIGHT_TRACING_SHARE,
    };

    /// One sample from the camera `ray` at `start`: the light reaching the sample's pixel
    /// (camera strategies); light paths' splats land in `splats`.
    pub fn sample<R: SampleRng + ?Sized, L: SampleRng + ?Sized>(
        &self,
        ray: Ray,
        start: Probe,
        streams: Streams<'_, R, L>,
        paths: &mut Paths,
        splats: &mut Splats,
        rays: &mut u64,
    ) -> Vec3 {
        let Streams { camera: rng, light: light_rng } = streams;
        paths.camera.clear();
        paths.camera.push(Vertex::camera(ray.origin));
        let first = Start {
            direction: Direction::FromCamera,
            ray,
            beta: Vec3::ONE,
            pdf: self.camera.direction_pdf(ray.dir),
            probe: start,
            max_vertices: self.max_depth as usize + 1,
        };
        let (scene, camera) = (self.scene, self.camera);
        let mut radiance = walk(scene, camera, first, rng, &mut paths.camera, rays);
        paths.light.clear();
        let light_start = Probe { medium_seed: mix(start.medium_seed ^ LIGHT_KEY), ..start };
        if let Some(emission) = scene.lights().sample_emission(start.time, light_rng) {
            let dir = emitted_direction(emission.normal, light_rng);
            let origin = emission.point + emission.offset * emission.normal;
            // Emission × cos over (area density × cos/π): the cosines cancel.
            let beta = emission.emitted * (PI / emission.pdf);
            let first = Start {
                direction: Direction::FromLight,
                ray: Ray { origin, dir },
                beta,
                pdf: dir.dot(emission.normal).max(0.0) / PI,
                probe: light_start,
                max_vertices: LIGHT_VERTICES,
            };
            let y0 = Vertex::light(emission.point, emission.normal, emission.emitted, emission.pdf);
            paths.light.push(y0);
            walk(scene, camera, first, light_rng, &mut paths.light, rays);
        }
        for t in 2..=paths.camera.len() {
            radiance += self.at_camera_vertex(t, paths, start, rng, rays);
        }
        for s in 2..=paths.light.len().min(self.max_depth as usize) {
            self.splat_to_camera(s, paths, start, light_rng, splats, rays);
        }
        radiance
    }

    /// Every strategy that ends the camera path at its `t`-th vertex (`s = 0`: it is an
    /// emitter; `s = 1`: a shadow ray; `s ≥ 2`: joined to the light path's `s`-th vertex).
    fn at_camera_vertex<R: SampleRng + ?Sized>(
        &self,
        t: usize,
        paths: &Paths,
        start: Probe,
        rng: &mut R,
        rays: &mut u64,
    ) -> Vec3 {
        let (camera_path, light_path) = (&paths.camera[..t], &paths.light);
        let z = &camera_path[t - 1];
        let mut sum = Vec3::ZERO;
        if z.emitted != Vec3::ZERO {
            let as_light = Vertex { kind: Kind::Light, ..*z };
            let ends = Ends {
                camera_last: self.scene.lights().origin_pdf(z.emitted),
                camera_next: as_light.density_to(&camera_path[t - 2], self.camera),
                ..Ends::default()
            };
            sum += z.beta * z.emitted * weight(&[], camera_path, &ends, Bidir::LIMITS);
        }
        if !z.connectable() || z.beta == Vec3::ZERO {
            return sum;
        }
        if t <= self.max_depth as usize {
            rng.light(t as u32 - 2);
            sum += self.shadow_ray(camera_path, start, rng, rays);
        }
        for s in 2..=light_path.len() {
            if s + t - 1 > self.max_depth as usize || !Bidir::LIMITS.used(s, t) {
                break;
            }
            sum += self.join(&light_path[..s], camera_path, start, rays);
        }
        sum
    }

    /// Strategy `s = 1`: a point drawn on a light, seen from the camera path's last vertex.
    fn shadow_ray<R: SampleRng + ?Sized>(
        &self,
        camera_path: &[Vertex],
        start: Probe,
        rng: &mut R,
        rays: &mut u64,
    ) -> Vec3 {
        let z = &camera_path[camera_path.len() - 1];
        let lights = self.scene.lights();
        let Some(toward) = lights.sample(z.point, start.time, rng) else { return Vec3::ZERO };
        let scattered = z.scattered(toward.dir);
        if toward.emitted == Vec3::ZERO || scattered == Vec3::ZERO {
            return Vec3::ZERO;
        }
        if !self.visible(z, toward.dir, toward.distance, start, Strategy { s: 1, t: camera_path.len() }, rays)
        {
            return Vec3::ZERO;
        }
        let y0 =
            Vertex::light(toward.point, toward.normal, toward.emitted, lights.origin_pdf(toward.emitted));
        let ends = self.ends(&[y0], camera_path);
        let w = weight(&[y0], camera_path, &ends, Bidir::LIMITS);
        z.beta * scattered * toward.emitted * (w / toward.pdf)
    }

    /// Strategy `s ≥ 2, t ≥ 2`: the light path's last vertex joined to the camera path's.
    fn join(&self, light_path: &[Vertex], camera_path: &[Vertex], start: Probe, rays: &mut u64) -> Vec3 {
        let (y, z) = (&light_path[light_path.len() - 1], &camera_path[camera_path.len() - 1]);
        if !y.connectable() || y.beta == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let to = y.point - z.point;
        let d2 = to.length_squared();
        let dir = to / d2.sqrt();
        let light = z.scattered(dir) * y.scattered(-dir) * z.beta * y.beta;
        if light == Vec3::ZERO || !light.is_finite() {
            return Vec3::ZERO;
        }
        let strategy = Strategy { s: light_path.len(), t: camera_path.len() };
        if !self.visible(z, dir, d2.sqrt(), start, strategy, rays) {
            return Vec3::ZERO;
        }
        let ends = self.ends(light_path, camera_path);
        light * (weight(light_path, camera_path, &ends, Bidir::LIMITS) / d2)
    }

    /// Strategy `t = 1`: the light path's `s`-th vertex seen through a lens point, splatted
    /// into the pixel it lands in.
    fn splat_to_camera<L: SampleRng + ?Sized>(
        &self,
        s: usize,
        paths: &Paths,
        start: Probe,
        light_rng: &mut L,
        splats: &mut Splats,
        rays: &mut u64,
    ) {
        let light_path = &paths.light[..s];
        let y = &light_path[s - 1];
        if !y.connectable() || y.beta == Vec3::ZERO || !Bidir::LIMITS.used(s, 1) {
            return;
        }
        let lens = self.camera.lens_point(light_rng);
        let Some((i, j)) = self.camera.pixel_of(lens, y.point) else { return };
        let to = lens - y.point;
        let d2 = to.length_squared();
        let dir = to / d2.sqrt();
        let light = y.beta * y.scattered(dir) * (self.camera.direction_pdf(-dir) / d2);
        if light == Vec3::ZERO || !light.is_finite() {
            return;
        }
        if !self.visible(y, dir, d2.sqrt(), start, Strategy { s, t: 1 }, rays) {
            return;
        }
        let camera_path = [Vertex::camera(lens)];
        let ends = self.ends(light_path, &camera_path);
        splats.add(j * self.width + i, light * weight(light_path, &camera_path, &ends, Bidir::LIMITS));
    }

    /// The densities at the ends of the connection between `light_path` and `camera_path`.
    fn ends(&self, light_path: &[Vertex], camera_path: &[Vertex]) -> Ends {
        let (s, t) = (light_path.len(), camera_path.len());
        let (y, z) = (&light_path[s - 1], &camera_path[t - 1]);
        let camera = self.camera;
        Ends {
            camera_last: if t >= 2 { y.density_to(z, camera) } else { 0.0 },
            camera_next: if t >= 2 { z.density_to(&camera_path[t - 2], camera) } else { 0.0 },
            light_last: z.density_to(y, camera),
            light_next: if s >= 2 { y.density_to(&light_path[s - 2], camera) } else { 0.0 },
        }
    }

    /// Whether nothing stands between `from` and the point `distance` away along the unit
    /// `dir` (no surface, no scattering in a medium): the shadow ray of `strategy`, its media
    /// numbers its own, counted in `rays`.
    fn visible(
        &self,
        from: &Vertex,
        dir: Vec3,
        distance: Real,
        start: Probe,
        strategy: Strategy,
        rays: &mut u64,
    ) -> bool {
        *rays += 1;
        let Some(hit) = &from.hit else { return true };
        let key = (strategy.s as u64) << 32 | strategy.t as u64;
        let seed = mix(start.medium_seed ^ CONNECT_KEY ^ key);
        let (shadow, reach) = Ray::towards(hit.spawn(dir).origin, hit.point + distance * dir);
        !self.scene.occluded(&shadow, reach, &Probe { medium_seed: seed, ..start })
    }
}
