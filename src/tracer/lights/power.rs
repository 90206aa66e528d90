//! The scene's lights, all together: which one a sample is drawn on, and the density of a
//! point or a direction over all of them (pbrt's `PowerLightSampler`, and its `PDF_Li` summed
//! over the lights). Every emitting quad, disc, triangle (of a mesh too) and sphere (a moving
//! one where it is at the path's time), at the top level or inside instances, is one [`Light`].
//!
//! - **Choice**: a light is chosen in proportion to its power (the luminance of its `emit`
//!   times its area), so a big bright lamp gets most of the shadow rays. Every flat light is
//!   then drawn uniformly by area, so a point on any of them has the same density per unit
//!   area, `luminance(emit) / total power`: a hit knows it without knowing which light it is.
//! - **A point on it**: the light's own file says how (a quad, disc or triangle by area,
//!   density `d²/(cos θ·A)` per solid angle; a sphere uniformly over the cone it fills from
//!   the point).
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
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::lights::sample::{Chosen, LightSample};
use crate::tracer::lights::{Found, Light, gather, luminance};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::warp::uniform;
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::{Object, TREE_MIN_OBJECTS};

/// Lights per leaf of the lights' tree.
const LEAF: usize = 4;

/// The scene's lights and the probabilities of choosing each.
#[derive(Clone, Debug, Default)]
pub struct Lights {
    pub(super) lights: Vec<Light>,
    /// Probability of choosing each light (summing to 1).
    chance: Vec<Real>,
    /// What each light gives off from its front.
    pub(super) emit: Vec<Vec3>,
    /// Running sums of `chance`, for the choice.
    pub(super) running: Vec<Real>,
    /// The sum of the lights' powers.
    pub(super) total: Real,
    /// Which lights are not drawn by area (spheres, drawn by their cone): a point on one is told
    /// apart by where it lies.
    by_cone: Vec<usize>,
    /// Per light, whether no other light drawn by its cone comes near it ([`apart`]).
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
    /// The emitting quads, discs, triangles and spheres among `objects` and inside their instances
    /// (their materials in `materials`), placed in the world.
    ///
    /// ```
    /// use raypool::tracer::geometry::quad::Quad;
    /// use raypool::tracer::math::real::Vec3;
    /// use raypool::tracer::shading::material::Material;
    /// use raypool::tracer::lights::power::Lights;
    /// use raypool::tracer::world::object::Object;
    /// let lamp = Quad::new(Vec3::new(-1.0, 2.0, -1.0), Vec3::X * 2.0, Vec3::Z * 2.0, 0).unwrap();
    /// let lights = Lights::new(&[Object::shape(lamp)], &[Material::DiffuseLight { emit: Vec3::ONE, albedo: 0.0 }]);
    /// assert_eq!(lights.len(), 1);
    /// ```
    pub fn new(objects: &[Object], materials: &[Material]) -> Lights {
        let mut found: Vec<Found> = Vec::new();
        let mut shaded = false;
        gather(objects, &Transform::IDENTITY, materials, &mut found, &mut shaded);
        found.retain(|light| light.power > 0.0 && light.power.is_finite());
        // The tree reorders the lights; every list below follows its order.
        let tree = (found.len() >= TREE_MIN_OBJECTS).then(|| {
            let binary = Bvh::build_with_leaves(&mut found, LEAF);
            WideBvh::collapse_plain(&binary, found.len())
        });
        let total: Real = found.iter().map(|l| l.power).sum();
        let chance: Vec<Real> = found.iter().map(|l| l.power / total).collect();
        let mut sum = 0.0;
        let running = chance.iter().map(|c| {
            sum += c;
            sum
        });
        let running = running.collect();
        let by_cone = found.iter().enumerate().filter(|(_, l)| !l.light.by_area());
        let by_cone = by_cone.map(|(k, _)| k).collect();
        let emit = found.iter().map(|l| l.emit).collect();
        let apart = apart(&found);
        let bounds = found.iter().fold(Aabb::EMPTY, |b, light| b.union(light.bounds()));
        Lights {
            lights: found.into_iter().map(|l| l.light).collect(),
            chance,
            emit,
            running,
            total,
            by_cone,
            apart,
            shaded,
            bounds,
            tree,
        }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    /// Whether the scene has no light to aim at.
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// A direction from `from` towards a light at `time`: three draws (the choice, then a
    /// point on it). `None` if there is no light, `from` is inside the chosen sphere, or the
    /// point drawn is seen exactly edge-on.
    #[inline]
    pub fn sample<R: Rng + ?Sized>(&self, from: Vec3, time: Real, rng: &mut R) -> Option<LightSample> {
        let pick = uniform(rng);
        let (a, b) = (uniform(rng), uniform(rng));
        let k = self.running.partition_point(|&r| r <= pick).min(self.lights.len().checked_sub(1)?);
        let chosen = Chosen { light: k, chance: self.chance[k], emit: self.emit[k] };
        self.lights[k].sample(from, time, [a, b], chosen)
    }

    /// The density, per unit solid angle, with which [`Lights::sample`] from `from` at `time`
    /// draws a point on some light along the unit direction `dir`, summed over every light
    /// that way (0 where none lies): the third book's mixture weighs its bounce by it.
    #[inline]
    pub fn pdf(&self, from: Vec3, dir: Vec3, time: Real) -> Real {
        let ray = Ray::new(from, dir);
        let mut sum = 0.0;
        let mut add = |k: usize| sum += self.chance[k] * self.lights[k].density_along(&ray, time);
        match &self.tree {
            None => (0..self.lights.len()).for_each(&mut add),
            // Nothing is offered to the search's bound, so every box the ray enters is visited.
            Some(tree) => {
                tree.traverse(&ray, &mut Closest::none(Real::INFINITY), |leaf, _| leaf.for_each(&mut add))
            }
        }
        if sum.is_finite() { sum } else { 0.0 }
    }

    /// [`Lights::pdf`] along the direction of `sample`, a sample [`Lights::sample`] drew from
    /// `from` at `time`: with one light, the sample's own density (the same number, without
    /// searching the light again along the way to it); else the sum over every light.
    #[inline]
    pub fn pdf_toward(&self, from: Vec3, sample: &LightSample, time: Real) -> Real {
        if self.lights.len() == 1 { sample.pdf } else { self.pdf(from, sample.dir, time) }
    }

    /// The density, per unit solid angle seen from `from`, with which [`Lights::sample`]
    /// draws the point `point` of an emitter (normal `normal`, at `time`) that gives off
    /// `emitted`: by the cone of the sphere light the point lies on, else by area,
    /// `luminance(emitted) / total power · d² / cos θ`. A function of the point alone, so that
    /// the shadow ray that reaches a point and the bounce that meets it weigh it alike (0 when
    /// not finite: the point then counts by bouncing only, under both).
    #[inline]
    pub fn pdf_of_point(&self, from: Vec3, point: Vec3, normal: Vec3, emitted: Vec3, time: Real) -> Real {
        if let Some(pdf) = self.cone_pdf_of_point(from, point, time) {
            return pdf;
        }
        self.pdf_by_area(from, point, normal, emitted)
    }

    /// The density [`Lights::pdf_of_point`] gives the point `sample` drew (from `from`, at
    /// `time`); for a light apart from every other light drawn by its cone, without its lookup
    /// (which cost as much as the shadow ray with many sphere lights): the sample's own cone
    /// density, computed by the same expression, or a flat light's by area.
    #[inline]
    pub fn pdf_of_sample(&self, from: Vec3, sample: &LightSample, time: Real) -> Real {
        let (point, normal, emitted) = (sample.point, sample.normal, sample.emitted);
        if !self.apart[sample.light] {
            return self.pdf_of_point(from, point, normal, emitted, time);
        }
        if self.lights[sample.light].by_area() {
            self.pdf_by_area(from, point, normal, emitted)
        } else {
            sample.pdf
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
        let at_point = |k: usize| self.lights[k].face_normal(&ray, distance);
        self.first_on_the_way(&ray, distance, 0..self.lights.len(), at_point)
    }

    /// The cone density of the light drawn by its cone whose surface `point` lies on, if there
    /// is one: those lights tested one by one, or, with a tree, those whose boxes the way from
    /// `from` to `point` enters.
    #[inline]
    fn cone_pdf_of_point(&self, from: Vec3, point: Vec3, time: Real) -> Option<Real> {
        let on_it = |k: usize| self.lights[k].density_at(from, point, time, self.chance[k]);
        if self.by_cone.is_empty() {
            return None;
        }
        let to = point - from;
        let distance = to.length();
        let ray = Ray::new(from, to / distance);
        self.first_on_the_way(&ray, distance, self.by_cone.iter().copied(), on_it)
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

/// Per light, whether no *other* light drawn by its cone comes near it (their boxes, widened by
/// 1% of their size, far beyond the lookup's tolerance `|d² − r²| ≤ 10⁻³ r²`, do not meet), so
/// that its points lie on no other such light. Those lights are swept in order of their lower x.
fn apart(found: &[Found]) -> Vec<bool> {
    let reach = |light: &Found| {
        let b = light.bounds();
        b.padded(0.01 * (b.max - b.min).length() + 8.0 * Real::EPSILON * b.magnitude())
    };
    let by_cone = found.iter().enumerate().filter(|(_, l)| !l.light.by_area());
    let mut by_cone: Vec<(usize, Aabb)> = by_cone.map(|(k, l)| (k, reach(l))).collect();
    by_cone.sort_by(|a, b| a.1.min.x.total_cmp(&b.1.min.x));
    let widest = by_cone.iter().fold(0.0, |w: Real, (_, b)| w.max(b.max.x - b.min.x));
    let alone = |k: usize, light: &Found| {
        let own = reach(light);
        let first = by_cone.partition_point(|(_, other)| other.min.x < own.min.x - widest);
        let mut near = by_cone[first..].iter().take_while(|(_, other)| other.min.x <= own.max.x);
        !near.any(|(j, other)| *j != k && own.meets(other))
    };
    found.iter().enumerate().map(|(k, light)| alone(k, light)).collect()
}
