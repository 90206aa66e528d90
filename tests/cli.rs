//! The `raypool` command: good runs write complete files, bad input exits 2 with one line
//! and leaves no file behind.

mod deadline;

use std::path::Path;
use std::process::{Command, Output};

use deadline::{output_within, raypool, scratch};

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

const SMALL: &[&str] = &["--width", "24", "--spp", "2", "--depth", "8"];

fn render(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render"];
    args.extend_from_slice(SMALL);
    args.extend_from_slice(extra);
    raypool(&args, dir)
}

#[test]
fn render_writes_each_format_and_prints_a_summary() {
    let dir = scratch("formats");
    for name in ["a.png", "a.ppm", "a.pfm"] {
        let out = render(&dir, &["--scene", "paper1", "--out", name]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let summary = String::from_utf8_lossy(&out.stderr);
        assert!(summary.contains("24x16, 2 spp") && summary.contains("Mrays/s"), "{summary}");
    }
    assert_eq!(files_in(&dir), ["a.pfm", "a.png", "a.ppm"], "no temporary file left over");
    let png = image::open(dir.join("a.png")).unwrap();
    assert_eq!((png.width(), png.height()), (24, 16), "height follows the scene's 3:2 aspect");
}

#[test]
fn thread_count_and_mode_do_not_change_the_bytes() {
    let dir = scratch("threads");
    let mut files = Vec::new();
    let runs = [
        ("serial", "1"),
        ("static", "2"),
        ("interleaved", "3"),
        ("pool-rows", "2"),
        ("pool", "5"),
        ("steal", "4"),
    ];
    for (k, (mode, threads)) in runs.into_iter().enumerate() {
        let name = format!("{k}.pfm");
        let out = render(&dir, &["--mode", mode, "--threads", threads, "--out", &name]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        files.push(std::fs::read(dir.join(name)).unwrap());
    }
    assert!(files.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn printed_scene_renders_like_the_builtin() {
    let dir = scratch("roundtrip");
    let printed = raypool(&["scene", "final"], &dir);
    assert!(printed.status.success());
    std::fs::write(dir.join("final.toml"), &printed.stdout).unwrap();
    let a = render(&dir, &["--scene", "final", "--out", "builtin.pfm"]);
    let b = render(&dir, &["--scene-file", "final.toml", "--out", "file.pfm"]);
    assert!(a.status.success() && b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    assert!(std::fs::read(dir.join("builtin.pfm")).unwrap() == std::fs::read(dir.join("file.pfm")).unwrap());
}

#[test]
fn scenes_lists_every_builtin() {
    let out = raypool(&["scenes"], &std::env::temp_dir());
    let text = String::from_utf8(out.stdout).unwrap();
    for name in ["final", "paper1", "paper2", "paper3", "three-spheres", "furnace"] {
        assert!(text.lines().any(|l| l.starts_with(name)), "{name} missing from:\n{text}");
    }
}

/// Asserts exit code 2, a one-line message containing `needle`, and an untouched directory.
fn assert_rejected(dir: &Path, args: &[&str], needle: &str) {
    let before = files_in(dir);
    let out = raypool(args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?} → {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: not one line:\n{stderr}");
    assert!(stderr.contains(needle), "{args:?}: '{needle}' not in: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "{stderr}");
    assert_eq!(files_in(dir), before, "{args:?} left a file behind");
}

#[test]
fn bad_flags_exit_2_with_one_line() {
    let dir = scratch("flags");
    let r = |extra: &[&str], needle: &str| {
        let mut args = vec!["render", "--out", "x.png"];
        args.extend_from_slice(extra);
        assert_rejected(&dir, &args, needle);
    };
    r(&["--width", "0"], "--width");
    r(&["--width", "16385"], "--width");
    r(&["--height", "0"], "--height");
    r(&["--spp", "0"], "--spp");
    r(&["--depth", "0"], "--depth");
    r(&["--threads", "0"], "--threads");
    r(&["--width", "ten"], "--width");
    r(&["--mode", "turbo"], "turbo");
    r(&["--tile", "0"], "--tile");
    r(&["--rng", "global"], "global");
    r(&["--scene", "nosuch"], "unknown scene 'nosuch'");
    r(&["--scene", "final", "--scene-file", "a.toml"], "--scene-file");
    r(&["--frobnicate"], "--frobnicate");
    r(&["--target-error", "0"], "--target-error");
    r(&["--target-error", "-1"], "--target-error");
    r(&["--target-error", "much"], "--target-error");
    r(&["--target-error", "0.1", "--spp", "8"], "--spp");
    r(&["--min-spp", "4"], "--target-error");
    r(&["--target-error", "0.1", "--min-spp", "64", "--max-spp", "8"], "--min-spp 64 is above --max-spp 8");
    r(&["--guiding", "on", "--light-sampling", "bdpt"], "use mis or bsdf");
    r(&["--guiding", "on", "--light-sampling", "mixture"], "use mis or bsdf");
    r(&["--guiding", "on", "--target-error", "0.1"], "use one or the other");
    r(&["--guide-pilot", "4"], "--guiding on");
    r(&["--guiding", "maybe"], "maybe");
    assert_rejected(&dir, &["scene", "nosuch"], "unknown scene");
    assert_rejected(&dir, &["paint"], "paint");
    assert_rejected(&dir, &["bench", "--threads", "1,0"], "'0' is not a count of at least 1");
    assert_rejected(&dir, &["bench", "--threads", "2", "--paper"], "--paper");
    assert_rejected(&dir, &["grade", "--threads", "2"], "--mode");
    assert_rejected(&dir, &["grade", "--mode", "steal", "--discipline", "locked"], "--discipline");
    assert_rejected(&dir, &["grade", "--discipline", "lifo"], "lifo");
    assert_rejected(&dir, &["grade", "--mode", "steal", "--threads", "two"], "'two' is not a count");
    assert_rejected(
        &dir,
        &["grade", "--mode", "steal", "--pass", "101"],
        "'101' is not a score from 0 to 100",
    );
}

#[test]
fn bad_outputs_exit_2_and_leave_no_file() {
    let dir = scratch("outputs");
    let r =
        |out: &str, needle: &str| assert_rejected(&dir, &["render", "--width", "8", "--out", out], needle);
    r("picture.jpg", "picture.jpg");
    r("picture", ".png, .ppm, .pfm, .exr or .rpart");
    r("no/such/dir/x.png", "no/such/dir/x.png");
    std::fs::create_dir(dir.join("taken.png")).unwrap();
    let before = files_in(&dir);
    let out = raypool(&["render", "--width", "8", "--spp", "1", "--out", "taken.png"], &dir);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(files_in(&dir), before, "the failed rename left its temporary file");
}

#[test]
fn bad_scene_files_exit_2_with_location() {
    let dir = scratch("scenes");
    let good = String::from_utf8(raypool(&["scene", "paper1"], &dir).stdout).unwrap();
    let cases = [
        ("syntax.toml", good.replacen("radius = 100.0", "radius = = 100.0", 1), "syntax.toml:"),
        ("kind.toml", good.replacen("\"metal\"", "\"chrome\"", 1), "chrome"),
        ("nan.toml", good.replacen("radius = 100.0", "radius = nan", 1), "radius"),
        ("zero.toml", good.replacen("radius = 100.0", "radius = 0.0", 1), "radius"),
        ("extra.toml", good.replacen("[camera]", "[camera]\nzoom = 3.0", 1), "zoom"),
    ];
    for (name, text, needle) in cases {
        assert_ne!(text, good, "{name}: the test's edit did not apply");
        std::fs::write(dir.join(name), text).unwrap();
        assert_rejected(&dir, &["render", "--scene-file", name, "--out", "x.png"], needle);
    }
    assert_rejected(&dir, &["render", "--scene-file", "missing.toml", "--out", "x.png"], "missing.toml");
}

#[test]
fn every_accel_gives_the_same_bytes() {
    let dir = scratch("accel");
    let mut files = Vec::new();
    for accel in ["auto", "flat", "binary", "wide", "wide-packets", "wide-huge-apart"] {
        let name = format!("{accel}.pfm");
        let out = render(&dir, &["--scene", "paper3", "--accel", accel, "--out", &name]);
        assert!(out.status.success(), "{accel}: {}", String::from_utf8_lossy(&out.stderr));
        files.push((accel, std::fs::read(dir.join(&name)).unwrap()));
    }
    for (accel, bytes) in &files[1..] {
        assert!(*bytes == files[0].1, "--accel {accel} changed the image");
    }
}

#[test]
fn oversized_and_endless_scene_files_are_refused_without_reading_them_whole() {
    let dir = scratch("big-scenes");
    let limit = raypool::scenes::format::MAX_SCENE_FILE_BYTES;
    // A sparse file one byte over the bound: refused by size, not by its (zero) bytes.
    std::fs::File::create(dir.join("huge.toml")).unwrap().set_len(limit + 1).unwrap();
    assert_rejected(&dir, &["render", "--scene-file", "huge.toml", "--out", "x.png"], "larger than 16 MiB");
    // Endless: reading it whole would run until the process is killed for memory.
    assert_rejected(&dir, &["render", "--scene-file", "/dev/zero", "--out", "x.png"], "larger than 16 MiB");
    std::fs::write(dir.join("binary.toml"), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    assert_rejected(&dir, &["render", "--scene-file", "binary.toml", "--out", "x.png"], "not UTF-8");
    // A scene just under the bound, padded with a TOML comment, is still read.
    let mut padded = raypool(&["scene", "paper1"], &dir).stdout;
    padded.extend(b"\n#");
    padded.resize(limit as usize - 1, b'x');
    padded.push(b'\n');
    std::fs::write(dir.join("padded.toml"), padded).unwrap();
    let out = render(&dir, &["--scene-file", "padded.toml", "--out", "padded.png"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn compare_reports_error_figures_and_writes_a_difference_map() {
    let dir = scratch("compare");
    for (name, spp) in [("noisy.pfm", "2"), ("ref.pfm", "32")] {
        let out =
            raypool(&["render", "--scene", "paper1", "--width", "30", "--spp", spp, "--out", name], &dir);
        assert!(out.status.success());
    }
    let same = raypool(&["compare", "ref.pfm", "ref.pfm"], &dir);
    let text = String::from_utf8_lossy(&same.stdout);
    assert!(text.contains("rmse 0.000000") && text.contains("psnr inf"), "{text}");
    let noisy = raypool(&["compare", "noisy.pfm", "ref.pfm", "--diff", "diff.png"], &dir);
    let text = String::from_utf8_lossy(&noisy.stdout);
    let rmse: f64 = text.split_whitespace().nth(1).and_then(|v| v.parse().ok()).expect("rmse printed");
    assert!(rmse > 0.001 && rmse < 0.5, "2 spp against 32 spp: {text}");
    let diff = image::open(dir.join("diff.png")).expect("a PNG difference map");
    assert_eq!((diff.width(), diff.height()), (30, 20));
}

#[test]
fn compare_rejects_bad_inputs() {
    let dir = scratch("compare-bad");
    for (name, width) in [("a.pfm", "30"), ("b.pfm", "20")] {
        assert!(
            raypool(&["render", "--width", width, "--spp", "1", "--depth", "2", "--out", name], &dir)
                .status
                .success()
        );
    }
    std::fs::write(dir.join("text.pfm"), "not an image").unwrap();
    assert_rejected(&dir, &["compare", "a.pfm", "b.pfm"], "sizes differ");
    assert_rejected(&dir, &["compare", "a.pfm", "missing.pfm"], "missing.pfm");
    assert_rejected(&dir, &["compare", "a.pfm", "text.pfm"], "not a PFM image");
    assert_rejected(&dir, &["compare", "a.pfm", "a.pfm", "--diff", "no/dir/d.png"], "no/dir/d.png");
}

#[test]
fn raypool_alone_prints_the_usage_and_the_subcommands() {
    let dir = scratch("alone");
    let out = raypool(&[], &dir);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("Usage: raypool <COMMAND>"), "{stderr}");
    for command in ["render", "merge", "simulate", "view", "bench"] {
        assert!(stderr.contains(&format!("  {command} ")), "{command} missing from {stderr}");
    }
    assert!(out.stdout.is_empty());
}

#[test]
fn a_light_turned_away_from_everything_is_warned_of() {
    let dir = scratch("turned");
    let scene = |lamp_u: &str, lamp_v: &str| {
        format!(
            "[camera]\nlookfrom = [0.0, 1.0, 4.0]\nlookat = [0.0, 0.0, 0.0]\nvup = [0.0, 1.0, 0.0]\nvfov = 40.0\n\
             [background]\nkind = \"black\"\n[materials]\n\
             grey = {{ kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }}\n\
             lamp = {{ kind = \"diffuse_light\", emit = [4.0, 4.0, 4.0] }}\n\
             [[quad]]\nq = [-2.0, 0.0, -2.0]\nu = [4.0, 0.0, 0.0]\nv = [0.0, 0.0, 4.0]\nmaterial = \"grey\"\n\
             [[quad]]\nq = [-0.5, 2.0, -0.5]\nu = {lamp_u}\nv = {lamp_v}\nmaterial = \"lamp\"\n"
        )
    };
    // u × v up: the lamp faces the sky; down: the floor.
    for (name, u, v, warned) in [
        ("away", "[0.0, 0.0, 1.0]", "[1.0, 0.0, 0.0]", true),
        ("down", "[1.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]", false),
    ] {
        std::fs::write(dir.join(format!("{name}.toml")), scene(u, v)).unwrap();
        let out = render(&dir, &["--scene-file", &format!("{name}.toml"), "--out", &format!("{name}.png")]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(stderr.contains("warning: every pixel is black"), warned, "{name}: {stderr}");
    }
}

/// The flags `raypool help SUBCOMMAND` lists (`--help` and `--version` aside): clap indents an
/// option's line by six spaces at most, its description by ten.
fn flags_of(help: &str) -> Vec<String> {
    let indented = |line: &&str| line.len() - line.trim_start().len() <= 6;
    let options = help.lines().filter(indented).map(str::trim_start).filter(|line| line.starts_with('-'));
    let words = options.flat_map(|line| line.split_whitespace().take(2));
    let flags = words.map(|w| w.trim_end_matches(',')).filter(|w| w.starts_with("--"));
    flags.filter(|f| !matches!(*f, "--help" | "--version")).map(str::to_owned).collect()
}

/// Whether `text` names `flag` itself (`--out`, not only `--out-dir`).
fn names(text: &str, flag: &str) -> bool {
    text.match_indices(flag).any(|(at, _)| {
        let next = text[at + flag.len()..].chars().next();
        !next.is_some_and(|c| c.is_ascii_alphanumeric() || c == '-')
    })
}

#[test]
fn the_command_line_chapter_names_every_flag() {
    // The README sends a user there for "every flag"; the binary's help is what exists.
    let chapter = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/command-line.md");
    let chapter = std::fs::read_to_string(chapter).unwrap();
    let dir = scratch("flags");
    let mut missing = Vec::new();
    for command in ["render", "merge", "view", "simulate", "scenes", "scene", "bench", "grade", "compare"] {
        let help = raypool(&["help", command], &dir);
        assert!(help.status.success(), "`raypool help {command}` failed");
        let flags = flags_of(&String::from_utf8_lossy(&help.stdout));
        missing.extend(flags.iter().filter(|f| !names(&chapter, f)).map(|f| format!("{command} {f}")));
    }
    let sample = "  -h, --help\n      --out <OUT>\n          --not-a-flag in a description\n";
    assert_eq!(flags_of(sample), ["--out"], "an option line is read, a description is not");
    assert!(missing.is_empty(), "docs/src/command-line.md does not name: {missing:?}");
}

#[test]
fn an_interrupted_render_leaves_no_file_and_exits_130_or_143() {
    for (signal, code) in [("INT", 130), ("TERM", 143)] {
        let dir = scratch(&format!("signal-{signal}"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_raypool"))
            .args(["render", "--scene", "final", "--width", "300", "--spp", "2000", "--out", "k.png"])
            .current_dir(&dir)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until the render has reserved its output (a temporary file beside it).
        let start = std::time::Instant::now();
        while !files_in(&dir).iter().any(|f| f.ends_with(".tmp")) {
            assert!(start.elapsed().as_secs() < 60, "the render never created its temporary file");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let pid = child.id().to_string();
        assert!(
            output_within(Command::new("kill").args([&format!("-{signal}"), &pid]), "`kill` to exit")
                .status
                .success()
        );
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            assert!(start.elapsed().as_secs() < 120, "SIG{signal}: the render never stopped");
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        let mut stderr = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
        assert_eq!(status.code(), Some(code), "SIG{signal}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr:?}");
        assert!(stderr.contains(&format!("interrupted by SIG{signal}")), "{stderr}");
        assert!(files_in(&dir).is_empty(), "SIG{signal} left {:?}", files_in(&dir));
    }
}

/// `raypool render …` run by `sh` under `ulimit -v 1500000` (1.5 GB of address space).
fn render_under_memory_limit(dir: &Path, args: &str) -> Output {
    let script = format!("ulimit -v 1500000 && exec '{}' render {args}", env!("CARGO_BIN_EXE_raypool"));
    output_within(
        Command::new("sh").args(["-c", &script]).current_dir(dir),
        "a render under ulimit -v to exit",
    )
}

#[test]
fn a_render_too_big_for_the_memory_limit_is_refused_before_it_starts() {
    let dir = scratch("memory");
    for (args, advice) in [
        ("--width 16384 --height 16384 --out big.png", "render fewer pixels (--width, --height)"),
        ("--width 8192 --height 8192 --target-error 0.1 --out big.pfm", "without --target-error"),
        ("--width 16384 --height 16384 --shard 1/4 --out big.rpart", "render fewer pixels"),
    ] {
        let out = render_under_memory_limit(&dir, args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args}: one line: {stderr}");
        assert!(stderr.contains("of memory, more than the") && stderr.contains("(ulimit -v)"), "{stderr}");
        assert!(stderr.contains(advice), "{args}: {stderr}");
        assert!(files_in(&dir).is_empty(), "{args}: nothing written, not even a temporary file");
    }
    let small = render_under_memory_limit(&dir, "--width 64 --spp 1 --out small.png");
    assert!(small.status.success(), "a small render fits: {}", String::from_utf8_lossy(&small.stderr));
    assert_eq!(files_in(&dir), ["small.png"]);
}

#[test]
fn grade_writes_its_report_and_prints_it() {
    let dir = scratch("grade");
    let out = raypool(
        &["grade", "--mode", "interleaved", "--threads", "2", "--rounds", "1", "--out", "g.md"],
        &dir,
    );
    // 0: passed; 3: the machine (busy with other tests) was too busy to judge, and said so.
    let code = out.status.code();
    assert!(matches!(code, Some(0 | 3)), "exit {code:?}: {}", String::from_utf8_lossy(&out.stderr));
    let report = std::fs::read_to_string(dir.join("g.md")).unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim_end(), report.trim_end(), "printed as written");
    assert!(report.starts_with("# Grade: mode interleaved") && report.contains("Machine: nproc"), "{report}");
    assert!(report.contains("Conformance: **passed** at [2] threads"), "{report}");
    if code == Some(3) {
        assert!(report.contains("**incomplete**") && report.contains("too busy to judge"), "{report}");
    }
    for workload in ["balanced", "one-band", "heavy-tail", "tiny-tiles", "many-frames", "smoke-room"] {
        assert!(report.contains(&format!("| {workload} |")), "{workload} missing: {report}");
    }
    assert_eq!(files_in(&dir), ["g.md"], "no temporary file left over");
}

#[test]
fn a_reader_that_stops_early_ends_the_output_quietly() {
    // `head` closes the pipe after 10 bytes of the 120 KB scene: more than a pipe's buffer
    // stays unwritten, so raypool's next write meets a closed pipe.
    let dir = scratch("pipe");
    let script = r#"set -o pipefail; "$0" scene next-week | head -c 10 > /dev/null"#;
    let bin = env!("CARGO_BIN_EXE_raypool");
    let out = output_within(
        Command::new("bash").args(["-c", script, bin]).current_dir(&dir),
        "`raypool scene | head` to exit",
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && stderr.is_empty(), "status {:?}, stderr: {stderr}", out.status);
}
