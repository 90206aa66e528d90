//! **Random numbers**: one stream per pixel sample, made from `(render seed, pixel, sample)`,
//! so an image is bit-identical under every schedule, thread count and shard.
//!
//! Read [`sampler`] first (the interface the render loop draws through, and the `--sampler`
//! choice with its one default), then the two samplers: [`independent`] numbers and Owen-
//! scrambled [`sobol`] points (made fast in `sobol_table`), and last the [`warp`]s that turn
//! uniform numbers into directions and lens points. The [`keys`] that set one stream's seed
//! apart from another's are all in one file, with a test that no two meet.
//!
//! A new sampler is a new file here and one arm of [`sampler::Sampler`], plus, a layer up
//! where threads are known, one variant of `crate::schedule::random::RngSource`, its arm in
//! `RngSource::new`, and its arm in `Frame::render`'s dispatch (`crate::schedule::frame`). The
//! generator the seed paper shared between threads behind a lock is not here: it needs
//! threads, and lives in [`crate::schedule::random`].

pub mod sampler;
pub mod independent;
pub mod sobol;
mod sobol_table;
pub mod warp;
pub mod keys;
