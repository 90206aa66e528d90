//! Materials: how a surface turns an incoming ray into a scattered one (or absorbs it).
//!
//! An `enum`, not a trait object: a material is 32 bytes of data (in the f32 build: a
//! 16-byte vector, a number and the tag), matching on it costs a
//! predictable branch, and a scene without glass never executes a line of the glass code.
//! Every scattered direction is a unit vector and every attenuation is finite.
//!
//! The second book's materials join the first's: a textured diffuse surface (its colour from
//! the scene's [`Textures`]), a light (`diffuse_light`: it emits from its front face only, the
//! third book's convention, and scatters nothing) and the isotropic phase function of fog and
//! smoke. A sphere-only scene of the first book's materials never reaches their arms: the
//! render loop it runs does not even ask for emission (`render.rs`).

use rand::Rng;

use crate::tracer::geometry::hit::Hit;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::warp::{random_unit_vector, uniform};
use crate::tracer::shading::texture::{Texture, Textures};

/// A surface's material, as in *Ray Tracing in One Weekend*.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Ideal diffuse: scatters around the normal with a cosine distribution.
    Lambertian {
        /// Fraction of light reflected, per channel.
        albedo: Vec3,
    },
    /// A mirror blurred by `fuzz` (0 = perfect mirror; values above 1 act as 1).
    Metal {
        /// Fraction of light reflected, per channel.
        albedo: Vec3,
        /// Radius of the sphere the reflected direction is jittered within.
        fuzz: Real,
    },
    /// Clear glass-like material: reflects or refracts by Snell's law, with the chance of
    /// reflecting given by `fresnel` (the books' Schlick approximation, or the exact equations).
    Dielectric {
        /// Refractive index relative to the surrounding medium (glass ≈ 1.5).
        ior: Real,
        /// How the reflectance is computed.
        fresnel: Fresnel,
    },
    /// Ideal diffuse with its colour from a texture.
    Textured {
        /// Index into the scene's [`Textures`].
        texture: u32,
    },
    /// A light: emits `emit` from its front face; reflects diffusely a grey fraction
    /// `albedo` of what arrives (0, the books' light, absorbs it all).
    DiffuseLight {
        /// Emitted radiance, linear RGB.
        emit: Vec3,
        /// Diffuse reflectance, the same in every channel (an emissive wall of the exact
        /// furnace test reflects too).
        albedo: Real,
    },
    /// The phase function of a participating medium: scatters into every direction alike.
    Isotropic {
        /// Fraction of light scattered (not absorbed), per channel.
        albedo: Vec3,
    },
}

/// A scattered ray's direction and how much of the light it carries back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scatter {
    /// Per-channel factor applied to the light arriving along `direction`.
    pub attenuation: Vec3,
    /// Unit direction of the scattered ray.
    pub direction: Vec3,
}

impl Material {
    /// Scatters a ray arriving along the unit vector `incoming` at `hit`; `None` = absorbed.
    /// Forced inline into the render loop: left to the compiler it became a call once the
    /// sphere warp's sine and cosine were inlined (`results/history/comment-figures.md`).
    /// `textures` is only read by [`Material::Textured`].
    #[inline(always)]
    pub fn scatter<R: Rng + ?Sized>(
        &self,
        incoming: Vec3,
        hit: &Hit,
        textures: &Textures,
        rng: &mut R,
    ) -> Option<Scatter> {
        match *self {
            Material::Lambertian { albedo } => Some(diffuse(albedo, hit, rng)),
            Material::Textured { texture } => {
                Some(diffuse(textures.value(texture, hit.u, hit.v, hit.point), hit, rng))
            }
            Material::DiffuseLight { albedo, .. } => {
                (albedo > 0.0).then(|| diffuse(Vec3::splat(albedo), hit, rng))
            }
            Material::Isotropic { albedo } => {
                Some(Scatter { attenuation: albedo, direction: random_unit_vector(rng) })
            }
            Material::Metal { albedo, fuzz } => {
                let mirror = reflect(incoming, hit.normal);
                let fuzzed = mirror + fuzz.min(1.0) * random_unit_vector(rng);
                let direction = fuzzed.try_normalize()?;
                // Fuzz can push the ray below the surface: the book absorbs it.
                (direction.dot(hit.normal) > 0.0).then_some(Scatter { attenuation: albedo, direction })
            }
            Material::Dielectric { ior, fresnel } => {
                let ratio = if hit.front_face { 1.0 / ior } else { ior };
                let cos_theta = (-incoming).dot(hit.normal).min(1.0);
                let direction = match refract(incoming, hit.normal, ratio) {
                    Some(refracted) if fresnel.reflectance(cos_theta, ratio) <= uniform(rng) => refracted,
                    // Total internal reflection, or the Fresnel coin chose reflection.
                    _ => reflect(incoming, hit.normal),
                };
                Some(Scatter { attenuation: Vec3::ONE, direction })
            }
        }
    }
}

