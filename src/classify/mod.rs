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
use crate::mesh::Mesh;

pub use edges::{EdgeClass, InPlaneEdge, RidgeKind};
pub use faces::{Facing, Region};
pub use vertices::{Extremum, ExtremumKind};

/// The exact sign of `h(v) - c` for every vertex.
pub fn vertex_signs(mesh: &Mesh, level: &Level) -> Vec<Sign> {
    mesh.positions.iter().map(|p| level.sign_of(p[2])).collect()
}
