//! The documents cannot rot: the README, the book (`docs/src/`) and `results/README.md`.
//!
//! - Every relative link (and image) points at a file or folder that exists, and every
//!   `#anchor` into a Markdown file at one of its headings.
//! - Every `raypool` command in a shell block (```` ```sh ````, ```` ```console ````) of the
//!   README or the book is run here, in the order written, in a temporary folder, at a small
//!   size (`--width 48 --spp 1`), under a deadline, unless [`RUN_ELSEWHERE`] names it with the
//!   test or script that runs it instead. `cargo run --release --` counts as `raypool`.
//! - Every ```` ```toml ```` block of the scene-format chapter is a scene that renders,
//!   beside the chapter's ```` ```obj ```` files; except a ```` ```toml,refused ```` block, which
//!   must be refused (exit code 2) with exactly the one line of the ```` ```text ```` block
//!   after it.
//! - Every chapter is in `SUMMARY.md`, and every chapter with Rust in it is included into
//!   `src/lib.rs`, so `cargo test --doc` runs its Rust.
//!
//! Run it alone with `cargo test --release --test docs`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Commands of the README and the book that this test does not run, each with what runs it.
const RUN_ELSEWHERE: &[(&str, &str)] = &[
    (
        "raypool view --scene final --threads 2 --spp 256",
        "serves until stopped: tests/view.rs and tests/browser.rs start `raypool view` and drive it",
    ),
    ("raypool bench --quick", "takes minutes: benches/all.sh --quick runs it; tests/cli.rs checks its flags"),
];

/// How long one command of the book may take at its small size.
const DEADLINE: Duration = Duration::from_secs(20);

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The book's chapters, sorted.
fn chapters() -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(root().join("docs/src"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    found.sort();
    found
}

/// Every document whose links are checked.
fn documents() -> Vec<PathBuf> {
    [root().join("README.md"), root().join("results/README.md")].into_iter().chain(chapters()).collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn shown(path: &Path) -> String {
    path.strip_prefix(root()).unwrap_or(path).display().to_string()
}

/// A fenced code block: its language (the info string's first word), its whole info string
/// (`toml,refused`) and its lines, each with its line number in the file.
struct Block {
    lang: String,
    info: String,
    lines: Vec<(usize, String)>,
}

/// The fenced blocks of `text`, and the lines outside them (with their numbers).
fn split(text: &str) -> (Vec<Block>, Vec<(usize, &str)>) {
    let (mut blocks, mut prose) = (Vec::new(), Vec::new());
    let mut open: Option<(String, Block)> = None;
    for (n, line) in text.lines().enumerate().map(|(i, l)| (i + 1, l)) {
        let trimmed = line.trim_start();
        match open.take() {
            None if trimmed.starts_with("```") => {
                let fence: String = trimmed.chars().take_while(|c| *c == '`').collect();
                let info = trimmed[fence.len()..].trim();
                let lang = info.split([',', ' ']).next().unwrap_or("").to_owned();
                open = Some((fence, Block { lang, info: info.to_owned(), lines: Vec::new() }));
            }
            None => prose.push((n, line)),
            Some((fence, block)) if trimmed.starts_with(&fence) && trimmed.trim_matches('`').is_empty() => {
                blocks.push(block)
            }
            Some((fence, mut block)) => {
                block.lines.push((n, trimmed.to_owned()));
                open = Some((fence, block));
            }
        }
    }
    (blocks, prose)
}

/// A heading's anchor, as mdBook and GitHub make it: lower case, spaces to `-`, only
/// letters, digits, `-` and `_` kept.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(path: &Path) -> Vec<String> {
    let text = read(path);
    let (_, prose) = split(&text);
    prose
        .iter()
        .filter_map(|(_, line)| line.strip_prefix('#'))
        .map(|h| slug(h.trim_start_matches('#')))
        .collect()
}

/// The targets of the inline links and images of one line of prose (inline code left out).
fn link_targets(line: &str) -> Vec<String> {
    let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
    prose
        .match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &prose[at + 2..];
            rest.find(')').map(|end| rest[..end].trim().to_owned())
        })
        .collect()
}

