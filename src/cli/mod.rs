//! **The command line**: `raypool render | merge | simulate | scenes | scene | bench | grade |
//! compare`. Every failure is an [`Error`] that `main` prints on one line before exiting with
//! code 2 (130 or 143 when Ctrl-C or SIGTERM stopped a render: [`interrupt`]); a render too big
//! for the memory this process may use is refused before it starts ([`memory`]).
//!
//! [`args`] holds the flags (clap's definition), [`settings`] what they resolve to (the scene,
//! the render settings, the threads), [`transport`] the light transport and sampling they
//! choose, every refused combination in one place, and each command has a file of its own (`render.rs`,
//! `merge.rs`, `simulate.rs`, `scenes.rs` for `scenes` and `scene`, `bench.rs`, `grade.rs`,
//! `compare.rs`); [`run`] only dispatches.
//!
//! It may use every layer below it. `main.rs` calls [`run`]; the viewer, the one layer above,
//! uses [`args`] and [`settings`] alone (`tests/layers.rs` checks it).

pub mod args;
pub mod settings;
pub mod transport;
pub mod interrupt;
pub mod memory;
mod render;
mod merge;
mod simulate;
mod scenes;
mod bench;
mod grade;
mod compare;

use std::io::{ErrorKind, Write};

use crate::cli::args::{Cli, Command};
use crate::error::Error;

/// Writes `text` to standard output. A reader that has gone (`raypool scene final | head`)
/// ends the output quietly, as Unix tools do; `print!` would panic there.
fn output(text: &str) -> Result<(), Error> {
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != ErrorKind::BrokenPipe => {
            Err(Error::new(format!("cannot write to standard output: {e}")))
        }
        _ => Ok(()),
    }
}

/// Runs one parsed command line (all but `view`, which the viewer layer runs: see `main.rs`).
pub fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::View(_) => Err(Error::new("raypool view is run by raypool::view::run")),
        Command::Render(args) => render::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Scenes => scenes::list(),
        Command::Scene(args) => scenes::print(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Grade(args) => grade::run(&args),
        Command::Compare(args) => compare::run(&args),
    }
}
