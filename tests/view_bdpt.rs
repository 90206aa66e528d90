//! `raypool view` under `--light-sampling bdpt`: light paths light pixels of other tiles than
//! their own, so the tiles' events cannot show it. Each pass ends with a `frame` event, the
//! whole image; after every pass that frame is the command line's image at that pass's samples
//! per pixel, byte for byte, and the final image served is `raypool render`'s. A page that
//! joins after the last pass is shown that frame over the replayed tiles.

mod common;

use base64::Engine;
use common::viewer::{Viewer, until_done};
use serde_json::Value;

/// The 8-bit RGB bytes of a PPM file (`P6\n<w> <h> 255\n` then the pixels).
fn ppm_pixels(ppm: &[u8]) -> &[u8] {
    let header = ppm.iter().enumerate().filter(|(_, b)| **b == b'\n').nth(1).expect("a PPM header").0;
    &ppm[header + 1..]
}

#[test]
fn each_bdpt_pass_is_the_command_lines_image_at_its_samples() {
    let flags = ["--width", "40", "--light-sampling", "bdpt"];
    let viewer = Viewer::start(
        &[&flags[..], &["--scene", "cornell", "--spp", "4", "--threads", "2", "--tile", "8"]].concat(),
    );
    until_done(&mut viewer.events(), 1);
    // A page listening from the start of render 2 sees every pass of it.
    let mut stream = viewer.events();
    let (status, body) = viewer.post("/render?spp=4", b"");
    assert_eq!(status, 202, "{body}");
    let events = until_done(&mut stream, 2);
    let frames: Vec<&Value> = events.iter().filter(|e| e["type"] == "frame").collect();
    let passes: Vec<&Value> = events.iter().filter(|e| e["type"] == "pass").collect();
    // Passes of 1, 1 and 2 samples: after 1, 2 and 4.
    let spps: Vec<u64> = passes.iter().map(|p| p["spp"].as_u64().unwrap()).collect();
    assert_eq!(spps, [1, 2, 4], "the passes");
    assert_eq!(frames.len(), passes.len(), "one frame per pass");
    for frame in frames {
        let spp = frame["spp"].as_u64().unwrap().to_string();
        let rgb = base64::engine::general_purpose::STANDARD.decode(frame["rgb"].as_str().unwrap()).unwrap();
        let cli = viewer.cli_render(&[&flags[..], &["--spp", &spp]].concat(), "cli.ppm");
        assert!(rgb == ppm_pixels(&cli), "the frame after {spp} spp is not the command line's image");
    }
    let (status, served) = viewer.get("/image.pfm");
    assert_eq!(status, 200);
    assert!(
        served == viewer.cli_render(&[&flags[..], &["--spp", "4"]].concat(), "cli.pfm"),
        "the final image"
    );

    let late = until_done(&mut viewer.events(), 2);
    let kinds: Vec<&str> = late.iter().map(|e| e["type"].as_str().unwrap()).collect();
    let last_tile = kinds.iter().rposition(|&k| k == "tile").expect("the last pass's tiles replayed");
    assert_eq!(kinds[last_tile + 1..], ["frame", "pass", "done"], "a late page's replay: {kinds:?}");
}
