//! One thing a scene holds, of any kind: an `enum`, so a group of mixed shapes is one flat
//! array its tree indexes, and a search matches on the kind (a predictable branch) instead of
//! calling through a pointer. Composite kinds (meshes, instances, media) hold their parts
//! behind a pointer, which keeps the array's entries small.
//!
//! The kinds that hold other objects live here too (a [`Group`], an [`Instance`], a
//! [`Medium`]): an object may be made of objects, so these types are one recursive family, and
//! one file keeps the imports free of circles.

use crate::tracer::geometry::Shape;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::lanes::{Lanes8, WithLanes8};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::world::mesh::Mesh;
pub use crate::tracer::world::probe::Probe;
use crate::tracer::world::runs;
use crate::tracer::world::runs::{Best, Item, Kind, Run, Runs};
use std::sync::Arc;

/// One object of a scene or of a group (pbrt's `Primitive`): a shape, or what is made of
/// shapes.
#[derive(Clone, Debug)]
pub enum Object {
    /// A simple shape ([`Shape`]).
    Shape(Shape),
    /// A triangle mesh (shared: one mesh may be placed many times) and its material.
    Mesh(Arc<Mesh>, u32),
    /// A group placed by a rigid transform.
    Instance(Box<Instance>),
    /// Fog or smoke inside a closed boundary.
    Medium(Box<Medium>),
}

impl Object {
    /// `shape` (a sphere, a quad, …) as an object.
    pub fn shape(shape: impl Into<Shape>) -> Object {
        Object::Shape(shape.into())
    }

    /// The nearest hit in `(0, t_max)`, if any.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        match self {
            Object::Shape(shape) => shape.hit(ray, t_max, probe.time),
            Object::Mesh(mesh, material) => mesh.hit(ray, t_max, *material, probe.isa),
            Object::Instance(instance) => instance.hit(ray, t_max, probe),
            Object::Medium(medium) => medium.hit(ray, t_max, probe),
        }
    }

    /// `hit`, its closest, with what [`Object::hit`] left out for hits that may not be the
    /// closest: the texture coordinates a shape makes late ([`Shape::with_uv`]).
    #[inline]
    fn with_uv(&self, hit: Hit, probe: &Probe) -> Hit {
        match self {
            Object::Shape(shape) => shape.with_uv(hit, probe.time),
            Object::Mesh(..) | Object::Instance(_) | Object::Medium(_) => hit,
        }
    }

    /// Whether anything of it is hit in `(0, t_max)` (a shadow ray's question: which hit is
    /// nearest does not matter, so a search may end at the first).
    #[inline]
    pub fn occludes(&self, ray: &Ray, t_max: Real, probe: &Probe) -> bool {
        match self {
            Object::Shape(shape) => shape.intersects(ray, t_max, probe.time),
            Object::Mesh(mesh, _) => mesh.occludes(ray, t_max, probe.isa),
            Object::Instance(instance) => {
                let local = instance.transform.inverse_ray(ray);
                instance.group.may_hit(&local, t_max) && instance.group.occludes(&local, t_max, probe)
            }
            Object::Medium(medium) => medium.hit(ray, t_max, probe).is_some(),
        }
    }

    /// The materials this object's surfaces use.
    pub fn materials(&self, out: &mut Vec<u32>) {
        match self {
            Object::Shape(shape) => out.push(shape.material()),
            Object::Mesh(_, material) => out.push(*material),
            Object::Instance(instance) => instance.group.objects().iter().for_each(|o| o.materials(out)),
            Object::Medium(medium) => out.push(medium.material),
        }
    }

    /// Whether it holds a mesh shaded by normals from its file (in an instance too).
    pub fn has_shading_normals(&self) -> bool {
        match self {
            Object::Mesh(mesh, _) => mesh.has_normals(),
            Object::Instance(instance) => instance.group.objects().iter().any(Object::has_shading_normals),
            Object::Shape(_) | Object::Medium(_) => false,
        }
    }

    /// Whether anything in it moves or is a medium: `(moves, media)`.
    pub fn needs(&self) -> (bool, bool) {
        match self {
            Object::Shape(shape) => (shape.moves(), false),
            Object::Medium(_) => (false, true),
            Object::Instance(instance) => instance.group.needs(),
            Object::Mesh(..) => (false, false),
        }
    }
}

