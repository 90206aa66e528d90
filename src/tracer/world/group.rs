//! A group: objects searched together, through a four-wide tree of their boxes once there are
//! enough of them (the same trees `accel` builds for spheres). A scene's world is a group; so
//! is what an instance places and what bounds a medium.
//!
//! Ties in distance go to the lower index ([`Closest`]), so a group searched through its tree
//! finds exactly what testing its objects in order finds (`--accel flat`).

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::wide::WideBvh;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;
use crate::tracer::world::object::{Object, Probe};

/// Groups of fewer objects than this test them all: a tree costs more than it saves.
pub const TREE_MIN_OBJECTS: usize = 6;

/// Objects per leaf of a group's four-wide tree.
const LEAF: usize = 4;

/// Objects, and the tree over them (none for small groups, or when asked for none).
#[derive(Clone, Debug)]
pub struct Group {
    objects: Vec<Object>,
    tree: Option<WideBvh>,
    bounds: Aabb,
}

impl Group {
    /// A group of `objects`, with a tree if there are at least [`TREE_MIN_OBJECTS`] of them
    /// (which reorders them).
    pub fn new(objects: Vec<Object>) -> Group {
        let tree = objects.len() >= TREE_MIN_OBJECTS;
        Group::with_tree(objects, tree)
    }

    /// A group of `objects`, searched through a tree or, with `tree` false, one by one in
    /// their current order.
    pub fn with_tree(mut objects: Vec<Object>, tree: bool) -> Group {
        let bounds = objects.iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union);
        let tree = (tree && !objects.is_empty()).then(|| {
            let binary = Bvh::build_with_leaves(&mut objects, LEAF);
            WideBvh::collapse_plain(&binary, objects.len())
        });
        Group { objects, tree, bounds }
    }

    /// The same objects searched the other way (for `--accel` comparisons).
    pub fn rebuilt(self, tree: bool) -> Group {
        Group::with_tree(self.objects, tree)
    }

    /// The objects, in the order the tree stored them.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Whether a tree is searched.
    pub fn has_tree(&self) -> bool {
        self.tree.is_some()
    }

    /// `(moves, media)`: whether any object moves, or is a medium.
    pub fn needs(&self) -> (bool, bool) {
        self.objects.iter().map(Object::needs).fold((false, false), |a, b| (a.0 | b.0, a.1 | b.1))
    }

    /// The nearest hit in `(0, t_max)`.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, probe: &Probe) -> Option<Hit> {
        let mut closest = Closest::none(t_max);
        let mut best = None;
        let mut offer = |i: usize, closest: &mut Closest| {
            if let Some(hit) = self.objects[i].hit(ray, closest.bound(), probe) {
                closest.offer(hit.t, i as u32);
                if closest.index == i as u32 {
                    best = Some(hit);
                }
            }
        };
        match &self.tree {
            None => (0..self.objects.len()).for_each(|i| offer(i, &mut closest)),
            Some(tree) => {
                tree.traverse(ray, &mut closest, |leaf, closest| leaf.for_each(|i| offer(i, closest)))
            }
        }
        best
    }
}

impl Bounded for Group {
    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn centroid(&self) -> crate::tracer::math::real::Vec3 {
        0.5 * (self.bounds.min + self.bounds.max)
    }
}
