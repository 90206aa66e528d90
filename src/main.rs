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
            // clap names the problem in its first paragraph (one line, or a line ending in ':'
            // followed by the missing arguments); a usage block follows. Keep the paragraph.
            let text = e.render().to_string();
            let problem: Vec<&str> = text.lines().map(str::trim).take_while(|l| !l.is_empty()).collect();
            let problem = problem.join(" ");
            let problem = if problem.is_empty() { "invalid command line" } else { &problem };
            eprintln!("raypool: error: {}", problem.trim_start_matches("error: "));
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
