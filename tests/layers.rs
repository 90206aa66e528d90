//! The source tree shows the architecture: `src/` holds the top-level files and one folder per
//! layer, a module uses only its own folder and the layers below it, the tracer's rooms use
//! only the rooms before them, the viewer uses only the command line's flags and settings (not
//! its commands), no two modules of either crate import each other, directly or through
//! others, and no `.rs` file under `src/`, `pool/`, `tests/` or `benches/` grows past what a
//! student reads in one sitting.
//!
//! Run it alone with `cargo test --release --test layers`. It reads `src/` and `pool/src/` as
//! text: every `crate::a::b::…` path outside comments is an edge from the file that writes it
//! to the longest module it names. (`super::` is written only inside a file's own inner
//! modules, its tests and loom models, so it names the file itself: no edge.)

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers, lowest first. A module may use its own folder and any folder of a lower rank.
/// `scenes` and `files` share a rank, as do `schedule` and `denoise`: neither may use the other.
const LAYERS: &[(&str, u32)] = &[
    ("error", 0),
    ("tracer", 1),
    ("scenes", 2),
    ("files", 2),
    ("schedule", 3),
    ("denoise", 3),
    ("measure", 4),
    ("cli", 5),
    ("view", 6),
];

/// The tracer's rooms in reading order (`src/tracer/mod.rs`): a room may use itself and the
/// rooms before it, never one after it.
const TRACER_ROOMS: &[&str] = &[
    "math", "sampling", "geometry", "shading", "accel", "world", "lights", "camera", "scene", "lighting",
    "guiding", "splats", "bidir", "tile", "render",
];

/// The only modules of the command line that the viewer may reach, directly or through them:
/// the flags and what they resolve to, never `cli` itself or a command's file.
const CLI_FOR_THE_VIEWER: &[&str] = &["cli::args", "cli::settings", "cli::transport"];

/// The only files that may sit directly in `src/` (besides the layer folders).
const TOP_FILES: &[&str] = &["lib.rs", "main.rs", "error.rs"];

/// The most lines a `.rs` file under [`CAPPED`] may have: one sitting's reading.
const MAX_LINES: usize = 450;

fn rank(layer: &str) -> u32 {
    LAYERS.iter().find(|(name, _)| *name == layer).unwrap_or_else(|| panic!("'{layer}' is not a layer")).1
}

fn root(crate_src: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(crate_src)
}

/// Every `.rs` file under `dir`, with its module path (`tracer::sampling::sobol`; a folder's
/// `mod.rs` is the folder's module), `lib.rs` and `main.rs` left out.
fn files(dir: &Path, prefix: &[String], out: &mut BTreeMap<String, PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            files(&path, &[prefix, &[name]].concat(), out);
        } else if let Some(stem) = name.strip_suffix(".rs") {
            let module = match stem {
                "lib" | "main" if prefix.is_empty() => continue,
                "mod" => prefix.join("::"),
                _ => [prefix, &[stem.to_owned()]].concat().join("::"),
            };
            out.insert(module, path);
        }
    }
}

/// Module path → source text, for every module of the crate whose sources are in `crate_src`.
fn modules_of(crate_src: &str) -> BTreeMap<String, String> {
    let mut paths = BTreeMap::new();
    files(&root(crate_src), &[], &mut paths);
    paths.into_iter().map(|(module, path)| (module, std::fs::read_to_string(path).unwrap())).collect()
}

fn modules() -> BTreeMap<String, String> {
    modules_of("src")
}

/// The modules that `module`'s code (not its comments) names.
fn uses(module: &str, text: &str, all: &BTreeMap<String, String>) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap();
        assert!(
            !code.contains("crate::{"),
            "{module}: write one `use` per module, not `crate::{{…}}`: {line}"
        );
        for (at, _) in code.match_indices("crate::") {
            let path: Vec<&str> = code[at + "crate::".len()..]
                .split("::")
                .map(|part| part.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap())
                .collect();
            // The longest prefix of the path that is a module.
            let target = (1..=path.len())
                .rev()
                .map(|n| path[..n].join("::"))
                .find(|candidate| all.contains_key(candidate))
                .unwrap_or_else(|| panic!("{module}: cannot resolve '{line}'"));
            if target != module {
                found.insert(target);
            }
        }
    }
    found
}

fn layer(module: &str) -> &str {
    module.split("::").next().unwrap()
}

/// The rank of a tracer module's room (`tracer::sampling::sobol` → 1), if it is in one.
fn room(module: &str) -> Option<usize> {
    let name = module.strip_prefix("tracer::")?.split("::").next()?;
    Some(
        TRACER_ROOMS
            .iter()
            .position(|r| *r == name)
            .unwrap_or_else(|| panic!("'{name}' is not a tracer room")),
    )
}

#[test]
fn src_holds_only_the_top_files_and_the_layer_folders() {
    for entry in std::fs::read_dir(root("src")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            rank(&name);
        } else {
            assert!(TOP_FILES.contains(&name.as_str()), "src/{name}: put it in a layer folder");
        }
    }
}

