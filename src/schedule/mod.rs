//! **Scheduling: who renders which tile.** [`random`] picks where a render's random numbers
//! come from (per-sample streams, or the seed paper's generator shared behind a lock); a
//! [`frame::Frame`] is a render in progress and the only way to render a tile; [`modes`] holds
//! the [`modes::Scheduler`] trait and the six built-in ways to share a frame's tiles among
//! threads (serial, static blocks, interleaved rows, the two pools, stealing), and [`kept`]
//! keeps a pool mode's pool from one render to the next; [`progressive`] refines
//! an image pass after pass, cancellably, on any of them, [`adaptive`] spends those passes
//! where the image is still noisy, and [`guided`] learns from each pass a guide for the next; [`observe`] records, from inside a frame, which threads
//! rendered which pixels how often; [`conformance`] is the check a student's scheduler must pass.
//!
//! It may use [`crate::tracer`], [`crate::files`] (a frame is assembled into an
//! [`crate::files::image::Image`]), [`crate::scenes`] (the conformance check renders a built-in
//! scene), the `pool` crate and [`crate::error`]. The measurements and the command line use it.

pub mod random;
pub mod progressive;
pub mod frame;
pub mod adaptive;
pub mod guided;
pub mod modes;
pub mod kept;
pub mod observe;
pub mod conformance;
