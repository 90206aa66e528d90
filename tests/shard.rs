//! Shards: `render --shard K/N` parts merged by `raypool merge` are the one-process image,
//! byte for byte, whatever N, tile size and scheduler, bdpt's light paths included; a
//! missing, duplicated, foreign, truncated or corrupt part is one line naming it, exit code 2,
//! and no image.

mod deadline;

use std::path::Path;

use deadline::{ok, raypool, scratch};

use raypool::files::image::Image;
use raypool::files::part::{Part, PartSettings, merge};
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::splats::Splats;
use raypool::{RenderSettings, Shard, Tile};

/// Renders `scene` whole into `whole.pfm` and as `n` parts with the modes taken in turn,
/// merges the parts, and returns (whole bytes, merged bytes).
fn whole_and_merged(dir: &Path, scene: &str, n: u32, tile: &str, modes: &[&str]) -> (Vec<u8>, Vec<u8>) {
    whole_and_merged_with(dir, scene, n, tile, modes, &["--spp", "3"])
}

/// [`whole_and_merged`] with `sampling` flags instead of `--spp 3`.
fn whole_and_merged_with(
    dir: &Path,
    scene: &str,
    n: u32,
    tile: &str,
    modes: &[&str],
    sampling: &[&str],
) -> (Vec<u8>, Vec<u8>) {
    let mut common = vec!["--scene", scene, "--width", "61", "--depth", "10", "--tile", tile];
    common.extend_from_slice(sampling);
    let mut args = vec!["render", "--out", "whole.pfm"];
    args.extend_from_slice(&common);
    ok(raypool(&args, dir));
    let mut parts = Vec::new();
    for k in 0..n {
        let (shard, part) = (format!("{k}/{n}"), format!("part-{k}.rpart"));
        let threads = (k % 3 + 1).to_string();
        let mode = modes[k as usize % modes.len()];
        let mut args =
            vec!["render", "--shard", &shard, "--out", &part, "--mode", mode, "--threads", &threads];
        args.extend_from_slice(&common);
        ok(raypool(&args, dir));
        parts.push(part);
    }
    parts.reverse(); // any order
    let mut args = vec!["merge", "--out", "merged.pfm"];
    args.extend(parts.iter().map(String::as_str));
    let out = ok(raypool(&args, dir));
    let summary = String::from_utf8_lossy(&out.stderr);
    assert!(summary.contains(&format!("merged {n} parts")), "{summary}");
    (std::fs::read(dir.join("whole.pfm")).unwrap(), std::fs::read(dir.join("merged.pfm")).unwrap())
}

#[test]
fn merged_parts_equal_the_one_process_render_for_1_3_and_7_shards() {
    let modes = ["serial", "static", "interleaved", "pool-rows", "pool", "steal"];
    // `cornell`: a lit scene, its light's edge pixels taking edge points (`lighting/edges.rs`).
    let cases = [
        (1, "16", "final"),
        (3, "16", "final"),
        (7, "9", "paper2"),
        (3, "64", "paper1"),
        (3, "8", "cornell"),
    ];
    for (n, tile, scene) in cases {
        let dir = scratch(&format!("merge-{n}-{tile}-{scene}"));
        let (whole, merged) = whole_and_merged(&dir, scene, n, tile, &modes);
        assert!(whole == merged, "{n} shards of {tile}-pixel tiles ({scene}): merged image differs");
    }
}

#[test]
fn guided_parts_merge_into_the_one_process_image() {
    // Each shard learns its guides from every pixel, as the one-process render does, and
    // renders its own pixels with them.
    let modes = ["serial", "interleaved", "pool", "steal"];
    let dir = scratch("merge-guided");
    let guided = ["--spp", "8", "--guiding", "on", "--guide-pilot", "4"];
    let (whole, merged) = whole_and_merged_with(&dir, "cornell", 3, "8", &modes, &guided);
    assert!(whole == merged, "3 guided shards: merged image differs");
}

