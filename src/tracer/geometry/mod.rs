//! **Geometry**: the shapes rays meet, each in a file of its own with its robust ray test, and
//! [`hit`], what every test reports: [`sphere`]s, [`moving`] spheres (motion blur), the second
//! book's [`quad`]s (and boxes of six; [`quads`] tests eight at once), pbrt's [`disc`]s, and
//! [`triangle`]s (the watertight test meshes use); and the [`cone`] a sphere fills seen from a
//! point, by which a sphere light is aimed at.
//!
//! [`Shape`] is any one of the simple shapes, as pbrt's `Shape` is: the rooms above ask a
//! `Shape` for its hit, box and material and never name the kinds, except where a kind has a
//! way of its own (a group tests its quads eight at once, `lights/` makes each kind's light).
//! So a new shape's geometry is its file here and its arm in each of `Shape`'s matches below
//! (its other places: the book's architecture chapter). What is built from shapes (meshes,
//! instances, media) is the `world` room's.

pub mod hit;
pub mod sphere;
pub mod moving;
pub mod quad;
pub mod quads;
pub mod disc;
pub mod triangle;
pub mod cone;

use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use disc::Disc;
use hit::Hit;
use moving::MovingSphere;
use quad::Quad;
use sphere::Sphere;

/// One simple shape, of any kind. `time` is the instant in the shutter interval a ray
/// samples (only a moving sphere reads it).
///
/// ```
/// use raypool::tracer::geometry::{Shape, sphere::Sphere};
/// use raypool::tracer::math::{ray::Ray, real::Vec3};
/// let ball = Shape::from(Sphere { center: Vec3::ZERO, radius: 1.0, material: 3 });
/// let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
/// assert_eq!(ball.hit(&ray, 10.0, 0.0).map(|hit| hit.t), Some(4.0));
/// assert!(!ball.intersects(&ray, 3.0, 0.0), "nothing before t = 3");
/// assert_eq!(ball.material(), 3);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere, tested with the robust test of `sphere.rs`.
    Sphere(Sphere),
    /// A sphere moving during the shutter interval.
    Moving(MovingSphere),
    /// A parallelogram.
    Quad(Quad),
    /// A disc.
    Disc(Disc),
}

impl Shape {
    /// The nearest hit in `(0, t_max)`, if any, without the texture coordinates
    /// [`Shape::with_uv`] adds.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, time: Real) -> Option<Hit> {
        match self {
            Shape::Sphere(sphere) => sphere.hit(ray, t_max),
            Shape::Moving(moving) => moving.at(time).hit(ray, t_max),
            Shape::Quad(quad) => {
                let (t, alpha, beta) = quad.intersect(ray, t_max)?;
                Some(quad.hit_at(t, alpha, beta, ray.dir.dot(quad.normal()) < 0.0))
            }
            Shape::Disc(disc) => disc.hit(ray, t_max),
        }
    }

    /// Whether it is hit in `(0, t_max)` (a shadow ray's question: no hit record is made).
    #[inline]
    pub fn intersects(&self, ray: &Ray, t_max: Real, time: Real) -> bool {
        match self {
            Shape::Sphere(sphere) => sphere.intersect(ray, t_max).is_some(),
            Shape::Moving(moving) => moving.at(time).intersect(ray, t_max).is_some(),
            Shape::Quad(quad) => quad.intersect(ray, t_max).is_some(),
            Shape::Disc(disc) => disc.intersect(ray, t_max).is_some(),
        }
    }

    /// `hit`, the closest of a search and one of [`Shape::hit`]'s, with its texture
    /// coordinates, where the kind leaves them out of `hit` ([`Shape::late_uv`]).
    #[inline]
    pub fn with_uv(&self, hit: Hit, time: Real) -> Hit {
        match self {
            Shape::Sphere(sphere) => sphere.with_uv(hit),
            Shape::Moving(moving) => moving.at(time).with_uv(hit),
            Shape::Disc(disc) => disc.with_uv(hit),
            Shape::Quad(_) => hit,
        }
    }

    /// Whether [`Shape::with_uv`] adds anything: a sphere's and a disc's texture coordinates
    /// take an arc tangent, paid for the closest hit only, and only where a material reads
    /// them; a quad's cost nothing, and `hit` makes them.
    pub fn late_uv(&self) -> bool {
        match self {
            Shape::Sphere(_) | Shape::Moving(_) | Shape::Disc(_) => true,
            Shape::Quad(_) => false,
        }
    }

    /// Index of its material in the scene's table.
    pub fn material(&self) -> u32 {
        match self {
            Shape::Sphere(sphere) => sphere.material,
            Shape::Moving(moving) => moving.material,
            Shape::Quad(quad) => quad.material,
            Shape::Disc(disc) => disc.material,
        }
    }

    /// Whether it moves while the shutter is open.
    pub fn moves(&self) -> bool {
        matches!(self, Shape::Moving(moving) if moving.center0 != moving.center1)
    }
}

impl Bounded for Shape {
    fn bounds(&self) -> Aabb {
        match self {
            Shape::Sphere(sphere) => sphere.bounds(),
            Shape::Moving(moving) => moving.bounds(),
            Shape::Quad(quad) => quad.bounds(),
            Shape::Disc(disc) => disc.bounds(),
        }
    }

    /// The point a tree sorts it by: a sphere's or a disc's centre, else its box's.
    fn centroid(&self) -> Vec3 {
        match self {
            Shape::Sphere(sphere) => sphere.center,
            Shape::Disc(disc) => disc.center,
            Shape::Moving(_) | Shape::Quad(_) => {
                let b = self.bounds();
                0.5 * (b.min + b.max)
            }
        }
    }
}

impl From<Sphere> for Shape {
    fn from(sphere: Sphere) -> Shape {
        Shape::Sphere(sphere)
    }
}

impl From<MovingSphere> for Shape {
    fn from(moving: MovingSphere) -> Shape {
        Shape::Moving(moving)
    }
}

impl From<Quad> for Shape {
    fn from(quad: Quad) -> Shape {
        Shape::Quad(quad)
    }
}

impl From<Disc> for Shape {
    fn from(disc: Disc) -> Shape {
        Shape::Disc(disc)
    }
}
