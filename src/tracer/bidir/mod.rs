//! **Bidirectional path tracing** (`--light-sampling bdpt`, Veach 1997 ch. 10; pbrt's `BDPT`):
//! a path from the camera and a path from a light, joined at every pair of their vertices, so
//! that light which only a light path finds well — through glass onto a wall (a caustic), seen
//! directly or after another bounce — is found by the strategy that finds it best. Each
//! joined path is weighted by the power heuristic over every strategy that could have made it,
//! so the image is the same image the other settings render, with less noise where they are
//! weak.
//!
//! Read in this order: a path's [`vertex`] and its densities; the [`walk`] that makes both
//! paths, and the densities it measures through [`chain`]s of mirrors and glass; the
//! [`weight`] of a connection; the [`connect`]ions of one sample; the [`splats`](crate::tracer::splats)
//! that light paths leave in other pixels, summed in fixed point so the image stays
//! bit-identical whatever the schedule.

pub mod vertex;
pub mod chain;
pub mod walk;
pub mod weight;
pub mod connect;
