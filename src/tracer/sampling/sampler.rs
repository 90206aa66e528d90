//! The sampler interface: where a pixel sample's random numbers come from.
//!
//! An image must be bit-identical whatever the scheduler and thread count. So no random
//! generator is shared, global or thread-local: sample `s` of pixel `p` draws from its own
//! stream, made from `(render seed, p, s)`. Which thread renders the sample, and in what order,
//! cannot change a single number it draws. [`RandomStreams`] hands out those streams, a pixel
//! at a time; [`Sampler`] (`--sampler`) names the two real ones, each in a file of its own.

use rand::Rng;
use rand::rngs::SmallRng;
use rand_xoshiro::SplitMix64;

use crate::tracer::math::real::Real;
use crate::tracer::sampling::warp::uniform;

/// Which numbers pixel samples draw (`--sampler`): independent numbers
/// ([`PerSample`](crate::tracer::sampling::independent::PerSample)) or Owen-scrambled Sobol
/// points ([`SobolStreams`](crate::tracer::sampling::sobol::SobolStreams)). Its default is the
/// renderer's, stated here once: the command line, the viewer,
/// [`RenderSettings::default`](crate::tracer::render::RenderSettings) and the benchmarks all
/// take it from this `#[default]`. (The variants' own lines are `--help`'s text.)
///
/// ```
/// use raypool::tracer::sampling::sampler::Sampler;
/// assert_eq!(Sampler::default(), Sampler::Sobol);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Sampler {
    /// Independent numbers per pixel sample.
    Independent,
    /// An Owen-scrambled Sobol sequence per pixel, indexed by the sample number.
    #[default]
    Sobol,
}

impl Sampler {
    /// The `--sampler` name.
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Independent => "independent",
            Sampler::Sobol => "sobol",
        }
    }
}

/// A pixel sample's generator, told when a new bounce begins, so that a low-discrepancy
/// sampler can give each use of random numbers its own dimensions. Independent generators
/// ignore it.
pub trait SampleRng: Rng {
    /// The next numbers are for bounce `bounce` (0 for the camera ray's first scatter). Until
    /// the first call, they are the camera's: pixel jitter (2), then lens (2).
    fn bounce(&mut self, bounce: u32) {
        let _ = bounce;
    }

    /// The next numbers (up to four: a coin, the choice of a light, a point on it) are a
    /// light sample at bounce `bounce`'s hit. Until the next [`SampleRng::bounce`]. Used by
    /// next-event estimation (`render/path.rs`) and bidirectional shadow rays (`bidir/`).
    fn light(&mut self, bounce: u32) {
        let _ = bounce;
    }

    /// The next numbers (up to four: a glass ball, a light, a point on it) are a light sample
    /// through a glass ball, the path's `aim`-th. Until the next [`SampleRng::bounce`]. Used by
    /// manifold samples (`lighting/manifold.rs`, which numbers the aims along the path).
    fn light_through_glass(&mut self, aim: u32) {
        let _ = aim;
    }

    /// A point in the pixel, two numbers in `[0, 1)`: the `k`-th of the `of` extra points this
    /// pixel sample takes. A low-discrepancy sampler takes them from a sequence of their own,
    /// `of` points per sample, so that the first `n` samples' points fill the pixel as
    /// `n × of` samples would; others draw two more numbers. Used by the lights' edges
    /// (`lighting/edges.rs`).
    fn pixel_point(&mut self, k: u32, of: u32) -> [Real; 2] {
        let _ = (k, of);
        [uniform(self), uniform(self)]
    }
}

impl SampleRng for SmallRng {}
impl SampleRng for SplitMix64 {}

/// Where the random numbers of each pixel sample come from.
///
/// [`PerSample`](crate::tracer::sampling::independent::PerSample) and
/// [`SobolStreams`](crate::tracer::sampling::sobol::SobolStreams) are the renderer's real sources. The trait also lets an
/// ablation (the paper's single shared `rand()`) be plugged into the same render loop.
///
/// It has two levels because a pixel's samples share work: the render loop asks once per pixel
/// for its [`PixelStreams`] (for Sobol, the scramble keys of the pixel's dimension sets), then
/// for one stream per sample. What a stream draws still depends only on `(seed, pixel, sample)`.
///
/// ```
/// use raypool::tracer::sampling::independent::PerSample;
/// use raypool::tracer::sampling::sampler::{PixelStreams, RandomStreams};
/// use raypool::tracer::sampling::warp::uniform;
/// let streams = PerSample { seed: 1 };
/// let pixel = streams.pixel(42);
/// // The same sample of the same pixel draws the same numbers, however it is reached.
/// assert_eq!(uniform(&mut pixel.stream(3)), uniform(&mut streams.pixel(42).stream(3)));
/// ```
pub trait RandomStreams: Sync {
    /// What the samples of one pixel share.
    type Pixel<'a>: PixelStreams
    where
        Self: 'a;
    /// The streams of pixel `pixel` (row-major index).
    fn pixel(&self, pixel: u64) -> Self::Pixel<'_>;
}

/// The random streams of one pixel's samples (see [`RandomStreams`]).
pub trait PixelStreams {
    /// The generator type handed to one pixel sample.
    type Stream<'a>: SampleRng
    where
        Self: 'a;
    /// The stream of sample `sample` of this pixel.
    fn stream(&self, sample: u64) -> Self::Stream<'_>;
}
