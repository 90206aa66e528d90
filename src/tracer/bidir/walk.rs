//! The random walk that makes both halves of a bidirectional sample: from the camera (the
//! camera path) and from a light (the light path). It is the path tracer's loop (`render.rs`)
//! with nothing gathered on the way: each vertex is kept with its throughput and densities,
//! and the connections are made afterwards (`connect.rs`).
//!
//! One difference between the directions: glass chooses reflection or refraction by
//! Schlick's formula at the angle on the side the walk arrives from, and Schlick's formula is
//! not symmetric. The camera's choice defines the image (it is what `bsdf` renders), so a light
//! path that refracts is weighed by the ratio of the camera's chance of that refraction, read
//! backwards, to its own: both directions then estimate the same light.

use crate::tracer::bidir::chain::{Chain, Leaving, density_through};
use crate::tracer::bidir::vertex::{Kind, Vertex};
use crate::tracer::camera::Camera;
use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::independent::mix;
use crate::tracer::sampling::sampler::SampleRng;
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::Probe;

/// Which way a walk goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// From the camera: radiance flows back along it.
    FromCamera,
    /// From a light: importance flows back along it.
    FromLight,
}

/// How a walk starts from its path's first vertex (pbrt's `RandomWalk` arguments): which way
/// it goes, its first ray with the throughput it carries and the density per unit solid angle
/// its direction was drawn with, its path's time and media seed, and the most vertices its
/// path may hold.
#[derive(Clone, Copy, Debug)]
pub struct Start {
    /// From the camera or from a light.
    pub direction: Direction,
    /// The first ray.
    pub ray: Ray,
    /// Its throughput.
    pub beta: Vec3,
    /// The density its direction was drawn with.
    pub pdf: Real,
    /// The path's time and media seed.
    pub probe: Probe,
    /// The most vertices the path may hold.
    pub max_vertices: usize,
}

/// Extends `path` (which holds its first vertex) by following `start`'s ray until it holds
/// `start.max_vertices`, leaves the scene, or is absorbed. Returns the background light a
/// camera path met on leaving the scene (black for a light path). Each ray counts in `rays`.
pub fn walk<R: SampleRng + ?Sized>(
    scene: &Scene,
    camera: &Camera,
    start: Start,
    rng: &mut R,
    path: &mut Vec<Vertex>,
    rays: &mut u64,
) -> Vec3 {
    let Start { direction, mut ray, mut beta, mut pdf, probe, max_vertices } = start;
    let media = scene.has_media();
    let mut anchor = Anchor { at: path.len() - 1, leaving: Leaving { dir: ray.dir, pdf } };
    for cast in 1u64.. {
        if path.len() >= max_vertices {
            break;
        }
        *rays += 1;
        let medium_seed = if media { mix(probe.medium_seed ^ cast) } else { 0 };
        let Some(hit) = scene.hit_world(&ray, &Probe { medium_seed, ..probe }) else {
            return match direction {
                Direction::FromCamera => beta * scene.background.radiance(ray.dir),
                Direction::FromLight => Vec3::ZERO,
            };
        };
        rng.bounce(cast as u32 - 1);
        let material = scene.material(&hit);
        let mut vertex = Vertex::at(hit, material, &scene.textures, beta);
        if vertex.connectable() || vertex.emitted != Vec3::ZERO {
            link(scene, camera, path, anchor, &mut vertex, Probe { medium_seed: 0, ..probe }, rays);
        }
        path.push(vertex);
        if path.len() >= max_vertices {
            break;
        }
        let Some(scatter) = material.scatter(ray.dir, &hit, &scene.textures, rng) else { break };
        beta *= scatter.attenuation;
        if direction == Direction::FromLight {
            beta *= refraction_reweight(material, ray.dir, &hit, scatter.direction);
        }
        if vertex.connectable() {
            pdf = vertex.direction_pdf(scatter.direction, camera);
            anchor = Anchor { at: path.len() - 1, leaving: Leaving { dir: scatter.direction, pdf } };
        }
        if beta == Vec3::ZERO {
            break;
        }
        ray = hit.spawn(scatter.direction);
    }
    Vec3::ZERO
}

/// The last vertex that scatters into every direction (or the path's first), and how the walk
/// left it: where a chain of mirrors and glass, if one follows, begins (`chain.rs`).
#[derive(Clone, Copy, Debug)]
struct Anchor {
    /// Its index in the path.
    at: usize,
    leaving: Leaving,
}

/// Sets the two densities between `vertex` (which scatters into every direction, or emits)
/// and the anchor it was reached from: straight, or through the mirrors and glass after it
/// (whose rays count in `rays`).
fn link(
    scene: &Scene,
    camera: &Camera,
    path: &mut [Vertex],
    anchor: Anchor,
    vertex: &mut Vertex,
    probe: Probe,
    rays: &mut u64,
) {
    let Anchor { at: a, leaving: Leaving { dir, pdf } } = anchor;
    let last = path[path.len() - 1].point;
    let back = (last - vertex.point).normalize();
    // The other walk's density here: a light's cosine law where this emits, else its lobe.
    let other = if vertex.emitted != Vec3::ZERO {
        back.dot(vertex.normal).max(0.0) / PI
    } else {
        vertex.direction_pdf(back, camera)
    };
    if a == path.len() - 1 {
        let d2 = (vertex.point - path[a].point).length_squared();
        vertex.pdf_fwd = vertex.area_density(pdf, dir, d2);
        path[a].pdf_rev = path[a].area_density(other, back, d2);
        return;
    }
    let chain = &path[a + 1..];
    let forwards = Chain { vertices: chain, backwards: false };
    vertex.pdf_fwd = density_through(scene, &path[a], anchor.leaving, forwards, vertex, probe, rays);
    // No walk draws the camera's point: its density is never asked for.
    if path[a].kind != Kind::Camera {
        let backwards = Chain { vertices: chain, backwards: true };
        let leaving = Leaving { dir: back, pdf: other };
        path[a].pdf_rev = density_through(scene, vertex, leaving, backwards, &path[a], probe, rays);
    }
}

/// For a light path refracted by glass at `hit` (arriving along `incoming`, leaving along
/// `out`): the camera's chance of refracting the other way, over the light path's own
/// (Schlick's reflectance is taken at the angle on the arriving side); 1 otherwise.
fn refraction_reweight(material: &Material, incoming: Vec3, hit: &Hit, out: Vec3) -> Real {
    let Material::Dielectric { ior, fresnel } = *material else { return 1.0 };
    if out.dot(hit.normal) >= 0.0 {
        return 1.0; // reflected: the same angle and side both ways
    }
    let ratio = if hit.front_face { 1.0 / ior } else { ior };
    let own = fresnel.reflectance((-incoming).dot(hit.normal).min(1.0), ratio);
    let camera = fresnel.reflectance((-out).dot(hit.normal).min(1.0), 1.0 / ratio);
    (1.0 - camera) / (1.0 - own)
}
