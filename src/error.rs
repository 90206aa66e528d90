//! The one error type: a message fit to print on one line after `raypool: error: `.

use std::fmt;

/// A user-facing error (bad input, unwritable file…). Its message names the problem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error(String);

impl Error {
    /// An error with this message.
    pub fn new(message: impl Into<String>) -> Error {
        Error(message.into())
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

/// An I/O error's message without the trailing "(os error N)".
pub fn io_reason(e: &std::io::Error) -> String {
    // The io::Error Display adds "(os error N)"; the kind's description reads better.
    let text = e.to_string();
    text.split(" (os error").next().unwrap_or(&text).to_owned()
}