#[test]
fn adaptive_parts_merge_into_the_one_process_image() {
    // A pixel's sample count reads its neighbours' pilots; a shard renders the pilots of the
    // pixels next to its tiles too, so each part holds the one-process pixels. Small tiles,
    // so most pixels have a neighbour in another shard.
    let modes = ["steal", "static", "serial"];
    let adaptive = ["--target-error", "0.05", "--min-spp", "4", "--max-spp", "32"];
    for (n, tile, scene) in [(3, "8", "final"), (5, "5", "paper3")] {
        let dir = scratch(&format!("adaptive-{n}"));
        let (whole, merged) = whole_and_merged_with(&dir, scene, n, tile, &modes, &adaptive);
        assert!(whole == merged, "{n} adaptive shards of {tile}-pixel tiles ({scene}): merged image differs");
    }
}

#[test]
fn bdpt_parts_carry_their_light_paths_splats_into_the_one_process_image() {
    // A light path's light lands in any shard's pixels: each part holds its shard's splats
    // in fixed point and the merge adds their sum once, as the one-process render does.
    let modes = ["steal", "serial", "static"];
    let bdpt = ["--spp", "3", "--light-sampling", "bdpt"];
    for (n, tile, scene) in [(3, "8", "cornell"), (4, "16", "cornell-smoke")] {
        let dir = scratch(&format!("bdpt-{n}-{scene}"));
        let (whole, merged) = whole_and_merged_with(&dir, scene, n, tile, &modes, &bdpt);
        assert!(whole == merged, "{n} bdpt shards of {tile}-pixel tiles ({scene}): merged image differs");
        let part = Part::from_bytes(&std::fs::read(dir.join("part-0.rpart")).unwrap()).unwrap();
        assert!(part.header.splat_pixels > 0, "{scene}: shard 0's light paths splatted nothing");
    }
}

#[test]
fn more_shards_than_tiles_leave_some_parts_empty_and_still_merge() {
    let dir = scratch("empty");
    // 61 × 41 in 64-pixel tiles is one tile: shards 1 and 2 hold none.
    let (whole, merged) = whole_and_merged(&dir, "three-spheres", 3, "64", &["steal", "static"]);
    assert!(whole == merged);
}

/// Renders 3 parts of `paper1` into `dir` (part-0..2.rpart); returns their names.
fn three_parts(dir: &Path, extra: &[&str]) -> Vec<String> {
    (0..3)
        .map(|k| {
            let (shard, part) = (format!("{k}/3"), format!("part-{k}{}.rpart", extra.join("")));
            let mut args = vec!["render", "--scene", "paper1", "--width", "40", "--spp", "2", "--depth", "6"];
            args.extend_from_slice(&["--shard", &shard, "--out", &part]);
            args.extend_from_slice(extra);
            ok(raypool(&args, dir));
            part
        })
        .collect()
}

