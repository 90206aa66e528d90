//! `raypool`: parse the command line, run it, and turn every failure into one line on stderr
//! and exit code 2.

// Like the library: the binary is safe Rust too (only the optional Embree bridge is not).
#![forbid(unsafe_code)]

use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;
use raypool::cli::args::{Cli, Command, one_line};
use raypool::cli::run;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        // `raypool` alone: the usage and the subcommands on stderr, as cargo and git do.
        Err(e) if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            eprint!("{}", e.render());
            return ExitCode::from(2);
        }
        Err(e) => {
            eprintln!("raypool: error: {}", one_line(&e));
            return ExitCode::from(2);
        }
    };
    let outcome = match cli.command {
        Command::View(args) => raypool::view::run(args),
        command => run(Cli { command }),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("raypool: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
