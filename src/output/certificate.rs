//! Input: what was sliced (the input's bytes or a built-in dataset, the
//! mesh as sliced, snapping and flips), the options, the level sets and
//! the result's bytes. Output: the `wmslice-certificate` JSON document:
//! the SHA-256 of the input (the file's bytes, or for a built-in dataset
//! its canonical mesh bytes) and of the result exactly as written, the
//! tool version and build commit, the levels as exact rationals, the
//! numeric mode (exact, or snapped to a grid with the largest coordinate
//! move), counts and exact areas per level, and the verdict of
//! [`crate::verify`] on the exact JSON of the result (whose SHA-256 is
//! given too). No time stamp and no absolute path: the same input and
//! options give the same bytes.
//!
//! Made by the command line (`slice --certificate`) and by the Python
//! package's batches, which verify a large part in shards of levels and
//! merge the verdicts ([`Verdict::merge`]: every check is per level).

use crate::exact::rational::{rat_to_string, Rat};
use crate::levelset::{total_area, LevelSet, Loop};
use crate::mesh::prepare::SnapStats;
use crate::mesh::Mesh;
use crate::nest::Role;
use crate::output::json::{hex, mesh_sha256, MeshHeader};
use crate::verify::report::{Checked, Report};
use crate::verify::{Verifier, VerifyError};
use serde::Serialize;
use sha2::{Digest, Sha256};

/// The build commit, when the build sets `WMSLICE_BUILD_COMMIT`.
const BUILD_COMMIT: Option<&str> = option_env!("WMSLICE_BUILD_COMMIT");

/// The certificate document.
#[derive(Clone, Debug, Serialize)]
pub struct Certificate {
    /// `"wmslice-certificate"`.
    pub format: &'static str,
    /// 1.
    pub version: u32,
    /// This tool.
    pub tool: Tool,
    /// The input as given.
    pub input: InputPart,
    /// The mesh as sliced (the result's header).
    pub mesh: MeshHeader,
    /// Exact coordinates or snapped, and the flips.
    pub numeric: Numeric,
    /// The options of the result.
    pub options: Options,
    /// The result as written.
    pub result: ResultPart,
    /// Counts and exact areas per level.
    pub levels: Vec<LevelPart>,
    /// The independent verifier's verdict.
    pub verification: Verification,
}

/// The tool that made the result.
#[derive(Clone, Debug, Serialize)]
pub struct Tool {
    /// `"wmslice"`.
    pub name: &'static str,
    /// The crate version.
    pub version: &'static str,
    /// The build commit, when known.
    pub commit: Option<&'static str>,
}

impl Tool {
    /// This build.
    pub fn this() -> Self {
        Tool {
            name: env!("CARGO_PKG_NAME"),
            version: env!("CARGO_PKG_VERSION"),
            commit: BUILD_COMMIT,
        }
    }
}

/// The input, as given.
#[derive(Clone, Debug, Serialize)]
pub struct InputPart {
    /// The mesh argument as typed.
    pub name: String,
    /// `file` or `dataset`.
    pub kind: &'static str,
    /// What `sha256` is the hash of.
    pub hashed: &'static str,
    /// The SHA-256.
    pub sha256: String,
    /// Size of the file (None for a dataset).
    pub bytes: Option<usize>,
}

impl InputPart {
    /// A file, by its bytes.
    pub fn file(name: String, bytes: &[u8]) -> Self {
        InputPart {
            name,
            kind: "file",
            hashed: "file bytes",
            sha256: sha256_hex(bytes),
            bytes: Some(bytes.len()),
        }
    }

    /// A built-in dataset, by its canonical mesh bytes as built (before
    /// snapping and flips).
    pub fn dataset(name: String, built: &Mesh) -> Self {
        InputPart {
            name,
            kind: "dataset",
            hashed: "canonical mesh bytes (wmslice-mesh-v1) of the built-in dataset",
            sha256: mesh_sha256(built),
            bytes: None,
        }
    }
}

/// How coordinates were taken.
#[derive(Clone, Debug, Serialize)]
pub struct Numeric {
    /// `exact` (coordinates as stored in the file) or `snapped`.
    pub mode: &'static str,
    /// The snap grid.
    pub grid: Option<String>,
    /// The largest coordinate move, exact.
    pub largest_move: Option<String>,
    /// Vertices moved by snapping.
    pub moved_vertices: Option<usize>,
    /// Vertices merged by snapping.
    pub merged_vertices: Option<usize>,
    /// Degenerate faces removed by edge flips (SPEC 1) before slicing.
    pub flipped_faces: usize,
}

impl Numeric {
    /// From what snapping did (if snapped) and the number of flips.
    pub fn new(snap: Option<&SnapStats>, flipped_faces: usize) -> Self {
        match snap {
            None => Numeric {
                mode: "exact",
                grid: None,
                largest_move: None,
                moved_vertices: None,
                merged_vertices: None,
                flipped_faces,
            },
            Some(s) => Numeric {
                mode: "snapped",
                grid: Some(rat_to_string(&s.grid)),
                largest_move: Some(rat_to_string(&s.max_move)),
                moved_vertices: Some(s.moved),
                merged_vertices: Some(s.merged),
                flipped_faces,
            },
        }
    }
}

/// The options of the result (as the command line names them).
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Output format (`json`, `summary`).
    pub format: String,
    /// Exact rationals in the output.
    pub exact: bool,
    /// The output path, as given (None for stdout).
    pub output: Option<String>,
    /// Which one-sided limit rendered formats draw.
    pub side: String,
    /// Ridges drawn.
    pub with_ridges: bool,
    /// Direction arrows drawn.
    pub arrows: bool,
}

