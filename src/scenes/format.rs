//! The TOML scene format: what a student writes by hand, and what `raypool scene` prints.
//!
//! ```toml
//! [camera]
//! lookfrom = [13.0, 2.0, 3.0]
//! lookat = [0.0, 0.0, 0.0]
//! vup = [0.0, 1.0, 0.0]
//! vfov = 20.0          # vertical field of view, degrees
//! aperture = 0.1       # lens diameter; 0 = pinhole
//! focus_dist = 10.0
//! aspect = 1.5         # width / height when --height is not given (default 1.5)
//!
//! [background]
//! kind = "gradient"    # or: kind = "constant", color = [1.0, 1.0, 1.0]
//! horizon = [1.0, 1.0, 1.0]
//! zenith = [0.5, 0.7, 1.0]
//!
//! [materials]          # optional named materials
//! gold = { kind = "metal", albedo = [0.8, 0.6, 0.2], fuzz = 0.1 }
//!
//! [[sphere]]
//! center = [0.0, -1000.0, 0.0]
//! radius = 1000.0      # negative: a hollow shell (normals inwards)
//! material = { kind = "lambertian", albedo = [0.5, 0.5, 0.5] }
//!
//! [[sphere]]
//! center = [4.0, 1.0, 0.0]
//! radius = 1.0
//! material = "gold"    # a named material
//! ```
//!
//! Parsing reports `file:line:col: message`; [`SceneFile::validate`] then rejects what TOML
//! accepts but a renderer cannot use (NaN, zero radius, a camera looking nowhere…).

use std::collections::BTreeMap;
use std::fmt;
use std::io::Read;
use std::path::Path;

use glam::DVec3;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};

use crate::error::{Error, io_reason};
use crate::tracer::camera::CameraSettings;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::real::{Real, vec3};
use crate::tracer::scene::Scene;
use crate::tracer::shading::background::Background;
use crate::tracer::shading::material::Material;

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The camera block.
    pub camera: CameraSettings,
    /// The background block (the book's gradient when absent).
    #[serde(default)]
    pub background: BackgroundSpec,
    /// Named materials that spheres may refer to.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// The spheres, one `[[sphere]]` table each.
    #[serde(default, rename = "sphere", skip_serializing_if = "Vec::is_empty")]
    pub spheres: Vec<SphereSpec>,
}

/// The `[background]` block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum BackgroundSpec {
    /// `kind = "gradient"`: blend from `horizon` (looking down) to `zenith` (looking up).
    Gradient {
        /// Linear RGB.
        horizon: [f64; 3],
        /// Linear RGB.
        zenith: [f64; 3],
    },
    /// `kind = "constant"`: one colour in every direction.
    Constant {
        /// Linear RGB.
        color: [f64; 3],
    },
}

impl Default for BackgroundSpec {
    fn default() -> Self {
        BackgroundSpec::Gradient { horizon: [1.0, 1.0, 1.0], zenith: [0.5, 0.7, 1.0] }
    }
}

/// A material as written: `{ kind = "lambertian" | "metal" | "dielectric", … }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum MaterialSpec {
    /// Diffuse.
    Lambertian {
        /// Reflectance per channel, each ≥ 0.
        albedo: [f64; 3],
    },
    /// Fuzzy mirror.
    Metal {
        /// Reflectance per channel, each ≥ 0.
        albedo: [f64; 3],
        /// Blur, ≥ 0 (values above 1 act as 1); default 0.
        #[serde(default)]
        fuzz: f64,
    },
    /// Glass.
    Dielectric {
        /// Refractive index, > 0.
        ior: f64,
    },
}

/// One `[[sphere]]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Radius, non-zero; negative for a hollow shell.
    pub radius: f64,
    /// Inline material or the name of one in `[materials]`.
    pub material: MaterialRef,
}

/// A sphere's material: written inline as a table, or as the name of a named material.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum MaterialRef {
    /// `material = "gold"`.
    Named(String),
    /// `material = { kind = "metal", … }`.
    Inline(MaterialSpec),
}

// Hand-written so that an inline table's errors (an unknown `kind`, a missing field) reach
// the user verbatim, instead of serde's "data did not match any variant".
impl<'de> Deserialize<'de> for MaterialRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct RefVisitor;
        impl<'de> Visitor<'de> for RefVisitor {
            type Value = MaterialRef;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a material table or the name of a material in [materials]")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<MaterialRef, E> {
                Ok(MaterialRef::Named(name.to_owned()))
            }
            fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<MaterialRef, M::Error> {
                MaterialSpec::deserialize(de::value::MapAccessDeserializer::new(map)).map(MaterialRef::Inline)
            }
        }
        deserializer.deserialize_any(RefVisitor)
    }
}