// ---- Groups:
// A group: objects searched together (a scene's world, what an instance places, what bounds
// a medium) in runs, through an eight-wide tree of their boxes once there are enough of them,
// a run's quads in the lanes of the scene's vector level (`runs.rs`); only the closest hit's
// record is made, at the end. Ties go to the lower index ([`Closest`]), so a group searched
// through its tree finds what testing its objects in order finds (`--accel flat`).

/// Groups of fewer objects than this keep the order they were given; larger ones are ordered
/// as their tree's leaves, the order in which ties go to the lower index.
pub const TREE_MIN_OBJECTS: usize = 6;

/// Objects, and how they are searched: a tree over them (none for small groups, or when
/// asked for none), the runs of its leaves, and the media apart (`runs.rs`).
#[derive(Clone, Debug)]
pub struct Group {
    objects: Vec<Object>,
    runs: Runs,
    bounds: Aabb,
    /// Whether the closest hit gets the texture coordinates its shape makes late (a sphere's
    /// arc tangent and arc cosine, [`Shape::late_uv`]): only where a material reads them
    /// ([`Group::keep_uv_for`]).
    uv: bool,
}

impl Group {
    /// A group of `objects`, ordered by a tree if there are at least [`TREE_MIN_OBJECTS`] of
    /// them, and searched through it if there are more than [`runs::FLAT_MAX_OBJECTS`].
    pub fn new(objects: Vec<Object>) -> Group {
        let tree = objects.len() >= TREE_MIN_OBJECTS;
        Group::with_tree(objects, tree)
    }

    /// A group of `objects`, ordered by a tree and searched through it (if more than
    /// [`runs::FLAT_MAX_OBJECTS`]), or with `tree` false one run after another as they are.
    pub fn with_tree(mut objects: Vec<Object>, tree: bool) -> Group {
        let bounds = objects.iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union);
        let tree = if tree { runs::ordered(&mut objects) } else { None };
        let items: Vec<Item> = objects
            .iter()
            .map(|object| Item {
                bounds: object.bounds(),
                centroid: object.centroid(),
                kind: match object {
                    Object::Shape(Shape::Quad(quad)) => Kind::Quad(quad),
                    Object::Shape(Shape::Sphere(_)) => Kind::Sphere,
                    Object::Medium(_) => Kind::Medium,
                    Object::Shape(_) | Object::Mesh(..) | Object::Instance(_) => Kind::Other,
                },
            })
            .collect();
        let runs = Runs::new(&items, tree);
        Group { objects, runs, bounds, uv: true }
    }

    /// The same objects searched the other way (for `--accel` comparisons).
    pub fn rebuilt(self, tree: bool) -> Group {
        Group { uv: self.uv, ..Group::with_tree(self.objects, tree) }
    }

    /// Makes texture coordinates only for the shapes that make them late ([`Shape::late_uv`])
    /// and whose material `reads_uv`, here and in the groups inside (a
    /// medium's boundary never: its hits are not shaded).
    pub fn keep_uv_for(&mut self, reads_uv: &dyn Fn(u32) -> bool) {
        self.uv = false;
        for object in &mut self.objects {
            match object {
                Object::Shape(shape) => self.uv |= shape.late_uv() && reads_uv(shape.material()),
                Object::Instance(instance) => instance.group.keep_uv_for(reads_uv),
                Object::Medium(medium) => medium.boundary.keep_uv_for(&|_| false),
                Object::Mesh(..) => {}
            }
        }
    }

    /// The objects, in the order the tree stored them.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Whether a tree is searched.
    pub fn has_tree(&self) -> bool {
        self.runs.has_tree()
    }

    /// Whether the search may find a hit along `ray` before `t_max`: a group without a tree
    /// tests its box (a tree's root does the same), branch-free ([`Aabb::enters`]).
    #[inline(always)]
    fn may_hit(&self, ray: &Ray, t_max: Real) -> bool {
        self.has_tree() || self.bounds.enters(ray, t_max)
    }

    /// `(moves, media)`: whether any object moves, or is a medium.
    pub fn needs(&self) -> (bool, bool) {
        self.objects.iter().map(Object::needs).fold((false, false), |a, b| (a.0 | b.0, a.1 | b.1))
    }

    /// The nearest hit in `(0, t_max)`, searched in the lanes of the scene's vector level.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        probe.isa.run_lanes(Nearest(self, ray, t_max, probe))
    }

    /// Asks object `i` alone for its hit below the closest so far, and keeps it if closer.
    #[inline(always)]
    fn offer(&self, i: usize, ray: &Ray, probe: &Probe, closest: &mut Closest, best: &mut Best) {
        if let Some(hit) = self.objects[i].hit(ray, closest.bound(), probe) {
            closest.offer(hit.t, i as u32);
            if closest.index == i as u32 {
                *best = Best::Other(hit);
            }
        }
    }

    /// Whether anything in the group is hit in `(0, t_max)`: the search ends at the first
    /// object found (pbrt's `IntersectP`, Embree's `rtcOccluded`).
    #[inline]
    pub fn occludes(&self, ray: &Ray, t_max: Real, probe: &Probe) -> bool {
        probe.isa.run_lanes(Blocked(self, ray, t_max, probe))
    }
}

