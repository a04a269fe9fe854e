//! Input: a mesh (in stored units, with its snap grid if any) and a result
//! written by `wmslice slice --format json --exact` (SPEC section 9).
//! Output: a [`Report`] listing every violation of SPEC section 7,
//! invariants 1 to 4, with its level, family, loop and point.
//!
//! The verifier is independent of the code that produced the result: it
//! shares only the mesh loader and validation, the edge table
//! ([`Topology`](crate::mesh::topology::Topology)), the mesh fingerprint
//! ([`mesh_sha256`]) and the exact number types ([`crate::exact`]). It
//! re-derives what the level set must be from SPEC sections 3, 4 and 6
//! (module `facts`), reads the JSON with its own parser, which keeps every
//! number as the text written ([`json`]), one level at a time, and checks:
//!
//! - header: counts, mesh fingerprint, snap grid;
//! - every loop point lies on the element it claims (a strictly crossed
//!   edge or a vertex on the plane), its `exact` value is that element's
//!   exact point at the level, its `points` entry rounds to the nearest
//!   doubles; `area_exact` is the exact shoelace area;
//! - cover, closure and direction: the consecutive points of the loops of
//!   each family are exactly the pieces the mesh gives (S_O: crossed faces,
//!   transversal edges, region edges with material on both sides; dF: each
//!   region's boundary half-edges; L-, L+: the perturbed face walk, where
//!   unused pieces must cancel out); F, S_NO (maximal polylines), P and the
//!   saddles' branch counts, each element exactly once with the right kind;
//! - orientation: the exact signed area's sign against the role (and, for
//!   dF, the region's facing); roles and parents against exact containment;
//! - no crossing within S_O, L-, L+ or one region's dF (segments, and
//!   passes through a shared element), with a uniform grid.
//!
//! ```
//! use wmslice::output::json::{to_json, Exactness, MeshHeader};
//! use wmslice::{datasets, exact::parse_rational, verify::verify, Slicer};
//! let mesh = datasets::by_name("octahedron").unwrap().build();
//! let ls = Slicer::new(&mesh).unwrap().slice_at(&parse_rational("0").unwrap()).unwrap();
//! let text = to_json(&MeshHeader::new(&mesh, None), &[ls], Exactness::WithExact);
//! let report = verify(&mesh, None, &text).unwrap();
//! assert!(report.passed(), "{:?}", report.violations);
//! // Calling the outer contour a hole is caught.
//! let bad = text.replacen(r#""role":"outer""#, r#""role":"hole""#, 1);
//! assert_ne!(bad, text);
//! let report = verify(&mesh, None, &bad).unwrap();
//! assert!(!report.passed());
//! println!("{}", report.violations[0]); // level 0 (z = 0): S_O loop 0: hole loop has signed area 2: ...
//! ```

pub mod doc;
mod facts;
mod geometry;
pub mod json;
mod level;
mod limits;
pub mod report;

pub use doc::FormatError;
pub use json::JsonError;
pub use report::{Checked, Family, Place, Problem, Report, Violation};

use crate::exact::frame::Frame;
use crate::exact::rational::{rat_to_string, Rat};
use crate::mesh::validate::{accept, Defect, Tally};
use crate::mesh::Mesh;
use crate::output::json::mesh_sha256;
use num_traits::One;
use std::cell::OnceCell;

/// Why a result could not be verified at all (as opposed to a result that
/// was verified and found wrong: that is a [`Report`] with violations).
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// The result is not JSON.
    #[error(transparent)]
    Json(#[from] JsonError),
    /// The result is JSON but not a `wmslice-levelset` document with
    /// exact output.
    #[error("the result is not a wmslice-levelset document with exact output: {0}")]
    Format(#[from] FormatError),
    /// The mesh is rejected for slicing, so no result can be right for it.
    #[error("the mesh is not accepted for slicing ({}{count} blocking defect{}{}), so no result can be verified against it", if *tally == Tally::AtLeast { "at least " } else { "" }, if *count == 1 { "" } else { "s" }, first.as_ref().map(|d| format!("; first: {d}")).unwrap_or_default())]
    MeshRejected {
        /// The first blocking defect.
        first: Option<Defect>,
        /// How many blocking defects were found.
        count: usize,
        /// Whether `count` is exact or a lower bound.
        tally: Tally,
    },
}

/// Verifies a result text against the mesh it claims to slice. `mesh` is
/// in stored units; `unit` is the snap grid the result was computed with
/// (true coordinate = stored * unit), `None` when not snapped. The levels
/// are read and checked one at a time, so memory holds one level.
pub fn verify(mesh: &Mesh, unit: Option<&Rat>, text: &str) -> Result<Report, VerifyError> {
    Verifier::new(mesh, unit)?.verify(text)
}

/// [`verify`] for many results (or shards of one result's levels) against
/// one mesh: validation, the edge table and the mesh fingerprint are made
/// once.
pub struct Verifier<'m> {
    ctx: level::MeshCtx<'m>,
    unit: Option<Rat>,
    sha256: String,
}