/// The result as written.
#[derive(Clone, Debug, Serialize)]
pub struct ResultPart {
    /// `file` or `stdout`.
    pub destination: &'static str,
    /// SHA-256 of the bytes written.
    pub sha256: String,
    /// Their length.
    pub bytes: usize,
    /// SHA-256 of the exact JSON document that was verified.
    pub verified_document_sha256: String,
}

/// Counts and exact areas of one level.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct LevelPart {
    /// The level, exact.
    pub z: String,
    /// S_O loops.
    pub contours: usize,
    /// S_O holes.
    pub contour_holes: usize,
    /// S_O's exact total signed area.
    pub contour_area: String,
    /// Up-facing regions.
    pub regions_up: usize,
    /// Down-facing regions.
    pub regions_down: usize,
    /// Flat regions.
    pub regions_flat: usize,
    /// S_NO polylines.
    pub ridges: usize,
    /// P.
    pub extrema: usize,
    /// Saddles.
    pub saddles: usize,
    /// L- loops.
    pub below: usize,
    /// L-'s exact total signed area.
    pub below_area: String,
    /// L+ loops.
    pub above: usize,
    /// L+'s exact total signed area.
    pub above_area: String,
}

fn area_text(loops: &[Loop]) -> String {
    rat_to_string(&total_area(loops))
}

impl LevelPart {
    /// The counts and exact areas of a level set.
    pub fn of(ls: &LevelSet) -> Self {
        use crate::classify::Facing;
        let regions = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
        LevelPart {
            z: rat_to_string(&ls.level),
            contours: ls.contours.len(),
            contour_holes: ls.contours.iter().filter(|l| l.role == Role::Hole).count(),
            contour_area: area_text(&ls.contours),
            regions_up: regions(Facing::Up),
            regions_down: regions(Facing::Down),
            regions_flat: regions(Facing::Flat),
            ridges: ls.ridges.len(),
            extrema: ls.extrema.len(),
            saddles: ls.saddles.len(),
            below: ls.below.len(),
            below_area: area_text(&ls.below),
            above: ls.above.len(),
            above_area: area_text(&ls.above),
        }
    }

    /// As [`LevelPart::of`], with the level as requested (`z`).
    pub fn at(z: &Rat, ls: &LevelSet) -> Self {
        LevelPart {
            z: rat_to_string(z),
            ..LevelPart::of(ls)
        }
    }
}

/// The verifier's verdict, as written.
#[derive(Clone, Debug, Serialize)]
pub struct Verification {
    /// Which verifier.
    pub verifier: &'static str,
    /// `"pass"` (a result that fails is never certified).
    pub verdict: &'static str,
    /// The verifier's summary line.
    pub summary: String,
}

/// Why a result is not certified: an internal error either way.
#[derive(Debug, thiserror::Error)]
pub enum CertificateError {
    /// The verifier could not read the exact document.
    #[error(
        "the independent verifier could not read the result: {0} (internal error, please report)"
    )]
    Unreadable(#[from] VerifyError),
    /// The verifier found violations.
    #[error("the independent verifier rejects the result (internal error, please report): {summary}\n{}", violations.join("\n"))]
    Rejected {
        /// The verifier's summary.
        summary: String,
        /// Every violation.
        violations: Vec<String>,
    },
}

/// The verifier's verdict on one exact document, or on several holding
/// disjoint levels of one result (shards), merged.
#[derive(Clone, Debug, Default)]
pub struct Verdict {
    report: Report,
}

impl Verdict {
    /// Verifies an exact `wmslice-levelset` document.
    pub fn of(verifier: &Verifier<'_>, exact_document: &str) -> Result<Self, VerifyError> {
        Ok(Verdict {
            report: verifier.verify(exact_document)?,
        })
    }

    /// The verdict on the union of two documents' levels: every check of
    /// the verifier is made within one level (and the header check is the
    /// same for every shard), so counts add up and violations are kept.
    pub fn merge(mut self, other: Verdict) -> Self {
        let (a, b) = (&mut self.report.checked, other.report.checked);
        *a = Checked {
            levels: a.levels + b.levels,
            loops: a.loops + b.loops,
            points: a.points + b.points,
            regions: a.regions + b.regions,
            ridges: a.ridges + b.ridges,
            extrema: a.extrema + b.extrema,
            saddles: a.saddles + b.saddles,
        };
        self.report.violations.extend(other.report.violations);
        self
    }

    /// What was checked.
    pub fn checked(&self) -> Checked {
        self.report.checked
    }

    /// The verdict of documents that passed, checking what `checked` says
    /// (a shard's verdict, passed on by its counts).
    pub fn passed(checked: Checked) -> Self {
        Verdict {
            report: Report {
                checked,
                violations: Vec::new(),
            },
        }
    }

    /// The certificate's verification part, or the violations.
    pub fn into_verification(self) -> Result<Verification, CertificateError> {
        let r = self.report;
        if !r.passed() {
            return Err(CertificateError::Rejected {
                summary: r.summary(),
                violations: r.violations.iter().map(|v| v.to_string()).collect(),
            });
        }
        Ok(Verification {
            verifier: "wmslice::verify (SPEC 7, invariants 1-4, exact)",
            verdict: "pass",
            summary: r.summary(),
        })
    }
}

/// Lower-case hex SHA-256 of bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

impl Certificate {
    /// The document's text: pretty JSON and a final newline.
    pub fn to_json(&self) -> String {
        // Plain data with string keys: cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}
