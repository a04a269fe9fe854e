//! Input: a mesh as read (with the exact positions of the vertices that
//! have no exact double, from 3MF transforms: [`ExactPositions`]), an
//! optional snap grid and the [`Repairs`] the user asks for. Output: the
//! mesh as sliced, with what was done to it: when asked, its vertices at
//! exactly one point merged ([`CoincidentVertices::Weld`], exact; nothing
//! moves), then snapped to the grid when asked ([`crate::mesh::snap`], the
//! one reported rounding), then, when asked, rid of the faces that use one
//! vertex twice ([`CollapsedFaces::Drop`]), then rid of the degenerate
//! faces edge flips remove ([`crate::mesh::flip`], exact; the surface does
//! not move).
//!
//! Every front end (the command line, the Python package) takes a mesh
//! through these steps, so the mesh hash in a result is that of the same
//! mesh whichever one sliced it.

use crate::exact::rational::{rat_to_string, Rat};
use crate::ids::FaceId;
use crate::mesh::flip::{repair_degenerate, Flip};
use crate::mesh::io::{ExactPositions, LoadError};
use crate::mesh::snap::{snap_exact, SnapError};
use crate::mesh::weld::weld_coincident;
use crate::mesh::Mesh;
use std::borrow::Cow;

/// What snapping did (SPEC 2).
#[derive(Clone, Debug, PartialEq)]
pub struct SnapStats {
    /// The grid step `q`.
    pub grid: Rat,
    /// Vertices whose position changed.
    pub moved: usize,
    /// The largest change of a single coordinate, exact.
    pub max_move: Rat,
    /// Vertices merged into another one that landed on the same point.
    pub merged: usize,
}

/// What to do with faces that use one vertex twice (after welding or
/// snapping): a segment or a point, no area.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CollapsedFaces {
    /// Leave them: validation refuses each by name (SPEC 1).
    #[default]
    Refuse,
    /// Remove them before the edge flips and validation: the lenient mode
    /// SPEC 1 allows at the user's request. They have no area, so the
    /// solid the other faces bound is the same; what they held off those
    /// faces' edges (a loose segment or point) is gone. The faces after a
    /// removed one are renumbered, so face ids are those of the mesh as
    /// sliced.
    Drop,
}

/// What to do with distinct vertices that lie at exactly one point (equal
/// coordinates, `-0` and `+0` alike): an indexed file's seams, or a
/// triangle soup written with indices. SPEC 1 welds an STL's corners by
/// exact equality; indexed formats are taken as given unless the user
/// asks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoincidentVertices {
    /// Keep them apart: faces across them do not connect, and validation
    /// names the open edges (with the coincident vertices as a note).
    #[default]
    Keep,
    /// Merge them before anything else, as an STL's corners are: a lenient
    /// mode SPEC 1 allows at the user's request. No coordinate changes; the
    /// vertices are renumbered in first-seen order. A vertex whose exact
    /// position is not a double ([`ExactPositions`]) is never merged here
    /// (snapping merges it when it lands on another vertex's grid point).
    Weld,
}

/// The lenient repairs a user may ask for (SPEC 1), beside snapping. The
/// default makes none: the mesh is sliced as read or refused by name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Repairs {
    /// Vertices at one point: kept apart or welded (first).
    pub coincident: CoincidentVertices,
    /// Faces that use one vertex twice: refused or dropped (after welding
    /// and snapping, which can make them).
    pub collapsed: CollapsedFaces,
}

impl Repairs {
    /// The repairs a front end's flags ask for (`--weld`,
    /// `--drop-collapsed`).
    pub fn from_flags(weld: bool, drop_collapsed: bool) -> Self {
        Repairs {
            coincident: if weld {
                CoincidentVertices::Weld
            } else {
                CoincidentVertices::Keep
            },
            collapsed: if drop_collapsed {
                CollapsedFaces::Drop
            } else {
                CollapsedFaces::Refuse
            },
        }
    }
}

impl From<CollapsedFaces> for Repairs {
    fn from(collapsed: CollapsedFaces) -> Self {
        Repairs {
            collapsed,
            ..Repairs::default()
        }
    }
}

/// A mesh ready to slice.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The mesh as sliced (in grid units when snapped: true coordinate =
    /// stored value * `unit`).
    pub mesh: Mesh,
    /// The snap grid, when snapped.
    pub unit: Option<Rat>,
    /// What snapping did, when snapped.
    pub snap: Option<SnapStats>,
    /// With [`CoincidentVertices::Weld`], how many vertices were merged
    /// into an earlier one at the same point; `None` in the default mode.
    pub welded: Option<usize>,
    /// With [`CollapsedFaces::Drop`], the faces it removed, by their ids
    /// as read (snapping keeps the faces in order); `None` in the default
    /// mode.
    pub dropped: Option<Vec<FaceId>>,
    /// The edge flips that removed degenerate faces, in the order made.
    pub flips: Vec<Flip>,
}

/// Snaps `mesh` to the grid `q` when given, then removes the degenerate
/// faces edge flips can remove. A mesh validation would refuse (an index
/// out of range, a non-finite coordinate) comes back unrepaired, for
/// validation to name its defects; snapping refuses a non-finite
/// coordinate itself.
pub fn prepare(mesh: Mesh, q: Option<&Rat>) -> Result<Prepared, SnapError> {
    prepare_with(mesh, q, Repairs::default())
}

