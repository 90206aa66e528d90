//! **Lights**: what a scene's lights are, in one room (pbrt's `lights.h`): what they give
//! off, how a point is drawn on them and with what density, and where a light path starts.
//! One light, whatever its shape, is a [`Light`]: an `enum` whose arms are the light shapes,
//! each in a file of its own ([`quad`], [`disc`], [`triangle`], [`sphere`]); `gather` finds the lights
//! among a scene's objects. [`power`] holds them all and chooses among them by power; a
//! shadow ray's point is a [`sample`], a light path's start an [`emission`]. Beside them, the
//! glass balls that light is aimed *through* ([`casters`]). How a path uses all this
//! (next-event estimation, multiple importance sampling, manifold samples, the lights'
//! edges) is the `lighting` room's, and bidirectional path tracing's (`bidir`); what a surface
//! emits where a ray meets it is its material's ([`Material::emitted`]).
//!
//! A new light shape is two files: its own here (how a point is drawn on it and with what
//! density, where a light path starts on it, its box), and this one: its `mod` line and its
//! arm of [`Light`] (with its line in each of `Light`'s matches, which the compiler asks for,
//! and in `gather`; `by_area`, `density_at`, `face_normal` and `size` compile whatever they
//! are told, so answer them as [`disc`] does). The estimators ask every light through `Light`
//! and [`power::Lights`], and need no change.
//!
//! The `--light-sampling` setting, [`LightSampling`], is declared here too, below both the
//! estimators and bidirectional path tracing, so that both may name it.
//!
//! [`Material::emitted`]: crate::tracer::shading::material::Material::emitted

pub mod sample;
pub mod quad;
pub mod disc;
pub mod triangle;
pub mod sphere;
pub mod power;
pub mod emission;
pub mod casters;

use rand::Rng;

use crate::tracer::geometry::Shape;
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::lights::disc::DiscLight;
use crate::tracer::lights::quad::QuadLight;
use crate::tracer::lights::sample::{Chosen, LightPoint, LightSample};
use crate::tracer::lights::sphere::SphereLight;
use crate::tracer::lights::triangle::TriangleLight;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::Object;

/// How paths find the lights (`--light-sampling`): four unbiased estimators of the same
/// image, with different noise. Declared here, below both the estimators that use the lights
/// (`lighting/`) and bidirectional path tracing (`bidir/`), so that neither names the other.
///
/// ```
/// use raypool::tracer::lights::LightSampling;
/// assert_eq!(LightSampling::default(), LightSampling::Mis);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum LightSampling {
    /// The material's scattering only: a light is found when a bounce happens to hit it
    /// (the second book's estimator).
    Bsdf,
    /// Each diffuse bounce drawn half the time towards a light, half by the material, and
    /// weighted by the mixture's density (the third book's).
    Mixture,
    /// A shadow ray to a light at every diffuse hit, plus the material's bounce, each
    /// weighted by the power heuristic (multiple importance sampling, as pbrt and Mitsuba);
    /// with glass balls, a light sample through a ball as well (manifold next-event
    /// estimation, as Cycles' shadow caustics).
    #[default]
    Mis,
    /// Bidirectional: a path from a light as well, joined to the camera's path at every pair
    /// of vertices, each joined path weighted by the power heuristic over all the ways of
    /// making it (Veach's BDPT). Finds caustics the others cannot aim at.
    Bdpt,
}

impl LightSampling {
    /// The `--light-sampling` name.
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Bsdf => "bsdf",
            LightSampling::Mixture => "mixture",
            LightSampling::Mis => "mis",
            LightSampling::Bdpt => "bdpt",
        }
    }
}

/// One light's shape, in world space.
#[derive(Clone, Debug)]
pub enum Light {
    /// A quad, drawn by area.
    Quad(QuadLight),
    /// A disc, drawn by area.
    Disc(DiscLight),
    /// A triangle (of a mesh too), drawn by area.
    Triangle(TriangleLight),
    /// A sphere, still or moving, drawn by the cone it fills.
    Sphere(SphereLight),
}

impl Light {
    /// A point drawn on it from `from` at `time` with the numbers `uv`, as the light `chosen`.
    /// `None` where none can be drawn (from inside a sphere, or seen exactly edge-on).
    #[inline(always)]
    pub fn sample(&self, from: Vec3, time: Real, uv: [Real; 2], chosen: Chosen) -> Option<LightSample> {
        match self {
            Light::Quad(quad) => quad.sample(from, uv, chosen),
            Light::Disc(disc) => disc.sample(from, uv, chosen),
            Light::Triangle(triangle) => triangle.sample(from, uv, chosen),
            Light::Sphere(sphere) => sphere.sample(from, time, uv, chosen),
        }
    }

    /// The density, per unit solid angle, with which [`Light::sample`] draws along `ray` (from
    /// its origin, in its unit direction) at `time`, the choice of the light left out; 0 if
    /// the ray misses it.
    #[inline]
    pub fn density_along(&self, ray: &Ray, time: Real) -> Real {
        match self {
            Light::Quad(quad) => quad.density_along(ray),
            Light::Disc(disc) => disc.density_along(ray),
            Light::Triangle(triangle) => triangle.density_along(ray),
            Light::Sphere(sphere) => sphere.density_along(ray, time),
        }
    }

    /// Whether it is drawn uniformly by area, so that its points' density is the same per unit
    /// area on every such light; otherwise [`Light::density_at`] gives it.
    #[inline]
    pub fn by_area(&self) -> bool {
        match self {
            Light::Quad(_) | Light::Disc(_) | Light::Triangle(_) => true,
            Light::Sphere(_) => false,
        }
    }

