//! The lights a path can aim at: every emitting quad, triangle (of a mesh too) and sphere (a
//! moving one where it is at the path's time), at the top level or inside instances, as *Ray
//! Tracing: The Rest of Your Life* and pbrt sample them.
//!
//! - **Choice**: a light is chosen in proportion to its power (the luminance of its `emit`
//!   times its area), so a big bright lamp gets most of the shadow rays. Every flat light is
//!   then drawn uniformly by area, so a point on any of them has the same density per unit
//!   area, `luminance(emit) / total power`: a hit knows it without knowing which light it is.
//! - **A point on it**: a quad or triangle uniformly by area (density `d²/(cos θ·A)` per
//!   solid angle); a sphere uniformly over the [`Cone`] it fills from the point.
//! - **Densities**: a sample carries the exact density with which it was drawn, which the
//!   shadow ray's estimate divides by. Multiple importance sampling weighs the two ways of
//!   reaching an emitter's point by [`Lights::pdf_of_point`], the density of drawing that very
//!   point, computed from the point alone so that a shadow ray and a bounce that reach the
//!   same point weigh it the same (the weights of a point then sum to 1, and the estimate stays
//!   unbiased); [`Lights::pdf_of_sample`] skips the lookup where only one answer is possible.
//!   The third book's mixture needs the density of a *direction* over every light it crosses
//!   ([`Lights::pdf`]): a sum over the lights whose boxes the direction enters, found through
//!   a four-wide tree of them (as a group's objects are) once there are six.

use rand::Rng;

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::wide::WideBvh;
use crate::tracer::geometry::cone::Cone;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::triangle;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::{Object, TREE_MIN_OBJECTS};

/// Lights per leaf of the lights' tree.
const LEAF: usize = 4;

/// One light's shape, in world space.
#[derive(Clone, Debug)]
pub(super) enum Shape {
    Quad(Quad),
    /// Corners, unit geometric normal and area.
    Triangle([Vec3; 3], Vec3, Real),
    /// Still spheres too, with equal end points.
    Sphere(MovingSphere),
}

/// A point on a light drawn by [`Lights::sample`], and the direction towards it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point.
    pub dir: Vec3,
    /// Distance along `dir` to the light's surface.
    pub distance: Real,
    /// The density, per unit solid angle, with which this direction was drawn (the light's
    /// choice included), > 0 and finite.
    pub pdf: Real,
    /// The point on the light.
    pub point: Vec3,
    /// The light's unit geometric normal there.
    pub normal: Vec3,
    /// What the point gives off towards the shading point (zero from behind: a light emits
    /// from its front only).
    pub emitted: Vec3,
    /// Which light it was drawn on.
    pub light: usize,
}

/// The scene's lights and the probabilities of choosing each.
#[derive(Clone, Debug, Default)]
pub struct Lights {
    pub(super) shapes: Vec<Shape>,
    /// Probability of choosing each light (summing to 1).
    chance: Vec<Real>,
    /// What each light gives off from its front.
    pub(super) emit: Vec<Vec3>,
    /// Running sums of `chance`, for the choice.
    pub(super) running: Vec<Real>,
    /// The sum of the lights' powers.
    pub(super) total: Real,
    /// Which of `shapes` are spheres (a hit on one is told apart by where it lies).
    spheres: Vec<usize>,
    /// Per light, whether no other sphere light comes near it ([`apart`]).
    apart: Vec<bool>,
    /// Whether some emitting mesh is shaded by normals from its file: a hit on it then tells
    /// the shading normal, not the face's ([`Lights::pdf_of_hit`] looks the face up).
    shaded: bool,
    /// A box around every point of every light (at any time); empty without lights.
    pub(crate) bounds: Aabb,
    /// A four-wide tree over the lights' boxes, once there are enough of them: the mixture's
    /// density visits only the lights a direction can meet (an emitting mesh may hold
    /// thousands).
    tree: Option<WideBvh>,
}