/// `merge` of `parts` fails with exit code 2, one line containing `expected`, and no image.
fn refused(dir: &Path, parts: &[&str], expected: &str) {
    let mut args = vec!["merge", "--out", "out.png"];
    args.extend_from_slice(parts);
    let out = raypool(&args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{parts:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(stderr.contains(expected), "{parts:?}: expected '{expected}' in: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.join("out.png").exists(), "no image after a refused merge");
    let leftovers = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with(".raypool-"));
    assert_eq!(leftovers.count(), 0, "no temporary file left behind");
}

#[test]
fn bad_parts_are_refused_by_name() {
    let dir = scratch("bad");
    let parts = three_parts(&dir, &[]);
    let p: Vec<&str> = parts.iter().map(String::as_str).collect();
    ok(raypool(&["merge", "--out", "good.png", p[0], p[1], p[2]], &dir));

    refused(&dir, &[p[0], p[2]], "shard 1 of 3 is missing");
    refused(&dir, &[p[0], p[1], p[1], p[2]], "part-1.rpart: shard 1 of 3 again");
    refused(&dir, &[p[0], p[1], p[2], "absent.rpart"], "absent.rpart: cannot read");

    // A part of another image: another seed; another scene.
    let other_seed = three_parts(&dir, &["--seed", "9"]);
    refused(
        &dir,
        &[p[0], &other_seed[1], p[2]],
        "part-1--seed9.rpart: not a part of the same image as part-0.rpart (seed 9 vs 1)",
    );
    let mut args = vec!["render", "--scene", "paper2", "--width", "40", "--spp", "2", "--depth", "6"];
    args.extend_from_slice(&["--shard", "1/3", "--out", "paper2.rpart"]);
    ok(raypool(&args, &dir));
    refused(
        &dir,
        &[p[0], "paper2.rpart", p[2]],
        "paper2.rpart: not a part of the same image as part-0.rpart (scene_digest",
    );
    // Cut into a different number of shards.
    let mut args = vec!["render", "--scene", "paper1", "--width", "40", "--spp", "2", "--depth", "6"];
    args.extend_from_slice(&["--shard", "1/4", "--out", "of4.rpart"]);
    ok(raypool(&args, &dir));
    refused(
        &dir,
        &[p[0], "of4.rpart", p[2]],
        "of4.rpart: not a part of the same image as part-0.rpart (shards 4 vs 3)",
    );

    // Damaged files.
    let bytes = std::fs::read(dir.join(p[1])).unwrap();
    std::fs::write(dir.join("cut.rpart"), &bytes[..bytes.len() - 100]).unwrap();
    refused(&dir, &[p[0], "cut.rpart", p[2]], "cut.rpart: truncated");
    std::fs::write(dir.join("header-cut.rpart"), &bytes[..40]).unwrap();
    refused(&dir, &[p[0], "header-cut.rpart", p[2]], "header-cut.rpart: truncated header");
    let mut flipped = bytes.clone();
    let last = flipped.len() - 5;
    flipped[last] ^= 0x10;
    std::fs::write(dir.join("flipped.rpart"), &flipped).unwrap();
    refused(&dir, &[p[0], "flipped.rpart", p[2]], "flipped.rpart: corrupt");
    let mut longer = bytes.clone();
    longer.extend_from_slice(b"junk");
    std::fs::write(dir.join("longer.rpart"), &longer).unwrap();
    refused(&dir, &[p[0], "longer.rpart", p[2]], "longer.rpart: 4 bytes past its data");
    let text = String::from_utf8_lossy(&bytes).replacen("raypool-part 2", "raypool-part 7", 1);
    std::fs::write(dir.join("future.rpart"), text.as_bytes()).unwrap();
    refused(&dir, &[p[0], "future.rpart", p[2]], "future.rpart: part format version 7");
    std::fs::write(dir.join("image.rpart"), b"P6\n1 1\n255\n\0\0\0").unwrap();
    refused(&dir, &[p[0], "image.rpart", p[2]], "image.rpart: not a raypool part file");
    std::fs::write(dir.join("empty.rpart"), b"").unwrap();
    refused(&dir, &[p[0], "empty.rpart", p[2]], "empty.rpart: not a raypool part file");
    let mut bad_header = bytes.clone();
    let at = bad_header.windows(6).position(|w| w == b"spp = ").unwrap();
    bad_header[at..at + 6].copy_from_slice(b"spp =\"");
    std::fs::write(dir.join("bad-header.rpart"), &bad_header).unwrap();
    refused(&dir, &[p[0], "bad-header.rpart", p[2]], "bad-header.rpart: bad header");

    // Bad command lines.
    let out = raypool(&["merge", "--out", "x.rpart", p[0], p[1], p[2]], &dir);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("merge writes an image"));
    for (args, expected) in [
        (vec!["render", "--shard", "3/3", "--out", "x.rpart"], "K must be below N"),
        (vec!["render", "--shard", "1/0", "--out", "x.rpart"], "N must be 1 to 65536"),
        (vec!["render", "--shard", "one/3", "--out", "x.rpart"], "'one' is not a whole number"),
        (vec!["render", "--shard", "1/3", "--out", "x.png"], "writes a part file"),
        (vec!["render", "--shard", "1/3", "--rng", "shared", "--out", "x.rpart"], "use --rng per-sample"),
    ] {
        let out = raypool(&args, &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected) && stderr.lines().count() == 1, "{args:?}: {stderr}");
        assert!(!dir.join("x.rpart").exists() && !dir.join("x.png").exists());
    }
}