/// [`Group::hit`]'s search and [`Group::occludes`]', run in the lanes of a vector level.
struct Nearest<'a>(&'a Group, &'a Ray, Real, &'a Probe);
struct Blocked<'a>(&'a Group, &'a Ray, Real, &'a Probe);

impl WithLanes8 for Nearest<'_> {
    type Output = Option<Hit>;
    #[inline(always)]
    fn run<L: Lanes8>(self, lanes: L) -> Option<Hit> {
        let Nearest(group, ray, t_max, probe) = self;
        let mut closest = Closest::none(t_max);
        let mut best = Best::Nothing;
        group.runs.search(
            lanes,
            ray,
            &mut closest,
            #[inline(always)]
            |run: &Run, closest: &mut Closest| {
                if let Some(quad) = run.offer_quads(lanes, ray, closest) {
                    best = quad;
                }
                for i in run.spheres() {
                    let Object::Shape(Shape::Sphere(sphere)) = &group.objects[i] else { continue };
                    if let Some(t) = sphere.intersect(ray, closest.bound()) {
                        closest.offer(t, i as u32);
                        best = if closest.index == i as u32 { Best::Sphere } else { best };
                    }
                }
                // A `for` loop: `for_each`'s `fold` was compiled out of line, a call per run.
                for i in run.others() {
                    group.offer(i, ray, probe, closest, &mut best);
                }
            },
        );
        // Media last, when the nearest surface bounds how far they must look ([`Medium::hit`]
        // then rarely searches its boundary).
        for i in group.runs.media() {
            group.offer(i, ray, probe, &mut closest, &mut best);
        }
        match (best, group.objects.get(closest.index as usize)?) {
            (Best::Quad { alpha, beta, front }, Object::Shape(Shape::Quad(quad))) => {
                Some(quad.hit_at(closest.t, alpha, beta, front))
            }
            (Best::Sphere, Object::Shape(Shape::Sphere(sphere))) => {
                let hit = sphere.hit_at(ray, closest.t);
                Some(if group.uv { sphere.with_uv(hit) } else { hit })
            }
            (Best::Other(hit), object) => Some(if group.uv { object.with_uv(hit, probe) } else { hit }),
            _ => None,
        }
    }
}

impl WithLanes8 for Blocked<'_> {
    type Output = bool;
    #[inline(always)]
    fn run<L: Lanes8>(self, lanes: L) -> bool {
        let Blocked(group, ray, t_max, probe) = self;
        let blocks = |i: usize| group.objects[i].occludes(ray, t_max, probe);
        let mut found = false;
        let mut closest = Closest::none(t_max);
        group.runs.search(
            lanes,
            ray,
            &mut closest,
            #[inline(always)]
            |run: &Run, closest: &mut Closest| {
                if run.quads_block(lanes, ray, t_max) || run.spheres().chain(run.others()).any(blocks) {
                    found = true;
                    closest.rule_out_rest();
                }
            },
        );
        found || group.runs.media().any(blocks)
    }
}

impl Bounded for Group {
    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn centroid(&self) -> Vec3 {
        0.5 * (self.bounds.min + self.bounds.max)
    }
}

// ---- Instances: a group placed by a rigid transform. The ray is moved into the group's
// frame and the hit moved back (the books' `translate` and `rotate_y`, pbrt's
// `TransformedPrimitive`), so the geometry exists once however many times it is placed.

/// A group and where it is placed.
#[derive(Clone, Debug)]
pub struct Instance {
    /// Object frame to world.
    pub transform: Transform,
    /// What is placed.
    pub group: Group,
    bounds: Aabb,
}

