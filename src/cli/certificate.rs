//! `slice --certificate FILE`: what was computed, from what, and the
//! independent verifier's verdict (the document is
//! `wmslice::output::certificate`'s).
//!
//! A result that fails verification is an internal error (exit 1, please
//! report): neither it nor a certificate is written.

use super::args::SliceArgs;
use super::input::Input;
use super::{ExitCode, Failure, Tag};
use anyhow::anyhow;
use clap::ValueEnum;
use wmslice::datasets;
use wmslice::exact::rational::Rat;
use wmslice::output::atomic::write_atomic;
use wmslice::output::certificate::{
    sha256_hex, Certificate, InputPart, LevelPart, Numeric, Options, ResultPart, Tool, Verdict,
};
use wmslice::output::json::{to_json, Exactness};
use wmslice::verify::Verifier;
use wmslice::LevelSet;

fn name_of<T: ValueEnum>(v: &T) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_owned())
        .unwrap_or_default()
}

/// Writes the certificate of a result whose bytes, exactly as written to
/// the output (file or stdout), are `result`.
pub fn write(
    path: &std::path::Path,
    a: &SliceArgs,
    input: &Input,
    levels: &[Rat],
    sets: &[LevelSet],
    result: &[u8],
) -> Result<(), Failure> {
    let header = input.header();
    let document = to_json(&header, sets, Exactness::WithExact);
    let verification = Verifier::new(&input.mesh, input.unit.as_ref())
        .and_then(|v| Verdict::of(&v, &document))
        .map_err(wmslice::output::certificate::CertificateError::from)
        .and_then(Verdict::into_verification)
        .tag(ExitCode::Internal)?;
    let input_part = if input.file_bytes.is_empty() {
        let built = datasets::by_name(&a.mesh)
            .map(|d| d.build())
            .ok_or_else(|| anyhow!("dataset {} vanished", a.mesh))
            .tag(ExitCode::Internal)?;
        InputPart::dataset(a.mesh.clone(), &built)
    } else {
        InputPart::file(a.mesh.clone(), &input.file_bytes)
    };
    let cert = Certificate {
        format: "wmslice-certificate",
        version: 1,
        tool: Tool::this(),
        input: input_part,
        mesh: header,
        numeric: Numeric::new(input.snap.as_ref(), input.flips.len()),
        options: Options {
            format: name_of(&a.format),
            exact: a.exact,
            output: a.output.as_ref().map(|p| p.display().to_string()),
            side: name_of(&a.side),
            with_ridges: a.with_ridges,
            arrows: a.arrows,
        },
        result: ResultPart {
            destination: if a.output.is_some() { "file" } else { "stdout" },
            sha256: sha256_hex(result),
            bytes: result.len(),
            verified_document_sha256: sha256_hex(document.as_bytes()),
        },
        levels: levels
            .iter()
            .zip(sets)
            .map(|(z, ls)| LevelPart::at(z, ls))
            .collect(),
        verification,
    };
    write_atomic(path, cert.to_json().as_bytes())
        .map_err(|e| anyhow!("cannot write {}: {e}", path.display()))
        .tag(ExitCode::Output)
}
