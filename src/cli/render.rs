//! `slice --format svg|html|cli|cli-binary`: rendered outputs.

use super::args::SliceArgs;
use super::input::Input;
use super::{usage, Failure};
use wmslice::LevelSet;

/// Writes the rendered format chosen in `a`.
pub fn write(a: &SliceArgs, _input: &Input, _sets: &[LevelSet]) -> Result<(), Failure> {
    Err(usage(format!(
        "--format {:?} is not available yet",
        a.format
    )))
}