impl Instance {
    /// `group` placed by `transform`.
    pub fn new(transform: Transform, group: Group) -> Instance {
        let inner = group.bounds();
        // The placed box is padded by the rounding of placing a point at its magnitude.
        let placed = transform.bounds(&inner);
        let pad = 4.0 * Real::EPSILON * (placed.magnitude() + inner.magnitude());
        Instance { transform, group, bounds: placed.padded(pad) }
    }

    /// The world box.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The nearest hit in `(0, t_max)`: found in the group's frame (a rigid placement keeps
    /// distances), then placed in the world's, its spawn offset grown by that rounding.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        let local = self.transform.inverse_ray(ray);
        if !self.group.may_hit(&local, t_max) {
            return None;
        }
        let mut hit = self.group.hit(&local, t_max, probe)?;
        hit.point = self.transform.point(hit.point);
        hit.normal = self.transform.vector(hit.normal);
        let magnitude = hit.point.abs().max_element() + self.transform.offset_magnitude();
        hit.offset += 8.0 * Real::EPSILON * magnitude;
        Some(hit)
    }
}

// ---- Media: a participating medium of constant density (the second book's
// `constant_medium`): fog or smoke filling a closed boundary. A ray crossing `L` of it
// scatters with probability `1 − e^(−density·L)`, at a distance drawn from that exponential
// law, into a direction drawn by the isotropic phase function (`Material::Isotropic`).
//
// The boundary is any closed group. If its first hit is a front face, the ray enters there
// and leaves at the next hit; if a back face, the ray starts inside (a camera in global fog,
// a path that scattered in the smoke) and leaves there, or it grazed an edge, so it is
// inside no sooner than the boundary's box.

/// Fog or smoke inside `boundary`.
#[derive(Clone, Debug)]
pub struct Medium {
    /// The closed surface the medium fills (its front faces outwards).
    pub boundary: Group,
    /// Scattering events per unit length, ≥ 0 (0: the medium is not there).
    pub density: Real,
    /// Index of its isotropic material in the scene's table.
    pub material: u32,
    /// Which medium this is: its own random number per ray ([`Probe::uniform`]).
    pub id: u32,
}

impl Medium {
    /// Where the ray scatters in the medium before `t_max`, if it does.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        if self.density.is_nan() || self.density <= 0.0 {
            return None;
        }
        // The distance is drawn first: in thin fog it mostly passes whatever was hit before,
        // and the boundary need not be searched (the path inside is no longer than `t_max`).
        // As −ln u ≥ 1 − u, most draws are past `t_max` before the logarithm (the margin is
        // far above the rounding of the logarithm and the division): the same answer.
        let u = probe.uniform(self.id);
        if 1.0 - u > t_max * self.density * (1.0 + 1e-4) {
            return None;
        }
        // The boundary's box bounds where the medium can lie along the ray: a ray that
        // meets no surface (`t_max` infinite) mostly draws a distance past the box's span,
        // and needs no search of the boundary.
        let bounds = self.boundary.bounds();
        let (near, far) = bounds.span(ray, t_max)?;
        // Above the span by far more than its rounding, the boundary's hit points' and their
        // spawn offsets': a draw beyond it is one past the boundary's exit.
        let longest = far - near + 1e-4 * (far + bounds.magnitude());
        if 1.0 - u > longest * self.density * (1.0 + 1e-4) {
            return None;
        }
        let distance = -u.ln() / self.density;
        if distance.is_nan() || distance >= t_max || distance >= longest {
            return None;
        }
        let first = self.boundary.hit(ray, Real::INFINITY, probe)?;
        let (enter, exit) = if first.front_face {
            // Cross into the boundary, then find where the ray leaves it.
            let inside = first.spawn(ray.dir);
            let last = self.boundary.hit(&inside, Real::INFINITY, probe)?;
            (first.t, (last.point - ray.origin).dot(ray.dir))
        } else {
            // Met from behind first: the ray starts inside, or, if it starts outside the
            // box, it met a face from behind at an edge it grazes (the medium starts no
            // sooner than the box; `near` is 0 for a start inside it).
            (near, first.t)
        };
        if enter >= t_max {
            return None;
        }
        let length = exit.min(t_max) - enter;
        if distance >= length {
            return None;
        }
        Some(Hit::in_medium(ray, enter + distance, self.material))
    }
}
