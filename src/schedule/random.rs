//! **Where a render's random numbers come from, once threads exist.** The tracer's samplers
//! (`crate::tracer::sampling`) give every pixel sample its own stream, so threads never meet
//! over a generator. This file adds the one source that does make them meet, the seed paper's
//! `rand()` behind a lock ([`SharedRng`], an ablation), and the one constructor every entry
//! point uses to pick a source: [`RngSource::new`] (the command line, the viewer, the
//! benchmarks and the measurements).

use std::sync::Arc;

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::tracer::render::RenderSettings;
use crate::tracer::sampling::independent::PerSample;
use crate::tracer::sampling::sampler::{PixelStreams, RandomStreams, SampleRng, Sampler};
use crate::tracer::sampling::sobol::SobolStreams;

/// Per-sample streams or one shared generator (`--rng`). `PerSample` here means "a stream per
/// pixel sample, of whichever sampler the settings name" (Sobol by default), not the
/// independent [`PerSample`] streams alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum RngChoice {
    /// One stream per pixel sample, seeded from (seed, pixel, sample): reproducible.
    #[default]
    PerSample,
    /// One generator behind a lock for all threads, as the seed paper's rand(): an ablation,
    /// not reproducible.
    Shared,
}

/// Where pixel samples get their random numbers.
#[derive(Clone, Debug)]
pub enum RngSource {
    /// One independent stream per pixel sample: images are identical under any schedule.
    PerSample(PerSample),
    /// An Owen-scrambled Sobol sequence per pixel, indexed by sample: also identical under
    /// any schedule.
    Sobol(SobolStreams),
    /// One generator behind a lock, shared by all threads (the seed paper's `rand()`).
    Shared(Arc<SharedRng>),
}

impl RngSource {
    /// The source `choice` asks for, seeded by `settings.seed`: per-sample streams of
    /// `settings.sampler`, or the shared generator (which no sampler steers: it draws
    /// independent numbers whatever `settings.sampler` says).
    ///
    /// ```
    /// use raypool::schedule::random::{RngChoice, RngSource};
    /// use raypool::tracer::render::RenderSettings;
    /// let settings = RenderSettings::default();
    /// assert!(matches!(RngSource::new(&settings, RngChoice::PerSample), RngSource::Sobol(_)));
    /// assert!(matches!(RngSource::new(&settings, RngChoice::Shared), RngSource::Shared(_)));
    /// ```
    pub fn new(settings: &RenderSettings, choice: RngChoice) -> RngSource {
        match (choice, settings.sampler) {
            (RngChoice::Shared, _) => RngSource::Shared(Arc::new(SharedRng::new(settings.seed))),
            (RngChoice::PerSample, Sampler::Independent) => {
                RngSource::PerSample(PerSample { seed: settings.seed })
            }
            (RngChoice::PerSample, Sampler::Sobol) => RngSource::Sobol(SobolStreams::new(settings.seed)),
        }
    }
}

/// The seed paper's random numbers: one generator shared by every thread, behind a lock (as
/// C's `rand()` is). For the ablation only: every draw takes the lock, so threads queue on
/// it, and which thread gets which number depends on timing, so images are not reproducible.
///
/// The lock is `std::sync::Mutex`, which on Linux, like glibc's lock inside `rand()`, is a
/// futex: a contended acquisition sleeps in the kernel. (`parking_lot`'s adaptive spinning
/// would hide part of the cost the paper ran into.)
#[derive(Debug)]
pub struct SharedRng {
    generator: std::sync::Mutex<SmallRng>,
}

impl SharedRng {
    /// One generator for the whole render, seeded with `seed`.
    pub fn new(seed: u64) -> SharedRng {
        SharedRng { generator: std::sync::Mutex::new(SmallRng::seed_from_u64(seed)) }
    }
}

/// A handle that draws from the [`SharedRng`], taking its lock for every number.
pub struct SharedStream<'a>(&'a SharedRng);

impl SharedStream<'_> {
    fn lock(&self) -> std::sync::MutexGuard<'_, SmallRng> {
        // A draw cannot panic while holding the lock, so it is never poisoned in practice;
        // if it were, the generator's state would still be valid.
        self.0.generator.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl rand::TryRng for SharedStream<'_> {
    type Error = std::convert::Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        Ok(self.lock().next_u32())
    }

    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        Ok(self.lock().next_u64())
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
        self.lock().fill_bytes(dst);
        Ok(())
    }
}

impl SampleRng for SharedStream<'_> {}

impl RandomStreams for SharedRng {
    type Pixel<'a> = &'a SharedRng;

    fn pixel(&self, _pixel: u64) -> &SharedRng {
        self
    }
}

impl PixelStreams for &SharedRng {
    type Stream<'a>
        = SharedStream<'a>
    where
        Self: 'a;

    fn stream(&self, _sample: u64) -> SharedStream<'_> {
        SharedStream(self)
    }
}
