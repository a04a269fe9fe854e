//! Input: a mesh as generated (and the snap grid its answers assume).
//! Output: its critical heights ([`crate::critical::analyze`]) and the answers:
//! at every critical height and at the midpoint between consecutive ones,
//! counts and exact areas of each part of the level set, re-checked by the
//! independent verifier before they are given.
//!
//! A height is critical when the level set there holds a face region
//! (F), a ridge or valley (S_NO), an extremum (P) or a saddle (2m >= 4
//! branches); `tests/families.rs` compares the list with an independent
//! exact classifier at every vertex height. Between two
//! consecutive critical heights the contours only move (SPEC 7, invariant
//! 5, holds across regular vertex heights too; `tests/families.rs` checks
//! that L- and L+ agree at every non-critical vertex height).
//!
//! The summary of each level is read from the `--exact` JSON document of
//! all listed levels after [`crate::verify::Verifier`] has passed it, so
//! every number given is one the verifier checked: loop counts, the exact
//! total signed area of each family of loops (outer loops positive, holes
//! negative; collapsed loops of L-, L+ count with their zero area), and
//! the exact unsigned area of the face regions.

use crate::datasets::families::Family;
use crate::exact::rational::{rat_to_string, Rat};
use crate::exact::{parse_rational, RationalParseError};
use crate::levelset::{SliceError, Slicer};
use crate::mesh::prepare::{prepare, Prepared};
use crate::mesh::snap::SnapError;
use crate::mesh::Mesh;
use crate::output::json::{to_json, Exactness, MeshHeader};
use crate::verify::doc::{document, LevelDoc, LoopDoc};
use crate::verify::{FormatError, JsonError, Verifier, VerifyError};
use num_traits::{One, Zero};
use serde::{Serialize, Serializer};

/// Why no answers could be given.
#[derive(Debug, thiserror::Error)]
pub enum AnswerError {
    /// Snapping refused the mesh.
    #[error(transparent)]
    Snap(#[from] SnapError),
    /// The slicer refused the mesh or failed.
    #[error(transparent)]
    Slice(#[from] SliceError),
    /// The critical-height sweep failed (a bug).
    #[error("finding the critical heights: {0}")]
    Critical(String),
    /// The verifier could not read the document.
    #[error(transparent)]
    Verify(#[from] VerifyError),
    /// The verified document could not be read back.
    #[error("reading the verified document back: {0}")]
    Reread(String),
    /// The verifier found the slicer's result wrong: an internal error.
    #[error(
        "the verifier rejects the answers (internal error, please report): {summary}\n{first}"
    )]
    Rejected {
        /// The verifier's summary line.
        summary: String,
        /// Its first violation.
        first: String,
    },
}

impl From<JsonError> for AnswerError {
    fn from(e: JsonError) -> Self {
        AnswerError::Reread(e.to_string())
    }
}

impl From<FormatError> for AnswerError {
    fn from(e: FormatError) -> Self {
        AnswerError::Reread(e.to_string())
    }
}

impl From<RationalParseError> for AnswerError {
    fn from(e: RationalParseError) -> Self {
        AnswerError::Reread(e.to_string())
    }
}

/// What is degenerate at a level, for grouping (`regular` when nothing;
/// `mixed` when more than one kind is present).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LevelKind {
    /// No face region, ridge, valley, extremum or saddle.
    Regular,
    /// Only up-facing face regions (material below).
    FlatUp,
    /// Only down-facing face regions (material above).
    FlatDown,
    /// Only ridges.
    Ridge,
    /// Only valleys.
    Valley,
    /// Only extremal points.
    Extremum,
    /// Only saddles.
    Saddle,
    /// Two or more of the above.
    Mixed,
}

fn ser_rat<S: Serializer>(r: &Rat, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&rat_to_string(r))
}

