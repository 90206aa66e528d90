//! The second book's shapes as a scene file writes them: `[[sphere]]`, `[[quad]]`, `[[box]]`,
//! pbrt's `[[disc]]`, `[[triangle]]`, `[[mesh]]`, `[[medium]]`, each also inside a `[[group]]`
//! (objects placed together by one transform, the scene file's instances: `placement.rs`);
//! how a table of them is read ([`Shapes::read`]), and the objects they become (their checks
//! are `shape_checks.rs`).
//!
//! ```toml
//! [[quad]]
//! q = [555.0, 0.0, 0.0]
//! u = [0.0, 555.0, 0.0]
//! v = [0.0, 0.0, 555.0]
//! material = "green"
//!
//! [[disc]]
//! center = [278.0, 0.1, 278.0]
//! normal = [0.0, 1.0, 0.0]
//! radius = 100.0
//! material = "white"
//!
//! [[box]]
//! min = [0.0, 0.0, 0.0]
//! max = [165.0, 330.0, 165.0]
//! material = "white"
//! transform = { rotate_y = 15.0, translate = [265.0, 0.0, 295.0] }
//!
//! [[medium]]
//! density = 0.01
//! albedo = [0.0, 0.0, 0.0]
//! boundary = { kind = "box", min = [0.0, 0.0, 0.0], max = [165.0, 330.0, 165.0] }
//!
//! [[mesh]]
//! obj = "bunny.obj"     # beside the scene file; or: generate = { kind = "terrain", … }
//! material = "white"
//! ```

use std::fmt;

use serde::de::{self, DeserializeSeed, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};

use crate::scenes::assets::{Assets, GeneratedMesh};
use crate::scenes::looks::{Looks, MaterialRef, Tables};
use crate::scenes::placement::{TransformSpec, placed};
use crate::tracer::geometry::disc::Disc;
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::geometry::quad::{Quad, box_faces};
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::real::{Real, Vec3, vec3};
use crate::tracer::shading::material::Material;
use crate::tracer::world::object::Group;
use crate::tracer::world::object::Medium;
use crate::tracer::world::object::Object;

/// One `[[sphere]]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Centre (at time 0, if it moves).
    pub center: [f64; 3],
    /// Radius, non-zero; negative for a hollow shell.
    pub radius: f64,
    /// Inline material or the name of one in `[materials]`.
    pub material: MaterialRef,
    /// Centre at time 1: the sphere moves while the shutter is open (motion blur).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center1: Option<[f64; 3]>,
}

/// One `[[quad]]`: the parallelogram `q + α·u + β·v`, facing `u × v`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadSpec {
    /// A corner.
    pub q: [f64; 3],
    /// First edge.
    pub u: [f64; 3],
    /// Second edge.
    pub v: [f64; 3],
    /// Its material.
    pub material: MaterialRef,
}

/// One `[[disc]]`: the points of a plane within `radius` of `center`, facing `normal`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiscSpec {
    /// Its centre.
    pub center: [f64; 3],
    /// The direction its front faces (any length but zero).
    pub normal: [f64; 3],
    /// Its radius, > 0.
    pub radius: f64,
    /// Its material.
    pub material: MaterialRef,
}

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

/// One `[[group]]`: objects placed together by one transform (one instance). Its shapes are
/// written as at the top level, `[[group.sphere]]` and so on (no nested groups).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct GroupSpec {
    /// Where the group is placed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformSpec>,
    /// Its shape tables.
    #[serde(flatten)]
    pub shapes: Shapes,
}

impl<'de> Deserialize<'de> for GroupSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<GroupSpec, D::Error> {
        deserializer.deserialize_map(GroupVisitor)
    }
}

/// Reads a `[[group]]`: its transform, and its shapes' tables ([`Shapes::read`]).
struct GroupVisitor;