#[test]
fn every_folder_opens_with_its_idea() {
    let mut paths = BTreeMap::new();
    files(&root("src"), &[], &mut paths);
    for (module, path) in paths.iter().filter(|(_, p)| p.ends_with("mod.rs")) {
        let opening = std::fs::read_to_string(path).unwrap();
        assert!(opening.starts_with("//! **"), "{module}'s mod.rs must open with its idea in bold");
    }
    let tracer = std::fs::read_to_string(root("src/tracer/mod.rs")).unwrap();
    let declared: Vec<&str> =
        tracer.lines().filter_map(|l| l.strip_prefix("pub mod")?.trim().strip_suffix(';')).collect();
    assert_eq!(declared, TRACER_ROOMS, "src/tracer/mod.rs must declare the rooms in their reading order");
}

#[test]
fn every_file_opens_with_its_idea() {
    for crate_src in ["src", "pool/src"] {
        let mut paths = BTreeMap::new();
        files(&root(crate_src), &[], &mut paths);
        for path in paths.values().chain([&root(crate_src).join("lib.rs")]) {
            let text = std::fs::read_to_string(path).unwrap();
            assert!(
                text.starts_with("//! "),
                "{} must open with a //! paragraph saying its idea",
                path.display()
            );
        }
    }
}

#[test]
fn lower_layers_never_use_upper_ones() {
    let all = modules();
    let mut wrong = Vec::new();
    for (module, text) in &all {
        for target in uses(module, text, &all) {
            let (from, to) = (layer(module), layer(&target));
            if from != to && rank(to) >= rank(from) {
                wrong.push(format!("{module} → {target}"));
            }
        }
    }
    assert!(wrong.is_empty(), "imports against the layering:\n{}", wrong.join("\n"));
}

#[test]
fn tracer_rooms_use_only_the_rooms_before_them() {
    let all = modules();
    let mut wrong = Vec::new();
    for (module, text) in all.iter().filter(|(m, _)| room(m).is_some()) {
        for target in uses(module, text, &all) {
            if let (Some(from), Some(to)) = (room(module), room(&target))
                && to > from
            {
                wrong.push(format!("{module} → {target}"));
            }
        }
    }
    assert!(wrong.is_empty(), "a tracer room reaches a later one:\n{}", wrong.join("\n"));
}

/// The command line's modules that the viewer's modules use, directly or through other
/// modules of the command line.
fn cli_reached_from_view(all: &BTreeMap<String, String>) -> BTreeSet<String> {
    let cli_uses = |module: &str| -> Vec<String> {
        uses(module, &all[module], all).into_iter().filter(|target| layer(target) == "cli").collect()
    };
    let mut to_visit: Vec<String> =
        all.keys().filter(|module| layer(module) == "view").flat_map(|module| cli_uses(module)).collect();
    let mut reached = BTreeSet::new();
    while let Some(module) = to_visit.pop() {
        if reached.insert(module.clone()) {
            to_visit.extend(cli_uses(&module));
        }
    }
    reached
}

#[test]
fn the_viewer_uses_only_the_flags_and_settings_of_the_command_line() {
    let wrong: Vec<String> = cli_reached_from_view(&modules())
        .into_iter()
        .filter(|module| !CLI_FOR_THE_VIEWER.contains(&module.as_str()))
        .collect();
    assert!(wrong.is_empty(), "the viewer reaches {wrong:?}; it may use only {CLI_FOR_THE_VIEWER:?}");
}

/// A cycle in `graph` (module → the modules it uses), as the path that closes it, if any.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<String> {
    // Depth-first search; a module met again while still on the stack closes a cycle.
    fn visit<'a>(
        m: &'a str,
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        stack: &mut Vec<&'a str>,
        done: &mut BTreeSet<&'a str>,
    ) -> Option<String> {
        if let Some(at) = stack.iter().position(|s| *s == m) {
            return Some(format!("{} → {m}", stack[at..].join(" → ")));
        }
        if !done.insert(m) {
            return None;
        }
        stack.push(m);
        let found = graph.get(m).into_iter().flatten().find_map(|next| visit(next, graph, stack, done));
        stack.pop();
        found
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|m| visit(m, graph, &mut Vec::new(), &mut done))
}

#[test]
fn no_module_imports_itself_through_others() {
    for crate_src in ["src", "pool/src"] {
        let all = modules_of(crate_src);
        let graph = all.iter().map(|(m, text)| (m.clone(), uses(m, text, &all))).collect();
        assert_eq!(find_cycle(&graph), None, "an import cycle in {crate_src}");
    }
}

/// The folders whose every `.rs` file, at any depth, is held to [`MAX_LINES`]: both crates'
/// sources, and the tests and benchmarks a student reads beside them.
const CAPPED: &[&str] = &["src", "pool", "tests", "benches"];