impl Material {
    /// Glass of index `ior` with the books' Schlick reflectance.
    pub fn glass(ior: Real) -> Material {
        Material::Dielectric { ior, fresnel: Fresnel::Schlick }
    }

    /// The light this material emits at `hit`: a light's `emit` on its front face, black
    /// everywhere else.
    #[inline]
    pub fn emitted(&self, hit: &Hit) -> Vec3 {
        match *self {
            Material::DiffuseLight { emit, .. } if hit.front_face => emit,
            _ => Vec3::ZERO,
        }
    }

    /// The colour a denoiser's guide records for this material at `hit`: what it multiplies
    /// the light arriving there by on average (its albedo; 1 for glass, which tints nothing;
    /// a light's emission from its front, so the light divides out to 1 as the sky does).
    pub fn albedo(&self, hit: &Hit, textures: &Textures) -> Vec3 {
        match *self {
            Material::Lambertian { albedo } | Material::Metal { albedo, .. } => albedo,
            Material::Isotropic { albedo } => albedo,
            Material::Textured { texture } => textures.value(texture, hit.u, hit.v, hit.point),
            Material::Dielectric { .. } => Vec3::ONE,
            Material::DiffuseLight { emit, .. } if hit.front_face => emit,
            Material::DiffuseLight { albedo, .. } => Vec3::splat(albedo),
        }
    }

    /// How [`Material::scatter`] draws its direction, for a material whose bounce a light
    /// sample can be weighed against: a diffuse material (or a light that reflects) draws
    /// with the cosine density, fog by the isotropic phase function; `None` for mirrors and
    /// glass (a single direction: no light sample can land on it).
    pub fn lobe(&self) -> Option<Lobe> {
        match *self {
            Material::Lambertian { .. } | Material::Textured { .. } => Some(Lobe::Cosine),
            Material::DiffuseLight { albedo, .. } if albedo > 0.0 => Some(Lobe::Cosine),
            Material::Isotropic { .. } => Some(Lobe::Sphere),
            _ => None,
        }
    }

    /// For glass met from outside, its mirror direction at `hit` for the unit `incoming` and
    /// the share of light it reflects there (Schlick's, the chance that [`Material::scatter`]
    /// reflects); `None` for any other material, or glass met from inside.
    pub fn glint(&self, incoming: Vec3, hit: &Hit) -> Option<(Vec3, Real)> {
        let Material::Dielectric { ior, fresnel } = *self else { return None };
        let cos_theta = (-incoming).dot(hit.normal).min(1.0);
        hit.front_face.then(|| (reflect(incoming, hit.normal), fresnel.reflectance(cos_theta, 1.0 / ior)))
    }

    /// Whether shading reads a hit's texture coordinates `(u, v)` (an image texture does;
    /// solid colours, the checker and the marble use the point).
    pub fn reads_uv(&self, textures: &Textures) -> bool {
        matches!(*self, Material::Textured { texture } if matches!(textures.textures[texture as usize], Texture::Image { .. }))
    }

    /// Whether the first book's render loop handles this material (no texture, no light, no
    /// medium).
    pub fn is_first_book(&self) -> bool {
        matches!(self, Material::Lambertian { .. } | Material::Metal { .. } | Material::Dielectric { .. })
    }
}

