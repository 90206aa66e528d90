//! The TOML scene format: what a student writes by hand, and what `raypool scene` prints.
//!
//! ```toml
//! [camera]
//! lookfrom = [13.0, 2.0, 3.0]
//! lookat = [0.0, 0.0, 0.0]
//! vup = [0.0, 1.0, 0.0]
//! vfov = 20.0          # vertical field of view, degrees
//! aperture = 0.1       # lens diameter; 0 = pinhole
//! focus_dist = 10.0     # default: the distance from lookfrom to lookat
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
use crate::scenes::assets::{Assets, BUILTIN_IMAGES};
use crate::scenes::checks::{REAL, check, colour, finite3, representable};
use crate::scenes::composites::MeshSpec;
use crate::scenes::looks::{Looks, Ref, Tables, TextureSpec, check_texture};
use crate::scenes::placement::placed;
use crate::scenes::world::{GroupSpec, Key, Shapes};
use crate::tracer::camera::CameraSettings;
use crate::tracer::math::real::vec3;
use crate::tracer::scene::Scene;
use crate::tracer::shading::background::Background;

pub use crate::scenes::looks::{MaterialRef, MaterialSpec};

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFile {
    /// The camera block.
    pub camera: CameraSettings,
    /// The background block (the book's gradient when absent).
    pub background: BackgroundSpec,
    /// Named materials that shapes may refer to.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Named textures that materials may refer to.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub textures: BTreeMap<String, TextureSpec>,
    /// Its shapes: `[[sphere]]`, `[[quad]]`, … tables.
    #[serde(flatten)]
    pub shapes: Shapes,
    /// `[[group]]` tables: shapes placed together (instances).
    #[serde(rename = "group", skip_serializing_if = "Vec::is_empty")]
    pub groups: Vec<GroupSpec>,
    /// The files it names, loaded ([`SceneFile::read`]); not part of what it says.
    #[serde(skip)]
    pub assets: Loaded,
}

impl<'de> Deserialize<'de> for SceneFile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<SceneFile, D::Error> {
        deserializer.deserialize_map(SceneVisitor)
    }
}

/// Reads a scene file: its own blocks, and its shapes' tables ([`Shapes`]).
struct SceneVisitor;

impl<'de> Visitor<'de> for SceneVisitor {
    type Value = SceneFile;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a scene file")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SceneFile, A::Error> {
        const KEYS: &[&str] = &["camera", "background", "materials", "textures", "group"];
        let (mut camera, mut shapes) = (None, Shapes::default());
        let (mut background, mut materials, mut textures, mut groups) = Default::default();
        while let Some(key) = map.next_key_seed(Key(KEYS))? {
            match key.as_str() {
                "camera" => camera = Some(map.next_value()?),
                "background" => background = map.next_value()?,
                "materials" => materials = map.next_value()?,
                "textures" => textures = map.next_value()?,
                "group" => groups = map.next_value()?,
                table => shapes.read(table, &mut map)?,
            }
        }
        let camera = camera.ok_or_else(|| de::Error::missing_field("camera"))?;
        Ok(SceneFile { camera, background, materials, textures, shapes, groups, assets: Loaded::default() })
    }
}

/// What a scene file's named files became. Equal for any two scenes: they are fixed by the
/// text, which is what [`SceneFile`] equality compares.
#[derive(Clone, Debug, Default)]
pub struct Loaded(pub Assets);

impl PartialEq for Loaded {
    fn eq(&self, _: &Loaded) -> bool {
        true
    }
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
    /// `kind = "black"`: no light from outside; only emitters light the scene.
    Black,
}

impl Default for BackgroundSpec {
    fn default() -> Self {
        BackgroundSpec::Gradient { horizon: [1.0, 1.0, 1.0], zenith: [0.5, 0.7, 1.0] }
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
    /// files and pipes are refused too), then loads the files it names (OBJ meshes, images)
    /// from its folder.
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
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        SceneFile::parse_in(&text, &name.to_string(), Some(folder))
    }

    /// Parses and validates TOML text; `origin` names the source in error messages. A scene
    /// parsed from text alone may not name files (it has no folder to find them in).
    pub fn parse(text: &str, origin: &str) -> Result<SceneFile, Error> {
        SceneFile::parse_in(text, origin, None)
    }

