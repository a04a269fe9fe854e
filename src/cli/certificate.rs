//! `slice --certificate FILE`: what was computed, from what, and the
//! verifier's verdict.

use super::args::SliceArgs;
use super::input::Input;
use super::{usage, Failure};
use std::path::Path;
use wmslice::exact::rational::Rat;
use wmslice::LevelSet;

/// Writes the certificate.
pub fn write(
    _path: &Path,
    _a: &SliceArgs,
    _input: &Input,
    _levels: &[Rat],
    _sets: &[LevelSet],
) -> Result<(), Failure> {
    Err(usage("--certificate is not available yet".into()))
}
