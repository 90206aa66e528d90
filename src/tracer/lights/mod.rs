//! **Lights**: what a scene's lights are, in one room (pbrt's `lights.h`): what they give
//! off, how a point is drawn on them and with what density, and where a light path starts.
//! Each light shape is a file of its own ([`quad`], [`triangle`], [`sphere`]) and one arm of
//! [`light::Light`], which `light::gather` finds among a scene's objects; [`power`] holds them
//! all and chooses among them by power; a shadow ray's point is a [`sample`], a light path's
//! start an [`emission`]. Beside them, the glass balls that light is aimed *through*
//! ([`casters`]). How a path uses all this (next-event estimation, multiple importance
//! sampling, manifold samples, the lights' edges) is the `lighting` room's, and bidirectional
//! path tracing's (`bidir`); what a surface emits where a ray meets it is its material's
//! ([`Material::emitted`]).
//!
//! A new light shape is a file here (how a point is drawn on it and with what density, where
//! a light path starts on it, its box) and an arm of [`light::Light`] (with its line in each of
//! `Light`'s matches and in `gather`). The estimators ask every light through `Light` and
//! [`power::Lights`], and need no change.
//!
//! The `--light-sampling` setting, [`LightSampling`], is declared here too, below both the
//! estimators and bidirectional path tracing, so that both may name it.
//!
//! [`Material::emitted`]: crate::tracer::shading::material::Material::emitted

pub mod sample;
pub mod quad;
pub mod triangle;
pub mod sphere;
pub mod light;
pub mod power;
pub mod emission;
pub mod casters;

/// How paths find the lights (`--light-sampling`): four unbiased estimators of the same
/// image, with different noise. Declared here, below both the estimators that use the lights
/// (`lighting/`) and bidirectional path tracing (`bidir/`), so that neither names the other.
///
/// ```
/// use raypool::tracer::lights::LightSampling;
/// assert_eq!(LightSampling::default(), LightSampling::Mis);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum LightSampling {
    /// The material's scattering only: a light is found when a bounce happens to hit it
    /// (the second book's estimator).
    Bsdf,
    /// Each diffuse bounce drawn half the time towards a light, half by the material, and
    /// weighted by the mixture's density (the third book's).
    Mixture,
    /// A shadow ray to a light at every diffuse hit, plus the material's bounce, each
    /// weighted by the power heuristic (multiple importance sampling, as pbrt and Mitsuba);
    /// with glass balls, a light sample through a ball as well (manifold next-event
    /// estimation, as Cycles' shadow caustics).
    #[default]
    Mis,
    /// Bidirectional: a path from a light as well, joined to the camera's path at every pair
    /// of vertices, each joined path weighted by the power heuristic over all the ways of
    /// making it (Veach's BDPT). Finds caustics the others cannot aim at.
    Bdpt,
}

impl LightSampling {
    /// The `--light-sampling` name.
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Bsdf => "bsdf",
            LightSampling::Mixture => "mixture",
            LightSampling::Mis => "mis",
            LightSampling::Bdpt => "bdpt",
        }
    }
}
