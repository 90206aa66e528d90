//! How surfaces look, as a scene file writes it: materials and textures, inline or by name,
//! their checks, and what they become in the tracer's tables.

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};

use crate::scenes::assets::Assets;
use crate::scenes::checks::{REAL, check, colour, representable};
use crate::tracer::math::real::{Real, vec3};
use crate::tracer::shading::material::{Fresnel, Material};
use crate::tracer::shading::perlin::Perlin;
use crate::tracer::shading::texture::{NOISE_SEED, Texture, Textures};

/// A material as written: `{ kind = "lambertian" | "metal" | "dielectric" | "diffuse_light", … }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialSpec {
    /// Diffuse, with a colour (`albedo`) or a texture (`texture`), exactly one.
    Lambertian {
        /// Reflectance per channel, each ≥ 0.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        albedo: Option<[f64; 3]>,
        /// A texture table or the name of one in `[textures]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        texture: Option<Ref<TextureSpec>>,
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
        /// `"schlick"` (the books' approximation, the default) or `"exact"` (the Fresnel
        /// equations, as pbrt and Mitsuba).
        #[serde(default, skip_serializing_if = "is_schlick")]
        fresnel: FresnelSpec,
    },
    /// A light: emits `emit` from its front face.
    DiffuseLight {
        /// Emitted radiance per channel, each ≥ 0.
        emit: [f64; 3],
        /// Grey diffuse reflectance in `[0, 1]` (default 0: the books' lights reflect nothing).
        #[serde(default, skip_serializing_if = "is_zero")]
        albedo: f64,
    },
}

/// How glass computes its reflectance, as written: `fresnel = "schlick" | "exact"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FresnelSpec {
    /// Schlick's approximation (the books').
    #[default]
    Schlick,
    /// The Fresnel equations.
    Exact,
}

fn is_schlick(fresnel: &FresnelSpec) -> bool {
    *fresnel == FresnelSpec::Schlick
}

impl MaterialSpec {
    /// Glass of index `ior` with the books' Schlick reflectance.
    pub fn glass(ior: f64) -> MaterialSpec {
        MaterialSpec::Dielectric { ior, fresnel: FresnelSpec::Schlick }
    }

    /// A plain diffuse colour.
    pub fn lambertian(albedo: [f64; 3]) -> MaterialSpec {
        MaterialSpec::Lambertian { albedo: Some(albedo), texture: None }
    }
}

/// A texture as written: `{ kind = "solid" | "checker" | "noise" | "image", … }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TextureSpec {
    /// One colour.
    Solid {
        /// Linear RGB, each ≥ 0.
        color: [f64; 3],
    },
    /// The book's 3-D checker of cells of side `scale`.
    Checker {
        /// Cell side, > 0.
        scale: f64,
        /// Colour of the even cells.
        even: [f64; 3],
        /// Colour of the odd cells.
        odd: [f64; 3],
    },
    /// The book's marble of Perlin turbulence.
    Noise {
        /// Stripe frequency, > 0.
        scale: f64,
    },
    /// An image: a PNG beside the scene file (`path`), or one the project makes (`builtin`).
    Image {
        /// Relative to the scene file's folder, inside it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        path: Option<String>,
        /// `"planet"`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        builtin: Option<String>,
    },
}

/// A value written inline as a table, or as the name of one in a named block.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Ref<T> {
    /// `material = "gold"`.
    Named(String),
    /// `material = { kind = "metal", … }`.
    Inline(T),
}

/// A shape's material.
pub type MaterialRef = Ref<MaterialSpec>;

// Hand-written so that an inline table's errors (an unknown `kind`, a missing field) reach
// the user verbatim, instead of serde's "data did not match any variant".
impl<'de, T: Deserialize<'de>> Deserialize<'de> for Ref<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct RefVisitor<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for RefVisitor<T> {
            type Value = Ref<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table, or the name of one in the scene's named block")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<Ref<T>, E> {
                Ok(Ref::Named(name.to_owned()))
            }
            fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<Ref<T>, M::Error> {
                T::deserialize(de::value::MapAccessDeserializer::new(map)).map(Ref::Inline)
            }
        }
        deserializer.deserialize_any(RefVisitor(std::marker::PhantomData))
    }
}

/// The scene's named materials and textures, as the checks and the conversion see them.
pub struct Looks<'a> {
    /// `[materials]`.
    pub materials: &'a BTreeMap<String, MaterialSpec>,
    /// `[textures]`.
    pub textures: &'a BTreeMap<String, TextureSpec>,
}

impl Looks<'_> {
    /// Checks a material reference (inline or named).
    pub fn check_material(&self, m: &MaterialRef) -> Result<(), String> {
        match m {
            Ref::Inline(spec) => self.check_material_spec(spec).map_err(|e| format!("material {e}")),
            Ref::Named(n) => check(self.materials.contains_key(n), || {
                format!("unknown material '{n}' (not in [materials])")
            }),
        }
    }

    /// Checks one material's numbers and its texture.
    pub fn check_material_spec(&self, m: &MaterialSpec) -> Result<(), String> {
        match m {
            MaterialSpec::Lambertian { albedo, texture } => match (albedo, texture) {
                (Some(albedo), None) => colour(*albedo).map_err(|e| format!("albedo {e}")),
                (None, Some(Ref::Inline(t))) => check_texture(t).map_err(|e| format!("texture {e}")),
                (None, Some(Ref::Named(n))) => check(self.textures.contains_key(n), || {
                    format!("unknown texture '{n}' (not in [textures])")
                }),
                _ => Err("lambertian needs exactly one of albedo and texture".to_owned()),
            },
            MaterialSpec::Metal { albedo, fuzz } => {
                colour(*albedo).map_err(|e| format!("albedo {e}"))?;
                check(representable(*fuzz) && *fuzz >= 0.0, || {
                    format!("fuzz must be finite (as {REAL}) and ≥ 0, got {fuzz}")
                })
            }
            MaterialSpec::Dielectric { ior, .. } => check(representable(*ior) && *ior > 0.0, || {
                format!("ior must be finite (as {REAL}) and > 0, got {ior}")
            }),
            MaterialSpec::DiffuseLight { emit, albedo } => {
                colour(*emit).map_err(|e| format!("emit {e}"))?;
                check((0.0..=1.0).contains(albedo), || format!("albedo must be in [0, 1], got {albedo}"))
            }
        }
    }
}

