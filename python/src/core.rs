//! Input: a mesh as read (or made from arrays) and an optional snap grid.
//! Output: a [`MeshCore`]: the mesh as sliced (snapped, degenerate faces
//! flipped: `wmslice::mesh::prepare`, as the command line does), validated,
//! with its topology, held with its [`Slicer`] for every later call, and
//! the JSON header made on first use.

use std::sync::OnceLock;
use wmslice::exact::rational::Rat;
use wmslice::ids::FaceId;
use wmslice::mesh::flip::Flip;
use wmslice::mesh::prepare::{prepare_with, Prepared, Repairs, SnapStats};
use wmslice::mesh::snap::SnapError;
use wmslice::mesh::validate::Report;
use wmslice::output::json::MeshHeader;
use wmslice::{Mesh, SliceError, Slicer};

/// The mesh and its grid unit (1 when not snapped): what the slicer borrows.
pub struct Owner {
    pub mesh: Mesh,
    pub unit: Rat,
}

type SlicerOf<'a> = Slicer<'a>;

self_cell::self_cell!(
    /// A mesh with the slicer made for it (validation and topology once).
    struct Cell {
        owner: Owner,
        #[covariant]
        dependent: SlicerOf,
    }
);

/// Why a mesh cannot be made ready.
pub enum CoreError {
    /// Snapping refused the grid or the mesh.
    Snap(SnapError),
    /// Validation refused the mesh.
    Invalid(Box<Report>),
    /// Any other slicer error (a bug).
    Internal(SliceError),
}

/// A mesh ready to slice.
pub struct MeshCore {
    cell: Cell,
    /// What snapping did, when snapped.
    pub snap: Option<SnapStats>,
    /// The degenerate faces removed by edge flips.
    pub flips: Vec<Flip>,
    /// How many vertices at one point were merged, when asked for
    /// (`weld`); `None` otherwise.
    pub welded: Option<usize>,
    /// The faces that used one vertex twice, removed (ids as given), when
    /// asked for (`drop_collapsed`); `None` otherwise.
    pub dropped: Option<Vec<FaceId>>,
    header: OnceLock<MeshHeader>,
}

impl MeshCore {
    /// Welds (when `repairs` says so), snaps (when `q` is given), removes
    /// collapsed faces (when `repairs` says so), flips degenerate faces,
    /// validates and builds the topology.
    pub fn new(mesh: Mesh, q: Option<&Rat>, repairs: Repairs) -> Result<Self, CoreError> {
        let p = prepare_with(mesh, q, repairs).map_err(CoreError::Snap)?;
        Self::prepared(p)
    }

    /// Validates a mesh already prepared (or unpickled: `unit` is its
    /// grid).
    pub fn prepared(p: Prepared) -> Result<Self, CoreError> {
        let Prepared {
            mesh,
            unit,
            snap,
            welded,
            dropped,
            flips,
        } = p;
        let owner = Owner {
            mesh,
            unit: unit.unwrap_or_else(|| Rat::from_integer(1.into())),
        };
        let cell =
            Cell::try_new(owner, |o| Slicer::with_unit(&o.mesh, o.unit.clone())).map_err(|e| {
                match e {
                    SliceError::InvalidMesh(r) => CoreError::Invalid(r),
                    other => CoreError::Internal(other),
                }
            })?;
        Ok(MeshCore {
            cell,
            snap,
            flips,
            welded,
            dropped,
            header: OnceLock::new(),
        })
    }

    /// The slicer.
    pub fn slicer(&self) -> &Slicer<'_> {
        self.cell.borrow_dependent()
    }

    /// The mesh as sliced (stored units).
    pub fn mesh(&self) -> &Mesh {
        &self.cell.borrow_owner().mesh
    }

    /// The grid unit: true coordinate = stored * unit.
    pub fn unit(&self) -> &Rat {
        &self.cell.borrow_owner().unit
    }

    /// The snap grid, when snapped.
    pub fn grid(&self) -> Option<&Rat> {
        self.snap.as_ref().map(|s| &s.grid)
    }

    /// The JSON header (the mesh's SHA-256 is computed on first use).
    pub fn header(&self) -> &MeshHeader {
        self.header.get_or_init(|| {
            MeshHeader::new(self.mesh(), self.grid())
                .with_repairs(self.welded, self.dropped.as_ref().map(Vec::len))
        })
    }
}
