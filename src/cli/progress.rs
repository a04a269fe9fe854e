//! Progress on stderr for long work: a spinner naming a step, a bar
//! counting levels. Hidden when stderr is not a terminal or with
//! `--quiet`, so scripts and pipes see nothing of it.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar on stderr for long runs; hidden when stderr is not a
/// terminal or with `--quiet`.
pub fn progress(len: usize, quiet: bool) -> ProgressBar {
    if quiet || len < 2 || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    if let Ok(style) =
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} levels ({eta})")
    {
        bar.set_style(style);
    }
    bar
}

/// A spinner naming a long step before the levels (reading, welding,
/// validating a large mesh takes seconds); hidden like the bar.
pub fn step(message: &'static str, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let spinner = ProgressBar::new_spinner().with_message(message);
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    spinner
}
