//! `raypool`: parse the command line, run it, and turn every failure into one line on stderr
//! and exit code 2.

use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;
use raypool::cli::{Cli, run};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            // clap's first line names the problem; its usage block follows. Keep the line.
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("invalid command line");
            eprintln!("raypool: error: {}", first.trim_start_matches("error: "));
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("raypool: error: {e}");
            ExitCode::from(2)
        }
    }
}
