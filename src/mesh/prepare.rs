//! Input: a mesh as read (with the exact positions of the vertices that
//! have no exact double, from 3MF transforms: [`ExactPositions`]) and an
//! optional snap grid. Output: the mesh as sliced, with what was done to
//! it: snapped to the grid when asked ([`crate::mesh::snap`], the one
//! reported rounding), then rid of the degenerate faces edge flips remove
//! ([`crate::mesh::flip`], exact; the surface does not move).
//!
//! Every front end (the command line, the Python package) takes a mesh
//! through these steps, so the mesh hash in a result is that of the same
//! mesh whichever one sliced it.

use crate::exact::rational::Rat;
use crate::mesh::flip::{repair_degenerate, Flip};
use crate::mesh::io::{ExactPositions, LoadError};
use crate::mesh::snap::{snap_exact, SnapError};
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
    /// The edge flips that removed degenerate faces, in the order made.
    pub flips: Vec<Flip>,
}

/// Snaps `mesh` to the grid `q` when given, then removes the degenerate
/// faces edge flips can remove. A mesh validation would refuse (an index
/// out of range, a non-finite coordinate) comes back unrepaired, for
/// validation to name its defects; snapping refuses a non-finite
/// coordinate itself.
pub fn prepare(mesh: Mesh, q: Option<&Rat>) -> Result<Prepared, SnapError> {
    match q {
        None => Ok(repair(mesh, None, None)),
        Some(q) => on_grid(mesh, &ExactPositions::default(), q),
    }
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
    match (q, exact.refusal()) {
        (Some(q), _) => Ok(on_grid(mesh, exact, q)?),
        (None, None) => Ok(repair(mesh, None, None)),
        (None, Some(e)) => Err(PrepareError::NotDoubles(e)),
    }
}

/// Snaps to `q` (the vertices in `exact` from their exact positions), then
/// repairs.
fn on_grid(mesh: Mesh, exact: &ExactPositions, q: &Rat) -> Result<Prepared, SnapError> {
    let s = snap_exact(&mesh, exact, q)?;
    drop(mesh);
    let stats = SnapStats {
        grid: s.unit.clone(),
        moved: s.moved,
        max_move: s.max_move,
        merged: s.merged,
    };
    Ok(repair(s.mesh, Some(s.unit), Some(stats)))
}

/// Removes the degenerate faces edge flips can remove.
fn repair(mesh: Mesh, unit: Option<Rat>, snap: Option<SnapStats>) -> Prepared {
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
        flips,
    }
}
