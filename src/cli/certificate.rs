//! `slice --certificate FILE`: what was computed, from what, and the
//! independent verifier's verdict.
//!
//! Input: the arguments, the loaded input (file bytes or dataset), the
//! exact levels, the level sets and the result bytes. Output: a JSON file
//! (`"format": "wmslice-certificate"`) with the SHA-256 of the input (the
//! file's bytes, or for a built-in dataset its canonical mesh bytes) and of
//! the result exactly as written, the tool version and build commit, the
//! levels as exact rationals, the numeric mode (exact, or snapped to a grid
//! with the largest coordinate move), counts and exact areas per level, and
//! the verdict of `wmslice::verify` on the exact JSON of the result (whose
//! SHA-256 is given too: `slice ... --format json --exact -o F` reproduces
//! it). No time stamp and no absolute path: the same input and options give
//! the same bytes.
//!
//! A result that fails verification is an internal error (exit 1, please
//! report): neither it nor a certificate is written.

use super::args::SliceArgs;
use super::input::Input;
use super::{ExitCode, Failure, Tag};
use anyhow::anyhow;
use clap::ValueEnum;
use serde::Serialize;
use sha2::{Digest, Sha256};
use std::path::Path;
use wmslice::datasets;
use wmslice::exact::rational::{rat_to_string, Rat};
use wmslice::mesh::io::{load_bytes, MeshFormat};
use wmslice::mesh::snap::snap;
use wmslice::nest::Role;
use wmslice::output::atomic::write_atomic;
use wmslice::output::json::{hex, mesh_sha256, to_json, Exactness, MeshHeader};
use wmslice::verify::verify;
use wmslice::{LevelSet, Mesh};

/// The build commit, when the build sets `WMSLICE_BUILD_COMMIT`.
const BUILD_COMMIT: Option<&str> = option_env!("WMSLICE_BUILD_COMMIT");

#[derive(Serialize)]
struct Certificate {
    format: &'static str,
    version: u32,
    tool: Tool,
    input: InputPart,
    mesh: MeshHeader,
    numeric: Numeric,
    options: Options,
    result: ResultPart,
    levels: Vec<LevelPart>,
    verification: Verification,
}

#[derive(Serialize)]
struct Tool {
    name: &'static str,
    version: &'static str,
    commit: Option<&'static str>,
}

#[derive(Serialize)]
struct InputPart {
    /// The mesh argument as typed.
    name: String,
    /// `file` or `dataset`.
    kind: &'static str,
    /// What `sha256` is the hash of.
    hashed: &'static str,
    sha256: String,
    /// Size of the file (None for a dataset).
    bytes: Option<usize>,
}

#[derive(Serialize)]
struct Numeric {
    /// `exact` (coordinates as stored in the file) or `snapped`.
    mode: &'static str,
    grid: Option<String>,
    largest_move: Option<String>,
    moved_vertices: Option<usize>,
    merged_vertices: Option<usize>,
    /// Degenerate faces removed by edge flips (SPEC 1) before slicing.
    flipped_faces: usize,
}

#[derive(Serialize)]
struct Options {
    format: String,
    exact: bool,
    output: Option<String>,
    side: String,
    with_ridges: bool,
    arrows: bool,
}

#[derive(Serialize)]
struct ResultPart {
    /// `file` or `stdout`.
    destination: &'static str,
    /// SHA-256 of the bytes written.
    sha256: String,
    bytes: usize,
    /// SHA-256 of the exact JSON document that was verified.
    verified_document_sha256: String,
}

#[derive(Serialize)]
struct LevelPart {
    z: String,
    contours: usize,
    contour_holes: usize,
    contour_area: String,
    regions_up: usize,
    regions_down: usize,
    regions_flat: usize,
    ridges: usize,
    extrema: usize,
    saddles: usize,
    below: usize,
    below_area: String,
    above: usize,
    above_area: String,
}

#[derive(Serialize)]
struct Verification {
    verifier: &'static str,
    verdict: &'static str,
    summary: String,
}