    fn parse_in(text: &str, origin: &str, folder: Option<&Path>) -> Result<SceneFile, Error> {
        let mut file: SceneFile = toml::from_str(text).map_err(|e| {
            let (line, col) = e.span().map_or((1, 1), |span| line_col(text, span.start));
            let message = missing_camera_fields(text, e.message())
                .unwrap_or_else(|| e.message().trim_end().replace('\n', " "));
            Error::new(format!("{origin}:{line}:{col}: {message}"))
        })?;
        file.validate().map_err(|e| Error::new(format!("{origin}: {e}")))?;
        file.assets = Loaded(file.load_assets(folder).map_err(|e| Error::new(format!("{origin}: {e}")))?);
        Ok(file)
    }

    /// An empty scene seen by `camera` under `background`.
    pub fn new(camera: CameraSettings, background: BackgroundSpec) -> SceneFile {
        SceneFile {
            camera,
            background,
            materials: BTreeMap::new(),
            textures: BTreeMap::new(),
            shapes: Shapes::default(),
            groups: Vec::new(),
            assets: Loaded::default(),
        }
    }

    /// Every shape list: the top level's, then each group's.
    fn all_shapes(&self) -> impl Iterator<Item = &Shapes> {
        std::iter::once(&self.shapes).chain(self.groups.iter().map(|group| &group.shapes))
    }

    /// The scene as TOML text that [`SceneFile::parse`] reads back to an equal value.
    ///
    /// Spheres are written as the format's documentation shows them, one `[[sphere]]` table
    /// each with its material inline, rather than as `toml`'s default `[sphere.material]`
    /// sub-tables, which would double the length of a 480-sphere scene.
    pub fn to_toml(&self) -> String {
        let mut head = self.clone();
        head.shapes.spheres.clear();
        let mut text = toml::to_string(&head).expect("scene files always serialise");
        for s in &self.shapes.spheres {
            text += &format!(
                "\n[[sphere]]\ncenter = {}\nradius = {}\nmaterial = {}\n",
                inline(&s.center),
                inline(&s.radius),
                inline(&s.material)
            );
            if let Some(c1) = &s.center1 {
                text += &format!("center1 = {}\n", inline(c1));
            }
        }
        text
    }

