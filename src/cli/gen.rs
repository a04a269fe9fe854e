//! `wmslice gen`: list or write the built-in datasets.

use super::args::GenArgs;
use super::{usage, ExitCode, Failure, Tag};
use crate::say;
use wmslice::datasets;

/// Runs `gen`.
pub fn run(a: GenArgs) -> Result<(), Failure> {
    if a.list {
        for d in datasets::all() {
            say!("{:<20} {}", d.name, d.summary);
        }
        return Ok(());
    }
    let name = a.name.unwrap_or_default();
    let d = datasets::by_name(&name)
        .ok_or_else(|| usage(format!("unknown dataset {name} (see `wmslice gen --list`)")))?;
    let out = a.output.ok_or_else(|| usage("missing -o FILE".into()))?;
    d.build().save(&out).tag(ExitCode::Output)?;
    eprintln!("wrote {} to {}", d.name, out.display());
    Ok(())
}
