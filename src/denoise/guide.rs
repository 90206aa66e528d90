//! The guide buffers: what each pixel's first sample sees first, free of the path's noise.
//!
//! For every pixel, the camera ray of its sample 0 (the same numbers the render drew for it:
//! same stream, same shutter time) is followed to its first hit, and the guide keeps that
//! hit's colour (its material's [`albedo`](crate::tracer::shading::material::Material::albedo)),
//! its normal facing the camera, its point and its distance. A ray that meets nothing keeps
//! the sky's colour there and no normal. These are the edges a noisy image hides: where one
//! object ends and another starts, where a surface turns, where a texture changes.
//!
//! Invariant: a guide depends only on the job (scene, camera, size, seed, sampler), never on
//! the schedule, so a denoised image keeps the renderer's property that its bits do not depend
//! on threads, mode or viewer.

use crate::denoise::in_row_bands;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::render::RenderJob;
use crate::tracer::sampling::independent::PerSample;
use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams, SampleRng, Sampler};
use crate::tracer::sampling::sobol::SobolStreams;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::Probe;

/// One pixel's guide.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Guide {
    /// The first hit's albedo, or the sky's radiance where the ray meets nothing.
    pub albedo: Vec3,
    /// The first hit's unit normal, facing the camera; zero for the sky.
    pub normal: Vec3,
    /// The first hit's point.
    pub point: Vec3,
    /// Its distance from the camera (infinite for the sky).
    pub distance: Real,
}

impl Guide {
    /// Whether the pixel's first ray met nothing.
    pub fn is_sky(&self) -> bool {
        self.normal == Vec3::ZERO
    }
}

/// The guides of a whole image.
#[derive(Clone, Debug, PartialEq)]
pub struct Guides {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// The angle between neighbouring pixels' rays, radians (the camera's
    /// [`pixel_angle`](crate::tracer::camera::Camera::pixel_angle)).
    pub pixel_angle: Real,
    /// One per pixel, row-major.
    pub pixels: Vec<Guide>,
}

impl Guides {
    /// Every pixel's guide for `job`, computed on `threads` threads (the same guides however
    /// many).
    ///
    /// ```
    /// use raypool::denoise::guide::Guides;
    /// use raypool::scenes::builtin::builtin_scene;
    /// use raypool::{RenderJob, RenderSettings};
    /// let scene = builtin_scene("final", 0).unwrap().to_scene();
    /// let job = RenderJob::new(scene, RenderSettings { width: 24, height: 16, ..RenderSettings::default() });
    /// let guides = Guides::of(&job, 2);
    /// assert!(guides.pixels[0].is_sky() && !guides.pixels[24 * 16 - 1].is_sky(), "sky above, ground below");
    /// assert_eq!(guides, Guides::of(&job, 1));
    /// ```
    pub fn of(job: &RenderJob, threads: usize) -> Guides {
        let settings = &job.settings;
        let mut pixels = vec![Guide::default(); settings.width as usize * settings.height as usize];
        match settings.sampler {
            Sampler::Independent => fill(job, &PerSample { seed: settings.seed }, &mut pixels, threads),
            Sampler::Sobol => fill(job, &SobolStreams::new(settings.seed), &mut pixels, threads),
        }
        let pixel_angle = job.camera.pixel_angle();
        Guides { width: settings.width, height: settings.height, pixel_angle, pixels }
    }

    /// The pixels (row-major indices) whose 3 × 3 neighbourhood is one surface by its guides
    /// (no sky, normals within 26°, albedos within 0.02): away from every edge. There a
    /// few-sample image's error is noise; at an edge it is also the aliasing of a silhouette,
    /// which the guides share and no filter undoes. How the denoiser's error is measured apart.
    pub fn inside_surfaces(&self) -> Vec<usize> {
        let (w, h) = (self.width as usize, self.height as usize);
        let alike = |a: &Guide, b: &Guide| {
            !a.is_sky() && a.normal.dot(b.normal) > 0.9 && (a.albedo - b.albedo).abs().max_element() < 0.02
        };
        let inside = |k: usize| {
            let (x, y) = (k % w, k / w);
            (1..w.saturating_sub(1)).contains(&x)
                && (1..h.saturating_sub(1)).contains(&y)
                && (0..9).all(|o| alike(&self.pixels[k], &self.pixels[(y + o / 3 - 1) * w + x + o % 3 - 1]))
        };
        (0..w * h).filter(|&k| inside(k)).collect()
    }
}

fn fill<S: RandomStreams>(job: &RenderJob, streams: &S, out: &mut [Guide], threads: usize) {
    let width = job.settings.width as usize;
    in_row_bands(out, width, threads, |first_row, band| {
        for (k, guide) in band.iter_mut().enumerate() {
            let pixel = first_row * width + k;
            let (i, j) = ((pixel % width) as u32, (pixel / width) as u32);
            *guide = first_hit(job, &mut streams.pixel(pixel as u64).stream(0), i, j);
        }
    });
}

/// The most mirror and glass bounces a guide follows before it settles for what it sees.
const SPECULAR_DEPTH: u32 = 8;

/// The guide of pixel `(i, j)` from its sample's stream `rng`, drawn as the render loop draws:
/// at a mirror or glass the guide follows the path's own bounce (the same numbers, so at one
/// sample per pixel the very direction the pixel's value came from) and records the surface
/// seen in it, its colour tinted by the mirror's. A reflection is a picture of another
/// surface, whose edges must stay as sharp as that surface's own.
fn first_hit<R: SampleRng>(job: &RenderJob, rng: &mut R, i: u32, j: u32) -> Guide {
    let scene = &job.scene;
    let mut ray = job.camera.ray(i, j, rng);
    // The shutter time as the render draws it; a medium's seed of 0: the guide records the
    // first surface or scattering point of one possible path, which is all it needs.
    let time = if !scene.is_first_book() && scene.has_motion() { uniform(rng) } else { 0.0 };
    let (mut tint, mut travelled) = (Vec3::ONE, 0.0);
    let casts = SPECULAR_DEPTH.min(job.settings.max_depth);
    for cast in 1..=casts {
        let found = if scene.is_first_book() {
            scene.hit(&ray, Real::INFINITY)
        } else {
            scene.hit_world(&ray, &Probe { time, medium_seed: 0, isa: scene.isa() })
        };
        let Some(hit) = found else {
            let albedo = tint * scene.background.radiance(ray.dir);
            return Guide { albedo, normal: Vec3::ZERO, point: ray.origin, distance: Real::INFINITY };
        };
        travelled += hit.t * ray.dir.length();
        rng.bounce(cast - 1);
        let material = scene.material(&hit);
        let specular = matches!(material, Material::Metal { .. } | Material::Dielectric { .. });
        let bounce = if specular { material.scatter(ray.dir, &hit, &scene.textures, rng) } else { None };
        let Some(bounce) = bounce.filter(|_| cast < casts) else {
            let normal = if hit.normal.dot(ray.dir) > 0.0 { -hit.normal } else { hit.normal };
            let albedo = tint * material.albedo(&hit, &scene.textures);
            return Guide {
                albedo,
                normal: normal.normalize_or_zero(),
                point: hit.point,
                distance: travelled,
            };
        };
        tint *= bounce.attenuation;
        ray = hit.spawn(bounce.direction);
    }
    unreachable!("the last cast returns")
}
