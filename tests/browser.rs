//! The viewer's page in a real browser: headless Chromium (Debian's `chromium`) loads it, lets
//! it render, and the DOM must show a drawn image, one timeline lane per worker, a camera that
//! orbits on a mouse drag (to the image the command line renders from there, byte for byte),
//! the outline toggle, and a pasted scene's error; and its guiding control, whose render is the
//! command line's `--guiding on` image, byte for byte.
//!
//! Without Chromium the test says so and skips; under `.ci/run` (which installs it and sets
//! `RAYPOOL_CI=1`) it fails instead.

mod common;
mod deadline;

use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

use common::browser::{Browser, chromium};
use common::viewer::Viewer;
use deadline::output_within;
use serde_json::json;

const MINUTE: Duration = Duration::from_secs(60);

/// Chromium, or `None` after saying that `test` skips for want of it; under `.ci/run`
/// (`RAYPOOL_CI`) its absence fails the test instead.
fn chromium_or_skip(test: &str) -> Option<PathBuf> {
    let binary = chromium();
    if binary.is_none() {
        assert!(
            std::env::var_os("RAYPOOL_CI").is_none(),
            "Chromium is required under .ci/run: apt-get install -y chromium"
        );
        deadline::skipped(test, "chromium not installed (apt-get install -y chromium)");
    }
    binary
}