/// Counts and exact areas of one level set (the keys of the answers file).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Summary {
    /// S_O loops.
    #[serde(rename = "S_O_loops")]
    pub s_o_loops: usize,
    /// Total signed area of S_O, exact.
    #[serde(rename = "S_O_area", serialize_with = "ser_rat")]
    pub s_o_area: Rat,
    /// Face regions F.
    #[serde(rename = "F_regions")]
    pub f_regions: usize,
    /// Up-facing regions.
    #[serde(rename = "F_up")]
    pub f_up: usize,
    /// Down-facing regions.
    #[serde(rename = "F_down")]
    pub f_down: usize,
    /// Total unsigned area of F, exact.
    #[serde(rename = "F_area", serialize_with = "ser_rat")]
    pub f_area: Rat,
    /// S_NO polylines.
    #[serde(rename = "S_NO_polylines")]
    pub s_no_polylines: usize,
    /// Of which ridges.
    #[serde(rename = "S_NO_ridges")]
    pub s_no_ridges: usize,
    /// Of which valleys.
    #[serde(rename = "S_NO_valleys")]
    pub s_no_valleys: usize,
    /// Minima in P.
    #[serde(rename = "P_min")]
    pub p_min: usize,
    /// Maxima in P.
    #[serde(rename = "P_max")]
    pub p_max: usize,
    /// The m of each saddle (2m branches), ascending.
    pub saddles: Vec<u64>,
    /// L- loops (collapsed ones included).
    #[serde(rename = "L_minus_loops")]
    pub l_minus_loops: usize,
    /// Of which collapsed (zero area in the limit).
    #[serde(rename = "L_minus_collapsed")]
    pub l_minus_collapsed: usize,
    /// Total signed area of L-, exact.
    #[serde(rename = "L_minus_area", serialize_with = "ser_rat")]
    pub l_minus_area: Rat,
    /// L+ loops (collapsed ones included).
    #[serde(rename = "L_plus_loops")]
    pub l_plus_loops: usize,
    /// Of which collapsed.
    #[serde(rename = "L_plus_collapsed")]
    pub l_plus_collapsed: usize,
    /// Total signed area of L+, exact.
    #[serde(rename = "L_plus_area", serialize_with = "ser_rat")]
    pub l_plus_area: Rat,
}

impl Summary {
    /// The degeneracy kind of the level.
    pub fn kind(&self) -> LevelKind {
        let present = [
            (self.f_up > 0, LevelKind::FlatUp),
            (self.f_down > 0, LevelKind::FlatDown),
            (self.s_no_ridges > 0, LevelKind::Ridge),
            (self.s_no_valleys > 0, LevelKind::Valley),
            (self.p_min + self.p_max > 0, LevelKind::Extremum),
            (!self.saddles.is_empty(), LevelKind::Saddle),
        ];
        let mut kinds = present.iter().filter(|p| p.0).map(|p| p.1);
        match (kinds.next(), kinds.next()) {
            (None, _) => LevelKind::Regular,
            (Some(k), None) => k,
            _ => LevelKind::Mixed,
        }
    }

    /// Whether the level is critical: it holds F, S_NO, P or a saddle.
    pub fn is_critical(&self) -> bool {
        self.kind() != LevelKind::Regular
    }
}

fn loops_area(loops: &[LoopDoc]) -> Result<Rat, AnswerError> {
    loops
        .iter()
        .try_fold(Rat::zero(), |s, l| Ok(s + parse_rational(&l.area_exact)?))
}

/// The summary of one verified level, read from its document.
pub fn summarize(l: &LevelDoc) -> Result<Summary, AnswerError> {
    let facing = |f: &str| l.faces.iter().filter(|r| r.facing == f).count();
    let kind = |k: &str| l.ridges.iter().filter(|r| r.kind == k).count();
    let point = |k: &str| l.points.iter().filter(|p| p.kind == k).count();
    let f_area = l.faces.iter().try_fold(Rat::zero(), |s, r| {
        Ok::<_, AnswerError>(s + parse_rational(&r.area)?)
    })?;
    let mut saddles: Vec<u64> = l.saddles.iter().map(|s| s.branches / 2).collect();
    saddles.sort_unstable();
    Ok(Summary {
        s_o_loops: l.contours.len(),
        s_o_area: loops_area(&l.contours)?,
        f_regions: l.faces.len(),
        f_up: facing("up"),
        f_down: facing("down"),
        f_area,
        s_no_polylines: l.ridges.len(),
        s_no_ridges: kind("ridge"),
        s_no_valleys: kind("valley"),
        p_min: point("min"),
        p_max: point("max"),
        saddles,
        l_minus_loops: l.below.len(),
        l_minus_collapsed: l.below.iter().filter(|x| x.collapsed).count(),
        l_minus_area: loops_area(&l.below)?,
        l_plus_loops: l.above.len(),
        l_plus_collapsed: l.above.iter().filter(|x| x.collapsed).count(),
        l_plus_area: loops_area(&l.above)?,
    })
}

