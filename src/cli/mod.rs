//! Input: command-line arguments. Output: files, stdout, and an exit code.
//!
//! Exit codes: 0 success; 1 internal error (a bug: please report);
//! 2 bad arguments; 3 the mesh is invalid (rejected by validation);
//! 4 the input cannot be read or parsed; 5 an output cannot be written.
//! A panic (101) is a bug.

mod args;
mod commands;

use clap::Parser;
use std::fmt;

/// A failure with the exit code it maps to.
#[derive(Debug)]
pub struct Failure {
    /// The exit code.
    pub code: ExitCode,
    /// The message (with its chain of causes).
    pub error: anyhow::Error,
}

/// The documented exit codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExitCode {
    /// A bug.
    Internal = 1,
    /// Bad arguments.
    Usage = 2,
    /// The mesh is rejected by validation.
    InvalidMesh = 3,
    /// The input cannot be read or parsed.
    Input = 4,
    /// An output cannot be written.
    Output = 5,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:#}", self.error)
    }
}

/// Shorthand to tag an error with its exit code.
pub trait Tag<T> {
    /// Tags the error.
    fn tag(self, code: ExitCode) -> Result<T, Failure>;
}

impl<T, E: Into<anyhow::Error>> Tag<T> for Result<T, E> {
    fn tag(self, code: ExitCode) -> Result<T, Failure> {
        self.map_err(|e| Failure {
            code,
            error: e.into(),
        })
    }
}

/// Runs the program and returns its exit code.
pub fn run() -> i32 {
    let cli = match args::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::Usage as i32
            } else {
                0
            };
        }
    };
    match commands::dispatch(cli) {
        Ok(()) => 0,
        Err(f) => {
            eprintln!("error: {f}");
            f.code as i32
        }
    }
}