impl Lights {
    /// The emitting quads, triangles and spheres among `objects` and inside their instances
    /// (their materials in `materials`), placed in the world.
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
        let mut found: Vec<(Shape, Real, Vec3)> = Vec::new();
        let mut shaded = false;
        collect(objects, &Transform::IDENTITY, materials, &mut found, &mut shaded);
        found.retain(|light| light.1 > 0.0 && light.1.is_finite());
        // The tree reorders the lights; every list below follows its order.
        let tree = (found.len() >= TREE_MIN_OBJECTS).then(|| {
            let binary = Bvh::build_with_leaves(&mut found, LEAF);
            WideBvh::collapse_plain(&binary, found.len())
        });
        let total: Real = found.iter().map(|l| l.1).sum();
        let chance: Vec<Real> = found.iter().map(|l| l.1 / total).collect();
        let mut sum = 0.0;
        let running = chance.iter().map(|c| {
            sum += c;
            sum
        });
        let running = running.collect();
        let spheres = found.iter().enumerate().filter(|(_, l)| matches!(l.0, Shape::Sphere(_)));
        let spheres = spheres.map(|(k, _)| k).collect();
        let emit = found.iter().map(|l| l.2).collect();
        let apart = apart(&found);
        let bounds = found.iter().fold(Aabb::EMPTY, |b, light| b.union(light.bounds()));
        Lights {
            shapes: found.into_iter().map(|l| l.0).collect(),
            chance,
            emit,
            running,
            total,
            spheres,
            apart,
            shaded,
            bounds,
            tree,
        }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether the scene has no light to aim at.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// A direction from `from` towards a light at `time`: three draws (the choice, then a
    /// point on it). `None` if there is no light, `from` is inside the chosen sphere, or the
    /// point drawn is seen exactly edge-on.
    #[inline]
    pub fn sample<R: Rng + ?Sized>(&self, from: Vec3, time: Real, rng: &mut R) -> Option<LightSample> {
        let pick = uniform(rng);
        let (a, b) = (uniform(rng), uniform(rng));
        let k = self.running.partition_point(|&r| r <= pick).min(self.shapes.len().checked_sub(1)?);
        let (chance, emit) = (self.chance[k], self.emit[k]);
        let toward_area = |point: Vec3, normal: Vec3, area: Real| {
            let to = point - from;
            let distance = to.length();
            let dir = to / distance;
            let cos = dir.dot(normal);
            let pdf = chance * distance * distance / (cos.abs() * area);
            // From its front (the direction against the normal), as `Quad::hit_at` decides.
            let emitted = if cos < 0.0 { emit } else { Vec3::ZERO };
            let sample = LightSample { dir, distance, pdf, point, normal, emitted, light: k };
            (distance > 0.0 && pdf > 0.0 && pdf.is_finite()).then_some(sample)
        };
        match &self.shapes[k] {
            Shape::Quad(quad) => toward_area(quad.q + a * quad.u + b * quad.v, quad.normal(), quad.area()),
            Shape::Triangle(p, normal, area) => {
                // Uniform by area: the square root spreads the first number over the
                // triangle's height (pbrt's `SampleUniformTriangle`, in its older form).
                let r = a.sqrt();
                let point = p[0] + (r * (1.0 - b)) * (p[1] - p[0]) + (r * b) * (p[2] - p[0]);
                toward_area(point, *normal, *area)
            }
            Shape::Sphere(moving) => {
                let sphere = moving.at(time);
                let cone = Cone::of(&sphere, from)?;
                let (dir, point) = cone.draw(&sphere, a, b);
                let distance = (point - from).length();
                let pdf = cone.density(chance);
                let r = sphere.radius;
                let normal = (point - sphere.center) / r;
                // Seen from outside: the front of a sphere, the back of an inward shell.
                let emitted = if r > 0.0 { emit } else { Vec3::ZERO };
                Some(LightSample { dir, distance, pdf, point, normal, emitted, light: k })
            }
        }
    }