/// The listed levels: every critical height and the midpoint between
/// each consecutive pair, ascending, each with whether it is critical.
pub fn listed_levels(critical: &[Rat]) -> Vec<(Rat, bool)> {
    let two = Rat::from_integer(2.into());
    let mut out = Vec::with_capacity(2 * critical.len());
    for (k, c) in critical.iter().enumerate() {
        if k > 0 {
            out.push(((&critical[k - 1] + c) / &two, false));
        }
        out.push((c.clone(), true));
    }
    out
}

/// The answer at one level.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct LevelAnswer {
    /// The exact level (true units).
    #[serde(serialize_with = "ser_rat")]
    pub z: Rat,
    /// A critical height (else a midpoint between two).
    pub critical: bool,
    /// What is degenerate there.
    pub kind: LevelKind,
    /// Counts and exact areas.
    pub summary: Summary,
}

/// The answers for one mesh.
#[derive(Clone, Debug)]
pub struct Answers {
    /// The mesh as sliced (snapped when the family has a grid; degenerate
    /// faces flipped away, as every front end does).
    pub prepared: Prepared,
    /// The levels, ascending.
    pub levels: Vec<LevelAnswer>,
}

/// Slices `mesh` (snapped to `snap` first, when given) at its critical
/// heights and between them, verifies the exact result with the
/// independent verifier and summarises each level from the verified
/// document.
pub fn answers(mesh: Mesh, snap: Option<&Rat>) -> Result<Answers, AnswerError> {
    let prepared = prepare(mesh, snap)?;
    let unit = prepared.unit.clone().unwrap_or_else(Rat::one);
    let slicer = Slicer::with_unit(&prepared.mesh, unit)?;
    let critical: Vec<Rat> = crate::critical::analyze(&slicer)
        .map_err(|e| AnswerError::Critical(e.to_string()))?
        .levels
        .into_iter()
        .map(|l| l.z)
        .collect();
    let listed = listed_levels(&critical);
    let sets = listed
        .iter()
        .map(|(z, _)| slicer.slice_at(z))
        .collect::<Result<Vec<_>, _>>()?;
    let header = MeshHeader::new(&prepared.mesh, prepared.unit.as_ref());
    let text = to_json(&header, &sets, Exactness::WithExact);
    let report = Verifier::new(&prepared.mesh, prepared.unit.as_ref())?.verify(&text)?;
    if !report.passed() {
        return Err(AnswerError::Rejected {
            summary: report.summary(),
            first: report
                .violations
                .first()
                .map(ToString::to_string)
                .unwrap_or_default(),
        });
    }
    let doc = document(&crate::verify::json::parse(&text)?)?;
    let levels = listed
        .into_iter()
        .zip(&doc.levels)
        .map(|((z, critical), l)| {
            let summary = summarize(l)?;
            Ok(LevelAnswer {
                z,
                critical,
                kind: summary.kind(),
                summary,
            })
        })
        .collect::<Result<Vec<_>, AnswerError>>()?;
    Ok(Answers { prepared, levels })
}

#[derive(Serialize)]
struct AnswersDoc<'a> {
    format: &'static str,
    version: u32,
    family: &'a str,
    seed: u64,
    mesh: MeshHeader,
    areas: &'static str,
    levels: &'a [LevelAnswer],
}

/// What the areas in an answers file are.
pub const AREAS_NOTE: &str = "exact p/q; S_O, L-, L+: total signed area of the loops (outer +, hole -; collapsed loops 0); F: total unsigned area";

impl Answers {
    /// The answers file (`"format": "wmslice-answers"`): the family, the
    /// seed, the header of the mesh as sliced (its snap grid included) and
    /// one entry per level. Deterministic text.
    pub fn to_json(&self, family: &Family, seed: u64) -> String {
        let doc = AnswersDoc {
            format: "wmslice-answers",
            version: 1,
            family: family.name,
            seed,
            mesh: MeshHeader::new(&self.prepared.mesh, self.prepared.unit.as_ref()),
            areas: AREAS_NOTE,
            levels: &self.levels,
        };
        let mut s = serde_json::to_string_pretty(&doc).expect("plain data serialises");
        s.push('\n');
        s
    }
}
