//! **The light transport and the sampling a render asks for**, as types, chosen in one place.
//!
//! The flags `--light-sampling`, `--roulette`, `--guiding`, `--guide-pilot`, `--spp`,
//! `--target-error`, `--min-spp` and `--max-spp` say two things: how a sample's light is found (an [`Integrator`]) and how many
//! samples a pixel takes ([`Sampling`]). [`Transport::new`] is the one constructor the command
//! line and the viewer both call; every combination that is refused is refused in this file
//! (flags in `refusal`, a scene in [`Integrator::admits`]), one line each, and what it admits is written into the tracer's flat
//! [`RenderSettings`] by [`Transport::apply`], so no other file asks again.

use crate::cli::args::{ImageArgs, Switch};
use crate::error::Error;
use crate::tracer::guiding::Guiding;
use crate::tracer::lights::LightSampling;
use crate::tracer::math::real::{Real, to_f64};
use crate::tracer::render::{Adaptive, RenderSettings};
use crate::tracer::scene::Scene;

/// How a sample's light is found (Veach's words: a path tracer's estimator, or bidirectional
/// path tracing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// A path from the camera, finding the lights by `light_sampling` (`bsdf`, `mixture` or
    /// `mis`), ended early by Russian roulette if `roulette`, its diffuse bounces guided by
    /// what earlier passes learnt if `guiding`.
    Path {
        /// How the path's hits aim at the lights.
        light_sampling: LightSampling,
        /// Russian roulette after four rays.
        roulette: bool,
        /// Path guiding (`--guiding on`).
        guiding: Option<Guiding>,
    },
    /// A path from the camera and one from a light, joined at every pair of vertices
    /// (`--light-sampling bdpt`): every sample takes its light path, none is ended by roulette.
    Bidir,
}

impl Integrator {
    /// What `settings` ask for.
    pub fn of(settings: &RenderSettings) -> Integrator {
        match settings.light_sampling {
            LightSampling::Bdpt => Integrator::Bidir,
            light_sampling => {
                Integrator::Path { light_sampling, roulette: settings.roulette, guiding: settings.guiding }
            }
        }
    }

    /// Whether `scene` can be rendered this way; the one line that refuses it if not.
    pub fn admits(&self, scene: &Scene) -> Result<(), Error> {
        if *self == Integrator::Bidir && scene.has_shading_normals() {
            return Err(Error::new(
                "--light-sampling bdpt does not take meshes shaded by their files' normals (its light paths would see them unlike the camera's): use mis",
            ));
        }
        Ok(())
    }
}

/// How many samples each pixel takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampling {
    /// `spp` samples in every pixel.
    Fixed {
        /// Samples per pixel.
        spp: u32,
    },
    /// A pilot of `min_spp`, then samples where the pilot is noisy, up to `max_spp`, until
    /// the predicted relative error is `target_error` (`--target-error`).
    Adaptive {
        /// The pilot's samples per pixel.
        min_spp: u32,
        /// The most samples any pixel takes.
        max_spp: u32,
        /// The relative error aimed at.
        target_error: f64,
    },
}

impl Sampling {
    /// What `settings` ask for.
    ///
    /// ```
    /// use raypool::cli::transport::Sampling;
    /// use raypool::tracer::render::{Adaptive, RenderSettings};
    /// let fixed = RenderSettings { spp: 8, ..RenderSettings::default() };
    /// assert_eq!(Sampling::of(&fixed), Sampling::Fixed { spp: 8 });
    /// let adaptive = RenderSettings { adaptive: Some(Adaptive { target_error: 0.5, min_spp: 4 }), ..fixed };
    /// assert_eq!(Sampling::of(&adaptive), Sampling::Adaptive { min_spp: 4, max_spp: 8, target_error: 0.5 });
    /// ```
    pub fn of(settings: &RenderSettings) -> Sampling {
        match settings.adaptive {
            None => Sampling::Fixed { spp: settings.spp },
            Some(a) => Sampling::Adaptive {
                min_spp: a.min_spp,
                max_spp: settings.spp,
                target_error: to_f64(a.target_error),
            },
        }
    }
}

/// Who renders: the command line's `render` (and `simulate`), or the viewer, which renders
/// progressive passes of a fixed number of samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    /// `raypool render`, `raypool simulate`.
    CommandLine,
    /// `raypool view`.
    Viewer,
}