    /// The density, per unit solid angle, with which [`Lights::sample`] from `from` at `time`
    /// draws a point on some light along the unit direction `dir`, summed over every light
    /// that way (0 where none lies): the third book's mixture weighs its bounce by it.
    #[inline]
    pub fn pdf(&self, from: Vec3, dir: Vec3, time: Real) -> Real {
        let ray = Ray::new(from, dir);
        let mut sum = 0.0;
        let mut add = |k: usize| sum += self.chance[k] * self.density_along(k, &ray, time);
        match &self.tree {
            None => (0..self.shapes.len()).for_each(&mut add),
            // Nothing is offered to the search's bound, so every box the ray enters is visited.
            Some(tree) => {
                tree.traverse(&ray, &mut Closest::none(Real::INFINITY), |leaf, _| leaf.for_each(&mut add))
            }
        }
        if sum.is_finite() { sum } else { 0.0 }
    }

    /// The density, per unit solid angle, with which light `k` alone is drawn along `ray`
    /// (from its origin, in its unit direction) at `time`; 0 if the ray misses it.
    #[inline]
    fn density_along(&self, k: usize, ray: &Ray, time: Real) -> Real {
        let by_area = |t: Real, normal: Vec3, area: Real| t * t / (ray.dir.dot(normal).abs() * area);
        match &self.shapes[k] {
            Shape::Quad(quad) => quad
                .intersect(ray, Real::INFINITY)
                .map_or(0.0, |(t, _, _)| by_area(t, quad.normal(), quad.area())),
            Shape::Triangle(p, normal, area) => triangle::intersect(*p, ray, Real::INFINITY)
                .map_or(0.0, |found| by_area(found.t, *normal, *area)),
            Shape::Sphere(moving) => Cone::of(&moving.at(time), ray.origin)
                .filter(|cone| cone.contains(ray.dir))
                .map_or(0.0, |cone| cone.density(1.0)),
        }
    }

    /// The density, per unit solid angle seen from `from`, with which [`Lights::sample`]
    /// draws the point `point` of an emitter (normal `normal`, at `time`) that gives off
    /// `emitted`: by the cone of the sphere light the point lies on, else by area,
    /// `luminance(emitted) / total power · d² / cos θ`. A function of the point alone, so that
    /// the shadow ray that reaches a point and the bounce that meets it weigh it alike (0 when
    /// not finite: the point then counts by bouncing only, under both).
    #[inline]
    pub fn pdf_of_point(&self, from: Vec3, point: Vec3, normal: Vec3, emitted: Vec3, time: Real) -> Real {
        if let Some(pdf) = self.sphere_pdf_of_point(from, point, time) {
            return pdf;
        }
        self.pdf_by_area(from, point, normal, emitted)
    }

    /// The density [`Lights::pdf_of_point`] gives the point `sample` drew (from `from`, at
    /// `time`); for a light apart from every other sphere light, without its lookup (which
    /// cost as much as the shadow ray with many sphere lights): the sample's own cone density,
    /// computed by the same expression, or a flat light's by area.
    #[inline]
    pub fn pdf_of_sample(&self, from: Vec3, sample: &LightSample, time: Real) -> Real {
        let (point, normal, emitted) = (sample.point, sample.normal, sample.emitted);
        if !self.apart[sample.light] {
            return self.pdf_of_point(from, point, normal, emitted, time);
        }
        match self.shapes[sample.light] {
            Shape::Sphere(_) => sample.pdf,
            Shape::Quad(_) | Shape::Triangle(..) => self.pdf_by_area(from, point, normal, emitted),
        }
    }

    /// The density per unit solid angle of drawing `point` on a flat light (every flat light
    /// has the same density per unit area); 0 where not finite.
    #[inline]
    fn pdf_by_area(&self, from: Vec3, point: Vec3, normal: Vec3, emitted: Vec3) -> Real {
        let to = point - from;
        let d2 = to.length_squared();
        let pdf = luminance(emitted) / self.total * d2 / (to.dot(normal).abs() / d2.sqrt());
        if pdf.is_finite() { pdf } else { 0.0 }
    }

