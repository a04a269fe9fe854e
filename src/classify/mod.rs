//! Input: a valid mesh, its topology and an exact level `c`.
//! Output: the weak-Morse classification of SPEC section 3: vertex signs,
//! face regions F (with facing and boundary edges dF), in-plane edges
//! (interior of F, boundary of F, ridge/valley S_NO, transversal S_O) and
//! extremal vertices P.
//!
//! Every decision is an exact sign. An in-plane edge is decided once, by
//! the edge table, never once per face (SPEC section 8).

pub mod edges;
pub mod faces;
pub mod vertices;

use crate::exact::{Level, Sign};
use crate::ids::VertexId;
use crate::mesh::Mesh;

pub use edges::{EdgeClass, InPlaneEdge, RidgeKind};
pub use faces::{Facing, Region};
pub use vertices::{Extremum, ExtremumKind};

/// The exact sign of `h(v) - c` for every vertex.
pub fn vertex_signs(mesh: &Mesh, level: &Level) -> Vec<Sign> {
    mesh.positions.iter().map(|p| level.sign_of(p[2])).collect()
}

/// Which way a zero sign is perturbed for a one-sided limit (SPEC
/// section 6, the project's one perturbation rule).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// L-: the contour at `c - epsilon`; vertices on the plane count as above.
    Below,
    /// L+: the contour at `c + epsilon`; vertices on the plane count as below.
    Above,
}

impl Side {
    /// The perturbed sign of a vertex.
    #[inline]
    pub fn perturb(self, s: Sign) -> Sign {
        match (s, self) {
            (Sign::Zero, Side::Below) => Sign::Positive,
            (Sign::Zero, Side::Above) => Sign::Negative,
            (s, _) => s,
        }
    }
}

/// The signs of vertices at one level, computed on demand (two float
/// comparisons each, exact), optionally perturbed to one side. A view, so a
/// layer touches only the vertices of its active faces.
#[derive(Clone, Copy, Debug)]
pub struct Signs<'a> {
    mesh: &'a Mesh,
    level: &'a Level,
    side: Option<Side>,
}

impl<'a> Signs<'a> {
    /// Exact signs at `level`.
    pub fn new(mesh: &'a Mesh, level: &'a Level) -> Self {
        Signs {
            mesh,
            level,
            side: None,
        }
    }

    /// The same signs with zeros perturbed to `side`.
    pub fn perturbed(self, side: Side) -> Self {
        Signs {
            side: Some(side),
            ..self
        }
    }

    /// `sign(h(v) - c)`, perturbed if this view is.
    #[inline]
    pub fn of(&self, v: VertexId) -> Sign {
        let s = self.level.sign_of(self.mesh.positions[v.idx()][2]);
        match self.side {
            Some(side) => side.perturb(s),
            None => s,
        }
    }

    /// Whether `v` lies on the plane (unperturbed).
    #[inline]
    pub fn is_zero(&self, v: VertexId) -> bool {
        self.level.sign_of(self.mesh.positions[v.idx()][2]) == Sign::Zero
    }
}