/// Checks a texture's numbers (an image's source is checked when assets are loaded).
pub fn check_texture(t: &TextureSpec) -> Result<(), String> {
    match t {
        TextureSpec::Solid { color } => colour(*color).map_err(|e| format!("color {e}")),
        TextureSpec::Checker { scale, even, odd } => {
            check(representable(*scale) && *scale > 0.0, || {
                format!("scale must be finite (as {REAL}) and > 0, got {scale}")
            })?;
            colour(*even).map_err(|e| format!("even {e}"))?;
            colour(*odd).map_err(|e| format!("odd {e}"))
        }
        TextureSpec::Noise { scale } => check(representable(*scale) && *scale > 0.0, || {
            format!("scale must be finite (as {REAL}) and > 0, got {scale}")
        }),
        TextureSpec::Image { path, builtin } => match (path, builtin) {
            (Some(_), None) | (None, Some(_)) => Ok(()),
            _ => Err("an image texture needs exactly one of path and builtin".to_owned()),
        },
    }
}

/// The tracer's material and texture tables, filled as a scene's shapes name them.
#[derive(Default)]
pub struct Tables {
    /// The material table.
    pub materials: Vec<Material>,
    /// The textures.
    pub textures: Textures,
    named_materials: BTreeMap<String, u32>,
    named_textures: BTreeMap<String, u32>,
}

impl Tables {
    /// The index of a (checked) material, added on first use; named ones once.
    pub fn material(&mut self, looks: &Looks, assets: &Assets, m: &MaterialRef) -> u32 {
        match m {
            Ref::Named(n) => {
                if let Some(&i) = self.named_materials.get(n) {
                    return i;
                }
                let i = self.add_material(looks, assets, &looks.materials[n]);
                self.named_materials.insert(n.clone(), i);
                i
            }
            Ref::Inline(spec) => self.add_material(looks, assets, spec),
        }
    }

    /// Adds a material of its own (a medium's isotropic phase function).
    pub fn push(&mut self, material: Material) -> u32 {
        self.materials.push(material);
        (self.materials.len() - 1) as u32
    }

    fn add_material(&mut self, looks: &Looks, assets: &Assets, spec: &MaterialSpec) -> u32 {
        let material = match spec {
            MaterialSpec::Lambertian { albedo: Some(albedo), .. } => {
                Material::Lambertian { albedo: vec3(*albedo) }
            }
            MaterialSpec::Lambertian { texture: Some(t), .. } => {
                Material::Textured { texture: self.texture(looks, assets, t) }
            }
            MaterialSpec::Lambertian { .. } => unreachable!("checked: albedo or texture"),
            MaterialSpec::Metal { albedo, fuzz } => {
                Material::Metal { albedo: vec3(*albedo), fuzz: *fuzz as Real }
            }
            MaterialSpec::Dielectric { ior, fresnel } => {
                let fresnel = match fresnel {
                    FresnelSpec::Schlick => Fresnel::Schlick,
                    FresnelSpec::Exact => Fresnel::Exact,
                };
                Material::Dielectric { ior: *ior as Real, fresnel }
            }
            MaterialSpec::DiffuseLight { emit, albedo } => {
                Material::DiffuseLight { emit: vec3(*emit), albedo: *albedo as Real }
            }
        };
        self.push(material)
    }

    fn texture(&mut self, looks: &Looks, assets: &Assets, t: &Ref<TextureSpec>) -> u32 {
        let spec = match t {
            Ref::Named(n) => {
                if let Some(&i) = self.named_textures.get(n) {
                    return i;
                }
                &looks.textures[n]
            }
            Ref::Inline(spec) => spec,
        };
        let texture = match spec {
            TextureSpec::Solid { color } => Texture::Solid { color: vec3(*color) },
            TextureSpec::Checker { scale, even, odd } => {
                Texture::Checker { inv_scale: (1.0 / scale) as Real, even: vec3(*even), odd: vec3(*odd) }
            }
            TextureSpec::Noise { scale } => {
                self.textures.noise.get_or_insert_with(|| Perlin::new(NOISE_SEED));
                Texture::Marble { scale: *scale as Real }
            }
            TextureSpec::Image { path, builtin } => {
                self.textures.images.push(assets.image(path.as_deref(), builtin.as_deref()));
                Texture::Image { image: (self.textures.images.len() - 1) as u32 }
            }
        };
        self.textures.textures.push(texture);
        let i = (self.textures.textures.len() - 1) as u32;
        if let Ref::Named(n) = t {
            self.named_textures.insert(n.clone(), i);
        }
        i
    }
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
