//! Comments say *why*; measured figures live in `results/`, where the command, machine and
//! commit that measured them stand beside them, and a comment points there. A figure in a
//! comment goes stale the day the code beside it changes: this test finds comments in `src/`
//! and `pool/src/` that quote one — a percentage (`12%`, `0.3 %`) or a ratio written against
//! its number (`1.08×`, `0.6x the time`) — in its comment lines (a comment after code on its
//! line is not read: none quotes one today), outside the Rust of a doc example. A dimension
//! (`3 × 3`, `2×CPUs`) is not a ratio. The few figures that are definitions, not
//! measurements, are named in [`NOT_MEASURED`] with the reason; each must still be found, so
//! the list cannot outlive its lines.
//!
//! Where an old figure went: `results/history/comment-figures.md`.
//!
//! Run it alone with `cargo test --release --test comments`.

use std::path::{Path, PathBuf};

/// `(file, words of the line, why it is not a measurement)`.
const NOT_MEASURED: &[(&str, &str, &str)] = &[
    ("src/scenes/builtin.rs", "(80% diffuse, 15%", "the book's scene: its recipe"),
    ("src/scenes/builtin.rs", "metal, 5% glass)", "the book's scene: its recipe"),
    (
        "src/tracer/lighting/passage.rs",
        "narrow its interval to 0.07%",
        "arithmetic: 0.618 to the power of the steps",
    ),
    ("src/tracer/lights/power.rs", "1% of their size", "a margin chosen, beside the tolerance it clears"),
];

/// The `.rs` files under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The prose of each comment line of `text` as `(line number, prose)`: `//`, `///` and `//!`
/// lines, without the Rust between a doc comment's ```` ``` ```` fences.
fn comment_prose(text: &str) -> Vec<(usize, &str)> {
    let mut in_example = false;
    let mut prose = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let Some(comment) = line.trim_start().strip_prefix("//") else { continue };
        let comment = comment.trim_start_matches(['/', '!']).trim();
        if comment.starts_with("```") {
            in_example = !in_example;
        } else if !in_example {
            prose.push((k + 1, comment));
        }
    }
    prose
}

/// Whether `prose` quotes a figure: a number followed by `%` (a space between allowed), or by
/// `×` or `x` with no space and no letter or digit after (`1.08×`, `0.6x the`).
fn quotes_a_figure(prose: &str) -> bool {
    let chars: Vec<char> = prose.chars().collect();
    (0..chars.len()).any(|k| {
        if !chars[k].is_ascii_digit() {
            return false;
        }
        let next = |j: usize| chars.get(j).copied();
        let percent = next(k + 1) == Some('%') || (next(k + 1) == Some(' ') && next(k + 2) == Some('%'));
        let ratio = matches!(next(k + 1), Some('×' | 'x')) && !next(k + 2).is_some_and(char::is_alphanumeric);
        percent || ratio
    })
}

#[test]
fn the_detector_sees_figures_and_not_dimensions() {
    for figure in ["1.08× faster", "12% of the time", "0.3 % off", "in 0.3-0.6x the time", "(3×)"] {
        assert!(quotes_a_figure(figure), "a figure missed: {figure:?}");
    }
    for plain in ["a 3 × 3 grid", "1…2×CPUs threads", "4 × u32", "0x1f", "k % 13", "seen twice"] {
        assert!(!quotes_a_figure(plain), "taken for a figure: {plain:?}");
    }
    let text = "/// 10% here\n/// ```\n/// let r = k % 13; // 5% in code\n/// ```\nlet x = 3; // 7% trailing\n// 2× too\n";
    let found: Vec<usize> =
        comment_prose(text).into_iter().filter(|(_, p)| quotes_a_figure(p)).map(|(k, _)| k).collect();
    assert_eq!(found, [1, 6], "prose lines only: not a doc example's code, not a line of code");
}

#[test]
fn no_comment_quotes_a_measured_figure() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut quoted = Vec::new();
    let mut exempt_seen = vec![false; NOT_MEASURED.len()];
    for dir in ["src", "pool/src"] {
        for path in rust_files(&root.join(dir)) {
            let name = path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
            let text = std::fs::read_to_string(&path).unwrap();
            for (line, prose) in comment_prose(&text).into_iter().filter(|(_, p)| quotes_a_figure(p)) {
                match NOT_MEASURED.iter().position(|(file, words, _)| *file == name && prose.contains(words))
                {
                    Some(k) => exempt_seen[k] = true,
                    None => quoted.push(format!("{name}:{line}: {prose}")),
                }
            }
        }
    }
    assert!(
        quoted.is_empty(),
        "comments quoting figures (move each to results/ and point there, or name it in \
         NOT_MEASURED with why it is not a measurement):\n{}",
        quoted.join("\n")
    );
    let stale: Vec<_> =
        NOT_MEASURED.iter().zip(&exempt_seen).filter(|(_, seen)| !**seen).map(|(e, _)| e).collect();
    assert!(stale.is_empty(), "NOT_MEASURED names lines that no longer quote a figure: {stale:?}");
}
