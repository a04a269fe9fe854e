//! Input: a mesh argument (a file or a built-in dataset name), an optional
//! snap grid and the repairs asked for (`--weld`, `--drop-collapsed`).
//! Output: the mesh to slice, with notes for the user.
//!
//! Every command that loads a mesh (check, slice, critical, verify) takes
//! it through the same steps (`wmslice::mesh::prepare`): read, weld when
//! asked, snap when asked, remove collapsed faces when asked, then remove
//! degenerate faces by edge flips (SPEC 1; `wmslice::mesh::flip`), so that
//! the mesh hash in a result and the one `verify` computes are those of
//! the mesh as sliced.

use super::{ExitCode, Failure, Tag};
use anyhow::anyhow;
use std::path::Path;
use wmslice::datasets;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::mesh::flip::Flip;
use wmslice::mesh::io::{load_bytes_exact, ExactPositions, MeshFormat};
use wmslice::mesh::prepare::{
    is_collapsed, prepare_exact_with, CoincidentVertices, PrepareError, Repairs, SnapStats,
};
use wmslice::mesh::snap::SnapError;
use wmslice::output::json::MeshHeader;
use wmslice::{FaceId, Mesh};

/// A mesh as given on the command line: a file, or a built-in dataset.
pub struct Input {
    /// The mesh (in grid units when snapped).
    pub mesh: Mesh,
    /// The snap grid, if any.
    pub unit: Option<Rat>,
    /// What snapping did, if snapped.
    pub snap: Option<SnapStats>,
    /// What loading did, for the user.
    pub notes: Vec<String>,
    /// The bytes of the input file (empty for a built-in dataset).
    pub file_bytes: Vec<u8>,
    /// The edge flips that removed degenerate faces, in the order made.
    pub flips: Vec<Flip>,
    /// How many vertices `--weld` merged; `None` when not asked.
    pub welded: Option<usize>,
    /// The faces that used one vertex twice, removed (ids as read), when
    /// `--drop-collapsed` asked; `None` in the default mode.
    pub dropped: Option<Vec<FaceId>>,
}

/// At most this many flips or removed faces are listed in a note; the rest
/// are counted.
const LISTED: usize = 10;

/// The first [`LISTED`] items, then how many more.
fn listed<T: std::fmt::Display>(items: &[T]) -> String {
    let mut text: Vec<String> = items.iter().take(LISTED).map(T::to_string).collect();
    if items.len() > LISTED {
        text.push(format!("and {} more", items.len() - LISTED));
    }
    text.join(", ")
}

/// The note on the degenerate faces removed by edge flips.
fn flips_note(flips: &[Flip]) -> String {
    format!(
        "flipped {} degenerate faces (a vertex inside the opposite edge; the surface does not move): {}",
        flips.len(),
        listed(flips)
    )
}

/// How many faces use one vertex twice (by id).
fn collapsed_faces(mesh: &wmslice::mesh::Mesh) -> usize {
    mesh.faces.iter().filter(|&&f| is_collapsed(f)).count()
}

/// The note on the faces `--drop-collapsed` removed.
fn dropped_note(dropped: &[FaceId]) -> String {
    format!(
        "removed {} faces that use one vertex twice (no area; ids as read, later faces renumbered): {}",
        dropped.len(),
        listed(dropped)
    )
}

/// Everything on standard input (a mesh or a result given as `-`).
pub fn read_stdin() -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)?;
    Ok(bytes)
}

