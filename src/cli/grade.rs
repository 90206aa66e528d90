//! `raypool grade`: a built-in mode or queue discipline graded as a course's grader grades a
//! student's (`crate::measure::grade`).

use crate::cli::args::GradeArgs;
use crate::error::Error;
use crate::measure::grade::report::Verdict;
use crate::measure::grade::{Entry, Submission, command_line, grade_and_report};

/// Runs `raypool grade`.
pub fn run(args: &GradeArgs) -> Result<(), Error> {
    let submission = match (&args.mode, args.discipline) {
        (Some(mode), _) => {
            Submission { name: format!("mode {}", mode.name()), entry: Entry::Scheduler(mode) }
        }
        (None, Some(discipline)) => Submission {
            name: format!("discipline {}", discipline.name()),
            entry: Entry::Queue(discipline.queue()),
        },
        (None, None) => {
            return Err(Error::new("raypool grade: name a submission: --mode or --discipline"));
        }
    };
    match grade_and_report(&[&submission], &args.options, &command_line())? {
        Verdict::Passed => Ok(()),
        verdict => Err(Error::with_exit_code(
            match verdict {
                Verdict::Unjudged => "grade: the machine was too busy to judge (see the report)",
                _ => "grade: not passed (see the report)",
            },
            verdict.exit_code(),
        )),
    }
}