fn sha256(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

fn total_area(loops: &[wmslice::levelset::Loop]) -> String {
    rat_to_string(&wmslice::levelset::total_area(loops))
}

fn level_part(ls: &LevelSet) -> LevelPart {
    use wmslice::classify::Facing;
    let regions = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
    LevelPart {
        z: rat_to_string(&ls.level),
        contours: ls.contours.len(),
        contour_holes: ls.contours.iter().filter(|l| l.role == Role::Hole).count(),
        contour_area: total_area(&ls.contours),
        regions_up: regions(Facing::Up),
        regions_down: regions(Facing::Down),
        regions_flat: regions(Facing::Flat),
        ridges: ls.ridges.len(),
        extrema: ls.extrema.len(),
        saddles: ls.saddles.len(),
        below: ls.below.len(),
        below_area: total_area(&ls.below),
        above: ls.above.len(),
        above_area: total_area(&ls.above),
    }
}

/// The mesh as read, before snapping (re-read: `Input` keeps only the
/// snapped mesh).
fn original_mesh(a: &SliceArgs, input: &Input) -> Result<Mesh, Failure> {
    if input.file_bytes.is_empty() {
        return datasets::by_name(&a.mesh)
            .map(|d| d.build())
            .ok_or_else(|| anyhow!("dataset {} vanished", a.mesh))
            .tag(ExitCode::Internal);
    }
    let hint = Path::new(&a.mesh)
        .extension()
        .and_then(|e| e.to_str())
        .and_then(MeshFormat::from_extension);
    load_bytes(&input.file_bytes, hint)
        .map(|(m, _)| m)
        .tag(ExitCode::Input)
}

fn numeric(a: &SliceArgs, input: &Input) -> Result<Numeric, Failure> {
    let Some(q) = &input.unit else {
        return Ok(Numeric {
            mode: "exact",
            grid: None,
            largest_move: None,
            moved_vertices: None,
            merged_vertices: None,
            flipped_faces: input.flips.len(),
        });
    };
    let s = snap(&original_mesh(a, input)?, q).tag(ExitCode::InvalidMesh)?;
    Ok(Numeric {
        mode: "snapped",
        grid: Some(rat_to_string(q)),
        largest_move: Some(rat_to_string(&s.max_move)),
        moved_vertices: Some(s.moved),
        merged_vertices: Some(s.merged),
        flipped_faces: input.flips.len(),
    })
}

fn name_of<T: ValueEnum>(v: &T) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_owned())
        .unwrap_or_default()
}

/// Writes the certificate of a result whose bytes, exactly as written to
/// the output (file or stdout), are `result`.
pub fn write(
    path: &Path,
    a: &SliceArgs,
    input: &Input,
    levels: &[Rat],
    sets: &[LevelSet],
    result: &[u8],
) -> Result<(), Failure> {
    let header = MeshHeader::new(&input.mesh, input.unit.as_ref());
    let document = to_json(&header, sets, Exactness::WithExact);
    let report = verify(&input.mesh, input.unit.as_ref(), &document)
        .map_err(|e| anyhow!("the independent verifier could not read the result: {e} (internal error, please report)"))
        .tag(ExitCode::Internal)?;
    if !report.passed() {
        let list: Vec<String> = report.violations.iter().map(|v| v.to_string()).collect();
        return Err(Failure {
            code: ExitCode::Internal,
            error: anyhow!(
                "the independent verifier rejects the result (internal error, please report): {}\n{}",
                report.summary(),
                list.join("\n")
            ),
        });
    }
    let (kind, hashed, input_sha, bytes) = if input.file_bytes.is_empty() {
        (
            "dataset",
            "canonical mesh bytes (wmslice-mesh-v1) of the built-in dataset",
            mesh_sha256(&original_mesh(a, input)?),
            None,
        )
    } else {
        (
            "file",
            "file bytes",
            sha256(&input.file_bytes),
            Some(input.file_bytes.len()),
        )
    };
    let written = result.to_vec();
    let cert = Certificate {
        format: "wmslice-certificate",
        version: 1,
        tool: Tool {
            name: env!("CARGO_PKG_NAME"),
            version: env!("CARGO_PKG_VERSION"),
            commit: BUILD_COMMIT,
        },
        input: InputPart {
            name: a.mesh.clone(),
            kind,
            hashed,
            sha256: input_sha,
            bytes,
        },
        mesh: header,
        numeric: numeric(a, input)?,
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
            sha256: sha256(&written),
            bytes: written.len(),
            verified_document_sha256: sha256(document.as_bytes()),
        },
        levels: levels
            .iter()
            .zip(sets)
            .map(|(z, ls)| LevelPart {
                z: rat_to_string(z),
                ..level_part(ls)
            })
            .collect(),
        verification: Verification {
            verifier: "wmslice::verify (SPEC 7, invariants 1-4, exact)",
            verdict: "pass",
            summary: report.summary(),
        },
    };
    let text = serde_json::to_string_pretty(&cert)
        .map_err(|e| anyhow!("cannot serialize the certificate: {e}"))
        .tag(ExitCode::Internal)?
        + "\n";
    write_atomic(path, text.as_bytes())
        .map_err(|e| anyhow!("cannot write {}: {e}", path.display()))
        .tag(ExitCode::Output)
}
