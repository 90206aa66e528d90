//! Golden images: every built-in scene, under both samplers (and `final` with roulette and
//! adaptive sampling), renders to exactly the bytes it rendered to when its hash was last
//! blessed. The hashes in `tests/golden/images.sha256` were first written by the `raypool`
//! binary of commit 5e09953; the lit scenes' have been re-blessed since, each for a deliberate
//! change of their bits, listed with its reason in `tests/golden/BLESSINGS.md`. A change that
//! was meant to move no pixel (a refactor, a new kind of object that sphere scenes do not use)
//! must leave every one of them as it is.
//!
//! The bits are those of the default f32 build on x86-64 (the f64 build's differ by design);
//! after a deliberate change of image bits, `RAYPOOL_BLESS=1 cargo test --release --test
//! golden` rewrites the file, and the commit says why.

#![cfg(not(feature = "f64"))]

mod deadline;

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use deadline::within;
use raypool::files::output::{Format, encode};
use raypool::scenes::builtin::{BUILTINS, DEFAULT_SCENE_SEED, builtin_scene};
use raypool::schedule::frame::{DEFAULT_TILE, Frame};
use raypool::schedule::modes::{Schedule, render};
use raypool::schedule::random::{RngChoice, RngSource};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::render::{Adaptive, RenderJob, RenderSettings};
use raypool::tracer::sampling::sampler::Sampler;
use sha2::{Digest, Sha256};

const HASHES: &str = "tests/golden/images.sha256";

/// `raypool render --width 48 --height 32 --spp 4 --threads 2` and the given sampler.
fn base(sampler: Sampler) -> RenderSettings {
    RenderSettings { width: 48, height: 32, spp: 4, max_depth: 50, seed: 1, sampler, ..Default::default() }
}

/// Each case's name (as in the hash file) and settings.
fn cases() -> Vec<(String, &'static str, RenderSettings)> {
    let mut cases = Vec::new();
    for builtin in BUILTINS {
        for sampler in [Sampler::Sobol, Sampler::Independent] {
            cases.push((format!("{}-{}", builtin.name, sampler.name()), builtin.name, base(sampler)));
        }
    }
    let sobol = base(Sampler::Sobol);
    cases.push(("final-sobol-roulette".into(), "final", RenderSettings { roulette: true, ..sobol }));
    let adaptive = Some(Adaptive { target_error: 0.1, min_spp: 4 });
    cases.push(("final-sobol-adaptive".into(), "final", RenderSettings { spp: 32, adaptive, ..sobol }));
    cases
}

fn sha256_of_render(scene: &str, settings: RenderSettings, isa: Isa) -> String {
    let scene = builtin_scene(scene, DEFAULT_SCENE_SEED).unwrap().to_scene().with_isa(isa);
    let rng = RngSource::new(&settings, RngChoice::PerSample);
    let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, 2, DEFAULT_TILE, Arc::new(|_| {})));
    let mut pfm = Vec::new();
    encode(&render(&frame, &Schedule::Stealing).image, Format::Pfm, &mut pfm).unwrap();
    Sha256::digest(&pfm).iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn every_builtin_scene_renders_the_bytes_it_rendered_before() {
    within("the golden renders to finish", || {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(HASHES);
        let text = std::fs::read_to_string(&path).unwrap();
        let header: String = text.lines().filter(|l| l.starts_with('#')).map(|l| format!("{l}\n")).collect();
        let expected: BTreeMap<&str, &str> =
            text.lines().filter(|l| !l.starts_with('#')).filter_map(|l| l.split_once(' ')).collect();
        let got: BTreeMap<String, String> = cases()
            .into_iter()
            .map(|(name, scene, settings)| (name, sha256_of_render(scene, settings, Isa::best())))
            .collect();
        if std::env::var_os("RAYPOOL_BLESS").is_some() {
            let lines: String = got.iter().map(|(name, hash)| format!("{name} {hash}\n")).collect();
            std::fs::write(&path, header + &lines).unwrap();
            return;
        }
        let changed: Vec<&str> = got
            .iter()
            .filter(|(name, hash)| expected.get(name.as_str()) != Some(&hash.as_str()))
            .map(|(name, _)| name.as_str())
            .collect();
        assert!(changed.is_empty(), "these images changed bits (or are new to {HASHES}): {changed:?}");
        assert_eq!(got.len(), expected.len(), "{HASHES} names images no case renders");
    })
}

/// The vector instructions change no bit: every golden image, searched with each level this
/// CPU offers other than the default (the test above renders at `Isa::best`), hashes as blessed. A CPU
/// without AVX2 or AVX-512 checks fewer levels, and says which.
#[test]
fn every_isa_level_renders_the_golden_bytes() {
    within("the golden renders at every ISA level to finish", || {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(HASHES);
        let text = std::fs::read_to_string(&path).unwrap();
        let expected: BTreeMap<&str, &str> =
            text.lines().filter(|l| !l.starts_with('#')).filter_map(|l| l.split_once(' ')).collect();
        let lower = Isa::available().into_iter().filter(|&isa| isa != Isa::best());
        for isa in lower {
            eprintln!("checking the golden images at {isa:?}");
            for (name, scene, settings) in cases() {
                let got = sha256_of_render(scene, settings, isa);
                assert_eq!(Some(got.as_str()), expected.get(name.as_str()).copied(), "{name} at {isa:?}");
            }
        }
    })
}