#[test]
fn a_part_round_trips_through_its_bytes() {
    let (width, height, tile) = (20, 9, 4);
    let image = Image {
        width,
        height,
        pixels: (0..width * height).map(|k| Vec3::new(k as Real / 7.0, 1e-30, 3.0e7)).collect(),
    };
    let settings = RenderSettings { width, height, ..RenderSettings::default() };
    let grid = Tile::grid(width, height, tile);
    let mut all_splats = Splats::default();
    let parts: Vec<(String, Part)> = (0..2)
        .map(|k| {
            let shard = Shard { index: k, count: 2 };
            // Light paths' splats land in any pixel, the other shard's too.
            let mut splats = Splats::default();
            splats.add(5, Vec3::new(0.5, 1e-9, 7.0));
            splats.add(3 * k, Vec3::splat(k as Real + 0.25));
            all_splats.merge(&splats);
            let part = Part::new(
                PartSettings::new("d".into(), &settings, tile, 2),
                shard,
                &shard.tiles(&grid),
                &image,
                splats,
            );
            let read = Part::from_bytes(&part.to_bytes()).expect("a part reads back");
            assert_eq!(read.tiles, part.tiles, "pixels exactly as written");
            assert_eq!(read.splats, part.splats, "splats exactly as written");
            (format!("p{k}"), read)
        })
        .collect();
    let mut expected = image.clone();
    expected.add_splats(&all_splats, settings.spp);
    assert_ne!(expected, image);
    assert_eq!(merge(&parts).unwrap(), expected);
}

#[test]
fn a_shards_rows_and_tiles_cover_exactly_its_pixels() {
    use raypool::schedule::random::RngSource;
    use raypool::tracer::sampling::independent::PerSample;
    use raypool::{Frame, RenderJob};
    let settings =
        RenderSettings { width: 37, height: 23, spp: 1, max_depth: 3, ..RenderSettings::default() };
    let scene = raypool::scenes::builtin::builtin_scene("paper1", 1).unwrap().to_scene();
    let mut covered = vec![0u32; 37 * 23];
    for k in 0..5 {
        let frame = Frame::new(
            RenderJob::new(scene.clone(), settings),
            RngSource::PerSample(PerSample { seed: 1 }),
            2,
            6,
            std::sync::Arc::new(|_| {}),
        )
        .sharded(Shard { index: k, count: 5 });
        let mut by_rows = vec![false; 37 * 23];
        for t in frame.rows() {
            assert_eq!(t.height, 1, "a shard's row is a strip a pixel high");
            for x in t.x..t.x + t.width {
                by_rows[(t.y * 37 + x) as usize] = true;
            }
        }
        for t in frame.tiles() {
            for y in t.y..t.y + t.height {
                for x in t.x..t.x + t.width {
                    assert!(by_rows[(y * 37 + x) as usize], "rows and tiles cover the same pixels");
                    covered[(y * 37 + x) as usize] += 1;
                }
            }
        }
        assert_eq!(by_rows.iter().filter(|&&b| b).count() as u64, frame.pixels());
    }
    assert!(covered.iter().all(|&c| c == 1), "five shards cover every pixel once");
}

/// The EXR of a render, and of a merge, hold exactly the PFM's floats.
#[test]
fn exr_from_render_and_from_merge_round_trips_against_the_pfm() {
    let dir = scratch("exr");
    let (_, merged_pfm) = whole_and_merged(&dir, "three-spheres", 3, "8", &["steal"]);
    let common = ["--scene", "three-spheres", "--width", "61", "--depth", "10", "--tile", "8", "--spp", "3"];
    ok(raypool(&[&["render", "--out", "whole.exr"][..], &common].concat(), &dir));
    ok(raypool(&["merge", "--out", "merged.exr", "part-0.rpart", "part-1.rpart", "part-2.rpart"], &dir));
    let floats = |name: &str| {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        let exr =
            image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr).unwrap().to_rgb32f();
        exr.pixels().map(|p| p.0).collect::<Vec<[f32; 3]>>()
    };
    let (_, _, pfm) = raypool::files::output::read_pfm(&merged_pfm).unwrap();
    assert_eq!(floats("whole.exr"), pfm, "render --out .exr");
    assert_eq!(floats("merged.exr"), pfm, "merge --out .exr");
    let _ = std::fs::remove_dir_all(&dir);
}
