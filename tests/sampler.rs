//! The Sobol sampler (`--sampler sobol`): images identical under every scheduler and thread
//! count, unbiased (its error keeps falling, faster than independent sampling's), two bounces
//! per 4-D set, a working fallback past a use's dimensions and past the sequence's 2^16
//! samples, and part files that refuse to mix samplers.

mod deadline;

use std::process::Command;
use std::sync::Arc;

use deadline::{output_within, within};
use raypool::measure::convergence::{Reference, log_log_fit, timed_render};
use raypool::scenes::builtin::builtin_scene;
use raypool::schedule::modes::render;
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::math::real::Real;
use raypool::tracer::render::{RenderSettings, render_tile};
use raypool::tracer::sampling::independent::PerSample;
use raypool::tracer::sampling::sampler::{PixelStreams, RandomStreams, SampleRng, Sampler};
use raypool::tracer::sampling::sobol::{SOBOL_SAMPLES, SobolStreams};
use raypool::tracer::sampling::warp::uniform;
use raypool::{Frame, RenderJob, Schedule, Tile};

fn sobol(settings: RenderSettings) -> RenderSettings {
    RenderSettings { sampler: Sampler::Sobol, ..settings }
}

#[test]
fn sobol_images_are_identical_under_every_mode_and_thread_count() {
    within("the Sobol renders under every mode and thread count to finish", move || {
        let scene = builtin_scene("final", 2026).unwrap().to_scene();
        let settings =
            sobol(RenderSettings { width: 48, height: 32, spp: 8, max_depth: 20, ..Default::default() });
        let image = |mode: Schedule, threads: usize| {
            let frame = Frame::new(
                RenderJob::new(scene.clone(), settings),
                RngSource::new(&settings, RngChoice::PerSample),
                threads,
                7,
                Arc::new(|_| {}),
            );
            render(&Arc::new(frame), &mode).image
        };
        let serial = image(Schedule::Serial, 1);
        for mode in Schedule::ALL {
            for threads in [2, 3, 7] {
                assert!(image(mode, threads) == serial, "{mode:?} on {threads} threads");
            }
        }
        let independent = {
            let plain = RenderSettings { sampler: Sampler::Independent, ..settings };
            let frame = Frame::new(
                RenderJob::new(scene.clone(), plain),
                RngSource::new(&plain, RngChoice::PerSample),
                2,
                7,
                Arc::new(|_| {}),
            );
            render(&Arc::new(frame), &Schedule::Stealing).image
        };
        assert!(independent != serial, "the sampler changes the numbers");
    });
}

