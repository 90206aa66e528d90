//! raypool: the ray tracer of *Ray Tracing in One Weekend*, written to study parallelism.
//!
//! The folders are the layers, lowest first: each uses only the layers listed before it in
//! this table (and [`error`], which every layer may use); `cargo test --test layers` checks it.
//!
//! | layer | what it holds |
//! |---|---|
//! | [`tracer`] | the book's tracer, in rooms: [`tracer::math`] (numbers, rays), [`tracer::sampling`] (random numbers), [`tracer::geometry`] (shapes, hits), [`tracer::shading`] (materials, background), [`tracer::accel`] (the trees), [`tracer::world`] (groups, meshes, instances, media), [`tracer::lights`], [`tracer::camera`], [`tracer::scene`], [`tracer::lighting`] (how paths find the lights), [`tracer::splats`], [`tracer::bidir`] (bidirectional paths), [`tracer::tile`], and [`tracer::render`], the one render loop |
//! | [`scenes`] | scenes as data: the TOML [`scenes::format`] and the [`scenes::builtin`] scenes |
//! | [`files`] | the frame buffer ([`files::image`]), the PNG/PPM/PFM/EXR writers ([`files::output`]) and the part files of sharded renders ([`files::part`]) |
//! | [`schedule`] | who renders which tile: [`schedule::random`] (where the random numbers come from), [`schedule::progressive`] passes, [`schedule::frame`] (a render in progress), [`schedule::adaptive`] sampling's passes, the [`schedule::modes`] and the [`schedule::conformance`] check |
//! | [`denoise`] | a few-sample image made presentable: first-hit [`denoise::guide`] buffers and the edge-avoiding [`denoise::atrous`] filter |
//! | [`measure`] | the [`measure::speedup`] benchmark, the [`measure::scaling`] model, error ([`measure::compare`], [`measure::convergence`]), [`measure::stress`] cases, [`measure::plot`]s, the [`measure::machine`] (CPUs, thread counts, labels), the course's [`measure::grade`]r |
//! | [`cli`] | the `raypool` command: [`cli::args`] (its flags), [`cli::settings`] (what they resolve to), [`cli::transport`] (the light transport and sampling they choose), a file per command, [`cli::interrupt`] (Ctrl-C) and [`cli::memory`] (will it fit?) |
//! | [`view`] | `raypool view`: the live viewer in the browser (its server, its render session, its page) |
//!
//! [`scenes`] and [`files`] sit side by side: neither uses the other; so do [`schedule`] and [`denoise`].
//! The types most programs need are re-exported here: `raypool::{SceneFile, RenderJob, Frame, Scheduler, …}`.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod error;
pub mod tracer;
pub mod scenes;
pub mod files;
pub mod schedule;
pub mod denoise;
pub mod measure;
pub mod cli;
pub mod view;

/// The README's Rust, compiled and run by `cargo test --doc`, so it cannot drift.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

/// The book's chapter on the course (`docs/src/course.md`): its Rust, a student's scheduler
/// and its conformance check, compiled and run by `cargo test --doc` as the README's is.
#[cfg(doctest)]
#[doc = include_str!("../docs/src/course.md")]
mod book_course {}

pub use error::Error;
pub use files::image::Image;
pub use scenes::format::SceneFile;
pub use schedule::frame::Frame;
pub use schedule::modes::{Schedule, Scheduler};
pub use schedule::random::{RngChoice, RngSource};
pub use tracer::render::{RenderJob, RenderSettings, TileOutput};
pub use tracer::tile::{Shard, Tile};