/// The light transport and the sampling of one render, admitted together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transport {
    /// How a sample's light is found.
    pub integrator: Integrator,
    /// How many samples a pixel takes.
    pub sampling: Sampling,
}

impl Transport {
    /// What the flags ask for, for `renderer`, or the one line that refuses it.
    pub fn new(args: &ImageArgs, renderer: Renderer) -> Result<Transport, Error> {
        let guiding = (args.guiding == Switch::On)
            .then(|| args.guide_pilot.map_or_else(|| Guiding::for_spp(args.spp), |pilot| Guiding { pilot }));
        let integrator = match args.light_sampling {
            LightSampling::Bdpt => Integrator::Bidir,
            light_sampling => Integrator::Path { light_sampling, roulette: args.roulette, guiding },
        };
        let sampling = match args.target_error {
            None => Sampling::Fixed { spp: args.spp },
            Some(target_error) => {
                Sampling::Adaptive { min_spp: args.min_spp, max_spp: args.max_spp, target_error }
            }
        };
        match refusal(args, integrator, sampling, renderer) {
            Some(reason) => Err(Error::new(reason)),
            None => Ok(Transport { integrator, sampling }),
        }
    }

    /// Writes the choice into `settings`' flat fields (`light_sampling`, `roulette`,
    /// `guiding`, `spp`, `adaptive`), which the tracer reads.
    pub fn apply(&self, settings: &mut RenderSettings) {
        (settings.light_sampling, settings.roulette, settings.guiding) = match self.integrator {
            Integrator::Path { light_sampling, roulette, guiding } => (light_sampling, roulette, guiding),
            Integrator::Bidir => (LightSampling::Bdpt, false, None),
        };
        (settings.spp, settings.adaptive) = match self.sampling {
            Sampling::Fixed { spp } => (spp, None),
            Sampling::Adaptive { min_spp, max_spp, target_error } => {
                (max_spp, Some(Adaptive { target_error: target_error as Real, min_spp }))
            }
        };
    }
}

/// Every combination of these flags that is refused, and why, one line each.
fn refusal(
    args: &ImageArgs,
    integrator: Integrator,
    sampling: Sampling,
    renderer: Renderer,
) -> Option<String> {
    let adaptive = matches!(sampling, Sampling::Adaptive { .. });
    match sampling {
        Sampling::Adaptive { min_spp, max_spp, target_error } if min_spp > max_spp => {
            return Some(format!(
                "--min-spp {min_spp} is above --max-spp {max_spp} (with --target-error {target_error})"
            ));
        }
        _ => {}
    }
    if renderer == Renderer::Viewer && adaptive {
        return Some("the viewer renders progressive passes, not adaptive sampling".into());
    }
    if let Some(refused) = guiding_refusal(args, integrator, adaptive) {
        return Some(refused.into());
    }
    let bidir_refuses = if adaptive { Some("--target-error") } else { args.roulette.then_some("--roulette") };
    match (integrator, bidir_refuses) {
        (Integrator::Bidir, Some(flag)) => Some(format!(
            "--light-sampling bdpt does not take {flag}: its light paths are weighed against a fixed number of samples per pixel, and it ends no path by roulette"
        )),
        _ => None,
    }
}

/// The combinations `--guiding` and `--guide-pilot` are refused in, and why.
fn guiding_refusal(args: &ImageArgs, integrator: Integrator, adaptive: bool) -> Option<&'static str> {
    let guided = args.guiding == Switch::On;
    if !guided {
        return args
            .guide_pilot
            .is_some()
            .then_some("--guide-pilot needs --guiding on (it sets the learning passes' samples per pixel)");
    }
    match (integrator, args.light_sampling) {
        (Integrator::Bidir, _) => Some(
            "--guiding on draws the bounces of paths from the camera, which bdpt weighs against paths from the lights without it: use mis or bsdf",
        ),
        (_, LightSampling::Mixture) => Some(
            "--guiding on and --light-sampling mixture would each draw the diffuse bounce their own way: use mis or bsdf",
        ),
        _ if adaptive => Some(
            "--guiding on learns in passes over every pixel, --target-error gives each pixel its own count: use one or the other",
        ),
        _ => None,
    }
}