#[test]
fn sobol_error_keeps_falling_and_beats_independent_sampling() {
    within("the reference and the Sobol renders of three-spheres to finish", move || {
        let scene = builtin_scene("three-spheres", 0).unwrap().to_scene();
        let base = RenderSettings {
            width: 48,
            height: 32,
            max_depth: 50,
            seed: 1,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let reference = Reference::render(&scene, base, 1024, 2); // independent numbers, two seeds
        let error =
            |settings: RenderSettings| reference.error_of(&timed_render(scene.clone(), settings, 2).0.image);
        let points: Vec<(f64, f64)> = [1, 2, 4, 8, 16, 32, 64]
            .iter()
            .map(|&spp| (spp as f64, error(sobol(RenderSettings { spp, ..base }))))
            .collect();
        let (slope, _) = log_log_fit(&points);
        // A biased sampler's error would stop falling at its bias (the slope flattens towards 0).
        assert!(
            slope < -0.5,
            "Sobol's slope {slope} should be steeper than independent sampling's -0.5: {points:?}"
        );
        let independent = error(RenderSettings { spp: 64, ..base });
        let low_discrepancy = points.last().unwrap().1;
        assert!(
            low_discrepancy < independent,
            "at 64 spp: Sobol {low_discrepancy}, independent {independent}"
        );
    });
}

#[test]
fn the_sobol_table_computes_the_crates_points_to_the_sequences_resolution() {
    // Every index of the sequence (2^16) under 64 scrambles, and under one scramble each:
    // the same top 16 bits as the crate's own `sample_4d` (its points have 16 significant
    // bits, so those are the whole Owen-scrambled point), 23 bits in all.
    let streams = SobolStreams::new(1);
    let cell = |x: f32| (x * 65536.0) as u32;
    let check = |index: u32, scramble: u32| {
        let ours = streams.sample_4d(index, scramble);
        assert_eq!(
            ours.map(cell),
            sobol_burley::sample_4d(index, 0, scramble).map(cell),
            "{index} {scramble}"
        );
        assert!(
            ours.iter().all(|&x| (0.0..1.0).contains(&x) && x * 8_388_608.0 == (x * 8_388_608.0).floor()),
            "{ours:?} should be 23-bit fractions in [0, 1)"
        );
    };
    for index in 0..SOBOL_SAMPLES as u32 {
        check(index, index.wrapping_mul(0x9E37_79B9) ^ 0x1234_5678);
    }
    for scramble in (0..64u32).map(|k| k.wrapping_mul(0x85EB_CA6B)) {
        for index in (0..SOBOL_SAMPLES as u32).step_by(97) {
            check(index, scramble);
        }
    }
}

#[test]
fn below_the_sequences_resolution_the_offset_in_the_cell_is_uniform() {
    // The 7 bits below a point's top 16: each of their 128 values equally often over the
    // sequence's 2^16 points, in each dimension, under several scrambles (a chi-squared test
    // with 127 degrees of freedom: 99.9% of uniform draws stay below 181.99), and not a
    // function of the cell alone (below).
    let streams = SobolStreams::new(1);
    let offset = |x: f32| (x * 8_388_608.0) as u32 & 0x7f;
    for scramble in [1u32, 0xDEAD_BEEF, 0x0BAD_F00D] {
        let mut counts = [[0u32; 128]; 4];
        for index in 0..SOBOL_SAMPLES as u32 {
            for (d, x) in streams.sample_4d(index, scramble).into_iter().enumerate() {
                counts[d][offset(x) as usize] += 1;
            }
        }
        for (d, counts) in counts.iter().enumerate() {
            let expected = SOBOL_SAMPLES as f64 / 128.0;
            let chi2: f64 = counts.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
            assert!(chi2 < 181.99, "scramble {scramble:#x}, dimension {d}: chi-squared {chi2}");
        }
    }
    // Points of different pixels (scrambles) that land in the same cell: their offsets agree
    // 1 time in 128 by chance; an offset made from the cell alone would always agree.
    let mut first_offset = std::collections::HashMap::new();
    let (mut meetings, mut agreements) = (0, 0);
    for scramble in (0..64u32).map(|k| k.wrapping_mul(0x2C1B_3C6D) ^ 0x51ED_270B) {
        for index in 0..4096 {
            let x = streams.sample_4d(index, scramble)[1];
            let cell = (x * 65536.0) as u32;
            if let Some(&seen) = first_offset.get(&cell) {
                meetings += 1;
                agreements += usize::from(seen == offset(x));
            } else {
                first_offset.insert(cell, offset(x));
            }
        }
    }
    assert!(meetings > 50_000, "{meetings} meetings");
    assert!(agreements * 64 < meetings, "{agreements} of {meetings} meetings in a cell at the same offset");
}

#[test]
fn past_the_sequence_samples_draw_independent_numbers() {
    let streams = SobolStreams::new(3);
    // Inside the sequence: the first draw of 2^k consecutive samples is stratified.
    let mut strata: Vec<usize> =
        (0..64).map(|s| (uniform(&mut streams.pixel(5).stream(s)) * 64.0) as usize).collect();
    strata.sort_unstable();
    assert_eq!(strata, (0..64).collect::<Vec<_>>());
    // Past it: the same numbers as the independent sampler's stream for that sample.
    let (pixel, plain_pixel) = (streams.pixel(5), PerSample { seed: 3 }.pixel(5));
    let (mut past, mut plain) = (pixel.stream(SOBOL_SAMPLES + 9), plain_pixel.stream(SOBOL_SAMPLES + 9));
    for _ in 0..10 {
        assert_eq!(uniform(&mut past), uniform(&mut plain));
    }
    // A pixel with more samples than the sequence holds renders (and is a sensible value).
    let scene = builtin_scene("furnace", 0).unwrap().to_scene();
    let settings = sobol(RenderSettings {
        width: 1,
        height: 1,
        spp: SOBOL_SAMPLES as u32 + 4000,
        max_depth: 8,
        ..Default::default()
    });
    let out =
        render_tile(&RenderJob::new(scene, settings), &streams, Tile { x: 0, y: 0, width: 1, height: 1 });
    assert_eq!(out.samples, SOBOL_SAMPLES + 4000);
    assert!(out.pixels[0].is_finite() && out.pixels[0].max_element() > 0.0, "{:?}", out.pixels[0]);
}

#[test]
fn a_pixels_kept_keys_draw_what_fresh_ones_draw() {
    // A pixel keeps its first dimension sets' keys for its later samples. Every number a
    // sample draws must be the same whether its pixel served other samples first (in any
    // order, to any depth) or was made for it alone: deep paths reach sets past those kept.
    let draws = |stream: &mut dyn FnMut() -> Real, bounce: &mut dyn FnMut(u32)| -> Vec<Real> {
        let mut numbers: Vec<Real> = (0..4).map(|_| stream()).collect();
        for b in 0..20 {
            bounce(b);
            numbers.extend((0..3).map(|_| stream()));
        }
        numbers
    };
    for streams_seed in [1, 9] {
        let streams = SobolStreams::new(streams_seed);
        let shared = streams.pixel(31);
        for sample in [5, 0, 17, 5, SOBOL_SAMPLES + 2, 3] {
            let fresh_pixel = streams.pixel(31);
            let mut drawn = Vec::new();
            for pixel in [&shared, &fresh_pixel] {
                let stream = std::cell::RefCell::new(pixel.stream(sample));
                drawn.push(draws(&mut || uniform(&mut *stream.borrow_mut()), &mut |b| {
                    stream.borrow_mut().bounce(b)
                }));
            }
            assert_eq!(drawn[0], drawn[1], "sample {sample}: a kept key differs from a fresh one");
        }
    }
}

#[test]
fn two_bounces_share_a_set_and_extra_draws_are_independent() {
    let streams = SobolStreams::new(4);
    // Over 16 samples of a pixel, bounce 0's first number and bounce 1's first number (the
    // set's dimensions 0 and 2) each fill the sixteen strata: both are Sobol dimensions.
    let firsts = |bounce: u32| {
        let mut strata: Vec<usize> = (0..16)
            .map(|s| {
                let pixel = streams.pixel(7);
                let mut stream = pixel.stream(s);
                (0..=bounce).for_each(|b| stream.bounce(b));
                (uniform(&mut stream) * 16.0) as usize
            })
            .collect();
        strata.sort_unstable();
        strata
    };
    assert_eq!(firsts(0), (0..16).collect::<Vec<_>>());
    assert_eq!(firsts(1), (0..16).collect::<Vec<_>>());
    // A third draw in one bounce (Russian roulette after a direction) is past the bounce's two
    // dimensions: the independent stream's first number for that sample.
    let pixel = streams.pixel(7);
    let mut stream = pixel.stream(3);
    stream.bounce(0);
    let (a, b) = (uniform(&mut stream), uniform(&mut stream));
    assert_ne!(a, b);
    // (In the f64 build each Sobol draw also took 32 low bits from that independent stream,
    // so its third number is a later one of the same stream.)
    if size_of::<Real>() == size_of::<f32>() {
        assert_eq!(uniform(&mut stream), uniform(&mut PerSample { seed: 4 }.pixel(7).stream(3)));
    }
}

#[test]
fn the_command_line_renders_with_sobol_and_parts_do_not_mix_samplers() {
    let dir = std::env::temp_dir().join(format!("raypool-sampler-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let raypool = |args: &[&str]| {
        let what = format!("`raypool {}` to exit", args[0]);
        output_within(Command::new(env!("CARGO_BIN_EXE_raypool")).args(args).current_dir(&dir), what)
    };
    let small = ["render", "--scene", "paper1", "--width", "32", "--spp", "4", "--depth", "6"];
    for (sampler, shard) in [("sobol", "0/2"), ("independent", "1/2")] {
        let part = format!("{sampler}.rpart");
        let out = raypool(&[&small[..], &["--sampler", sampler, "--shard", shard, "--out", &part]].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let out = raypool(&["merge", "sobol.rpart", "independent.rpart", "--out", "m.png"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("sampler \"independent\" vs \"sobol\""),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = raypool(&[&small[..], &["--sampler", "sobol", "--rng", "shared", "--out", "x.png"]].concat());
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot follow --sampler sobol"));
}