impl<'m> Verifier<'m> {
    /// Validates the mesh (in stored units; `unit` the snap grid) and
    /// builds what every level shares.
    pub fn new(mesh: &'m Mesh, unit: Option<&Rat>) -> Result<Self, VerifyError> {
        Ok(Verifier {
            ctx: prepare(mesh, unit)?,
            unit: unit.cloned(),
            sha256: mesh_sha256(mesh),
        })
    }

    /// Verifies one result text, as [`verify`] does.
    pub fn verify(&self, text: &str) -> Result<Report, VerifyError> {
        self.verify_with(text, |_| {})
    }

    /// [`Verifier::verify`], calling `done(n)` after the `n`-th level is
    /// checked (for progress: [`outline`] gives the number of levels).
    pub fn verify_with(
        &self,
        text: &str,
        mut done: impl FnMut(usize),
    ) -> Result<Report, VerifyError> {
        let mut report = Report::default();
        let root = json::parse_streaming(text, "levels", |i, v| -> Result<(), VerifyError> {
            let l = doc::level(v, i)?;
            level::check_level(
                &self.ctx,
                i,
                &l,
                &mut report.violations,
                &mut report.checked,
            );
            done(i + 1);
            Ok(())
        })?;
        let header = doc::header(&root)?;
        let mut violations = check_header(self.ctx.mesh, self.unit.as_ref(), &self.sha256, &header);
        violations.append(&mut report.violations);
        report.violations = violations;
        Ok(report)
    }
}

/// The header of a result text (to learn its snap grid before loading the
/// mesh); the levels are read for syntax only, one at a time.
pub fn read_header(text: &str) -> Result<doc::HeaderDoc, VerifyError> {
    outline(text).map(|(header, _)| header)
}

/// [`read_header`], and how many levels the text holds.
pub fn outline(text: &str) -> Result<(doc::HeaderDoc, usize), VerifyError> {
    let mut levels = 0;
    let root = json::parse_streaming(text, "levels", |i, _| {
        levels = i + 1;
        Ok::<(), VerifyError>(())
    })?;
    Ok((doc::header(&root)?, levels))
}

/// As [`verify`], for an already parsed document.
pub fn verify_value(
    mesh: &Mesh,
    unit: Option<&Rat>,
    value: &json::Value,
) -> Result<Report, VerifyError> {
    let header = doc::header(value)?;
    let ctx = prepare(mesh, unit)?;
    let mut report = Report {
        violations: check_header(mesh, unit, &mesh_sha256(mesh), &header),
        ..Report::default()
    };
    let levels = value.get("levels").and_then(json::Value::as_array);
    for (i, v) in levels.into_iter().flatten().enumerate() {
        let l = doc::level(v.clone(), i)?;
        level::check_level(&ctx, i, &l, &mut report.violations, &mut report.checked);
    }
    Ok(report)
}

/// Validates the mesh and builds what every level shares.
fn prepare<'m>(mesh: &'m Mesh, unit: Option<&Rat>) -> Result<level::MeshCtx<'m>, VerifyError> {
    let topo = accept(mesh).map_err(|report| VerifyError::MeshRejected {
        first: report.errors().next().cloned(),
        count: report.errors().count() + report.unlisted_errors,
        tally: report.tally,
    })?;
    Ok(level::MeshCtx {
        frame: Frame::for_points(mesh.positions.iter().copied()),
        mesh,
        topo,
        unit: unit.cloned().unwrap_or_else(Rat::one),
        edge_index: OnceCell::new(),
    })
}

/// The header must describe the mesh verified against.
fn check_header(mesh: &Mesh, unit: Option<&Rat>, sha: &str, h: &doc::HeaderDoc) -> Vec<Violation> {
    let place = Place {
        level: None,
        family: Family::Header,
        item: None,
        sub: None,
        point: None,
    };
    let mut out = Vec::new();
    let mut push = |problem| {
        out.push(Violation {
            place: place.clone(),
            problem,
        })
    };
    for (what, claimed, actual) in [
        ("vertices", h.vertices, mesh.num_vertices()),
        ("faces", h.faces, mesh.num_faces()),
    ] {
        if claimed != actual as u64 {
            push(Problem::HeaderCount {
                what,
                claimed,
                actual,
            });
        }
    }
    if h.sha256 != sha {
        push(Problem::MeshHash {
            claimed: h.sha256.clone(),
            actual: sha.to_owned(),
        });
    }
    let grid = unit.map(rat_to_string);
    if h.snap != grid {
        push(Problem::Snap {
            claimed: h.snap.clone(),
            actual: grid,
        });
    }
    out
}
