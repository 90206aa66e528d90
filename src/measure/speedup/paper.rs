//! The seed paper's table, reproduced: its three rows (single-threaded, naive static
//! blocks, a thread pool of scanlines) on its four images at 1200 × 800, each rendered with
//! its shared locked `rand()` and with per-sample streams, beside the paper's own seconds
//! (`paper-table.md`).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::files::output::write_text;
use crate::measure::machine::Machine;
use crate::measure::speedup::measure_once;
use crate::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use crate::schedule::modes::Schedule;
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::sampling::sampler::Sampler;

/// The seed paper's final-report table (seconds on its authors' machine, core count unknown)
/// and its final image's figures (88.98 and 20.66 minutes), with the row each corresponds to.
const PAPER: [(&str, [Option<f64>; 3]); 4] = [
    ("final", [Some(88.98 * 60.0), Some(20.66 * 60.0), None]),
    ("paper1", [Some(208.0), Some(330.0), Some(353.0)]),
    ("paper2", [Some(308.0), Some(453.0), Some(482.0)]),
    ("paper3", [Some(532.0), Some(488.0), Some(511.0)]),
];

/// The paper's three rows, and the modes that reproduce them (with its shared generator)
/// and that fix them (with per-sample streams; the thread-pool row is fixed by our best mode).
const PAPER_ROWS: [(&str, Schedule, Schedule); 3] = [
    ("single-threaded", Schedule::Serial, Schedule::Serial),
    ("naive multithreading (static blocks)", Schedule::StaticBlocks, Schedule::StaticBlocks),
    ("thread pool (a job per scanline)", Schedule::PoolRows, Schedule::Stealing),
];

/// One cell pair of the paper table: our time with the shared generator and with streams.
pub struct PaperCell {
    /// Scene name.
    pub scene: &'static str,
    /// Max depth used.
    pub depth: u32,
    /// Index into the paper's three rows.
    pub row: usize,
    /// Wall seconds with one shared locked generator (the paper's `rand()`).
    pub shared: Option<f64>,
    /// Wall seconds with per-sample streams.
    pub per_sample: f64,
}

/// Renders the paper's configurations at 1200 × 800 and `spp` samples on `threads` threads,
/// one run each: the paper's depth 10 on all four scenes, and the book's depth 50 on
/// `final` (per-sample streams only).
pub fn paper_table(spp: u32, threads: usize, mut log: impl FnMut(&str)) -> Result<Vec<PaperCell>, Error> {
    let mut cells = Vec::new();
    let configs = PAPER.iter().map(|p| (p.0, 10, true)).chain([("final", 50, false)]);
    for (scene_name, depth, with_shared) in configs {
        let scene = builtin_scene(scene_name, DEFAULT_SCENE_SEED)?.to_scene();
        let settings = RenderSettings {
            width: 1200,
            height: 800,
            spp,
            max_depth: depth,
            seed: 1,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let job = RenderJob::new(scene, settings);
        for (row, &(label, theirs, ours)) in PAPER_ROWS.iter().enumerate() {
            let threads = if row == 0 { 1 } else { threads };
            let shared = with_shared.then(|| measure_once(&job, &theirs, threads, true).0);
            let per_sample = measure_once(&job, &ours, threads, false).0;
            let shared_text = shared.map_or("–".into(), |s| format!("{s:.1} s"));
            log(&format!(
                "{scene_name:<7} depth {depth:<2} {label:<38} shared {shared_text:>9}   per-sample {per_sample:>8.1} s"
            ));
            cells.push(PaperCell { scene: scene_name, depth, row, shared, per_sample });
        }
    }
    Ok(cells)
}

/// Writes `paper-table.md`: the paper's table beside ours.
pub fn write_paper_table(
    dir: &Path,
    cells: &[PaperCell],
    spp: u32,
    threads: usize,
    command: &str,
) -> Result<(), Error> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::new(format!("cannot create '{}': {e}", dir.display())))?;
    let machine = Machine::current();
    let scale = 500.0 / spp as f64;
    let mut md = String::new();
    let _ = writeln!(md, "# The paper's table, reproduced\n");
    let _ = writeln!(md, "Command: `{command}` · {}\n", machine.describe());
    let _ = writeln!(
        md,
        "1200 × 800 pixels, {spp} samples per pixel{}, one run per cell, {threads} threads for the parallel rows. \
         The paper's columns are its own measurements (seconds, its authors' machine, core count unknown; \
         the final image's two figures are its 88.98 and 20.66 minutes). \
         *Shared rand()* draws every random number from one generator behind a futex lock, as the paper's C `rand()` did; \
         *per-sample* gives each pixel sample its own stream (raypool's normal mode); its thread-pool row uses raypool's best mode, `steal`.\n",
        if spp == 500 {
            String::new()
        } else {
            format!(
                " (measured at {spp} spp and multiplied by {scale:.0} to estimate the paper's 500: render time is linear in spp)"
            )
        }
    );
    let _ = writeln!(
        md,
        "| scene | depth | row | paper | ours, shared rand() | ours, per-sample | per-sample speedup |\n|---|---:|---|---:|---:|---:|---:|"
    );
    for c in cells {
        let paper = PAPER.iter().find(|p| p.0 == c.scene && c.depth == 10).and_then(|p| p.1[c.row]);
        let serial = cells
            .iter()
            .find(|d| d.scene == c.scene && d.depth == c.depth && d.row == 0)
            .map_or(f64::NAN, |d| d.per_sample);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {:.1} s | {:.2}× |",
            c.scene,
            c.depth,
            PAPER_ROWS[c.row].0,
            paper.map_or("–".into(), |p| format!("{p:.0} s")),
            c.shared.map_or("–".into(), |s| format!("{:.1} s", s * scale)),
            c.per_sample * scale,
            serial / c.per_sample
        );
    }
    write_text(&dir.join("paper-table.md"), &md)
}
