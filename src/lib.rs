//! raypool: the ray tracer of *Ray Tracing in One Weekend*, written to study parallelism.
//!
//! Read it in the book's order:
//!
//! | module | what it holds |
//! |---|---|
//! | [`real`] | `Real` (f32, or f64 with the `f64` feature) and `Vec3` |
//! | [`ray`] | `Ray`: origin + t·dir, unit dir |
//! | [`sphere`] | the robust ray–sphere test and `Hit` |
//! | [`material`] | lambertian, metal, dielectric as one `enum` |
//! | [`camera`] | the thin-lens camera |
//! | [`background`] | what escaping rays see |
//! | [`bvh`] | the bounding volume hierarchy for large scenes |
//! | [`scene`] | the render-ready scene |
//! | [`scene_file`] | the TOML scene format |
//! | [`builtin`] | the built-in scenes (paper figures, the book's final scene) |
//! | [`sampler`] | one random stream per pixel sample |
//! | [`render`] | `render_tile`, the one render loop |
//! | [`frame`] | a render in progress: what schedulers receive |
//! | [`schedule`] | who renders which tile: the `Scheduler` trait and six modes |
//! | [`conformance`] | the check a student's scheduler must pass |
//! | [`convergence`] | error against a reference, and how fast it falls with samples |
//! | [`stress`] | numerical stress scenes with known answers |
//! | [`image`], [`output`] | the frame buffer and PNG/PPM/PFM files |
//! | [`plot`] | speedup and timeline charts |
//! | [`machine`] | names the machine, commit and date of a measurement |
//! | [`bench`] | the speedup benchmark (`raypool bench`) |
//! | [`compare`] | error figures of an image against a reference |
//! | [`cli`] | the `raypool` command |

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod background;
pub mod bench;
pub mod builtin;
pub mod bvh;
pub mod camera;
pub mod cli;
pub mod compare;
pub mod conformance;
pub mod convergence;
pub mod error;
pub mod frame;
pub mod image;
pub mod machine;
pub mod material;
pub mod output;
pub mod plot;
pub mod ray;
pub mod real;
pub mod render;
pub mod sampler;
pub mod scene;
pub mod scene_file;
pub mod schedule;
pub mod sphere;
pub mod stress;

pub use error::Error;
