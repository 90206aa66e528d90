//! The conformance check for schedulers: what a course assignment's tests call.
//!
//! A scheduler conforms when, on a small image whose size divides evenly into nothing (61 ×
//! 37 pixels, tiles of 7), it renders every pixel exactly once and produces the very same
//! bytes as the `serial` schedule, for the thread count given.

use std::sync::Arc;

use crate::scenes::builtin::builtin_scene;
use crate::schedule::frame::{Frame, RngSource};
use crate::schedule::modes::{Schedule, Scheduler};
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::sampler::PerSample;

/// Checks `scheduler` on `threads` threads; the error says what went wrong.
///
/// ```
/// use raypool::schedule::modes::Schedule;
/// raypool::schedule::conformance::check(&Schedule::Stealing, 3).unwrap();
/// ```
pub fn check(scheduler: &dyn Scheduler, threads: usize) -> Result<(), String> {
    let frame = test_frame(threads);
    let reference = test_frame(1);
    let expected = reference.assemble(&Schedule::Serial.render(&reference)).expect("serial conforms");
    let tiles = scheduler.render(&frame);
    let image = frame.assemble(&tiles)?;
    match image.pixels.iter().zip(&expected.pixels).position(|(a, b)| a != b) {
        Some(k) => Err(format!(
            "pixel ({}, {}) differs from the serial render: {:?} instead of {:?}",
            k % image.width as usize,
            k / image.width as usize,
            image.pixels[k],
            expected.pixels[k]
        )),
        None => Ok(()),
    }
}

/// The small frame the check renders: the book's final scene, 61 × 37, 2 spp, depth 8.
pub fn test_frame(threads: usize) -> Arc<Frame> {
    let settings =
        RenderSettings { width: 61, height: 37, spp: 2, max_depth: 8, seed: 42, ..Default::default() };
    let scene = builtin_scene("final", 7).expect("the final scene builds").to_scene();
    let rng = RngSource::PerSample(PerSample { seed: settings.seed });
    Arc::new(Frame::new(RenderJob::new(scene, settings), rng, threads, 7, Arc::new(|_| {})))
}