#[test]
fn every_relative_link_points_at_something_that_exists() {
    let mut broken = Vec::new();
    for doc in documents() {
        let text = read(&doc);
        for (n, line) in split(&text).1 {
            for target in link_targets(line) {
                if target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                let (file, anchor) = target.split_once('#').unwrap_or((&target, ""));
                let path = if file.is_empty() { doc.clone() } else { doc.parent().unwrap().join(file) };
                if !path.exists() {
                    broken.push(format!("{}:{n}: {target}: no such file", shown(&doc)));
                } else if !anchor.is_empty()
                    && path.extension().is_some_and(|e| e == "md")
                    && !anchors(&path).iter().any(|a| a == anchor)
                {
                    broken.push(format!("{}:{n}: {target}: no heading with that anchor", shown(&doc)));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_link_checker_sees_links_and_anchors() {
    let line = "See [the pool](pool.md#break-it), ![a](../x.png) and `[not](a link)`.";
    assert_eq!(link_targets(line), ["pool.md#break-it", "../x.png"]);
    assert_eq!(slug(" Finding the lights: `--light-sampling`"), "finding-the-lights---light-sampling");
    let (blocks, prose) = split("a\n  ```sh\n  raypool scenes\n  ```\nb\n");
    assert_eq!((blocks.len(), blocks[0].lang.as_str(), prose.len()), (1, "sh", 2));
    assert_eq!(blocks[0].lines, [(3, "raypool scenes".to_owned())]);
}

/// The shell commands of a document's `sh` and `console` blocks that call raypool, as
/// written (continuation lines joined, prompts and comments taken off, `cargo run --release
/// --` written `raypool`), with their line numbers.
fn raypool_commands(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for block in split(text).0 {
        let console = block.lang == "console";
        if !matches!(block.lang.as_str(), "sh" | "console" | "bash" | "shell") {
            continue;
        }
        let mut pending: Option<(usize, String)> = None;
        for (n, line) in block.lines {
            let (start, mut command) = match pending.take() {
                Some((start, before)) => (start, before + " " + line.trim()),
                None if console => match line.strip_prefix("$ ") {
                    Some(command) => (n, command.to_owned()),
                    None => continue,
                },
                None => (n, line.clone()),
            };
            if let Some(joined) = command.strip_suffix('\\') {
                pending = Some((start, joined.trim_end().to_owned()));
                continue;
            }
            if let Some(at) = command.find(" #").or(command.starts_with('#').then_some(0)) {
                command.truncate(at);
            }
            let command = command.trim().replace("cargo run --release -- ", "raypool ");
            if command.split_whitespace().any(|word| word == "raypool") {
                found.push((start, command));
            }
        }
    }
    found
}

/// `command` made small: sizes and sample counts cut down, and a size and a sample count given
/// to `render` and `simulate` where the book leaves the defaults.
fn small(command: &str) -> String {
    let words: Vec<&str> = command.split_whitespace().collect();
    let mut out: Vec<String> = Vec::new();
    for (i, word) in words.iter().enumerate() {
        let after = |flag: &str| i > 0 && words[i - 1] == flag;
        out.push(match () {
            _ if after("--width") => "48".to_owned(),
            _ if after("--height") => "32".to_owned(),
            _ if after("--spp") => "1".to_owned(),
            _ if after("--min-spp") => "2".to_owned(),
            _ if after("--max-spp") => "8".to_owned(),
            _ if after("--runs") => "1".to_owned(),
            _ => word.to_string(),
        });
        let renders = matches!(*word, "render" | "simulate") && i > 0 && words[i - 1] == "raypool";
        if renders {
            if !words.contains(&"--width") {
                out.extend(["--width".to_owned(), "48".to_owned()]);
            }
            if !words.contains(&"--spp") && !words.contains(&"--target-error") {
                out.extend(["--spp".to_owned(), "1".to_owned()]);
            }
            if words.contains(&"--target-error") && !words.contains(&"--max-spp") {
                out.extend(["--min-spp", "2", "--max-spp", "8"].map(String::from));
            }
        }
    }
    out.join(" ")
}

/// A fresh temporary folder for `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raypool-docs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `program` in `dir` (stdout and stderr to files there) and waits at most
/// [`DEADLINE`]; the reason if it failed or ran out of time.
fn run(mut program: Command, dir: &Path) -> Result<(), String> {
    let out = std::fs::File::create(dir.join(".stdout")).unwrap();
    let err = std::fs::File::create(dir.join(".stderr")).unwrap();
    let mut child = program
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let stderr = std::fs::read_to_string(dir.join(".stderr")).unwrap_or_default();
            return if status.success() { Ok(()) } else { Err(format!("{status}: {}", stderr.trim())) };
        }
        if start.elapsed() > DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {} s", DEADLINE.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn every_raypool_command_of_the_readme_and_the_book_runs_or_is_run_elsewhere() {
    let binary = PathBuf::from(env!("CARGO_BIN_EXE_raypool"));
    let path = std::env::join_paths(
        std::iter::once(binary.parent().unwrap().to_path_buf())
            .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let mut failed = Vec::new();
    let mut seen = Vec::new();
    for doc in [root().join("README.md")].into_iter().chain(chapters()) {
        let name = doc.file_stem().unwrap().to_string_lossy().into_owned();
        let dir = scratch(&name);
        for (n, command) in raypool_commands(&read(&doc)) {
            seen.push(command.clone());
            if RUN_ELSEWHERE.iter().any(|(listed, _)| *listed == command) {
                continue;
            }
            let small = small(&command);
            let mut shell = Command::new("sh");
            shell.args(["-c", &small]).env("PATH", &path);
            if let Err(why) = run(shell, &dir) {
                failed.push(format!(
                    "{}:{n}: `{command}` (run as `{small}`): {why}\n  (if it cannot run here, list it in RUN_ELSEWHERE with what runs it)",
                    shown(&doc)
                ));
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        seen.len() >= 8,
        "only {} raypool commands found in the documents: is the parser blind?",
        seen.len()
    );
    let stale: Vec<_> =
        RUN_ELSEWHERE.iter().filter(|(listed, _)| !seen.iter().any(|c| c == listed)).collect();
    assert!(stale.is_empty(), "RUN_ELSEWHERE lists commands no document has: {stale:?}");
    assert!(failed.is_empty(), "commands of the documents that fail:\n{}", failed.join("\n"));
}

#[test]
fn commands_are_found_and_made_small() {
    let text = "```console\n$ raypool render --scene final \\\n    --spp 500   # long\nnot a command\n```\n\
                ```sh\ncargo run --release -- scenes\nexport RAYPOOL=target/release/raypool\n```\n";
    let found = raypool_commands(text);
    assert_eq!(
        found,
        [(2, "raypool render --scene final --spp 500".to_owned()), (7, "raypool scenes".to_owned())]
    );
    assert_eq!(small(&found[0].1), "raypool render --width 48 --scene final --spp 1");
    assert_eq!(
        small("for k in 0 1; do raypool render --target-error 0.1 --out p-$k.rpart; done"),
        "for k in 0 1; do raypool render --width 48 --min-spp 2 --max-spp 8 --target-error 0.1 --out p-$k.rpart; done"
    );
}

#[test]
fn every_scene_of_the_scene_format_chapter_renders_or_is_refused_as_it_says() {
    let chapter = root().join("docs/src/scene-format.md");
    let dir = scratch("scenes");
    let blocks = split(&read(&chapter)).0;
    for obj in blocks.iter().filter(|b| b.lang == "obj") {
        let name = obj.lines[0].1.trim_start_matches('#').split(':').next().unwrap().trim().to_owned();
        let body: String = obj.lines.iter().map(|(_, l)| format!("{l}\n")).collect();
        std::fs::write(dir.join(name), body).unwrap();
    }
    let (mut rendered, mut refused) = (0, 0);
    for (k, scene) in blocks.iter().enumerate().filter(|(_, b)| b.lang == "toml") {
        let at = format!("the scene at docs/src/scene-format.md:{}", scene.lines[0].0);
        let body: String = scene.lines.iter().map(|(_, l)| format!("{l}\n")).collect();
        std::fs::write(dir.join("scene.toml"), body).unwrap();
        let mut render = Command::new(env!("CARGO_BIN_EXE_raypool"));
        render.args(["render", "--scene-file", "scene.toml", "--width", "48", "--spp", "1"]);
        render.args(["--out", "scene.png"]);
        let outcome = run(render, &dir);
        if !scene.info.split(',').any(|word| word.trim() == "refused") {
            outcome.unwrap_or_else(|why| panic!("{at}: {why}"));
            rendered += 1;
            continue;
        }
        // The chapter shows what raypool says, in the `text` block right after the scene.
        let said = blocks.get(k + 1).filter(|b| b.lang == "text" && b.lines.len() == 1);
        let said =
            said.unwrap_or_else(|| panic!("{at}: follow it with a ```text block of its one-line error"));
        let stderr = std::fs::read_to_string(dir.join(".stderr")).unwrap();
        assert!(outcome.is_err_and(|why| why.contains("exit status: 2")), "{at}: not refused with code 2");
        assert_eq!(stderr.trim_end(), said.lines[0].1, "{at}: the chapter quotes another message");
        refused += 1;
    }
    assert!(
        rendered >= 4 && refused >= 1,
        "{rendered} scenes and {refused} refusals found: is the parser blind?"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_chapter_is_in_the_summary_and_its_rust_is_doc_tested() {
    let summary = read(&root().join("docs/src/SUMMARY.md"));
    let lib = read(&root().join("src/lib.rs"));
    for chapter in chapters() {
        let name = chapter.file_name().unwrap().to_string_lossy().into_owned();
        if name == "SUMMARY.md" {
            continue;
        }
        assert!(summary.contains(&format!("({name})")), "docs/src/SUMMARY.md does not list {name}");
        let rust = split(&read(&chapter)).0.iter().any(|b| b.lang == "rust");
        let included = lib.contains(&format!("include_str!(\"../docs/src/{name}\")"));
        assert!(
            !rust || included,
            "docs/src/{name} has Rust: include it in src/lib.rs (#[doc = include_str!(\"../docs/src/{name}\")]) so that cargo test --doc runs it"
        );
    }
}

/// The modes as `--mode` takes them, from the `Schedule` enum itself.
fn mode_names() -> Vec<String> {
    use clap::ValueEnum;
    raypool::schedule::modes::Schedule::value_variants()
        .iter()
        .filter_map(|mode| mode.to_possible_value())
        .map(|value| value.get_name().to_owned())
        .collect()
}

/// The lists of schedulers the book writes by hand cannot go stale: the course's table and the
/// command line's `--mode` row name exactly the modes `Schedule` has, in its order, and every
/// "N schedulers" or "N modes" in the README and the book counts them.
#[test]
fn the_books_lists_of_schedulers_are_the_modes_raypool_has() {
    let modes = mode_names();
    let course = read(&root().join("docs/src/course.md"));
    let section =
        course.split("\n## ").find(|s| s.contains("schedulers\n")).expect("the course's scheduler section");
    let rows: Vec<&str> = section
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .filter(|name| !name.starts_with("--"))
        .collect();
    assert_eq!(rows, modes, "docs/src/course.md's scheduler table against `Schedule`'s modes");
    let options = read(&root().join("docs/src/command-line.md"));
    let row = options.lines().find(|l| l.starts_with("| `--mode")).expect("command-line.md's --mode row");
    let listed: Vec<&str> = row
        .split(" | ")
        .nth(2)
        .unwrap_or("")
        .split('(')
        .next()
        .unwrap_or("")
        .split('`')
        .skip(1)
        .step_by(2)
        .collect();
    assert_eq!(listed, modes, "docs/src/command-line.md's --mode row against `Schedule`'s modes");
    let words = [
        "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
        "twelve",
    ];
    let count = words[modes.len()];
    for path in documents() {
        let text = read(&path).to_lowercase().replace('\n', " ");
        for (k, word) in words.iter().enumerate().filter(|&(k, _)| k != modes.len()) {
            for what in ["schedulers", "modes"] {
                assert!(
                    !text.contains(&format!(" {word} {what}")),
                    "{} says \"{word} {what}\" ({k}); raypool has {count}",
                    shown(&path)
                );
            }
        }
    }
}