/// Every `.rs` file under `dir`, at any depth (a `target` folder left out).
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() && !path.ends_with("target") {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `file (N lines)` for each file of `files` over [`MAX_LINES`].
fn too_long(files: &[PathBuf]) -> Vec<String> {
    files
        .iter()
        .filter_map(|path| {
            let lines = std::fs::read_to_string(path).unwrap().lines().count();
            let shown = path.strip_prefix(root("")).unwrap_or(path).display().to_string();
            (lines > MAX_LINES).then(|| format!("{shown} ({lines} lines)"))
        })
        .collect()
}

#[test]
fn no_source_file_is_longer_than_one_sitting() {
    let mut files = Vec::new();
    for folder in CAPPED {
        rust_files(&root(folder), &mut files);
    }
    assert!(files.len() > 100, "only {} .rs files found under {CAPPED:?}: is the walk blind?", files.len());
    let long = too_long(&files);
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines, more than one sitting's reading: split each by topic, every part opening with its idea: {}",
        long.join(", ")
    );
}

/// The book's chapter that maps the code: it must name every folder of either crate and every
/// room of the tracer, so that the map cannot go stale.
const MAP: &str = "docs/src/architecture.md";

/// Every folder under `dir` (itself included), as paths from the workspace's root ending in `/`.
fn folders(dir: &Path, out: &mut Vec<String>) {
    let from_root = dir.strip_prefix(root("")).unwrap().to_string_lossy().into_owned();
    out.push(format!("{from_root}/"));
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            folders(&path, out);
        }
    }
}

#[test]
fn the_book_names_every_folder_and_room() {
    let map = std::fs::read_to_string(root(MAP)).unwrap();
    let mut named = Vec::new();
    for crate_src in ["src", "pool/src"] {
        folders(&root(crate_src), &mut named);
    }
    let mut missing: Vec<String> =
        named.into_iter().filter(|folder| !map.contains(&format!("`{folder}`"))).collect();
    for room in TRACER_ROOMS {
        let (folder, file) = (format!("`src/tracer/{room}/`"), format!("`src/tracer/{room}.rs`"));
        if !map.contains(&folder) && !map.contains(&file) {
            missing.push(format!("the tracer's room {room}"));
        }
    }
    assert!(missing.is_empty(), "{MAP} does not name {missing:?}: add each to its map, with its idea");
}

#[test]
fn the_checker_sees_an_upward_import_a_later_room_a_viewer_reaching_the_command_line_and_a_cycle() {
    // The checks above pass only if they can fail: feed them a made-up tree.
    let mut all = BTreeMap::new();
    all.insert(
        "tracer::math::ray".to_owned(),
        "use crate::schedule::frame::Frame;\n// crate::cli in a comment\n".to_owned(),
    );
    all.insert("tracer::render".to_owned(), String::new());
    all.insert(
        "schedule::frame".to_owned(),
        "use crate::tracer::math::ray::Ray;\nuse crate::schedule::modes;\n".to_owned(),
    );
    all.insert("schedule::modes".to_owned(), String::new());
    all.insert("cli".to_owned(), String::new());
    all.insert("cli::args".to_owned(), "use crate::cli::run;\n".to_owned());
    all.insert("cli::settings".to_owned(), String::new());
    all.insert(
        "view::request".to_owned(),
        "use crate::cli::args::ViewArgs;\nuse crate::cli::settings::load_scene;\n".to_owned(),
    );
    assert_eq!(
        uses("tracer::math::ray", &all["tracer::math::ray"], &all),
        BTreeSet::from(["schedule::frame".to_owned()])
    );
    let frame = uses("schedule::frame", &all["schedule::frame"], &all);
    assert_eq!(frame, BTreeSet::from(["schedule::modes".to_owned(), "tracer::math::ray".to_owned()]));
    assert!(
        rank(layer("schedule::frame")) > rank(layer("tracer::math::ray")),
        "the upward edge is seen as upward"
    );
    assert!(room("tracer::render") > room("tracer::math::ray"), "render is a later room than math");
    assert_eq!(
        cli_reached_from_view(&all),
        BTreeSet::from(["cli".to_owned(), "cli::args".to_owned(), "cli::settings".to_owned()]),
        "the viewer reaches the command line itself through cli::args"
    );
    let graph = all.iter().map(|(m, text)| (m.clone(), uses(m, text, &all))).collect();
    assert_eq!(find_cycle(&graph).as_deref(), Some("schedule::frame → tracer::math::ray → schedule::frame"));
}

#[test]
fn the_line_cap_names_a_long_file_and_its_length() {
    // The cap check passes only if it can fail: a made-up file one line over the cap.
    let dir = std::env::temp_dir().join(format!("raypool-layers-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("deep")).unwrap();
    let (long, short) = (dir.join("deep/long.rs"), dir.join("short.rs"));
    std::fs::write(&long, "//\n".repeat(MAX_LINES + 1)).unwrap();
    std::fs::write(&short, "//\n".repeat(MAX_LINES)).unwrap();
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    let found = too_long(&files);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(found, [format!("{} ({} lines)", long.display(), MAX_LINES + 1)]);
}
