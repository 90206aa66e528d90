//! Where a scene file places things: a rigid transform (`transform = { rotate_y = 15.0,
//! translate = [265.0, 0.0, 295.0] }`, the books' `rotate_y` and `translate`), and the objects
//! a `[[box]]`, a `[[mesh]]`, a `[[medium]]` or a `[[group]]` makes, placed by it as one
//! instance (`world.rs` holds the shapes).

use serde::{Deserialize, Serialize};

use crate::scenes::checks::{REAL, check, finite3, representable};
use crate::tracer::math::real::vec3;
use crate::tracer::math::transform::Transform;
use crate::tracer::world::object::{Group, Instance, Object};

/// A rigid placement: rotations about x, then y, then z (degrees), then a translation.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformSpec {
    /// Degrees about x.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotate_x: f64,
    /// Degrees about y (the books' `rotate_y`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotate_y: f64,
    /// Degrees about z.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotate_z: f64,
    /// Moved by this, last.
    #[serde(default, skip_serializing_if = "is_origin")]
    pub translate: [f64; 3],
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_origin(v: &[f64; 3]) -> bool {
    *v == [0.0; 3]
}

impl TransformSpec {
    /// Every angle and offset finite.
    pub fn check(&self) -> Result<(), String> {
        let angles = [self.rotate_x, self.rotate_y, self.rotate_z];
        check(angles.iter().all(|&a| representable(a)) && finite3(self.translate), || {
            format!("transform must be finite numbers (as {REAL}), got {self:?}")
        })
    }

    /// The tracer's transform.
    pub fn to_transform(&self) -> Transform {
        Transform::rotate_x(self.rotate_x)
            .then(&Transform::rotate_y(self.rotate_y))
            .then(&Transform::rotate_z(self.rotate_z))
            .then_translate(vec3(self.translate))
    }
}

/// `objects` placed by `transform` as one instance (as they are, without one).
pub fn placed(objects: Vec<Object>, transform: Option<&TransformSpec>) -> Vec<Object> {
    match transform.map(TransformSpec::to_transform) {
        Some(t) if !t.is_identity() => {
            vec![Object::Instance(Box::new(Instance::new(t, Group::new(objects))))]
        }
        _ => objects,
    }
}