    /// Checks what the TOML grammar cannot: finite numbers, sensible camera, non-zero radii,
    /// shapes with area, known material and texture names. The message names the offending
    /// item.
    pub fn validate(&self) -> Result<(), String> {
        let c = &self.camera;
        for (name, v) in [("lookfrom", c.lookfrom), ("lookat", c.lookat), ("vup", c.vup)] {
            check(finite3(v), || format!("camera.{name} must be finite numbers, got {v:?}"))?;
        }
        for (name, x) in
            [("vfov", c.vfov), ("aperture", c.aperture), ("focus_dist", c.focus()), ("aspect", c.aspect)]
        {
            if !representable(x) {
                return Err(format!("camera.{name} must be a finite number (as {REAL}), got {x}"));
            }
        }
        check(c.vfov > 0.0 && c.vfov < 180.0, || {
            format!("camera.vfov must be in (0, 180) degrees, got {}", c.vfov)
        })?;
        check(c.aperture >= 0.0, || format!("camera.aperture must be ≥ 0, got {}", c.aperture))?;
        // Absent, it is the distance to lookat, which the check of the two points below keeps > 0.
        let focus = c.focus_dist.unwrap_or(1.0);
        check(focus > 0.0, || format!("camera.focus_dist must be > 0, got {focus}"))?;
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
            BackgroundSpec::Black => {}
        }
        let looks = Looks { materials: &self.materials, textures: &self.textures };
        for (name, t) in &self.textures {
            check_texture(t).map_err(|e| format!("textures.{name}: {e}"))?;
        }
        for (name, m) in &self.materials {
            looks.check_material_spec(m).map_err(|e| format!("materials.{name}: {e}"))?;
        }
        self.shapes.check(&looks, "")?;
        for (i, g) in self.groups.iter().enumerate() {
            if let Some(transform) = &g.transform {
                transform.check().map_err(|e| format!("group #{}: {e}", i + 1))?;
            }
            g.shapes.check(&looks, &format!("group #{} ", i + 1))?;
        }
        for (builtin, _) in self.image_sources().filter_map(|(p, b)| b.map(|b| (b, p))) {
            check(BUILTIN_IMAGES.contains(&builtin), || {
                format!("unknown built-in image '{builtin}' (known: {})", BUILTIN_IMAGES.join(", "))
            })?;
        }
        Ok(())
    }

    /// Every image texture's `(path, builtin)`, named or inline.
    fn image_sources(&self) -> impl Iterator<Item = (Option<&str>, Option<&str>)> {
        let inline = self.all_shapes().flat_map(|s| s.material_refs().collect::<Vec<_>>());
        let materials = self.materials.values().chain(inline.filter_map(|m| match m {
            Ref::Inline(spec) => Some(spec),
            Ref::Named(_) => None,
        }));
        let textures = materials
            .filter_map(|m| match m {
                MaterialSpec::Lambertian { texture: Some(Ref::Inline(t)), .. } => Some(t),
                _ => None,
            })
            .chain(self.textures.values());
        textures.filter_map(|t| match t {
            TextureSpec::Image { path, builtin } => Some((path.as_deref(), builtin.as_deref())),
            _ => None,
        })
    }

    /// Loads the OBJ files and images the (validated) scene names, from `folder`.
    fn load_assets(&self, folder: Option<&Path>) -> Result<Assets, String> {
        let meshes: Vec<(usize, &str, Option<f64>)> = self
            .all_shapes()
            .flat_map(|s| s.meshes.iter().enumerate())
            .filter_map(|(i, m): (usize, &MeshSpec)| Some((i + 1, m.obj.as_deref()?, m.scale)))
            .collect();
        let images: Vec<&str> = self.image_sources().filter_map(|(path, _)| path).collect();
        Assets::load(folder, &meshes, &images)
    }

    /// The render-ready scene. Call on a validated file (as [`SceneFile::parse`] returns).
    pub fn to_scene(&self) -> Scene {
        let looks = Looks { materials: &self.materials, textures: &self.textures };
        let mut tables = Tables::default();
        let mut media = 0;
        let assets = &self.assets.0;
        let (spheres, mut objects) = self.shapes.build(&looks, assets, &mut tables, &mut media);
        for g in &self.groups {
            let (inner_spheres, inner) = g.shapes.build(&looks, assets, &mut tables, &mut media);
            let inner =
                inner_spheres.into_iter().map(crate::tracer::world::object::Object::shape).chain(inner);
            objects.extend(placed(inner.collect(), g.transform.as_ref()));
        }
        let background = match self.background {
            BackgroundSpec::Gradient { horizon, zenith } => {
                Background::Gradient { horizon: vec3(horizon), zenith: vec3(zenith) }
            }
            BackgroundSpec::Constant { color } => Background::Constant { color: vec3(color) },
            BackgroundSpec::Black => Background::Constant { color: vec3([0.0; 3]) },
        };
        Scene::with_world(
            spheres,
            objects,
            tables.materials,
            tables.textures,
            background,
            self.camera.clone(),
        )
    }
}

/// The fields a `[camera]` must give; the others have defaults (`CameraSettings`).
pub const CAMERA_REQUIRED: [&str; 4] = ["lookfrom", "lookat", "vup", "vfov"];

/// Where toml's `message` reports one missing camera field, a message naming every required
/// field the `[camera]` table lacks: serde stops at the first, and a minimal camera would
/// otherwise be fixed one field per run. (The error's place, the table's line, is toml's.)
fn missing_camera_fields(text: &str, message: &str) -> Option<String> {
    let field = message.trim().strip_prefix("missing field `")?.strip_suffix('`')?;
    let document: toml::Table = toml::from_str(text).ok()?;
    if field == "camera" && !document.contains_key("camera") {
        return Some(format!("no [camera] table (a scene needs one, with {})", CAMERA_REQUIRED.join(", ")));
    }
    let camera = document.get("camera")?.as_table()?;
    let missing: Vec<String> =
        CAMERA_REQUIRED.iter().filter(|f| !camera.contains_key(**f)).map(|f| format!("`{f}`")).collect();
    if !missing.iter().any(|m| m.trim_matches('`') == field) {
        return None;
    }
    let plural = if missing.len() == 1 { "" } else { "s" };
    Some(format!(
        "[camera] is missing field{plural} {} (it needs {})",
        missing.join(", "),
        CAMERA_REQUIRED.join(", ")
    ))
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
