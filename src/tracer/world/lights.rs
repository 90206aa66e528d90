//! The lights a path can aim at: every emitting quad and still sphere among a scene's
//! top-level objects, as *Ray Tracing: The Rest of Your Life* and pbrt sample them.
//!
//! - **Choice**: a light is chosen in proportion to its power (the luminance of its `emit`
//!   times its area), so a big bright lamp gets most of the shadow rays.
//! - **A point on it**: a quad uniformly by area (density `d²/(cos θ·A)` per solid angle); a
//!   sphere by the cone of directions it subtends from the point (uniform in that cone, density
//!   `1/(2π(1 − cos θmax))`), which wastes no sample on its far side.
//! - **Density of a direction** ([`Lights::pdf`]): the sum over all lights of the choice
//!   probability times that light's density, the exact density with which [`Lights::sample`]
//!   draws the direction; multiple importance sampling weighs a material's sample by it.
//!
//! Lights inside groups or instances, moving spheres and emitting mesh triangles are not on
//! the list: paths still find them by scattering, and since their density here is 0, the
//! weights stay consistent (an emitter that is never aimed at keeps its whole weight when hit).

use std::f64::consts::PI;

use rand::Rng;

use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::warp::uniform;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::Object;

/// π in the tracer's precision.
const PI_REAL: Real = PI as Real;

/// One light's shape.
#[derive(Clone, Debug)]
enum Shape {
    Quad(Quad),
    Sphere(Sphere),
}

/// A direction towards a light, drawn by [`Lights::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point.
    pub dir: Vec3,
    /// Distance along `dir` to the light's surface.
    pub distance: Real,
}

/// The scene's lights and the probabilities of choosing each.
#[derive(Clone, Debug, Default)]
pub struct Lights {
    shapes: Vec<Shape>,
    /// Probability of choosing each light (summing to 1).
    chance: Vec<Real>,
    /// Running sums of `chance`, for the choice.
    running: Vec<Real>,
}

impl Lights {
    /// The emitting quads and still spheres among `objects` (their materials in `materials`).
    ///
    /// ```
    /// use raypool::tracer::geometry::quad::Quad;
    /// use raypool::tracer::math::real::Vec3;
    /// use raypool::tracer::shading::material::Material;
    /// use raypool::tracer::world::{lights::Lights, object::Object};
    /// let lamp = Quad::new(Vec3::new(-1.0, 2.0, -1.0), Vec3::X * 2.0, Vec3::Z * 2.0, 0).unwrap();
    /// let lights = Lights::new(&[Object::Quad(lamp)], &[Material::DiffuseLight { emit: Vec3::ONE, albedo: 0.0 }]);
    /// assert_eq!(lights.len(), 1);
    /// ```
    pub fn new(objects: &[Object], materials: &[Material]) -> Lights {
        let power = |material: u32, area: Real| match materials[material as usize] {
            Material::DiffuseLight { emit, .. } => luminance(emit) * area,
            _ => 0.0,
        };
        let mut found: Vec<(Shape, Real)> = Vec::new();
        for object in objects {
            let light = match object {
                Object::Quad(quad) => {
                    (Shape::Quad(*quad), power(quad.material, quad.u.cross(quad.v).length()))
                }
                Object::Sphere(sphere) if sphere.radius > 0.0 => (
                    Shape::Sphere(*sphere),
                    power(sphere.material, 4.0 * PI_REAL * sphere.radius * sphere.radius),
                ),
                _ => continue,
            };
            if light.1 > 0.0 && light.1.is_finite() {
                found.push(light);
            }
        }
        let total: Real = found.iter().map(|l| l.1).sum();
        let chance: Vec<Real> = found.iter().map(|l| l.1 / total).collect();
        let mut sum = 0.0;
        let running = chance.iter().map(|c| {
            sum += c;
            sum
        });
        let running = running.collect();
        Lights { shapes: found.into_iter().map(|l| l.0).collect(), chance, running }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether the scene has no light to aim at.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// A direction from `from` towards a light: three draws (the choice, then a point on it).
    /// `None` if there is no light, or `from` is inside the chosen sphere.
    #[inline]
    pub fn sample<R: Rng + ?Sized>(&self, from: Vec3, rng: &mut R) -> Option<LightSample> {
        let pick = uniform(rng);
        let (a, b) = (uniform(rng), uniform(rng));
        let k = self.running.iter().position(|&r| pick < r).unwrap_or(self.shapes.len().checked_sub(1)?);
        match &self.shapes[k] {
            Shape::Quad(quad) => {
                let to = quad.q + a * quad.u + b * quad.v - from;
                let distance = to.length();
                (distance > 0.0).then(|| LightSample { dir: to / distance, distance })
            }
            Shape::Sphere(sphere) => {
                let (axis, cos_max) = cone(sphere, from)?;
                let cos = 1.0 - a * (1.0 - cos_max);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let (s, c) = (2.0 * PI_REAL * b).sin_cos();
                let (t1, t2) = axis.any_orthonormal_pair();
                let dir = (cos * axis + sin * (c * t1 + s * t2)).normalize();
                // The near side of the sphere along `dir`, from the angle itself (as pbrt
                // does): a ray test would miss now and then at the cone's grazing edge.
                let d = (sphere.center - from).length();
                let r = sphere.radius;
                let distance = d * cos - (r * r - d * d * sin * sin).max(0.0).sqrt();
                Some(LightSample { dir, distance })
            }
        }
    }

    /// The density, per unit solid angle, with which [`Lights::sample`] draws the unit
    /// direction `dir` from `from` (0 where no light lies that way).
    #[inline]
    pub fn pdf(&self, from: Vec3, dir: Vec3) -> Real {
        let ray = Ray::new(from, dir);
        let mut sum = 0.0;
        for (shape, &chance) in self.shapes.iter().zip(&self.chance) {
            sum += chance
                * match shape {
                    Shape::Quad(quad) => quad.intersect(&ray, Real::INFINITY).map_or(0.0, |(t, _, _)| {
                        let cos = dir.dot(quad.normal()).abs();
                        t * t / (cos * quad.u.cross(quad.v).length())
                    }),
                    Shape::Sphere(sphere) => cone(sphere, from).map_or(0.0, |(axis, cos_max)| {
                        if dir.dot(axis) >= cos_max { 1.0 / (2.0 * PI_REAL * (1.0 - cos_max)) } else { 0.0 }
                    }),
                };
        }
        if sum.is_finite() { sum } else { 0.0 }
    }
}

/// The cone of directions `sphere` fills as seen from `from`: its axis (unit, towards the
/// centre) and the cosine of its half-angle; `None` from inside or on the sphere.
fn cone(sphere: &Sphere, from: Vec3) -> Option<(Vec3, Real)> {
    let to = sphere.center - from;
    let d2 = to.length_squared();
    let r2 = sphere.radius * sphere.radius;
    if d2 <= r2 {
        return None;
    }
    // 1 − cos θmax computed as sin²/(1 + cos) would be steadier for far, small spheres; the
    // plain form is kept while the sampling uses it too (both must agree exactly).
    let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
    (cos_max < 1.0).then(|| (to / d2.sqrt(), cos_max))
}

/// The luminance of a linear RGB colour (Rec. 709 weights).
fn luminance(c: Vec3) -> Real {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
