//! Input: command-line arguments. Output: files, stdout, and an exit code.
//!
//! Exit codes: 0 success; 1 internal error (a bug: please report);
//! 2 bad arguments; 3 the mesh is invalid (rejected by validation);
//! 4 the input cannot be read or parsed; 5 an output cannot be written;
//! 6 verification failed (`verify` found violations).
//! A panic (101) is a bug.

mod args;
mod certificate;
mod check;
mod critical;
mod demo;
mod gen;
mod input;
mod paths;
mod progress;
mod render;
mod slice;
mod verify;

use anyhow::anyhow;
use args::{Cli, Command};
use clap::Parser;
use std::fmt;
use std::path::{Path, PathBuf};
use wmslice::output::atomic::write_atomic;
use wmslice::SliceError;

/// A failure with the exit code it maps to.
#[derive(Debug)]
pub struct Failure {
    /// The exit code.
    pub code: ExitCode,
    /// The error; its message already names its causes (see `Display`).
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
    /// `verify` found the result wrong.
    Verification = 6,
    /// Stopped from outside (Ctrl-C, `SIGTERM`, `SIGHUP`) before the end;
    /// the output being written is removed (128 + `SIGINT`, as shells
    /// report an interrupted command).
    Interrupted = 130,
}

/// The error's own message only: every error of the library and of this
/// binary writes its cause's message into its own (`"3MF: broken zip
/// archive: {source}"`), and keeps the cause as `source()` for programs,
/// so printing the chain too would say each cause twice.
impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.error)
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
    // On Ctrl-C, SIGTERM or SIGHUP: remove the output being written, say
    // so, and stop. The handler runs on a thread of its own, not in the
    // signal's context. Without it (it could not be set) a stopped run
    // may leave a `.NAME.XXXXXX.partial` file, never a partial NAME.
    let _ = ctrlc::set_handler(|| {
        let removed = wmslice::output::atomic::remove_unfinished();
        let what = if removed == 0 {
            String::new()
        } else {
            format!(": the unfinished output was removed ({removed} file(s))")
        };
        eprintln!("\ninterrupted{what}");
        std::process::exit(ExitCode::Interrupted as i32);
    });
    let cli = match args::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let printed = e.print();
            if e.use_stderr() {
                return ExitCode::Usage as i32;
            }
            // --help and --version: their text is the output (a reader
            // that stopped early is not an error, as for every command).
            return match printed {
                Ok(()) => 0,
                Err(err) if err.kind() == std::io::ErrorKind::BrokenPipe => 0,
                Err(err) => {
                    eprintln!("error: cannot write to stdout: {err}");
                    ExitCode::Output as i32
                }
            };
        }
    };
    match dispatch(cli) {
        Ok(()) => 0,
        Err(f) => {
            eprintln!("error: {f}");
            f.code as i32
        }
    }
}

/// Runs one parsed command.
fn dispatch(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Demo(a) => demo::run(a),
        Command::Gen(a) => gen::run(a),
        Command::Check(a) => check::run(a),
        Command::Slice(mut a) => {
            a.output = dash_is_stdout(a.output);
            slice::run(a)
        }
        Command::Verify(a) => verify::run(a),
        Command::Critical(mut a) => {
            a.output = dash_is_stdout(a.output);
            critical::run(a)
        }
    }
}

/// `-o -` is standard output, as no `-o` is (it made a file named `-`);
/// a file named `-` is `-o ./-`.
fn dash_is_stdout(output: Option<PathBuf>) -> Option<PathBuf> {
    output.filter(|p| p.as_os_str() != "-")
}

/// Prints a line to stdout; a closed pipe (`wmslice ... | head`) ends the
/// output quietly instead of panicking.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::cli::write_stdout(&format!($($arg)*))?
    };
}

pub fn write_stdout(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}") {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        r => r
            .map_err(|e| anyhow!("cannot write to stdout: {e}"))
            .tag(ExitCode::Output),
    }
}

/// The worker count (`--threads N`, default all cores) and a pool of them.
///
/// This thread is the pool's first worker (where this thread is in no pool
/// yet), so work handed to the pool runs here rather than on a new thread:
/// with one thread, no thread at all is started. A new thread's memory
/// comes from a glibc arena that grows a page at a time, one `mprotect`
/// each (995 of them for a 20 000-level plan of a tetrahedron, 6% of the
/// run); this thread's heap grows in larger steps.
pub fn worker_pool(threads: Option<usize>) -> Result<(usize, rayon::ThreadPool), Failure> {
    if let Some(n) = threads {
        wmslice::layers::thread_count(n).map_err(|e| usage(format!("--threads {e}")))?;
    }
    let threads =
        threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let builder = || rayon::ThreadPoolBuilder::new().num_threads(threads);
    let pool = builder()
        .use_current_thread()
        .build()
        .or_else(|_| builder().build())
        .map_err(|e| Failure {
            code: ExitCode::Internal,
            error: anyhow!("cannot start worker threads: {e}"),
        })?;
    Ok((threads, pool))
}

/// A bad-arguments failure.
pub fn usage(msg: String) -> Failure {
    Failure {
        code: ExitCode::Usage,
        error: anyhow!(msg),
    }
}

/// The failure for a slicing error: an invalid mesh, or a bug.
pub fn slice_error(e: SliceError) -> Failure {
    let code = match e {
        SliceError::InvalidMesh(_) => ExitCode::InvalidMesh,
        _ => ExitCode::Internal,
    };
    Failure {
        code,
        error: e.into(),
    }
}

/// Writes `text` to `out` atomically, or to stdout.
/// The same bytes go to the file and to stdout: `text` ends with a newline.
pub fn emit(out: Option<&Path>, text: &str) -> Result<(), Failure> {
    match out {
        Some(p) => write_atomic(p, text.as_bytes())
            .map_err(|e| anyhow!("cannot write {}: {e}", p.display()))
            .tag(ExitCode::Output),
        None => write_stdout(text.strip_suffix('\n').unwrap_or(text)),
    }
}

#[cfg(test)]
mod tests {
    use super::worker_pool;

    /// The pool's work runs on the calling thread with one worker, and on
    /// exactly as many threads as asked; a second pool on a thread that is
    /// already a worker still builds (on threads of its own).
    #[test]
    fn the_calling_thread_is_the_first_worker() {
        std::thread::spawn(|| {
            let here = std::thread::current().id();
            let (n, one) = worker_pool(Some(1)).unwrap_or_else(|_| panic!("no pool"));
            assert_eq!(n, 1);
            assert_eq!(one.install(|| std::thread::current().id()), here);
            assert_eq!(one.current_num_threads(), 1);
            let (_, again) = worker_pool(Some(2)).unwrap_or_else(|_| panic!("no second pool"));
            assert_eq!(again.current_num_threads(), 2);
            assert_ne!(again.install(|| std::thread::current().id()), here);
        })
        .join()
        .unwrap();
    }
}
