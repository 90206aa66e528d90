//! Every object's box and centre, what a tree needs of it ([`Bounded`]). Apart from
//! `object.rs` only to keep that file one sitting's reading: an `impl` may live anywhere in the
//! crate, and this file imports `object` without `object` importing it, so no circle.

use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::real::Vec3;
use crate::tracer::world::object::Object;

impl Bounded for Object {
    fn bounds(&self) -> Aabb {
        match self {
            Object::Shape(shape) => shape.bounds(),
            Object::Mesh(mesh, _) => mesh.bounds(),
            Object::Instance(instance) => instance.bounds(),
            Object::Medium(medium) => medium.boundary.bounds(),
        }
    }

    fn centroid(&self) -> Vec3 {
        match self {
            Object::Shape(shape) => shape.centroid(),
            Object::Mesh(..) | Object::Instance(_) | Object::Medium(_) => {
                let b = self.bounds();
                0.5 * (b.min + b.max)
            }
        }
    }
}
