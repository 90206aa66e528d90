//! `raypool scenes` and `raypool scene`: the built-in scenes listed, and one printed as TOML.

use crate::cli::args::SceneArgs;
use crate::cli::output;
use crate::error::Error;
use crate::scenes::builtin::{BUILTINS, builtin_scene};

/// Runs `raypool scenes`: one line per built-in scene, its name and what it shows.
pub fn list() -> Result<(), Error> {
    let lines: Vec<String> = BUILTINS.iter().map(|b| format!("{:<14} {}\n", b.name, b.about)).collect();
    output(&lines.concat())
}

/// Runs `raypool scene`: the scene as TOML on stdout.
pub fn print(args: &SceneArgs) -> Result<(), Error> {
    output(&builtin_scene(&args.name, args.scene_seed)?.to_toml())
}
