//! The events a page receives (server-sent, one JSON object each): `start` opens a render,
//! `preview` says a navigation frame is ready at `/preview.rgba`, `tile` carries a finished
//! tile's pixels and timing (the teaching view: outlines in the worker's colour and the
//! timeline), `pass` ends a pass, `done` ends the render, and `frame` gives a page that joins
//! late the image so far.

use std::thread::ThreadId;

use base64::Engine as _;
use parking_lot::Mutex;
use serde_json::json;

use crate::files::image::Image;
use crate::schedule::random::RngChoice;
use crate::tracer::render::TileOutput;
use crate::view::preview::Preview;
use crate::view::request::Config;

/// The event that opens a render: its size, settings and camera (the page orbits from it).
pub fn start_event(generation: u64, config: &Config) -> String {
    let settings = &config.job.settings;
    json!({
        "type": "start", "gen": generation, "scene": config.name, "width": settings.width,
        "height": settings.height, "spp": settings.spp, "threads": config.threads,
        "mode": config.mode.name(), "tile": config.tile,
        "rng": if config.rng == RngChoice::Shared { "shared" } else { "per-sample" }, "sampler": settings.sampler.name(),
        "lookfrom": config.scene.camera.lookfrom, "lookat": config.scene.camera.lookat,
        "preview": config.preview,
    })
    .to_string()
}

/// A navigation frame is ready: its size and the divisor it was rendered at.
pub fn preview_event(preview: &Preview) -> String {
    json!({
        "type": "preview", "gen": preview.generation, "width": preview.width, "height": preview.height,
        "divisor": preview.divisor, "seconds": preview.took.as_secs_f64(),
        "denoised": preview.denoising.map(|d| d.as_secs_f64()),
    })
    .to_string()
}

/// The whole image of a finished pass, for a page that joins late.
pub fn frame_event(generation: u64, spp: u32, image: &Image) -> String {
    json!({
        "type": "frame", "gen": generation, "spp": spp, "width": image.width,
        "height": image.height, "rgb": base64::engine::general_purpose::STANDARD.encode(image.to_rgb8()),
    })
    .to_string()
}

/// A finished tile: where, which worker (lanes are numbered in the order workers first
/// finish a tile of this pass), when (seconds since the pass began), and its pixels as
/// 8-bit RGB after `spp` samples, base64. `None` for a tile that was not rendered.
pub fn tile_event(
    generation: u64,
    pass: u32,
    spp: u32,
    out: &TileOutput,
    lanes: &Mutex<Vec<ThreadId>>,
) -> Option<String> {
    let timing = out.timing?;
    let worker = {
        let mut lanes = lanes.lock();
        lanes.iter().position(|&t| t == timing.thread).unwrap_or_else(|| {
            lanes.push(timing.thread);
            lanes.len() - 1
        })
    };
    let t = out.tile;
    let rgb = Image { width: t.width, height: t.height, pixels: out.pixels.clone() }.to_rgb8();
    json!({
        "type": "tile", "gen": generation, "pass": pass, "spp": spp, "x": t.x, "y": t.y, "w": t.width,
        "h": t.height, "worker": worker, "start": timing.start.as_secs_f64(), "end": timing.end.as_secs_f64(),
        "rgb": base64::engine::general_purpose::STANDARD.encode(rgb),
    })
    .to_string()
    .into()
}