    /// [`Lights::pdf_of_point`] for a bounce's `hit` on an emitter (from `from`): with the
    /// face's own normal where the hit's is a mesh's shading normal (the shadow ray weighs
    /// the point by its face's, so must the bounce, or the two weights would not sum to 1).
    #[inline]
    pub fn pdf_of_hit(&self, from: Vec3, hit: &Hit, emitted: Vec3, time: Real) -> Real {
        let normal =
            if self.shaded { self.face_normal(from, hit.point).unwrap_or(hit.normal) } else { hit.normal };
        self.pdf_of_point(from, hit.point, normal, emitted, time)
    }

    /// The normal of the emitting triangle the way from `from` meets at `point`, if any.
    fn face_normal(&self, from: Vec3, point: Vec3) -> Option<Vec3> {
        let to = point - from;
        let distance = to.length();
        let ray = Ray::new(from, to / distance);
        let at_point = |k: usize| match &self.shapes[k] {
            Shape::Triangle(p, normal, _) => triangle::intersect(*p, &ray, 1.001 * distance)
                .filter(|found| found.t >= 0.999 * distance)
                .map(|_| *normal),
            _ => None,
        };
        self.first_on_the_way(&ray, distance, 0..self.shapes.len(), at_point)
    }

    /// The cone density of the sphere light whose surface `point` lies on, if there is one:
    /// the spheres tested one by one, or, with a tree, those whose boxes the way from `from` to
    /// `point` enters.
    #[inline]
    fn sphere_pdf_of_point(&self, from: Vec3, point: Vec3, time: Real) -> Option<Real> {
        let on_sphere = |k: usize| {
            let Shape::Sphere(moving) = &self.shapes[k] else { return None };
            let sphere = moving.at(time);
            let r2 = sphere.radius * sphere.radius;
            (((point - sphere.center).length_squared() - r2).abs() <= 1e-3 * r2)
                .then(|| Cone::of(&sphere, from).map_or(0.0, |cone| cone.density(self.chance[k])))
        };
        if self.spheres.is_empty() {
            return None;
        }
        let to = point - from;
        let distance = to.length();
        let ray = Ray::new(from, to / distance);
        self.first_on_the_way(&ray, distance, self.spheres.iter().copied(), on_sphere)
    }

    /// The first answer `at` gives for a light the unit `ray` can meet within `distance`:
    /// among `candidates` one by one, or, with a tree, among the lights whose boxes the ray
    /// enters (the search ends at the first answer).
    fn first_on_the_way<T>(
        &self,
        ray: &Ray,
        distance: Real,
        candidates: impl Iterator<Item = usize>,
        at: impl Fn(usize) -> Option<T>,
    ) -> Option<T> {
        let Some(tree) = &self.tree else { return candidates.into_iter().find_map(at) };
        let mut found = None;
        tree.traverse(ray, &mut Closest::none(1.001 * distance), |leaf, closest| {
            if found.is_none() {
                found = leaf.into_iter().find_map(&at);
                if found.is_some() {
                    closest.rule_out_rest();
                }
            }
        });
        found
    }
}

