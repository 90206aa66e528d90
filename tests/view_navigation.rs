//! Navigation frames (`POST /render` with `preview=1`, the request a camera drag sends): a
//! small 1-sample frame comes first, its pixels served as RGBA by `/preview.rgba` and equal to
//! `raypool render --denoise`'s at that size (`raypool render`'s with `denoise=0`); then the
//! full-size render follows, still the command line's image byte for byte. The start
//! resolution stays within its bounds.

mod common;
mod deadline;

use std::time::Duration;

use common::viewer::{Viewer, until_done};
use raypool::view::preview::{MAX_DIVISOR, StartResolution};
use serde_json::Value;

#[test]
fn a_moving_camera_gets_a_small_frame_first_then_the_command_lines_image() {
    for scene in ["final", "cornell"] {
        let viewer = Viewer::start(&[
            "--scene",
            scene,
            "--width",
            "96",
            "--spp",
            "4",
            "--threads",
            "2",
            "--tile",
            "8",
            "--sampler",
            "sobol",
        ]);
        until_done(&mut viewer.events(), 1);
        let (status, _) = viewer.get("/preview.rgba");
        assert_eq!(status, 409, "{scene}: the first render was not a move: no navigation frame");

        for (query, denoised) in
            [("lookfrom=10,3,5&preview=1", true), ("lookfrom=9,3,5&preview=1&denoise=0", false)]
        {
            let mut events = viewer.events();
            let (status, body) = viewer.post(&format!("/render?{query}"), b"");
            assert_eq!(status, 202, "{body}");
            let generation = serde_json::from_str::<Value>(&body).unwrap()["gen"].as_u64().unwrap();
            let render = until_done(&mut events, generation);
            let kinds: Vec<&str> = render.iter().map(|e| e["type"].as_str().unwrap()).collect();
            assert_eq!(kinds[..2], ["start", "preview"], "{scene}: the navigation frame comes first");
            assert!(kinds[2..].contains(&"tile") && !kinds[2..].contains(&"preview"), "then the full render");

            let preview = &render[1];
            assert_eq!(preview["denoised"].is_f64(), denoised, "{scene} {query}: {preview}");
            let divisor = preview["divisor"].as_u64().unwrap() as u32;
            let (width, height) =
                (preview["width"].as_u64().unwrap() as u32, preview["height"].as_u64().unwrap() as u32);
            let full_height = render[0]["height"].as_u64().unwrap() as u32;
            assert!((1..=8).contains(&divisor), "{preview}");
            assert_eq!(
                (width, height),
                (96u32.div_ceil(divisor), full_height.div_ceil(divisor)),
                "{preview}"
            );

            let (status, rgba) = viewer.get("/preview.rgba");
            assert_eq!(status, 200);
            assert_eq!(rgba.len(), (width * height * 4) as usize, "{scene}: RGBA, row by row");
            let size = [width.to_string(), height.to_string()];
            let mut flags =
                vec!["--width", &size[0], "--height", &size[1], "--spp", "1", "--sampler", "sobol"];
            if denoised {
                flags.push("--denoise");
            }
            let png = viewer.cli_render(&flags, "small.png");
            let cli = image::load_from_memory(&png).unwrap().to_rgba8().into_raw();
            assert!(
                rgba == cli,
                "{scene} {query}: the navigation frame is `raypool render {}`'s at {width} × {height}, 1 spp",
                flags.join(" ")
            );
        }

        let (status, image) = viewer.get("/image.pfm");
        assert_eq!(status, 200);
        let full = viewer.cli_render(&["--width", "96", "--spp", "4", "--sampler", "sobol"], "full.pfm");
        assert!(image == full, "{scene}: after the navigation frame, the full render is the command line's");
    }
}

#[test]
fn a_bad_preview_or_denoise_value_is_a_400() {
    let viewer = Viewer::start(&["--scene", "final", "--width", "32", "--spp", "1", "--threads", "1"]);
    let (status, body) = viewer.post("/render?preview=maybe", b"");
    assert_eq!((status, body.trim_end()), (400, "preview must be true or false, not 'maybe'"));
    let (status, body) = viewer.post("/render?denoise=2", b"");
    assert_eq!((status, body.trim_end()), (400, "denoise must be true or false, not '2'"));
}

#[test]
fn the_start_resolution_stays_between_full_size_and_an_eighth() {
    let mut start = StartResolution::default();
    for _ in 0..20 {
        start.record(start.divisor(), Duration::from_secs(5));
    }
    assert_eq!(f64::from(start.divisor()), MAX_DIVISOR, "a very slow scene: the smallest frames");
    for _ in 0..20 {
        start.record(start.divisor(), Duration::ZERO);
    }
    assert_eq!(start.divisor(), 1, "an instant scene: full size");
}
