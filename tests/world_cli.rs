//! The second book's scenes through the `raypool` command: every mode, thread count, sampler,
//! `--accel` and shard gives the same bytes, a printed scene renders like the built-in, and
//! every mistake in a scene file (or in the files it names) exits 2 with one line.

mod deadline;

use std::path::Path;

use deadline::{ok, raypool, scratch};

/// The new scenes, each with what it exercises.
const SCENES: &[&str] = &["cornell", "cornell-smoke", "next-week", "quads", "perlin", "bouncing", "mesh"];

fn render(dir: &Path, scene: &str, extra: &[&str], out: &str) -> Vec<u8> {
    let mut args =
        vec!["render", "--scene", scene, "--width", "20", "--spp", "3", "--depth", "8", "--out", out];
    args.extend_from_slice(extra);
    ok(raypool(&args, dir));
    std::fs::read(dir.join(out)).unwrap()
}

#[test]
fn every_mode_thread_count_and_accel_gives_the_same_bytes_on_every_new_scene() {
    let runs: &[&[&str]] = &[
        &["--mode", "static", "--threads", "2"],
        &["--mode", "interleaved", "--threads", "3"],
        &["--mode", "pool", "--threads", "2"],
        &["--mode", "steal", "--threads", "4", "--tile", "7"],
        &["--accel", "flat", "--threads", "2"],
        &["--accel", "binary"],
    ];
    for scene in SCENES {
        let dir = scratch(&format!("modes-{scene}"));
        for sampler in ["sobol", "independent"] {
            let serial = render(&dir, scene, &["--mode", "serial", "--sampler", sampler], "serial.pfm");
            for (k, run) in runs.iter().enumerate() {
                let mut args = run.to_vec();
                args.extend(["--sampler", sampler]);
                let bytes = render(&dir, scene, &args, &format!("{k}.pfm"));
                assert!(bytes == serial, "{scene}, {sampler}: {run:?} changed the image");
            }
        }
    }
}

#[test]
fn every_light_sampling_gives_the_same_bytes_under_every_mode_and_shard() {
    // The default (`mis`) is covered above; the other two draw their own numbers (a coin, a
    // point on a light), still from each sample's own stream.
    for light_sampling in ["bsdf", "mixture", "mis"] {
        let dir = scratch(&format!("lights-{light_sampling}"));
        let render_with = |run: &[&str], out: &str| {
            let mut args = run.to_vec();
            args.extend(["--light-sampling", light_sampling, "--tile", "6"]);
            render(&dir, "cornell-smoke", &args, out)
        };
        let serial = render_with(&["--mode", "serial"], "serial.pfm");
        for (k, run) in [&["--mode", "static", "--threads", "2"][..], &["--mode", "steal", "--threads", "3"]]
            .iter()
            .enumerate()
        {
            let bytes = render_with(run, &format!("{k}.pfm"));
            assert!(bytes == serial, "{light_sampling}: {run:?} changed the image");
        }
        let parts = ["p0.rpart", "p1.rpart"];
        for (k, part) in parts.iter().enumerate() {
            render_with(&["--shard", &format!("{k}/2")], part);
        }
        ok(raypool(&["merge", "--out", "merged.pfm", parts[0], parts[1]], &dir));
        assert!(std::fs::read(dir.join("merged.pfm")).unwrap() == serial, "{light_sampling}: shards differ");
    }
}

#[test]
fn shards_merge_into_the_one_process_image_on_the_new_scenes() {
    for scene in ["next-week", "cornell-smoke", "bouncing"] {
        let dir = scratch(&format!("shards-{scene}"));
        let whole = render(&dir, scene, &["--tile", "6"], "whole.pfm");
        let mut parts = Vec::new();
        for k in 0..3 {
            let (shard, part) = (format!("{k}/3"), format!("p{k}.rpart"));
            render(
                &dir,
                scene,
                &["--tile", "6", "--shard", &shard, "--threads", &(k + 1).to_string()],
                &part,
            );
            parts.push(part);
        }
        let mut args = vec!["merge", "--out", "merged.pfm"];
        args.extend(parts.iter().map(String::as_str));
        ok(raypool(&args, &dir));
        assert!(std::fs::read(dir.join("merged.pfm")).unwrap() == whole, "{scene}: merged shards differ");
    }
}

