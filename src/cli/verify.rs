//! `wmslice verify MESH RESULT.json`: the independent exact re-check.

use super::args::VerifyArgs;
use super::{usage, Failure};

/// Runs `verify`.
pub fn run(_a: VerifyArgs) -> Result<(), Failure> {
    Err(usage("verify is not available yet".into()))
}
