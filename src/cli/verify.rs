//! `wmslice verify MESH RESULT.json`: the independent exact re-check.
//!
//! Input: a mesh (file or built-in dataset) and a result written by
//! `slice --format json --exact`. Output: one summary line and exit 0, or
//! every violation (one per line: level, family, loop, point, what) and
//! exit 6. A result that is not JSON or not a `wmslice-levelset` document
//! with exact output exits 4; a mesh the slicer rejects exits 3.
//!
//! The snap grid is `--snap Q` when given, else the one the result's header
//! names; the header must match the grid verified against. Vertices at one
//! point are merged first when the header has `welded` (`slice --weld`),
//! and faces that use one vertex twice removed when it has
//! `dropped_collapsed` (`slice --drop-collapsed`).

use super::args::VerifyArgs;
use super::input::{load_input, read_stdin};
use super::progress::{progress, step};
use super::{usage, ExitCode, Failure, Tag};
use crate::say;
use anyhow::anyhow;
use wmslice::mesh::prepare::Repairs;
use wmslice::verify::{outline, Verifier, VerifyError};

/// Runs `verify`.
pub fn run(a: VerifyArgs) -> Result<(), Failure> {
    // `-` is standard input, for one of the two (`slice ... -o - |
    // wmslice verify MESH -`).
    let from_stdin = a.result.as_os_str() == "-";
    if from_stdin && a.mesh == "-" {
        return Err(usage(
            "the mesh and the result cannot both be standard input".into(),
        ));
    }
    let shown = if from_stdin {
        "standard input".to_string()
    } else {
        a.result.display().to_string()
    };
    let reading = step("reading the result", a.quiet);
    let bytes = if from_stdin {
        read_stdin()
    } else {
        std::fs::read(&a.result)
    }
    .map_err(|e| anyhow!("cannot read {shown}: {e}"))
    .tag(ExitCode::Input)?;
    let text = String::from_utf8(bytes)
        .map_err(|e| anyhow!("{shown} is not UTF-8 text: {e}"))
        .tag(ExitCode::Input)?;
    let unreadable = |e: VerifyError| Failure {
        code: match e {
            VerifyError::MeshRejected { .. } => ExitCode::InvalidMesh,
            VerifyError::Json(_) | VerifyError::Format(_) => ExitCode::Input,
        },
        error: anyhow!("{shown}: {e}"),
    };
    let (header, levels) = outline(&text).map_err(unreadable)?;
    reading.finish_and_clear();
    let snap = a.snap.clone().or(header.snap);
    // Vertices are welded and collapsed faces removed as the header says
    // the slicer did; the mesh hash then tells whether the same went.
    let repairs = Repairs::from_flags(header.welded.is_some(), header.dropped_collapsed.is_some());
    let validating = step("reading and validating the mesh", a.quiet);
    let input = load_input(&a.mesh, snap.as_deref(), repairs)?;
    let verifier = Verifier::new(&input.mesh, input.unit.as_ref()).map_err(unreadable)?;
    validating.finish_and_clear();
    let bar = progress(levels, a.quiet);
    let report = verifier
        .verify_with(&text, |n| bar.set_position(n as u64))
        .map_err(unreadable)?;
    bar.finish_and_clear();
    if report.passed() {
        say!("{shown}: {}", report.summary());
        return Ok(());
    }
    for v in &report.violations {
        say!("{v}");
    }
    Err(Failure {
        code: ExitCode::Verification,
        error: anyhow!("{shown}: {}", report.summary()),
    })
}