/// The largest scene file [`SceneFile::read`] accepts, in bytes (16 MiB).
///
/// The book's final scene, 488 spheres, is 45 KiB of TOML; a scene of 100 000 spheres fits
/// in 10 MiB. The bound exists so that a wrong path (`/dev/zero`, a video, a pipe that never
/// ends) is refused at once instead of being read until memory runs out.
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;

impl SceneFile {
    /// Reads, parses and validates the scene file at `path`, refusing one longer than
    /// [`MAX_SCENE_FILE_BYTES`] after reading at most one byte past that bound (so endless
    /// files and pipes are refused too).
    ///
    /// ```
    /// # use raypool::scenes::format::SceneFile;
    /// let err = SceneFile::read("/dev/zero".as_ref()).unwrap_err();
    /// assert!(err.to_string().contains("larger than 16 MiB"), "{err}");
    /// ```
    pub fn read(path: &Path) -> Result<SceneFile, Error> {
        let name = path.display();
        let cannot =
            |e: std::io::Error| Error::new(format!("cannot read scene file '{name}': {}", io_reason(&e)));
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|file| file.take(MAX_SCENE_FILE_BYTES + 1).read_to_end(&mut bytes))
            .map_err(cannot)?;
        if bytes.len() as u64 > MAX_SCENE_FILE_BYTES {
            return Err(Error::new(format!(
                "scene file '{name}' is larger than {} MiB: not a scene",
                MAX_SCENE_FILE_BYTES >> 20
            )));
        }
        let text = String::from_utf8(bytes)
            .map_err(|_| Error::new(format!("scene file '{name}' is not UTF-8 text: not a scene")))?;
        SceneFile::parse(&text, &name.to_string())
    }

    /// Parses and validates TOML text; `origin` names the source in error messages.
    pub fn parse(text: &str, origin: &str) -> Result<SceneFile, Error> {
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let (line, col) = e.span().map_or((1, 1), |span| line_col(text, span.start));
            let message = e.message().trim_end().replace('\n', " ");
            Error::new(format!("{origin}:{line}:{col}: {message}"))
        })?;
        file.validate().map_err(|e| Error::new(format!("{origin}: {e}")))?;
        Ok(file)
    }

    /// The scene as TOML text that [`SceneFile::parse`] reads back to an equal value.
    ///
    /// Spheres are written as the format's documentation shows them, one `[[sphere]]` table
    /// each with its material inline, rather than as `toml`'s default `[sphere.material]`
    /// sub-tables, which would double the length of a 480-sphere scene.
    pub fn to_toml(&self) -> String {
        let head = SceneFile { spheres: Vec::new(), ..self.clone() };
        let mut text = toml::to_string(&head).expect("scene files always serialise");
        for s in &self.spheres {
            text += &format!(
                "\n[[sphere]]\ncenter = {}\nradius = {}\nmaterial = {}\n",
                inline(&s.center),
                inline(&s.radius),
                inline(&s.material)
            );
        }
        text
    }

    /// Checks what the TOML grammar cannot: finite numbers, sensible camera, non-zero radii,
    /// known material names. The message names the offending item.
    pub fn validate(&self) -> Result<(), String> {
        let c = &self.camera;
        for (name, v) in [("lookfrom", c.lookfrom), ("lookat", c.lookat), ("vup", c.vup)] {
            finite3(v).map_err(|_| format!("camera.{name} must be finite numbers, got {v:?}"))?;
        }
        for (name, x) in
            [("vfov", c.vfov), ("aperture", c.aperture), ("focus_dist", c.focus_dist), ("aspect", c.aspect)]
        {
            if !x.is_finite() {
                return Err(format!("camera.{name} must be a finite number, got {x}"));
            }
        }
        check(c.vfov > 0.0 && c.vfov < 180.0, || {
            format!("camera.vfov must be in (0, 180) degrees, got {}", c.vfov)
        })?;
        check(c.aperture >= 0.0, || format!("camera.aperture must be ≥ 0, got {}", c.aperture))?;
        check(c.focus_dist > 0.0, || format!("camera.focus_dist must be > 0, got {}", c.focus_dist))?;
        check(c.aspect > 0.0, || format!("camera.aspect must be > 0, got {}", c.aspect))?;
        let (view, vup) = (DVec3::from(c.lookat) - DVec3::from(c.lookfrom), DVec3::from(c.vup));
        check(view != DVec3::ZERO, || "camera.lookfrom and camera.lookat are the same point".to_owned())?;
        check(vup.cross(view).length() > 1e-9 * view.length() * vup.length(), || {
            "camera.vup must not be zero or parallel to the view direction".to_owned()
        })?;
        match self.background {
            BackgroundSpec::Gradient { horizon, zenith } => {
                colour(horizon).map_err(|e| format!("background.horizon {e}"))?;
                colour(zenith).map_err(|e| format!("background.zenith {e}"))?;
            }
            BackgroundSpec::Constant { color } => {
                colour(color).map_err(|e| format!("background.color {e}"))?
            }
        }
        for (name, m) in &self.materials {
            validate_material(m).map_err(|e| format!("materials.{name}: {e}"))?;
        }
        for (i, s) in self.spheres.iter().enumerate() {
            let at = format!("sphere #{} (center {:?})", i + 1, s.center);
            finite3(s.center).map_err(|_| format!("sphere #{}: center must be finite numbers", i + 1))?;
            check(s.radius.is_finite() && s.radius != 0.0, || {
                format!("{at}: radius must be finite and non-zero, got {}", s.radius)
            })?;
            match &s.material {
                MaterialRef::Inline(m) => validate_material(m).map_err(|e| format!("{at}: material {e}"))?,
                MaterialRef::Named(n) => check(self.materials.contains_key(n), || {
                    format!("{at}: unknown material '{n}' (not in [materials])")
                })?,
            }
        }
        Ok(())
    }

    /// The render-ready scene. Call on a validated file (as [`SceneFile::parse`] returns).
    pub fn to_scene(&self) -> Scene {
        let mut materials = Vec::new();
        let named: BTreeMap<&str, u32> = self
            .materials
            .iter()
            .map(|(name, spec)| {
                materials.push(spec.to_material());
                (name.as_str(), (materials.len() - 1) as u32)
            })
            .collect();
        let spheres = self
            .spheres
            .iter()
            .map(|s| {
                let material = match &s.material {
                    MaterialRef::Named(n) => named[n.as_str()],
                    MaterialRef::Inline(spec) => {
                        materials.push(spec.to_material());
                        (materials.len() - 1) as u32
                    }
                };
                Sphere { center: vec3(s.center), radius: s.radius as Real, material }
            })
            .collect();
        let background = match self.background {
            BackgroundSpec::Gradient { horizon, zenith } => {
                Background::Gradient { horizon: vec3(horizon), zenith: vec3(zenith) }
            }
            BackgroundSpec::Constant { color } => Background::Constant { color: vec3(color) },
        };
        Scene::new(spheres, materials, background, self.camera.clone())
    }
}

