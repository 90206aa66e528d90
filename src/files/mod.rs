//! **Files**: the frame buffer that rendered tiles are assembled into, the PNG, PPM and PFM
//! files it is written to, and the part files that carry one shard of an image between
//! machines. Every file is written atomically (a temporary file, then a rename), so a failed
//! run never leaves half a file behind.
//!
//! It may use [`crate::tracer`] (pixels are [`crate::tracer::math::real::Vec3`], tiles arrive as
//! [`crate::tracer::render::TileOutput`]) and [`crate::error`], nothing above. The schedulers
//! assemble images with it; the measurements, the command line and the viewer read and write files with it.

pub mod image;
pub mod output;
pub mod part;