/// Appends the lights among `objects`, placed by `place`, with their powers and emission;
/// sets `shaded` if an emitting mesh has normals of its own.
fn collect(
    objects: &[Object],
    place: &Transform,
    materials: &[Material],
    found: &mut Vec<(Shape, Real, Vec3)>,
    shaded: &mut bool,
) {
    let emit = |material: u32| match materials[material as usize] {
        Material::DiffuseLight { emit, .. } => emit,
        _ => Vec3::ZERO,
    };
    let glow = |material: u32| luminance(emit(material));
    let sphere = |moving: MovingSphere| {
        let (center0, center1) = (place.point(moving.center0), place.point(moving.center1));
        let power = glow(moving.material) * 4.0 * PI * moving.radius * moving.radius;
        (Shape::Sphere(MovingSphere { center0, center1, ..moving }), power, emit(moving.material))
    };
    for object in objects {
        match object {
            Object::Sphere(s) => found.push(sphere(MovingSphere {
                center0: s.center,
                center1: s.center,
                radius: s.radius,
                material: s.material,
            })),
            Object::Moving(moving) => found.push(sphere(*moving)),
            Object::Quad(quad) if glow(quad.material) > 0.0 => {
                let placed =
                    Quad::new(place.point(quad.q), place.vector(quad.u), place.vector(quad.v), quad.material);
                if let Some(placed) = placed {
                    let power = glow(quad.material) * placed.area();
                    found.push((Shape::Quad(placed), power, emit(quad.material)));
                }
            }
            Object::Mesh(mesh, material) if glow(*material) > 0.0 => {
                *shaded |= mesh.has_normals();
                for k in 0..mesh.triangle_count() {
                    let p = mesh.corners(k).map(|corner| place.point(corner));
                    let n = (p[1] - p[0]).cross(p[2] - p[0]);
                    let area = 0.5 * n.length();
                    let triangle = Shape::Triangle(p, n.normalize_or_zero(), area);
                    found.push((triangle, glow(*material) * area, emit(*material)));
                }
            }
            Object::Instance(instance) => {
                collect(instance.group.objects(), &instance.transform.then(place), materials, found, shaded)
            }
            // A medium's boundary gives off nothing (it is not a surface a ray meets).
            _ => {}
        }
    }
}

/// Per light, whether no *other* sphere light comes near it (their boxes, widened by 1% of
/// their size, far beyond the lookup's tolerance `|d² − r²| ≤ 10⁻³ r²`, do not meet), so that
/// its points lie on no other sphere. Sphere lights are swept in order of their lower x.
fn apart(found: &[(Shape, Real, Vec3)]) -> Vec<bool> {
    let reach = |light: &(Shape, Real, Vec3)| {
        let b = light.bounds();
        b.padded(0.01 * (b.max - b.min).length() + 8.0 * Real::EPSILON * b.magnitude())
    };
    let spheres = found.iter().enumerate().filter(|(_, l)| matches!(l.0, Shape::Sphere(_)));
    let mut spheres: Vec<(usize, Aabb)> = spheres.map(|(k, l)| (k, reach(l))).collect();
    spheres.sort_by(|a, b| a.1.min.x.total_cmp(&b.1.min.x));
    let widest = spheres.iter().fold(0.0, |w: Real, (_, b)| w.max(b.max.x - b.min.x));
    let alone = |(k, light): (usize, &(Shape, Real, Vec3))| {
        let own = reach(light);
        let first = spheres.partition_point(|(_, other)| other.min.x < own.min.x - widest);
        let mut near = spheres[first..].iter().take_while(|(_, other)| other.min.x <= own.max.x);
        !near.any(|(j, other)| *j != k && own.meets(other))
    };
    found.iter().enumerate().map(alone).collect()
}

impl Bounded for (Shape, Real, Vec3) {
    /// The light's box: every point a ray can meet it at (a moving sphere's whole path).
    fn bounds(&self) -> Aabb {
        match &self.0 {
            Shape::Quad(quad) => quad.bounds(),
            Shape::Triangle(p, ..) => {
                let corners = p.iter().fold(Aabb::EMPTY, |b, &c| b.grow(c));
                corners.padded(8.0 * Real::EPSILON * corners.magnitude())
            }
            Shape::Sphere(moving) => moving.bounds(),
        }
    }

    fn centroid(&self) -> Vec3 {
        let b = self.bounds();
        0.5 * (b.min + b.max)
    }
}

/// The luminance of a linear RGB colour (Rec. 709 weights).
pub(super) fn luminance(c: Vec3) -> Real {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
