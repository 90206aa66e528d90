//! The tables a scene file makes of other objects: `[[box]]` (six quads), `[[triangle]]`
//! (loose triangles, made into one mesh per material), `[[mesh]]` (an OBJ file or a generated
//! mesh) and `[[medium]]` (fog inside a closed boundary); for each, its spec, its checks and
//! the objects it becomes. `world.rs` holds the simple shapes and the lists of all of them.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::scenes::assets::{Assets, GeneratedMesh};
use crate::scenes::checks::{REAL, check, colour, finite3, representable};
use crate::scenes::looks::{MaterialRef, Tables};
use crate::scenes::placement::{TransformSpec, placed};
use crate::tracer::geometry::quad::box_faces;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::geometry::triangle;
use crate::tracer::math::real::{Real, Vec3, vec3};
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::{Group, Medium, Object};

/// One `[[box]]`: six quads between two opposite corners, optionally placed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// One corner.
    pub min: [f64; 3],
    /// The opposite corner.
    pub max: [f64; 3],
    /// Its material.
    pub material: MaterialRef,
    /// Where it is placed (as an instance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformSpec>,
}

/// One `[[triangle]]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangleSpec {
    /// Its three corners, counter-clockwise seen from its front.
    pub vertices: [[f64; 3]; 3],
    /// Its material.
    pub material: MaterialRef,
}

/// One `[[mesh]]`: a Wavefront OBJ file beside the scene file, or a mesh raypool generates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// The OBJ file, relative to the scene file's folder and inside it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obj: Option<String>,
    /// A generated mesh instead of a file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generate: Option<GeneratedMesh>,
    /// Multiplies every vertex when the mesh is loaded (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Its material.
    pub material: MaterialRef,
    /// Where it is placed (as an instance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformSpec>,
}

/// One `[[medium]]`: fog or smoke of constant density inside a closed boundary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MediumSpec {
    /// Scattering events per unit length, ≥ 0.
    pub density: f64,
    /// Fraction scattered per channel (the rest absorbed), each ≥ 0.
    pub albedo: [f64; 3],
    /// The closed surface it fills.
    pub boundary: BoundarySpec,
    /// Where it is placed (as an instance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformSpec>,
}

/// A medium's boundary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum BoundarySpec {
    /// A sphere.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius, > 0.
        radius: f64,
    },
    /// A box.
    Box {
        /// One corner.
        min: [f64; 3],
        /// The opposite corner.
        max: [f64; 3],
    },
}

impl BoxSpec {
    /// Its corners span a volume; its placement is finite.
    pub fn check(&self) -> Result<(), String> {
        check_box(self.min, self.max)?;
        self.transform.as_ref().map_or(Ok(()), TransformSpec::check)
    }

    /// Its six faces, placed, of `material`.
    pub fn objects(&self, material: u32) -> Vec<Object> {
        placed(box_objects(self.min, self.max, material), self.transform.as_ref())
    }
}

impl TriangleSpec {
    /// Finite corners that span an area.
    pub fn check(&self) -> Result<(), String> {
        check(self.vertices.iter().all(|&v| finite3(v)), || "vertices must be finite numbers".to_owned())?;
        check(!triangle::degenerate(self.vertices.map(vec3)), || {
            format!("degenerate (its vertices {:?} span no area)", self.vertices)
        })
    }
}

/// Loose triangles as meshes, one per material (each triangle's from `material`), in the
/// order written.
pub fn triangle_meshes(
    triangles: &[TriangleSpec],
    mut material: impl FnMut(&MaterialRef) -> u32,
    assets: &Assets,
) -> Vec<Object> {
    let mut by_material: Vec<(u32, Vec<Vec3>)> = Vec::new();
    for t in triangles {
        let m = material(&t.material);
        let at = by_material.iter().position(|(k, _)| *k == m).unwrap_or_else(|| {
            by_material.push((m, Vec::new()));
            by_material.len() - 1
        });
        by_material[at].1.extend(t.vertices.map(vec3));
    }
    by_material.into_iter().map(|(m, corners)| Object::Mesh(Arc::new(assets.soup(corners)), m)).collect()
}

impl MeshSpec {
    /// One source, a generated mesh's numbers, its scale and placement.
    pub fn check(&self) -> Result<(), String> {
        check(self.obj.is_some() != self.generate.is_some(), || {
            "needs exactly one of obj and generate".to_owned()
        })?;
        if let Some(g) = &self.generate {
            g.check()?;
        }
        check(self.scale.is_none_or(|s| representable(s) && s > 0.0), || {
            format!("scale must be finite (as {REAL}) and > 0")
        })?;
        self.transform.as_ref().map_or(Ok(()), TransformSpec::check)
    }

    /// The (loaded) mesh, placed, of `material`.
    pub fn objects(&self, assets: &Assets, material: u32) -> Vec<Object> {
        let mesh = assets.mesh(self.obj.as_deref(), self.generate.as_ref(), self.scale);
        placed(vec![Object::Mesh(mesh, material)], self.transform.as_ref())
    }
}

impl MediumSpec {
    /// A density ≥ 0, an albedo, a boundary with volume, a finite placement.
    pub fn check(&self) -> Result<(), String> {
        check(representable(self.density) && self.density >= 0.0, || {
            format!("density must be finite (as {REAL}) and ≥ 0, got {}", self.density)
        })?;
        colour(self.albedo).map_err(|e| format!("albedo {e}"))?;
        match self.boundary {
            BoundarySpec::Sphere { center, radius } => {
                check(finite3(center) && representable(radius) && radius > 0.0, || {
                    "a boundary sphere needs a finite centre and a radius > 0".to_owned()
                })?
            }
            BoundarySpec::Box { min, max } => check_box(min, max).map_err(|e| format!("boundary {e}"))?,
        }
        self.transform.as_ref().map_or(Ok(()), TransformSpec::check)
    }

    /// The medium, placed: its phase function added to `tables`, its id the next of `made`.
    pub fn objects(&self, tables: &mut Tables, made: &mut u32) -> Vec<Object> {
        let boundary = match self.boundary {
            BoundarySpec::Sphere { center, radius } => {
                vec![Object::shape(Sphere { center: vec3(center), radius: radius as Real, material: 0 })]
            }
            BoundarySpec::Box { min, max } => box_objects(min, max, 0),
        };
        let phase = tables.push(Material::Isotropic { albedo: vec3(self.albedo) });
        let medium = Medium {
            boundary: Group::new(boundary),
            density: self.density as Real,
            material: phase,
            id: *made,
        };
        *made += 1;
        placed(vec![Object::Medium(Box::new(medium))], self.transform.as_ref())
    }
}

fn box_objects(min: [f64; 3], max: [f64; 3], material: u32) -> Vec<Object> {
    let faces = box_faces(vec3(min), vec3(max), material).expect("checked: a box of some volume");
    faces.into_iter().map(Object::shape).collect()
}

fn check_box(min: [f64; 3], max: [f64; 3]) -> Result<(), String> {
    check(finite3(min) && finite3(max), || "min and max must be finite numbers".to_owned())?;
    check((0..3).all(|k| min[k] != max[k]), || {
        format!("degenerate: min {min:?} and max {max:?} span no volume")
    })
}