/// Reads the mesh, welds it when asked, snaps it when asked, removes
/// collapsed faces when asked and degenerate faces by flips
/// ([`wmslice::mesh::prepare`]), with notes for the user.
pub fn load_input(spec: &str, snap_arg: Option<&str>, repairs: Repairs) -> Result<Input, Failure> {
    let path = Path::new(spec);
    let mut notes = Vec::new();
    let mut file_bytes = Vec::new();
    let q = snap_arg
        .map(|q| parse_rational(q).tag(ExitCode::Usage))
        .transpose()?;
    // `-` is standard input (a file named `-` is `./-`), its format
    // recognised by content.
    let stdin = spec == "-";
    let (mesh, exact) = if stdin || path.exists() {
        file_bytes = if stdin {
            read_stdin().map_err(|e| anyhow!("cannot read standard input: {e}"))
        } else {
            wmslice::mesh::io::read_file(path).map_err(|e| anyhow!("cannot read {spec}: {e}"))
        }
        .tag(ExitCode::Input)?;
        let hint = path
            .extension()
            .and_then(|e| e.to_str())
            .and_then(MeshFormat::from_extension);
        let (mesh, report, exact) = load_bytes_exact(&file_bytes, hint).tag(ExitCode::Input)?;
        let name = if stdin { "standard input" } else { spec };
        notes.push(format!("read {name} as {}", report.format));
        notes.extend(report.notes.iter().map(|n| n.to_string()));
        if !exact.is_empty() {
            notes.push(format!(
                "{} vertices placed by a transform have no exact double: snapped from their exact positions",
                exact.len()
            ));
        }
        (mesh, exact)
    } else if let Some(d) = datasets::by_name(spec) {
        notes.push(format!("built-in dataset {}", d.name));
        (d.build(), ExactPositions::default())
    } else {
        return Err(Failure {
            code: ExitCode::Input,
            error: anyhow!("no such file or built-in dataset: {spec} (see `wmslice gen --list`)"),
        });
    };
    let collapsed_before = collapsed_faces(&mesh);
    let p = prepare_exact_with(mesh, &exact, q.as_ref(), repairs).map_err(|e| match e {
        PrepareError::NotDoubles(e) => Failure {
            code: ExitCode::Input,
            error: e.into(),
        },
        // A grid of zero or below is the argument's fault, not the mesh's.
        PrepareError::Snap(e @ SnapError::NonPositive(_)) => Failure {
            code: ExitCode::Usage,
            error: e.into(),
        },
        PrepareError::Snap(e) => Failure {
            code: ExitCode::InvalidMesh,
            error: e.into(),
        },
    })?;
    if let Some(w) = p.welded {
        notes.push(format!(
            "welded {w} vertices into an earlier vertex at exactly the same point (exact: nothing moved; vertices renumbered in first-seen order)"
        ));
    }
    if let Some(s) = &p.snap {
        notes.push(format!(
            "snapped to grid {}: {} vertices moved, largest coordinate move {} (~{}), {} vertices merged",
            rat_to_string(&s.grid),
            s.moved,
            rat_to_string(&s.max_move),
            rat_to_f64(&s.max_move),
            s.merged
        ));
    }
    let collapsed = collapsed_faces(&p.mesh);
    let made = collapsed.saturating_sub(collapsed_before);
    let welding = repairs.coincident == CoincidentVertices::Weld;
    if made > 0 && p.snap.is_none() && welding {
        notes.push(format!(
            "welding merged two corners of {made} faces: each repeats a vertex, which validation refuses; --drop-collapsed removes them (they have no area)"
        ));
    } else if made > 0 {
        let (by, point) = if welding {
            ("welding or snapping", "point")
        } else {
            ("snapping", "grid point")
        };
        notes.push(format!(
            "{by} put two corners of {made} faces on one {point}: each repeats a vertex, which validation refuses; a finer grid keeps them apart, or --drop-collapsed removes them"
        ));
    } else if collapsed > 0 {
        notes.push(format!(
            "{collapsed} faces use one vertex twice, which validation refuses; --drop-collapsed removes them (they have no area)"
        ));
    }
    let dropped = p.dropped;
    if let Some(d) = dropped.as_deref().filter(|d| !d.is_empty()) {
        notes.push(dropped_note(d));
    }
    if !p.flips.is_empty() {
        notes.push(flips_note(&p.flips));
    }
    Ok(Input {
        mesh: p.mesh,
        unit: p.unit,
        snap: p.snap,
        notes,
        file_bytes,
        flips: p.flips,
        welded: p.welded,
        dropped,
    })
}

impl Input {
    /// The JSON header of the mesh as sliced.
    pub fn header(&self) -> MeshHeader {
        MeshHeader::new(&self.mesh, self.unit.as_ref())
            .with_repairs(self.welded, self.dropped.as_ref().map(Vec::len))
    }
}