/// As [`prepare`], with the [`Repairs`] the user asks for.
pub fn prepare_with(mesh: Mesh, q: Option<&Rat>, repairs: Repairs) -> Result<Prepared, SnapError> {
    let none = ExactPositions::default();
    let (mesh, exact, welded) = weld_first(mesh, &none, repairs.coincident);
    let prepared = match q {
        None => repair(mesh, None, None, repairs.collapsed),
        Some(q) => on_grid(mesh, &exact, q, repairs.collapsed)?,
    };
    Ok(Prepared { welded, ..prepared })
}

/// Why a mesh read with its exact positions could not be prepared.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    /// Some vertex's exact position is not a double, and no grid was given
    /// to place it (the file's own error, naming the vertex).
    #[error(transparent)]
    NotDoubles(LoadError),
    /// Snapping failed.
    #[error(transparent)]
    Snap(#[from] SnapError),
}

/// As [`prepare`], for a mesh read with
/// [`crate::mesh::io::load_bytes_exact`]: on the grid `q` the vertices in
/// `exact` are snapped from their exact positions; without a grid they
/// have no exact place and the mesh is refused.
pub fn prepare_exact(
    mesh: Mesh,
    exact: &ExactPositions,
    q: Option<&Rat>,
) -> Result<Prepared, PrepareError> {
    prepare_exact_with(mesh, exact, q, Repairs::default())
}

/// As [`prepare_exact`], with the [`Repairs`] the user asks for.
pub fn prepare_exact_with(
    mesh: Mesh,
    exact: &ExactPositions,
    q: Option<&Rat>,
    repairs: Repairs,
) -> Result<Prepared, PrepareError> {
    let (mesh, exact, welded) = weld_first(mesh, exact, repairs.coincident);
    let prepared = match (q, exact.refusal()) {
        (Some(q), _) => on_grid(mesh, &exact, q, repairs.collapsed)?,
        (None, None) => repair(mesh, None, None, repairs.collapsed),
        (None, Some(e)) => return Err(PrepareError::NotDoubles(e)),
    };
    Ok(Prepared { welded, ..prepared })
}

/// The mesh with its coincident vertices merged when `coincident` says so
/// (`exact` renumbered with it), and how many were merged (`None`: not
/// asked).
fn weld_first(
    mesh: Mesh,
    exact: &ExactPositions,
    coincident: CoincidentVertices,
) -> (Mesh, Cow<'_, ExactPositions>, Option<usize>) {
    match coincident {
        CoincidentVertices::Keep => (mesh, Cow::Borrowed(exact), None),
        CoincidentVertices::Weld => {
            let w = weld_coincident(&mesh, exact);
            (w.mesh, Cow::Owned(w.exact), Some(w.merged))
        }
    }
}

/// Snaps to `q` (the vertices in `exact` from their exact positions), then
/// repairs.
fn on_grid(
    mesh: Mesh,
    exact: &ExactPositions,
    q: &Rat,
    collapsed: CollapsedFaces,
) -> Result<Prepared, SnapError> {
    let s = snap_exact(&mesh, exact, q)?;
    let faces = mesh.num_faces();
    let span = mesh
        .bounding_box()
        .map(|[lo, hi]| std::array::from_fn(|k| hi[k] - lo[k]))
        .unwrap_or_default();
    drop(mesh);
    let stats = SnapStats {
        grid: s.unit.clone(),
        moved: s.moved,
        max_move: s.max_move,
        merged: s.merged,
    };
    // Nothing is left to slice, dropped or not: say why once (the grid),
    // not once per face.
    if faces > 0 && s.mesh.faces.iter().all(|&f| is_collapsed(f)) {
        return Err(SnapError::CollapsedEverything {
            q: rat_to_string(q),
            faces,
            span,
        });
    }
    Ok(repair(s.mesh, Some(s.unit), Some(stats), collapsed))
}

/// Whether a face uses one vertex twice.
pub fn is_collapsed([a, b, c]: [crate::ids::VertexId; 3]) -> bool {
    a == b || b == c || a == c
}

/// Removes the collapsed faces when asked, then the degenerate faces edge
/// flips can remove.
fn repair(
    mut mesh: Mesh,
    unit: Option<Rat>,
    snap: Option<SnapStats>,
    collapsed: CollapsedFaces,
) -> Prepared {
    let dropped = (collapsed == CollapsedFaces::Drop).then(|| {
        let (mut dropped, mut id) = (Vec::new(), 0);
        mesh.faces.retain(|&f| {
            let keep = !is_collapsed(f);
            if !keep {
                dropped.push(FaceId::from_idx(id));
            }
            id += 1;
            keep
        });
        dropped
    });
    let r = repair_degenerate(&mesh);
    let flips = r.flips;
    let repaired = match r.mesh {
        Cow::Owned(m) => Some(m),
        Cow::Borrowed(_) => None,
    };
    Prepared {
        mesh: repaired.unwrap_or(mesh),
        unit,
        snap,
        welded: None,
        dropped,
        flips,
    }
}