impl<'de> Visitor<'de> for GroupVisitor {
    type Value = GroupSpec;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a [[group]] table")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<GroupSpec, A::Error> {
        let mut group = GroupSpec::default();
        while let Some(key) = map.next_key_seed(Key(&["transform"]))? {
            match key.as_str() {
                "transform" => group.transform = Some(map.next_value()?),
                table => group.shapes.read(table, &mut map)?,
            }
        }
        Ok(group)
    }
}

/// The shapes a scene file or a group holds, a list per kind, each read from the tables of
/// its name ([`Shapes::TABLES`]). The checks (`shape_checks.rs`) and the build name every
/// list (no `..`), so a new shape's list is a compile error in each.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Shapes {
    /// `[[sphere]]` tables.
    #[serde(rename = "sphere", skip_serializing_if = "Vec::is_empty")]
    pub spheres: Vec<SphereSpec>,
    /// `[[quad]]` tables.
    #[serde(rename = "quad", skip_serializing_if = "Vec::is_empty")]
    pub quads: Vec<QuadSpec>,
    /// `[[disc]]` tables.
    #[serde(rename = "disc", skip_serializing_if = "Vec::is_empty")]
    pub discs: Vec<DiscSpec>,
    /// `[[box]]` tables.
    #[serde(rename = "box", skip_serializing_if = "Vec::is_empty")]
    pub boxes: Vec<BoxSpec>,
    /// `[[triangle]]` tables.
    #[serde(rename = "triangle", skip_serializing_if = "Vec::is_empty")]
    pub triangles: Vec<TriangleSpec>,
    /// `[[mesh]]` tables.
    #[serde(rename = "mesh", skip_serializing_if = "Vec::is_empty")]
    pub meshes: Vec<MeshSpec>,
    /// `[[medium]]` tables.
    #[serde(rename = "medium", skip_serializing_if = "Vec::is_empty")]
    pub media: Vec<MediumSpec>,
}

impl Shapes {
    /// The names of the shape tables, as a scene file writes them.
    pub const TABLES: [&str; 7] = ["sphere", "quad", "disc", "box", "triangle", "mesh", "medium"];

    /// Reads the list of table `name` (one of [`Shapes::TABLES`]) as `map`'s next value.
    pub fn read<'de, A: MapAccess<'de>>(&mut self, name: &str, map: &mut A) -> Result<(), A::Error> {
        // Every list named (no `..`): a new one left unread is an unused variable.
        let Shapes { spheres, quads, discs, boxes, triangles, meshes, media } = self;
        match name {
            "sphere" => *spheres = map.next_value()?,
            "quad" => *quads = map.next_value()?,
            "disc" => *discs = map.next_value()?,
            "box" => *boxes = map.next_value()?,
            "triangle" => *triangles = map.next_value()?,
            "mesh" => *meshes = map.next_value()?,
            "medium" => *media = map.next_value()?,
            _ => return Err(de::Error::unknown_field(name, &Shapes::TABLES)),
        }
        Ok(())
    }
}

/// A key of a table that holds shapes (a scene file, a `[[group]]`): one of its own keys or a
/// shape's table ([`Shapes::TABLES`]), else refused where it stands, naming the keys expected.
/// (Not serde's `flatten` of [`Shapes`]: it would report every error inside a shape at `1:1`.)
pub struct Key(pub &'static [&'static str]);

impl<'de> DeserializeSeed<'de> for Key {
    type Value = String;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<String, D::Error> {
        let key = String::deserialize(deserializer)?;
        let mut known = self.0.iter().chain(&Shapes::TABLES);
        if known.clone().any(|k| *k == key) {
            return Ok(key);
        }
        let expected: Vec<String> = known.by_ref().map(|k| format!("`{k}`")).collect();
        Err(de::Error::custom(format!("unknown field `{key}`, expected one of {}", expected.join(", "))))
    }
}

