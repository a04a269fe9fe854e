//! Input: mesh files or in-memory triangle soups. Output: a [`Mesh`] (vertex
//! positions exactly as read, faces as vertex-id triples), its
//! [`Topology`](topology::Topology) and its validation [`Report`](validate::Report).
//!
//! Nothing here rounds: positions are kept as the exact binary floating-point
//! values the file holds (every finite `f64` is an exact dyadic rational).

pub mod flip;
pub mod intersect;
pub mod io;
pub mod prepare;
pub mod shells;
pub mod snap;
pub mod topology;
pub mod validate;
pub mod weld;

use crate::exact::frame::Frame;
use crate::ids::VertexId;
use std::borrow::Cow;

/// A triangle mesh as read: positions and faces, not yet validated.
///
/// Faces are counter-clockwise seen from outside (outward normals) in an
/// accepted mesh; indices may be out of range here, validation reports it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, exact as read (or as snapped).
    pub positions: Vec<[f64; 3]>,
    /// Faces as vertex-id triples, in the file's vertex order.
    pub faces: Vec<[VertexId; 3]>,
}

impl Mesh {
    /// Builds a mesh from positions and `u32` index triples.
    pub fn from_raw(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Self {
        let faces = faces
            .into_iter()
            .map(|[a, b, c]| [VertexId(a), VertexId(b), VertexId(c)])
            .collect();
        Mesh { positions, faces }
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }

    /// The smallest and largest finite coordinate along x, y and z (exact:
    /// stored values), or `None` without a finite vertex.
    pub fn bounding_box(&self) -> Option<[[f64; 3]; 2]> {
        let mut it = self
            .positions
            .iter()
            .filter(|p| p.iter().all(|x| x.is_finite()));
        let first = *it.next()?;
        let mut bb = [first, first];
        for p in it {
            for k in 0..3 {
                bb[0][k] = bb[0][k].min(p[k]);
                bb[1][k] = bb[1][k].max(p[k]);
            }
        }
        Some(bb)
    }

    /// The position of a vertex (exact as stored).
    #[inline]
    pub fn pos(&self, v: VertexId) -> [f64; 3] {
        self.positions[v.idx()]
    }

    /// This mesh where the exact predicates take it fastest: every
    /// coordinate multiplied by one power of two
    /// ([`Frame::for_predicates`]) when some lies outside their range and
    /// such a frame exists, else the mesh itself. Exact (each placed
    /// coordinate is a normal double), so every orientation, comparison
    /// and equality of coordinates has the mesh's sign; lengths, areas and
    /// volumes are scaled.
    pub fn in_predicate_frame(&self) -> Cow<'_, Mesh> {
        match Frame::for_predicates(&self.positions) {
            Some(frame) if !frame.is_identity() => Cow::Owned(Mesh {
                positions: self
                    .positions
                    .iter()
                    .map(|p| p.map(|x| frame.place(x)))
                    .collect(),
                faces: self.faces.clone(),
            }),
            _ => Cow::Borrowed(self),
        }
    }
}