#[test]
fn printed_new_scenes_render_like_the_builtins() {
    for scene in SCENES {
        let dir = scratch(&format!("print-{scene}"));
        let printed = ok(raypool(&["scene", scene], &dir));
        std::fs::write(dir.join("s.toml"), &printed.stdout).unwrap();
        let builtin = render(&dir, scene, &[], "a.pfm");
        let mut args =
            vec!["render", "--scene-file", "s.toml", "--width", "20", "--spp", "3", "--depth", "8"];
        args.extend(["--out", "b.pfm"]);
        ok(raypool(&args, &dir));
        assert!(std::fs::read(dir.join("b.pfm")).unwrap() == builtin, "{scene}: the printed scene differs");
    }
}

#[test]
fn scenes_lists_the_new_builtins() {
    let text = String::from_utf8(ok(raypool(&["scenes"], &std::env::temp_dir())).stdout).unwrap();
    for name in SCENES {
        assert!(text.lines().any(|l| l.starts_with(name)), "{name} missing from:\n{text}");
    }
}

/// Exit 2, one line naming the problem, no output file.
fn refused(dir: &Path, scene: &str, needle: &str) {
    let out =
        raypool(&["render", "--scene-file", scene, "--width", "8", "--spp", "1", "--out", "x.png"], dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{scene}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{scene}: one line, got {stderr}");
    assert!(stderr.contains(needle), "{scene}: expected '{needle}' in {stderr}");
    assert!(!dir.join("x.png").exists(), "{scene}: no output file");
}

#[test]
fn a_minimal_camera_is_told_every_missing_field_at_once_at_its_table() {
    // A new user's first scene: serde would name `vup`, then (once fixed) `vfov`.
    let dir = scratch("camera");
    let sphere = "[[sphere]]\ncenter = [0.0, 0.0, -1.0]\nradius = 0.5\nmaterial = { kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }\n";
    let text = format!(
        "# my first scene\n\n[camera]\nlookfrom = [0.0, 0.0, 0.0]\nlookat = [0.0, 0.0, -1.0]\n\n{sphere}"
    );
    std::fs::write(dir.join("camera.toml"), text).unwrap();
    refused(&dir, "camera.toml", "camera.toml:3:1: [camera] is missing fields `vup`, `vfov` (it needs");
    std::fs::write(dir.join("none.toml"), sphere).unwrap();
    refused(&dir, "none.toml", "none.toml:1:1: no [camera] table");
}

#[test]
fn bad_new_world_scene_files_exit_2_with_one_line() {
    let dir = scratch("bad");
    let head = "[camera]\nlookfrom = [0.0, 0.0, 5.0]\nlookat = [0.0, 0.0, 0.0]\nvup = [0.0, 1.0, 0.0]\nvfov = 40.0\nfocus_dist = 5.0\n";
    let grey = "material = { kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }";
    let mesh = |obj: &str| format!("{head}[[mesh]]\nobj = \"{obj}\"\n{grey}\n");
    std::fs::write(dir.join("good.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    std::fs::write(dir.join("garbage.obj"), "v one two three\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("late.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n# ok so far\nf 1 2 3\nf 1 2 x\n")
        .unwrap();
    std::fs::write(dir.join("binary.obj"), b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").unwrap();
    // Index 4 is past the 3 vertices there are when the group `g` ends the first object
    // (tobj checks there), though the file holds 4 in the end.
    let ahead = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\ng later\nv 1 1 1\nf 1 2 3\n";
    std::fs::write(dir.join("ahead.obj"), ahead).unwrap();
    let big = std::fs::File::create(dir.join("huge.obj")).unwrap();
    big.set_len(257 << 20).unwrap(); // sparse: refused by its size before a byte is read
    std::fs::create_dir_all(dir.join("inner")).unwrap();
    let cases = [
        (
            "quad.toml",
            format!(
                "{head}[[quad]]\nq = [0.0, 0.0, 0.0]\nu = [1.0, 0.0, 0.0]\nv = [2.0, 0.0, 0.0]\n{grey}\n"
            ),
            "quad #1: degenerate",
        ),
        (
            "triangle.toml",
            format!(
                "{head}[[triangle]]\nvertices = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]\n{grey}\n"
            ),
            "triangle #1: degenerate",
        ),
        (
            "box.toml",
            format!("{head}[[box]]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 0.0, 1.0]\n{grey}\n"),
            "box #1: degenerate",
        ),
        (
            "nan.toml",
            format!(
                "{head}[[quad]]\nq = [nan, 0.0, 0.0]\nu = [1.0, 0.0, 0.0]\nv = [0.0, 1.0, 0.0]\n{grey}\n"
            ),
            "finite",
        ),
        (
            "inf.toml",
            format!(
                "{head}[[medium]]\ndensity = inf\nalbedo = [1.0, 1.0, 1.0]\nboundary = {{ kind = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }}\n"
            ),
            "density",
        ),
        (
            "texture.toml",
            format!(
                "{head}[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = {{ kind = \"lambertian\", texture = {{ kind = \"plaid\" }} }}\n"
            ),
            "plaid",
        ),
        (
            "group.toml",
            format!(
                "{head}[[group]]\n[group.transform]\ntranslate = [nan, 0.0, 0.0]\n[[group.sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n{grey}\n"
            ),
            "group #1: transform must be finite",
        ),
        ("missing.toml", mesh("nowhere.obj"), "nowhere.obj"),
        // An OBJ's error names its line and quotes it.
        (
            "malformed.toml",
            mesh("broken.obj"),
            "'broken.obj': line 3: not a valid OBJ file (face vertex index out of bounds): \"f 1 2 9\"",
        ),
        (
            "garbage.toml",
            mesh("garbage.obj"),
            "'garbage.obj': line 1: not a valid OBJ file (position parse error): \"v one two three\"",
        ),
        (
            "late.toml",
            mesh("late.obj"),
            "'late.obj': line 6: not a valid OBJ file (face parse error): \"f 1 2 x\"",
        ),
        ("binary.toml", mesh("binary.obj"), "'binary.obj': line 1: not UTF-8 text, so not an OBJ file"),
        (
            "ahead.toml",
            mesh("ahead.obj"),
            "'ahead.obj': line 5: not a valid OBJ file (face vertex index out of bounds)",
        ),
        ("huge.toml", mesh("huge.obj"), "larger than 256 MiB"),
        ("escape.toml", mesh("../good.obj"), "leaves the scene file's folder"),
        ("absolute.toml", mesh("/etc/passwd"), "leaves the scene file's folder"),
        (
            "image.toml",
            format!(
                "{head}[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = {{ kind = \"lambertian\", texture = {{ kind = \"image\", path = \"good.obj\" }} }}\n"
            ),
            "not an image",
        ),
    ];
    let mut cases = cases.to_vec();
    if std::mem::size_of::<raypool::tracer::math::real::Real>() == 4 {
        // Finite as written, infinite as an f32.
        cases.push((
            "overflow.toml",
            format!(
                "{head}[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = {{ kind = \"diffuse_light\", emit = [1e39, 1.0, 1.0] }}\n"
            ),
            "must be finite (also as the renderer's",
        ));
        // Every other number of a scene file is checked so too.
        let sphere = "[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nmaterial = { kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }";
        let overflowing = [
            ("radius.toml", format!("{head}{sphere}\nradius = 1e39\n"), "radius must be finite (as f32)"),
            (
                "density.toml",
                format!(
                    "{head}[[medium]]\ndensity = 1e39\nalbedo = [1.0, 1.0, 1.0]\nboundary = {{ kind = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }}\n"
                ),
                "density must be finite (as f32)",
            ),
            (
                "ior.toml",
                format!(
                    "{head}[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = {{ kind = \"dielectric\", ior = 1e39 }}\n"
                ),
                "ior must be finite (as f32)",
            ),
            (
                "turn.toml",
                format!(
                    "{head}[[group]]\n[group.transform]\nrotate_y = 1e39\n[[group.sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n{grey}\n"
                ),
                "transform must be finite numbers (as f32)",
            ),
        ];
        cases.extend(overflowing.iter().map(|(n, t, w)| (*n, t.clone(), *w)));
    }
    for (name, text, needle) in cases {
        std::fs::write(dir.join(name), text).unwrap();
        refused(&dir, name, needle);
    }
    // A good OBJ beside the scene file renders.
    std::fs::write(dir.join("ok.toml"), mesh("good.obj")).unwrap();
    ok(raypool(
        &["render", "--scene-file", "ok.toml", "--width", "8", "--spp", "1", "--out", "ok.png"],
        &dir,
    ));
    // And a link out of the folder is refused.
    std::fs::write(dir.join("inner/link.toml"), mesh("link.obj")).unwrap();
    std::os::unix::fs::symlink(dir.join("good.obj"), dir.join("inner/link.obj")).unwrap();
    refused(&dir, "inner/link.toml", "leads out of the scene file's folder");
}