impl Shapes {
    /// Every shape's material reference, in order (a medium has none: its phase function is
    /// made from its albedo).
    pub fn material_refs(&self) -> impl Iterator<Item = &MaterialRef> {
        let Shapes { spheres, quads, discs, boxes, triangles, meshes, media: _ } = self;
        let s = spheres.iter().map(|x| &x.material);
        let q = quads.iter().map(|x| &x.material).chain(discs.iter().map(|x| &x.material));
        let b = boxes.iter().map(|x| &x.material);
        let t = triangles.iter().map(|x| &x.material);
        s.chain(q).chain(b).chain(t).chain(meshes.iter().map(|x| &x.material))
    }

    /// The (checked) shapes as static spheres and objects, their materials added to `tables`;
    /// `made` counts the media made so far (each gets its own id).
    pub fn build(
        &self,
        looks: &Looks,
        assets: &Assets,
        tables: &mut Tables,
        made: &mut u32,
    ) -> (Vec<Sphere>, Vec<Object>) {
        let Shapes { spheres, quads, discs, boxes, triangles, meshes, media } = self;
        let mut material = |m: &MaterialRef| tables.material(looks, assets, m);
        let mut still = Vec::new();
        let mut objects = Vec::new();
        for s in spheres {
            let (center, radius, material) = (vec3(s.center), s.radius as Real, material(&s.material));
            match s.center1 {
                None => still.push(Sphere { center, radius, material }),
                Some(c1) => objects.push(Object::shape(MovingSphere {
                    center0: center,
                    center1: vec3(c1),
                    radius,
                    material,
                })),
            }
        }
        for q in quads {
            let quad = Quad::new(vec3(q.q), vec3(q.u), vec3(q.v), material(&q.material))
                .expect("checked: not degenerate");
            objects.push(Object::shape(quad));
        }
        for d in discs {
            let disc = Disc::new(vec3(d.center), vec3(d.normal), d.radius as Real, material(&d.material));
            objects.push(Object::shape(disc.expect("checked: not degenerate")));
        }
        for b in boxes {
            let faces = box_objects(b.min, b.max, material(&b.material));
            objects.extend(placed(faces, b.transform.as_ref()));
        }
        if !triangles.is_empty() {
            // Loose triangles: one mesh per material, in the order written.
            let mut by_material: Vec<(u32, Vec<Vec3>)> = Vec::new();
            for t in triangles {
                let m = material(&t.material);
                let at = by_material.iter().position(|(k, _)| *k == m).unwrap_or_else(|| {
                    by_material.push((m, Vec::new()));
                    by_material.len() - 1
                });
                by_material[at].1.extend(t.vertices.map(vec3));
            }
            for (m, corners) in by_material {
                objects.push(Object::Mesh(std::sync::Arc::new(assets.soup(corners)), m));
            }
        }
        for m in meshes {
            let mesh = assets.mesh(m.obj.as_deref(), m.generate.as_ref(), m.scale);
            let object = Object::Mesh(mesh, material(&m.material));
            objects.extend(placed(vec![object], m.transform.as_ref()));
        }
        for m in media {
            let boundary = match m.boundary {
                BoundarySpec::Sphere { center, radius } => {
                    vec![Object::shape(Sphere { center: vec3(center), radius: radius as Real, material: 0 })]
                }
                BoundarySpec::Box { min, max } => box_objects(min, max, 0),
            };
            let phase = tables.push(Material::Isotropic { albedo: vec3(m.albedo) });
            let medium = Medium {
                boundary: Group::new(boundary),
                density: m.density as Real,
                material: phase,
                id: *made,
            };
            *made += 1;
            objects.extend(placed(vec![Object::Medium(Box::new(medium))], m.transform.as_ref()));
        }
        (still, objects)
    }
}

fn box_objects(min: [f64; 3], max: [f64; 3], material: u32) -> Vec<Object> {
    let faces = box_faces(vec3(min), vec3(max), material).expect("checked: a box of some volume");
    faces.into_iter().map(Object::shape).collect()
}