impl MaterialSpec {
    fn to_material(&self) -> Material {
        match *self {
            MaterialSpec::Lambertian { albedo } => Material::Lambertian { albedo: vec3(albedo) },
            MaterialSpec::Metal { albedo, fuzz } => {
                Material::Metal { albedo: vec3(albedo), fuzz: fuzz as Real }
            }
            MaterialSpec::Dielectric { ior } => Material::Dielectric { ior: ior as Real },
        }
    }
}

fn validate_material(m: &MaterialSpec) -> Result<(), String> {
    match *m {
        MaterialSpec::Lambertian { albedo } => colour(albedo).map_err(|e| format!("albedo {e}")),
        MaterialSpec::Metal { albedo, fuzz } => {
            colour(albedo).map_err(|e| format!("albedo {e}"))?;
            check(fuzz.is_finite() && fuzz >= 0.0, || format!("fuzz must be finite and ≥ 0, got {fuzz}"))
        }
        MaterialSpec::Dielectric { ior } => {
            check(ior.is_finite() && ior > 0.0, || format!("ior must be finite and > 0, got {ior}"))
        }
    }
}

fn check(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok { Ok(()) } else { Err(message()) }
}

fn finite3(v: [f64; 3]) -> Result<(), ()> {
    if v.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(()) }
}

fn colour(v: [f64; 3]) -> Result<(), String> {
    check(v.iter().all(|x| x.is_finite() && *x >= 0.0), || format!("must be finite and ≥ 0, got {v:?}"))
}

/// `value` as an inline TOML value.
fn inline<T: Serialize>(value: &T) -> String {
    let mut out = String::new();
    value.serialize(toml::ser::ValueSerializer::new(&mut out)).expect("scene values always serialise");
    out
}

/// 1-based line and column of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}
