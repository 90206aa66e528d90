//! Schedulers: every built-in mode conforms, broken ones are caught, and the measurements
//! the speedup table relies on (threads used, imbalance) mean what they say.

mod deadline;

use std::sync::Arc;

use deadline::within;
use raypool::schedule::conformance::{check, test_frame};
use raypool::schedule::frame::Frame;
use raypool::schedule::modes::{Schedule, Scheduler, render};
use raypool::schedule::random::RngSource;
use raypool::schedule::random::SharedRng;
use raypool::tracer::math::real::to_f64;
use raypool::tracer::render::{RenderJob, RenderSettings, TileOutput};

#[test]
fn every_builtin_mode_conforms_at_several_thread_counts() {
    within("the conformance check of every mode on 1, 2, 3 and 7 threads to finish", move || {
        for schedule in Schedule::ALL {
            // `serial` is the one-thread baseline: the check's parallelism rule is not for it.
            let counts: &[usize] = if schedule == Schedule::Serial { &[1] } else { &[1, 2, 3, 7] };
            for &threads in counts {
                check(&schedule, threads).unwrap_or_else(|e| panic!("{schedule:?} × {threads}: {e}"));
            }
        }
    });
}

/// Forgets the last row.
struct Lazy;
impl Scheduler for Lazy {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let mut rows = frame.rows();
        rows.pop();
        rows.into_iter().map(|r| frame.render(r)).collect()
    }
}

/// Renders the first tile twice.
struct Eager;
impl Scheduler for Eager {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let tiles = frame.tiles();
        let mut out: Vec<_> = tiles.iter().map(|&t| frame.render(t)).collect();
        out.push(frame.render(tiles[0]));
        out
    }
}

/// Renders every pixel once through the frame, then returns one pixel changed.
struct Tampered;
impl Scheduler for Tampered {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let mut out: Vec<TileOutput> = frame.rows().into_iter().map(|r| frame.render(r)).collect();
        out[0].pixels[0] += raypool::tracer::math::real::Vec3::splat(0.5);
        out
    }
}

#[test]
fn broken_schedulers_fail_the_check_with_a_reason() {
    within("the conformance checks of the broken schedulers to finish", move || {
        // On one thread, so that only the fault each one plants is found.
        let missing = check(&Lazy, 1).unwrap_err();
        assert!(missing.contains("never went through frame.render"), "{missing}");
        let twice = check(&Eager, 1).unwrap_err();
        assert!(twice.contains("went through frame.render 2 times"), "{twice}");
        let wrong = check(&Tampered, 1).unwrap_err();
        assert!(wrong.contains("differs from the serial render"), "{wrong}");
    });
}

#[test]
fn tiles_cover_odd_sizes_exactly() {
    let frame = test_frame(2); // 61 × 37 with tiles of 7
    let tiles = frame.tiles();
    assert_eq!(tiles.len(), 9 * 6);
    assert_eq!(tiles.iter().map(|t| t.area()).sum::<usize>(), 61 * 37);
    assert!(tiles.iter().all(|t| t.x + t.width <= 61 && t.y + t.height <= 37));
}

#[test]
fn parallel_modes_use_the_threads_they_are_given() {
    within("the renders of every mode on 3 threads to finish", move || {
        for schedule in [Schedule::StaticBlocks, Schedule::Interleaved] {
            let rendered = render(&test_frame(3), &schedule);
            assert_eq!(rendered.threads_used(), 3, "{schedule:?}: static modes start exactly T threads");
            assert!(rendered.imbalance() >= 1.0 && rendered.imbalance() <= 3.0);
        }
        for schedule in [Schedule::PoolRows, Schedule::PoolTiles, Schedule::Stealing] {
            let rendered = render(&test_frame(3), &schedule);
            assert!((1..=3).contains(&rendered.threads_used()), "{schedule:?}: at most T pool workers");
        }
        assert_eq!(render(&test_frame(3), &Schedule::Serial).threads_used(), 1);
    });
}

#[test]
fn shared_rng_renders_a_plausible_image_on_any_mode() {
    within("the shared-RNG renders of paper1 to finish", move || {
        for schedule in [Schedule::Serial, Schedule::StaticBlocks, Schedule::Stealing] {
            let settings = RenderSettings {
                width: 40,
                height: 27,
                spp: 4,
                max_depth: 10,
                seed: 3,
                ..Default::default()
            };
            let scene = raypool::scenes::builtin::builtin_scene("paper1", 0).unwrap().to_scene();
            let frame = Arc::new(Frame::new(
                RenderJob::new(scene, settings),
                RngSource::Shared(Arc::new(SharedRng::new(3))),
                2,
                8,
                Arc::new(|_| {}),
            ));
            let rendered = render(&frame, &schedule);
            let pixels = &rendered.image.pixels;
            assert!(pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{schedule:?}");
            let mean =
                pixels.iter().map(|p| to_f64(p.element_sum())).sum::<f64>() / pixels.len() as f64 / 3.0;
            assert!(mean > 0.2 && mean < 1.0, "{schedule:?}: mean {mean}: sky and ground expected");
        }
    });
}

#[test]
fn static_blocks_differ_by_at_most_one_row() {
    within("the static-blocks render on 4 threads to finish", move || {
        // 5 rows on 4 threads: blocks of 1, 1, 1 and 2 rows, not ceil(5/4) = 2 rows for 3 threads.
        let settings =
            RenderSettings { width: 8, height: 5, spp: 1, max_depth: 4, seed: 1, ..Default::default() };
        let scene = raypool::scenes::builtin::builtin_scene("paper1", 0).unwrap().to_scene();
        let rng = RngSource::PerSample(raypool::tracer::sampling::independent::PerSample { seed: 1 });
        let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, 4, 4, Arc::new(|_| {})));
        let rendered = render(&frame, &Schedule::StaticBlocks);
        assert_eq!(rendered.threads_used(), 4);
        let mut rows_per_thread: Vec<usize> = Vec::new();
        let mut last_thread = None;
        let mut timeline = rendered.timeline.clone();
        timeline.sort_by_key(|(tile, _)| tile.y);
        for (_, timing) in &timeline {
            if last_thread != Some(timing.thread) {
                rows_per_thread.push(0);
                last_thread = Some(timing.thread);
            }
            *rows_per_thread.last_mut().unwrap() += 1;
        }
        assert_eq!(rows_per_thread, [1, 1, 1, 2], "contiguous blocks, in row order");
    });
}
