//! The source tree shows the architecture: `src/` holds the top-level files and one folder per
//! layer, a module uses only its own folder and the layers below it, and no two modules import
//! each other, directly or through others.
//!
//! Run it alone with `cargo test --release --test layers`. It reads `src/` as text: every
//! `crate::a::b` and `super::b` path outside comments is an edge from the file that writes it
//! to the module it names.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The layers, lowest first. A module may use its own folder and any folder of a lower rank.
/// `scenes` and `files` share a rank: neither may use the other.
const LAYERS: &[(&str, u32)] = &[
    ("error", 0),
    ("tracer", 1),
    ("scenes", 2),
    ("files", 2),
    ("schedule", 3),
    ("measure", 4),
    ("cli", 5),
    ("view", 6),
];

/// The only files that may sit directly in `src/` (besides the layer folders).
const TOP_FILES: &[&str] = &["lib.rs", "main.rs", "error.rs"];

fn rank(layer: &str) -> u32 {
    LAYERS.iter().find(|(name, _)| *name == layer).unwrap_or_else(|| panic!("'{layer}' is not a layer")).1
}

/// Module path (`tracer::ray`) → source text, for every module of the library.
fn modules() -> BTreeMap<String, String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut modules = BTreeMap::new();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            for file in std::fs::read_dir(&path).unwrap() {
                let file = file.unwrap().path();
                if file.extension().is_some_and(|e| e == "rs") {
                    let stem = file.file_stem().unwrap().to_string_lossy().into_owned();
                    let module = if stem == "mod" { name.clone() } else { format!("{name}::{stem}") };
                    modules.insert(module, std::fs::read_to_string(&file).unwrap());
                }
            }
        } else if name.ends_with(".rs") && name != "lib.rs" && name != "main.rs" {
            modules.insert(name.trim_end_matches(".rs").to_owned(), std::fs::read_to_string(&path).unwrap());
        }
    }
    modules
}

/// The modules that `module`'s code (not its comments) names.
fn uses(module: &str, text: &str, all: &BTreeMap<String, String>) -> BTreeSet<String> {
    let folder = module.split("::").next().unwrap();
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap();
        assert!(
            !code.contains("crate::{"),
            "{module}: write one `use` per module, not `crate::{{…}}`: {line}"
        );
        for (prefix, base) in [("crate::", None), ("super::", Some(folder))] {
            for (at, _) in code.match_indices(prefix) {
                let path: Vec<&str> = code[at + prefix.len()..]
                    .split("::")
                    .map(|part| part.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap())
                    .take(2)
                    .collect();
                let candidates = match base {
                    Some(folder) => vec![format!("{folder}::{}", path[0]), folder.to_owned()],
                    None => {
                        let mut c = vec![path[0].to_owned()];
                        if let Some(second) = path.get(1) {
                            c.insert(0, format!("{}::{second}", path[0]));
                        }
                        c
                    }
                };
                let target = candidates.into_iter().find(|c| all.contains_key(c));
                let target = target.unwrap_or_else(|| panic!("{module}: cannot resolve '{line}'"));
                if target != module {
                    found.insert(target);
                }
            }
        }
    }
    found
}

fn layer(module: &str) -> &str {
    module.split("::").next().unwrap()
}

#[test]
fn src_holds_only_the_top_files_and_the_layer_folders() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            rank(&name);
            let opening = std::fs::read_to_string(path.join("mod.rs")).expect("each folder has a mod.rs");
            assert!(opening.starts_with("//! **"), "src/{name}/mod.rs must open with its idea in bold");
        } else {
            assert!(TOP_FILES.contains(&name.as_str()), "src/{name}: put it in a layer folder");
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
    let all = modules();
    let graph = all.iter().map(|(m, text)| (m.clone(), uses(m, text, &all))).collect();
    assert_eq!(find_cycle(&graph), None, "an import cycle");
}

#[test]
fn the_checker_sees_an_upward_import_and_a_cycle() {
    // The checks above pass only if they can fail: feed them a made-up tree.
    let mut all = BTreeMap::new();
    all.insert(
        "tracer::ray".to_owned(),
        "use crate::schedule::frame::Frame;\n// crate::cli in a comment\n".to_owned(),
    );
    all.insert("schedule::frame".to_owned(), "use crate::tracer::ray::Ray;\nuse super::modes;\n".to_owned());
    all.insert("schedule::modes".to_owned(), String::new());
    all.insert("cli".to_owned(), String::new());
    assert_eq!(
        uses("tracer::ray", &all["tracer::ray"], &all),
        BTreeSet::from(["schedule::frame".to_owned()])
    );
    let frame = uses("schedule::frame", &all["schedule::frame"], &all);
    assert_eq!(frame, BTreeSet::from(["schedule::modes".to_owned(), "tracer::ray".to_owned()]));
    assert!(rank(layer("schedule::frame")) > rank(layer("tracer::ray")), "the upward edge is seen as upward");
    let graph = all.iter().map(|(m, text)| (m.clone(), uses(m, text, &all))).collect();
    assert_eq!(find_cycle(&graph).as_deref(), Some("schedule::frame → tracer::ray → schedule::frame"));
}
