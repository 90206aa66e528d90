//! The grade binary's body: grade each part, turn a panicking part into a failed
//! conformance, print and write the reports, and exit with the verdict's code
//! ([`grade_and_report`], [`main`]).

use std::sync::Arc;

use crate::error::Error;
use crate::files::output::write_text;
use crate::measure::grade::report::{Report, Verdict};
use crate::measure::grade::{Options, Submission, grade};
use crate::measure::machine::Machine;

/// Grades each submission, prints the reports and writes them, one after the other, to
/// `options.out`: the body of `raypool grade` and of a starter's grade binary ([`main`]).
/// `command` is the command line, quoted in the reports. A submission whose code panics (an
/// unfinished part's `todo!()`) fails its conformance with the panic's message, and the
/// others are still graded. Returns the worst verdict.
pub fn grade_and_report(
    submissions: &[&Submission],
    options: &Options,
    command: &str,
) -> Result<Verdict, Error> {
    let mut reports = Vec::new();
    let mut verdict = Verdict::Passed;
    for submission in submissions {
        let report = grade_catching_panics(submission, options)?;
        verdict = match (verdict, report.verdict(options.pass)) {
            (Verdict::Failed, _) | (_, Verdict::Failed) => Verdict::Failed,
            (Verdict::Unjudged, _) | (_, Verdict::Unjudged) => Verdict::Unjudged,
            _ => Verdict::Passed,
        };
        reports.push(report.markdown(command, options.pass));
    }
    let all = reports.join("\n");
    write_text(&options.out, &all)?;
    println!("{all}");
    eprintln!("report written to {}", options.out.display());
    Ok(verdict)
}

/// [`grade`], with a panic in the submission's code turned into a failed conformance that
/// quotes it (where it happened, and its message), instead of a backtrace.
fn grade_catching_panics(submission: &Submission, options: &Options) -> Result<Report, Error> {
    let caught: Arc<parking_lot::Mutex<Option<String>>> = Arc::default();
    let seen = Arc::clone(&caught);
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into());
        let at = info.location().map_or(String::new(), |l| format!(" at {}:{}", l.file(), l.line()));
        seen.lock().get_or_insert(format!("{message}{at}"));
    }));
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        grade(submission, options, |line| eprintln!("{line}"))
    }));
    std::panic::set_hook(previous);
    let panicked = caught.lock().take();
    match outcome {
        // A panic the submission's own checks caught (the queue's contract runs it on its own
        // threads): the conformance failure quotes it.
        Ok(Ok(mut report)) => {
            if let (Err(e), Some(why)) = (&mut report.conformance, panicked) {
                let e_text = e.trim_end_matches(" (see the message above)");
                *e = format!("{e_text}: {why} (is this part finished?)");
            }
            Ok(report)
        }
        Ok(Err(e)) => Err(e),
        Err(_) => {
            let why = panicked.unwrap_or_else(|| "a panic".into());
            let conformance = Err(format!("the code panicked: {why} (is this part finished?)"));
            Ok(Report {
                name: submission.name.clone(),
                reference: "none (not timed)",
                conformance,
                scores: Vec::new(),
                machine_checks: Vec::new(),
                machine: Machine::current(),
            })
        }
    }
}

/// This process's command line for a report, the program by its file name only (the
/// folder it was built in is nobody else's).
pub fn command_line() -> String {
    let mut args: Vec<String> = std::env::args().collect();
    if let Some(program) = args.first_mut() {
        let name =
            std::path::Path::new(program.as_str()).file_name().map(|n| n.to_string_lossy().into_owned());
        *program = name.unwrap_or_default();
    }
    args.join(" ")
}

/// The command line of a starter's grade binary (see [`main`]).
#[derive(clap::Parser, Debug)]
#[command(about = "Grade this crate's submissions: conformance, then workloads timed against the reference")]
struct GradeCommand {
    /// Grade only this part [default: every part]
    #[arg(long)]
    part: Option<String>,
    /// Thread counts, rounds, report file, pass mark.
    #[command(flatten)]
    options: Options,
}

/// The whole of a starter's grade binary: parses `--part` (its values listed in `--help`),
/// `--threads`, `--rounds`, `--out` and `--pass`, grades each submission (or the one named),
/// prints the reports and writes them, one after the other, to `--out`. Exit code 0 when
/// every part graded passed, 1 when one failed its conformance or scored below `--pass`, 3
/// when the machine was too busy to judge, 2 for a bad command line or an unwritable report.
///
/// ```no_run
/// # struct MyScheduler;
/// # impl raypool::Scheduler for MyScheduler {
/// #     fn render(&self, f: &std::sync::Arc<raypool::Frame>) -> Vec<raypool::TileOutput> { unimplemented!() }
/// # }
/// use raypool::measure::grade::{Entry, Submission, main};
/// fn main_of_grade_rs() -> std::process::ExitCode {
///     main(&[Submission { name: "scheduler".into(), entry: Entry::Scheduler(&MyScheduler) }])
/// }
/// ```
pub fn main(submissions: &[Submission]) -> std::process::ExitCode {
    use clap::{CommandFactory as _, FromArgMatches as _};
    let names: Vec<String> = submissions.iter().map(|s| s.name.clone()).collect();
    let matches = GradeCommand::command()
        .mut_arg("part", |a| a.value_parser(clap::builder::PossibleValuesParser::new(names)))
        .get_matches();
    let command = GradeCommand::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let chosen: Vec<&Submission> =
        submissions.iter().filter(|s| command.part.as_ref().is_none_or(|p| *p == s.name)).collect();
    match grade_and_report(&chosen, &command.options, &command_line()) {
        Ok(verdict) => std::process::ExitCode::from(verdict.exit_code()),
        Err(e) => {
            eprintln!("grade: error: {e}");
            std::process::ExitCode::from(e.exit_code())
        }
    }
}
