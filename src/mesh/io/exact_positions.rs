//! The vertices of a mesh as read whose exact position, as the file
//! defines it, is not a double: the images of 3MF vertices under a build
//! or component transform whose result rounds (in practice every object
//! a slicer placed on its bed by a translation).
//!
//! SPEC 2 takes coordinates either exactly as doubles or snapped to a
//! grid. Such a vertex has no exact double, so it can only be snapped,
//! from its exact value ([`crate::mesh::prepare::prepare_exact`]); without
//! a grid it is refused ([`ExactPositions::refusal`]). The mesh beside it
//! holds the nearest doubles, a placeholder nothing is computed from.

use super::LoadError;
use crate::exact::rational::Rat;
use crate::ids::VertexId;

/// Where a file names a vertex placed by a transform (3MF).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct PlacedVertex {
    /// The build item (0-based).
    pub(super) item: usize,
    /// The mesh object whose vertex it is.
    pub(super) object: u64,
    /// The vertex's position in that object.
    pub(super) vertex: usize,
}

impl PlacedVertex {
    /// The refusal of this vertex's position: not a double.
    pub(super) fn error(self) -> LoadError {
        LoadError::InexactTransform {
            item: self.item,
            object: self.object,
            vertex: self.vertex,
        }
    }
}

/// Vertices whose exact position is not a double, with that position.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExactPositions {
    /// The first such vertex, as the file names it.
    first: Option<PlacedVertex>,
    /// Vertex id and exact position, in increasing id order.
    positions: Vec<(VertexId, [Rat; 3])>,
}

impl ExactPositions {
    /// Records `vertex`'s exact position; ids must come in increasing order.
    pub(super) fn push(&mut self, vertex: VertexId, at: PlacedVertex, exact: [Rat; 3]) {
        debug_assert!(self.positions.last().is_none_or(|(v, _)| *v < vertex));
        self.first.get_or_insert(at);
        self.positions.push((vertex, exact));
    }

    /// Records `vertex`'s exact position with no place in a file (tests).
    #[cfg(test)]
    pub(crate) fn push_for_test(&mut self, vertex: VertexId, exact: [Rat; 3]) {
        let at = PlacedVertex {
            item: 0,
            object: 0,
            vertex: vertex.idx(),
        };
        self.push(vertex, at, exact);
    }

    /// No vertex needs its exact position: the mesh's doubles are exact.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// How many vertices have no exact double.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// The same positions with every vertex `v` renamed `new_id[v]`, for a
    /// renumbering that keeps these vertices in order (welding never merges
    /// them, and keeps first-seen order).
    pub(crate) fn renumbered(&self, new_id: &[u32]) -> Self {
        ExactPositions {
            first: self.first,
            positions: self
                .positions
                .iter()
                .map(|(v, p)| {
                    (
                        new_id.get(v.idx()).map_or(*v, |&id| VertexId(id)),
                        p.clone(),
                    )
                })
                .collect(),
        }
    }

    /// The vertices and their exact positions, in increasing id order.
    pub fn iter(&self) -> impl Iterator<Item = &(VertexId, [Rat; 3])> {
        self.positions.iter()
    }

    /// The error for slicing without a grid: the first such vertex, named
    /// as the file names it. `None` when there is none.
    pub fn refusal(&self) -> Option<LoadError> {
        self.first.map(PlacedVertex::error)
    }
}
