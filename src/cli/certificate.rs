//! `slice --certificate FILE`: what was computed, from what, and the
//! verifier's verdict.

use super::args::SliceArgs;
use super::input::Input;
use super::{usage, Failure};
use std::path::Path;
use wmslice::exact::rational::Rat;
use wmslice::LevelSet;

/// Writes the certificate of a result whose bytes, exactly as written to
/// the output (file or stdout), are `result`.
pub fn write(
    _path: &Path,
    _a: &SliceArgs,
    _input: &Input,
    _levels: &[Rat],
    _sets: &[LevelSet],
    _result: &[u8],
) -> Result<(), Failure> {
    Err(usage("--certificate is not available yet".into()))
}
