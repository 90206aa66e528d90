//! A render's progressive passes ([`Passes`]): what the viewer's passes of one render share (its
//! numbers' source, the running sums every pass adds to, its clock), how far they have come,
//! and how many samples the next may take. `session.rs` renders each pass.

use std::time::Instant;

use crate::schedule::progressive::{Cancel, Sums};
use crate::schedule::random::RngSource;
use crate::tracer::lights::LightSampling;
use crate::view::request::Config;

/// One render's progressive passes: what every pass shares, and how far they have come.
/// The most samples one job may take: a 16 × 16 tile at 16 samples per pixel (a few
/// milliseconds of `final`). Passes double (1, 1, 2, 4, 8, 16, …) and then stay at the size that keeps a
/// job (a tile, or a row in the row modes) within this, so a cancel, which each job checks
/// before it starts, takes effect within one short job whatever the tile size or width (the
/// viewer's tiles are at most [`MAX_TILE`](crate::view::request::MAX_TILE) wide and its rows
/// at most 4,096 pixels: one sample per pixel at most fits).
const MAX_JOB_SAMPLES: u32 = 16 * 16 * 16;

pub(super) struct Passes<'a> {
    pub(super) generation: u64,
    pub(super) config: &'a Config,
    pub(super) cancel: &'a Cancel,
    pub(super) rng: RngSource,
    /// The running sums every pass adds its samples to.
    pub(super) sums: Sums,
    pub(super) started: Instant,
    /// Samples per pixel rendered so far, and passes announced.
    pub(super) done: u32,
    pub(super) pass: u32,
    /// The most samples a pass takes: a job (a tile, or a whole row in the row modes) stays
    /// under [`MAX_JOB_SAMPLES`].
    pub(super) most: u32,
    /// Whether paths light pixels of other tiles (bdpt's light paths).
    pub(super) splatted: bool,
}

impl<'a> Passes<'a> {
    pub(super) fn new(generation: u64, config: &'a Config, cancel: &'a Cancel) -> Passes<'a> {
        let settings = &config.job.settings;
        let job_pixels = (config.tile * config.tile).max(settings.width);
        Passes {
            generation,
            config,
            cancel,
            rng: RngSource::new(settings, config.rng),
            sums: Sums::default(),
            started: Instant::now(),
            done: 0,
            pass: 0,
            most: (MAX_JOB_SAMPLES / job_pixels).max(1),
            splatted: settings.light_sampling == LightSampling::Bdpt,
        }
    }
}