#[test]
fn the_page_renders_live_with_a_lane_per_worker_and_orbits() {
    let Some(binary) = chromium_or_skip("the_page_renders_live_with_a_lane_per_worker_and_orbits") else {
        return;
    };
    let viewer = Viewer::start(&["--scene", "final", "--width", "200", "--spp", "16", "--threads", "2"]);
    let mut page = Browser::open(&binary, &viewer.url, (1100, 720));
    // The command line's render may be over before the page connects (it then shows the
    // finished image); change a control, as a user would, and watch that render live.
    page.wait_for("document.body.dataset.spp === '16'", MINUTE);
    page.eval("const spp = document.getElementById('spp'); spp.value = 24; spp.dispatchEvent(new Event('change')); true");
    page.wait_for("document.body.dataset.gen === '2' && document.body.dataset.spp === '24'", MINUTE);
    let body = page.eval("JSON.stringify(document.body.dataset)");
    let data: serde_json::Value = serde_json::from_str(body.as_str().unwrap()).unwrap();
    assert_eq!(data["lanes"], "2", "one timeline lane per worker: {data}");
    let lit: u32 = data["lit"].as_str().unwrap().parse().unwrap();
    assert!(lit > 200 * 133 * 9 / 10, "the image is drawn: {lit} of {} pixels lit", 200 * 133);
    let bars = page.eval(
        "(() => { const c = document.getElementById('timeline'); \
         const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let n = 0; for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++; return n; })()",
    );
    assert!(bars.as_u64().unwrap() > 1000, "the timeline has bars: {bars}");
    assert!(page.eval("document.getElementById('stats').textContent").as_str().unwrap().contains("Mrays/s"));
    // The mode menu is filled from the code's own list (`/state`'s `modes`, `Schedule::ALL`).
    let modes = page.eval("[...document.getElementById('mode').options].map(o => o.textContent).join(' ')");
    assert_eq!(modes, "serial static interleaved pool-rows pool steal", "the page's modes");

    // Drag the image: the camera orbits, the render restarts, and the page records how long
    // the first whole frame took to reach the screen.
    let rect = page.eval("(() => { const r = document.getElementById('image').getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let r: Vec<f64> = serde_json::from_value(rect).unwrap();
    let centre = (r[0] + r[2] / 2.0, r[1] + r[3] / 2.0);
    page.drag(centre, (centre.0 + 60.0, centre.1 + 10.0), 6);
    page.wait_for("+document.body.dataset.gen >= 3 && document.body.dataset.spp === '24' && window.raypoolLatencies.length >= 2", MINUTE);
    // Let the last request of the drag finish, then compare with the command line.
    std::thread::sleep(Duration::from_millis(300));
    page.wait_for("document.body.dataset.spp === '24'", MINUTE);
    let generation = page.eval("+document.body.dataset.gen");
    let (_, image) = viewer.get("/image.pfm");
    let scene = viewer.get("/scene.toml").1;
    assert!(!String::from_utf8_lossy(&scene).contains("lookfrom = [13.0, 2.0, 3.0]"), "the camera moved");
    let dir = std::env::temp_dir().join(format!("raypool-browser-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = output_within(
        Command::new(env!("CARGO_BIN_EXE_raypool"))
            .args([
                "render",
                "--scene-file",
                dir.join("scene.toml").to_str().unwrap(),
                "--width",
                "200",
                "--spp",
                "24",
            ])
            .args(["--out", dir.join("cli.pfm").to_str().unwrap()]),
        "`raypool render` of the orbited scene to exit",
    );
    assert!(out.status.success());
    assert_eq!(page.eval("+document.body.dataset.gen"), generation, "no restart since");
    assert!(image == std::fs::read(dir.join("cli.pfm")).unwrap(), "the orbited view is the CLI's image");

    // The wheel moves the camera away from what it looks at.
    let distance = |viewer: &Viewer| {
        let scene: raypool::SceneFile =
            toml::from_str(&String::from_utf8(viewer.get("/scene.toml").1).unwrap()).unwrap();
        let (a, b) = (scene.camera.lookfrom, scene.camera.lookat);
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let before = distance(&viewer);
    page.wheel(centre, 300.0);
    page.wait_for(
        &format!("+document.body.dataset.gen > {generation} && document.body.dataset.spp === '24'"),
        MINUTE,
    );
    let after = distance(&viewer);
    assert!(after > before * 1.2, "the wheel moved the camera out: {before} -> {after}");

    // The download button, the outline toggle, and a bad pasted scene's one-line error.
    let href = page.eval("document.getElementById('download').getAttribute('href')");
    let (status, png) = viewer.get(href.as_str().unwrap());
    assert!(status == 200 && png.starts_with(b"\x89PNG"), "{status}");
    let display = page.eval("document.getElementById('show-outlines').click(); getComputedStyle(document.getElementById('outlines')).display");
    assert_eq!(display, json!("none"));
    page.eval("document.getElementById('custom').value = '[camera'; document.getElementById('use-custom').click(); true");
    page.wait_for("document.getElementById('status').textContent.includes('pasted scene:1:')", MINUTE);

    // A second page, opened after the render ended, shows what the first one showed: the image,
    // the tiles' outlines and one lane per worker with the last pass's bars, the pass figures.
    let first = page.eval("JSON.stringify([document.body.dataset.lanes, document.body.dataset.spp])");
    let mut late = Browser::open(&binary, &viewer.url, (1100, 720));
    late.wait_for("document.body.dataset.spp === '24' && +document.body.dataset.tiles > 0", MINUTE);
    let data: serde_json::Value =
        serde_json::from_str(late.eval("JSON.stringify(document.body.dataset)").as_str().unwrap()).unwrap();
    assert_eq!(json!([data["lanes"], data["spp"]]).to_string(), first.as_str().unwrap(), "late page: {data}");
    assert!(late.eval("document.getElementById('stats').textContent").as_str().unwrap().contains("Mrays/s"));
    let outlined = late.eval(
        "(() => { const c = document.getElementById('outlines'); \
         const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let n = 0; for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++; return n; })()",
    );
    assert!(outlined.as_u64().unwrap() > 1000, "the late page outlines the tiles: {outlined}");
}

/// The page's guiding control, clicked as a user would: the render it starts is the command
/// line's with `--guiding on`, byte for byte; bdpt with guiding is refused on the page in the
/// command line's one line; and switching guiding off renders as without the flag.
#[test]
fn the_pages_guiding_control_renders_the_command_lines_guided_image() {
    let Some(binary) = chromium_or_skip("the_pages_guiding_control_renders_the_command_lines_guided_image")
    else {
        return;
    };
    let flags = ["--scene", "cornell", "--width", "40", "--spp", "16", "--threads", "2"];
    let viewer = Viewer::start(&flags);
    let mut page = Browser::open(&binary, &viewer.url, (1100, 720));
    page.wait_for(
        "document.body.dataset.spp === '16' && document.getElementById('guiding').value === 'off'",
        MINUTE,
    );
    let choose = |page: &mut Browser, id: &str, value: &str| {
        page.eval(&format!(
            "(() => {{ const c = document.getElementById('{id}'); c.value = '{value}'; \
             c.dispatchEvent(new Event('change')); return true; }})()"
        ));
    };
    let generation = |page: &mut Browser| page.eval("+document.body.dataset.gen").as_u64().unwrap();
    let done_after = |page: &mut Browser, last: u64| {
        page.wait_for(
            &format!("+document.body.dataset.gen > {last} && document.body.dataset.spp === '16'"),
            MINUTE,
        );
        std::thread::sleep(Duration::from_millis(300));
        page.wait_for("document.body.dataset.spp === '16'", MINUTE);
    };

    let before = generation(&mut page);
    choose(&mut page, "guiding", "on");
    done_after(&mut page, before);
    let state: serde_json::Value = serde_json::from_slice(&viewer.get("/state").1).unwrap();
    assert_eq!(state["guiding"], "on", "the control reached the render: {state}");
    let guided = viewer.get("/image.pfm").1;
    let cli = viewer.cli_render(&["--width", "40", "--spp", "16", "--guiding", "on"], "guided.pfm");
    assert!(guided == cli, "the page's guided render is not the command line's");

    choose(&mut page, "light-sampling", "bdpt");
    page.wait_for("document.getElementById('status').textContent.includes('--guiding on')", MINUTE);
    choose(&mut page, "light-sampling", "mis");
    let before = generation(&mut page);
    choose(&mut page, "guiding", "off");
    done_after(&mut page, before);
    let unguided = viewer.get("/image.pfm").1;
    assert!(unguided == viewer.cli_render(&["--width", "40", "--spp", "16"], "plain.pfm"), "guiding off");
    assert!(unguided != guided, "the guide changed no pixel: the test would not see it ignored");
}