    /// For a light not drawn by area, the density with which [`Light::sample`] from `from`
    /// draws `point` if it lies on the light at `time` (the light chosen with `chance`).
    #[inline]
    pub fn density_at(&self, from: Vec3, point: Vec3, time: Real, chance: Real) -> Option<Real> {
        match self {
            Light::Sphere(sphere) => sphere.density_at(from, point, time, chance),
            Light::Quad(_) | Light::Disc(_) | Light::Triangle(_) => None,
        }
    }

    /// The normal of a mesh's face that the unit `ray` meets `distance` away, if it is this
    /// light (a shading normal differs from it).
    #[inline]
    pub fn face_normal(&self, ray: &Ray, distance: Real) -> Option<Vec3> {
        match self {
            Light::Triangle(triangle) => triangle.normal_at(ray, distance),
            Light::Quad(_) | Light::Disc(_) | Light::Sphere(_) => None,
        }
    }

    /// Where a light path starts on it at `time`. `None` where it sends no light out.
    pub fn emission<R: Rng + ?Sized>(&self, time: Real, rng: &mut R) -> Option<LightPoint> {
        match self {
            Light::Quad(quad) => Some(quad.emission(rng)),
            Light::Disc(disc) => Some(disc.emission(rng)),
            Light::Triangle(triangle) => Some(triangle.emission(rng)),
            Light::Sphere(sphere) => sphere.emission(time, rng),
        }
    }

    /// The size a ray leaving it is offset by, beside its point's magnitude: a quad's (its
    /// area's square root), a disc's (its radius); 0 for the other shapes.
    pub fn size(&self) -> Real {
        match self {
            Light::Quad(quad) => quad.size(),
            Light::Disc(disc) => disc.size(),
            Light::Triangle(_) | Light::Sphere(_) => 0.0,
        }
    }

    /// Its box: every point a ray can meet it at (a moving sphere's whole path).
    pub fn bounds(&self) -> Aabb {
        match self {
            Light::Quad(quad) => quad.bounds(),
            Light::Disc(disc) => disc.bounds(),
            Light::Triangle(triangle) => triangle.bounds(),
            Light::Sphere(sphere) => sphere.bounds(),
        }
    }
}

/// A light as [`gather`] finds it: its shape, its power (the luminance it gives off times its
/// area) and what it gives off from its front.
#[derive(Clone, Debug)]
struct Found {
    /// The light.
    pub light: Light,
    /// Its power.
    pub power: Real,
    /// What it gives off.
    pub emit: Vec3,
}

impl Bounded for Found {
    fn bounds(&self) -> Aabb {
        self.light.bounds()
    }

    fn centroid(&self) -> Vec3 {
        let b = self.bounds();
        0.5 * (b.min + b.max)
    }
}

/// Appends the lights among `objects`, placed by `place` (their materials in `materials`),
/// to `found`; sets `shaded` if an emitting mesh has normals of its own.
fn gather(
    objects: &[Object],
    place: &Transform,
    materials: &[Material],
    found: &mut Vec<Found>,
    shaded: &mut bool,
) {
    let emit = |material: u32| match materials[material as usize] {
        Material::DiffuseLight { emit, .. } => emit,
        _ => Vec3::ZERO,
    };
    let glow = |material: u32| luminance(emit(material));
    let sphere = |moving: MovingSphere| {
        let light = SphereLight::placed(moving, place);
        let power = light.power(glow(moving.material));
        Found { light: Light::Sphere(light), power, emit: emit(moving.material) }
    };
    for object in objects {
        match object {
            Object::Shape(Shape::Sphere(s)) => found.push(sphere(MovingSphere {
                center0: s.center,
                center1: s.center,
                radius: s.radius,
                material: s.material,
            })),
            Object::Shape(Shape::Moving(moving)) => found.push(sphere(*moving)),
            Object::Shape(Shape::Quad(quad)) if glow(quad.material) > 0.0 => {
                if let Some(light) = QuadLight::placed(quad, place) {
                    let power = light.power(glow(quad.material));
                    found.push(Found { light: Light::Quad(light), power, emit: emit(quad.material) });
                }
            }
            Object::Shape(Shape::Disc(disc)) if glow(disc.material) > 0.0 => {
                if let Some(light) = DiscLight::placed(disc, place) {
                    let power = light.power(glow(disc.material));
                    found.push(Found { light: Light::Disc(light), power, emit: emit(disc.material) });
                }
            }
            Object::Mesh(mesh, material) if glow(*material) > 0.0 => {
                *shaded |= mesh.has_normals();
                for k in 0..mesh.triangle_count() {
                    let light = TriangleLight::placed(mesh.corners(k), place);
                    let power = light.power(glow(*material));
                    found.push(Found { light: Light::Triangle(light), power, emit: emit(*material) });
                }
            }
            Object::Instance(instance) => {
                gather(instance.group.objects(), &instance.transform.then(place), materials, found, shaded)
            }
            // A dark quad, disc or mesh gives off nothing, nor does a medium's boundary (it is
            // not a surface a ray meets). No `_` arm: a shape that emits must be gathered, as a
            // light's density by area is found from its emission alone (`Lights::pdf_of_point`),
            // and an emitter left out would be weighed as if it were drawn: too dark.
            Object::Shape(Shape::Quad(_) | Shape::Disc(_)) | Object::Mesh(..) | Object::Medium(_) => {}
        }
    }
}

/// The luminance of a linear RGB colour (Rec. 709 weights).
fn luminance(c: Vec3) -> Real {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
