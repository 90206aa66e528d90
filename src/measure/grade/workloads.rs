//! The grader's workloads: small renders that each expose one weakness of a scheduler or a
//! queue, their scenes in `workloads/`.
//!
//! | workload | what it exposes |
//! |---|---|
//! | `balanced` | nothing: every tile costs the same (the baseline) |
//! | `one-band` | a static split: all the cost sits in the bottom rows |
//! | `heavy-tail` | big chunks, or an expensive tile left to the end |
//! | `tiny-tiles` | per-job overhead: 2 × 2 tiles, four samples |
//! | `many-frames` | per-frame overhead: 160 small frames in a row (threads or a pool started per frame) |
//! | `smoke-room` | a cost of another kind: the second book's smoky Cornell box, where no path escapes to a sky |
//! | `nested` (queues only) | the waiting rule: bands as jobs, each waiting on a batch of its tiles |
//!
//! Each workload takes 0.1–0.5 s on one thread of this project's 2-CPU machine: long enough
//! that a round's ratio is not noise, short enough that grading at 1, 2 and 4 threads with 5
//! rounds takes about half a minute.

use std::sync::Arc;

use crate::error::Error;
use crate::scenes::format::SceneFile;
use crate::schedule::frame::Frame;
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::render::{RenderJob, RenderSettings, default_height};
use crate::tracer::sampling::sampler::Sampler;

/// One workload of the suite.
pub struct Workload {
    /// Its name in the report.
    pub name: &'static str,
    /// The weakness it exposes, in the report's words.
    pub exposes: &'static str,
    /// The scene, as TOML.
    pub scene: &'static str,
    /// Image width (the height follows the camera's aspect).
    pub width: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Tile side, pixels.
    pub tile: u32,
    /// Frames rendered back to back per timing.
    pub frames: usize,
    /// Queues only: render through nested batches.
    pub nested: bool,
    /// Its cost sits in one part of the image: the points are capped by the ratio of the
    /// load imbalances the frames saw, which a busy machine does not change.
    pub judged_by_balance: bool,
}

const FLAT: &str = include_str!("workloads/flat.toml");

/// The suite (the table above); `nested` only for a queue.
pub fn workloads(queue: bool) -> Vec<Workload> {
    let base = Workload {
        name: "balanced",
        exposes: "nothing: every tile costs the same",
        scene: FLAT,
        width: 480,
        spp: 12,
        tile: 16,
        frames: 1,
        nested: false,
        judged_by_balance: false,
    };
    let mut suite = vec![
        Workload { ..base },
        Workload {
            name: "one-band",
            exposes: "a static split: the cost is all in the bottom rows",
            scene: include_str!("workloads/band.toml"),
            judged_by_balance: true,
            ..base
        },
        Workload {
            name: "heavy-tail",
            exposes: "big chunks: a few tiles, all in the upper half, cost ten times the others",
            scene: include_str!("workloads/tail.toml"),
            spp: 16,
            judged_by_balance: true,
            ..base
        },
        Workload {
            name: "tiny-tiles",
            exposes: "per-job overhead: 2 × 2 tiles, 4 samples",
            spp: 4,
            tile: 2,
            ..base
        },
        Workload {
            name: "many-frames",
            exposes: "per-frame overhead: 160 frames of 64 × 36 in a row",
            width: 64,
            spp: 2,
            frames: 160,
            ..base
        },
        Workload {
            name: "smoke-room",
            exposes: "a cost of another kind: a closed room lit by one lamp, smoke in two boxes; no path escapes to a sky",
            scene: include_str!("../../scenes/cornell-smoke.toml"),
            width: 160,
            spp: 8,
            ..base
        },
    ];
    if queue {
        suite.push(Workload {
            name: "nested",
            exposes: "the waiting rule: each band of tiles is a job waiting on its tiles' batch",
            nested: true,
            ..base
        });
    }
    suite
}

impl Workload {
    /// The frame to time: this workload's scene and sampling, on `threads` threads.
    pub fn frame(&self, threads: usize) -> Result<Arc<Frame>, Error> {
        let scene = SceneFile::parse(self.scene, self.name)?;
        let height = default_height(self.width, scene.camera.aspect)?;
        let settings = RenderSettings {
            width: self.width,
            height,
            spp: self.spp,
            max_depth: 50,
            seed: 7,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let rng = RngSource::new(&settings, RngChoice::PerSample);
        Ok(Arc::new(Frame::new(
            RenderJob::new(scene.to_scene(), settings),
            rng,
            threads,
            self.tile,
            Arc::new(|_| {}),
        )))
    }
}