/// The density a scattering material draws its directions with ([`Material::lobe`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// `cos θ / π` about the normal (Lambertian).
    Cosine,
    /// `1 / 4π` over every direction (the isotropic phase function).
    Sphere,
}

/// The Lambertian scatter: around the normal with a cosine distribution.
#[inline(always)]
fn diffuse<R: Rng + ?Sized>(albedo: Vec3, hit: &Hit, rng: &mut R) -> Scatter {
    let direction = (hit.normal + random_unit_vector(rng))
        .try_normalize()
        // The random vector can cancel the normal: fall back to the normal itself.
        .unwrap_or(hit.normal);
    Scatter { attenuation: albedo, direction }
}

/// Mirror reflection of `v` about the unit normal `n`: `v − 2(v·n)n`.
pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * v.dot(n) * n
}

/// Refraction of the unit vector `v` through a surface with unit normal `n` (facing `v`'s
/// origin side), with `eta_ratio = η / η′`. `None` on total internal reflection.
pub fn refract(v: Vec3, n: Vec3, eta_ratio: Real) -> Option<Vec3> {
    let cos_theta = (-v).dot(n).min(1.0);
    let perp = eta_ratio * (v + cos_theta * n);
    let k = 1.0 - perp.length_squared();
    if k < 0.0 {
        return None;
    }
    Some((perp - k.sqrt() * n).normalize())
}

/// How glass computes the share of light it reflects (`fresnel` in a scene file).
///
/// ```
/// use raypool::tracer::shading::material::Fresnel;
/// // Head-on into glass of 1.5 both give ((n − 1)/(n + 1))² = 0.04.
/// for fresnel in [Fresnel::Schlick, Fresnel::Exact] {
///     assert!((fresnel.reflectance(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
/// }
/// // Past the critical angle, inside the glass, both reflect everything.
/// assert_eq!(Fresnel::Exact.reflectance(0.1, 1.5), 1.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Fresnel {
    /// Schlick's approximation, as the books' glass (the default).
    #[default]
    Schlick,
    /// The Fresnel equations for unpolarised light, as pbrt's and Mitsuba's dielectrics.
    Exact,
}

impl Fresnel {
    /// The share of light reflected where it arrives at `cosine` to the normal, from a side
    /// whose index over the other's is `eta_ratio`.
    pub fn reflectance(self, cosine: Real, eta_ratio: Real) -> Real {
        match self {
            Fresnel::Schlick => schlick(cosine, eta_ratio),
            Fresnel::Exact => exact_fresnel(cosine, eta_ratio),
        }
    }
}

/// The Fresnel reflectance of unpolarised light, the mean of the two polarisations' (1 past
/// the critical angle), in `[0, 1]`.
pub fn exact_fresnel(cosine: Real, eta_ratio: Real) -> Real {
    let cos_i = cosine.clamp(0.0, 1.0);
    let sin_t2 = eta_ratio * eta_ratio * (1.0 - cos_i * cos_i);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let across = (eta_ratio * cos_i - cos_t) / (eta_ratio * cos_i + cos_t);
    let along = (cos_i - eta_ratio * cos_t) / (cos_i + eta_ratio * cos_t);
    (0.5 * (across * across + along * along)).clamp(0.0, 1.0)
}

/// Schlick's approximation of the Fresnel reflectance, in `[0, 1]`.
pub fn schlick(cosine: Real, eta_ratio: Real) -> Real {
    let r0 = ((1.0 - eta_ratio) / (1.0 + eta_ratio)).powi(2);
    let m = (1.0 - cosine).clamp(0.0, 1.0);
    r0 + (1.0 - r0) * m.powi(5)
}

#[cfg(all(test, not(feature = "f64")))]
mod tests {
    #[test]
    fn a_material_is_32_bytes_in_the_f32_build() {
        // The module's opening says so: a 16-byte vector (glam's Vec3A), a number and the tag.
        assert_eq!(std::mem::size_of::<super::Material>(), 32);
    }
}
