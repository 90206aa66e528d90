//! The second book's shapes as a scene file writes them: `[[sphere]]`, `[[quad]]`, `[[box]]`,
//! pbrt's `[[disc]]`, `[[triangle]]`, `[[mesh]]`, `[[medium]]`, each also inside a `[[group]]`
//! (objects placed together by one transform, the scene file's instances: `placement.rs`);
//! how a table of them is read ([`Shapes::read`]), what they must hold ([`Shapes::check`]) and
//! the objects they become. The simple shapes' specs are here; those the format makes of other
//! objects (boxes, loose triangles, meshes, media) are `composites.rs`.
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

use crate::scenes::assets::Assets;
use crate::scenes::checks::{REAL, check, finite3, representable};
use crate::scenes::composites::{BoxSpec, MediumSpec, MeshSpec, TriangleSpec, triangle_meshes};
use crate::scenes::looks::{Looks, MaterialRef, Tables};
use crate::scenes::placement::TransformSpec;
use crate::tracer::geometry::disc::Disc;
use crate::tracer::geometry::moving::MovingSphere;
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::real::{Real, vec3};
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
/// its name ([`Shapes::TABLES`]). The reading, the checks and the build name every
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
            objects.extend(b.objects(material(&b.material)));
        }
        objects.extend(triangle_meshes(triangles, &mut material, assets));
        for m in meshes {
            objects.extend(m.objects(assets, material(&m.material)));
        }
        for m in media {
            objects.extend(m.objects(tables, made));
        }
        (still, objects)
    }

    /// Checks every shape: what TOML accepts but a renderer cannot use (numbers that are not
    /// finite, a zero radius, a degenerate quad, disc, triangle or box), each refused with a
    /// message naming the shape; `at` names where they are (`""` or `"group #2 "`).
    pub fn check(&self, looks: &Looks, at: &str) -> Result<(), String> {
        let Shapes { spheres, quads, discs, boxes, triangles, meshes, media } = self;
        for (i, s) in spheres.iter().enumerate() {
            let name = format!("{at}sphere #{} (center {:?})", i + 1, s.center);
            check(finite3(s.center), || format!("{at}sphere #{}: center must be finite numbers", i + 1))?;
            check(representable(s.radius) && s.radius != 0.0, || {
                format!("{name}: radius must be finite (as {REAL}) and non-zero, got {}", s.radius)
            })?;
            check(s.center1.is_none_or(finite3), || format!("{name}: center1 must be finite numbers"))?;
            looks.check_material(&s.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, q) in quads.iter().enumerate() {
            let name = format!("{at}quad #{}", i + 1);
            check(finite3(q.q) && finite3(q.u) && finite3(q.v), || {
                format!("{name}: q, u, v must be finite numbers")
            })?;
            check(Quad::new(vec3(q.q), vec3(q.u), vec3(q.v), 0).is_some(), || {
                format!("{name}: degenerate (u = {:?} and v = {:?} span no area)", q.u, q.v)
            })?;
            looks.check_material(&q.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, d) in discs.iter().enumerate() {
            let name = format!("{at}disc #{}", i + 1);
            check(finite3(d.center) && finite3(d.normal), || {
                format!("{name}: center, normal must be finite numbers")
            })?;
            check(Disc::new(vec3(d.center), vec3(d.normal), d.radius as Real, 0).is_some(), || {
                format!(
                    "{name}: degenerate (normal {:?}, radius {}: needs a normal and a radius > 0)",
                    d.normal, d.radius
                )
            })?;
            looks.check_material(&d.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, b) in boxes.iter().enumerate() {
            b.check().and_then(|()| looks.check_material(&b.material)).map_err(named(at, "box", i))?;
        }
        for (i, t) in triangles.iter().enumerate() {
            t.check().and_then(|()| looks.check_material(&t.material)).map_err(named(at, "triangle", i))?;
        }
        for (i, m) in meshes.iter().enumerate() {
            m.check().and_then(|()| looks.check_material(&m.material)).map_err(named(at, "mesh", i))?;
        }
        for (i, m) in media.iter().enumerate() {
            m.check().map_err(named(at, "medium", i))?;
        }
        Ok(())
    }
}

/// An error's message, prefixed by the `i`th (from 0) item of `kind` in `at` (`group #2 box #3: …`).
fn named<'a>(at: &'a str, kind: &'a str, i: usize) -> impl Fn(String) -> String + 'a {
    move |e| format!("{at}{kind} #{}: {e}", i + 1)
}
