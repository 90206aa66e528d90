//! The one error type: a message fit to print on one line after `raypool: error: `.

use std::fmt;

/// A user-facing error (bad input, unwritable file…). Its message names the problem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    message: String,
    exit_code: u8,
}

impl Error {
    /// An error with this message (exit code 2).
    pub fn new(message: impl Into<String>) -> Error {
        Error { message: message.into(), exit_code: 2 }
    }

    /// An error with this message and exit code (a verdict, such as a grade not passed).
    ///
    /// ```
    /// assert_eq!(raypool::Error::with_exit_code("not passed", 1).exit_code(), 1);
    /// ```
    pub fn with_exit_code(message: impl Into<String>, exit_code: u8) -> Error {
        Error { message: message.into(), exit_code }
    }

    /// The command was stopped by signal `number` (exit code 128 + `number`, as shells do:
    /// 130 for Ctrl-C, 143 for SIGTERM).
    ///
    /// ```
    /// let e = raypool::Error::interrupted(2);
    /// assert_eq!((e.exit_code(), e.to_string().as_str()), (130, "interrupted by SIGINT: no output written"));
    /// ```
    pub fn interrupted(number: i32) -> Error {
        let name = match number {
            2 => "SIGINT".to_string(),
            15 => "SIGTERM".to_string(),
            n => format!("signal {n}"),
        };
        let exit_code = u8::try_from(128 + number).unwrap_or(1);
        Error { message: format!("interrupted by {name}: no output written"), exit_code }
    }

    /// The process's exit code for this error.
    pub fn exit_code(&self) -> u8 {
        self.exit_code
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// An I/O error's message without the trailing "(os error N)".
pub fn io_reason(e: &std::io::Error) -> String {
    // The io::Error Display adds "(os error N)"; the kind's description reads better.
    let text = e.to_string();
    text.split(" (os error").next().unwrap_or(&text).to_owned()
}
