//! Input: vertex signs (possibly perturbed), the classification of in-plane
//! edges. Output: the oriented pieces of S_O (and of L-, L+), each ending on
//! a mesh element: a crossed edge or a vertex on the plane.
//!
//! Orientation comes from the mesh alone (SPEC section 4): walking a crossed
//! face in its vertex order, its segment runs from where the walk passes
//! from + to - to where it passes from - to +. No arithmetic is done here.

use crate::classify::{EdgeClass, InPlaneEdge};
use crate::exact::Sign;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;

/// Where a segment ends: a strictly crossed edge, or a vertex on the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CutPoint {
    /// The crossing of an edge whose ends have opposite non-zero signs.
    OnEdge(EdgeId),
    /// A vertex with sign zero.
    AtVertex(VertexId),
}

/// What a segment runs through next to its ends: a face it crosses, or an
/// in-plane edge it lies on. This places it in the fan order of a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Via {
    /// The segment crosses this face.
    Face(FaceId),
    /// The segment lies on this edge.
    Edge(EdgeId),
}

/// An oriented piece of a contour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Segment {
    /// Start.
    pub from: CutPoint,
    /// End.
    pub to: CutPoint,
    /// The face crossed or the edge lain on.
    pub via: Via,
}

/// The mesh vertices that carry a cut point: the crossed edge's two ends,
/// or the vertex on the plane twice.
pub type Carrier = [VertexId; 2];

/// The S_O (or L-, L+) segment of face `f`, from its vertices `tri` and
/// their (possibly perturbed) signs `s`, if the signs change strictly;
/// with the vertices that carry its start and its end (so their points
/// can be computed, and crossings placed, without looking the edges up
/// again).
pub fn face_segment(
    topo: &Topology,
    f: FaceId,
    tri: [VertexId; 3],
    s: [Sign; 3],
) -> Option<(Segment, [Carrier; 2])> {
    let has = |x: Sign| s.contains(&x);
    if !(has(Sign::Positive) && has(Sign::Negative)) {
        return None;
    }
    // The crossing of corner i -> i + 1, with its edge's ends.
    let crossing = |i: usize| {
        (
            CutPoint::OnEdge(topo.face_edges[f.idx()][i]),
            [tri[i], tri[(i + 1) % 3]],
        )
    };
    let (start, end) = match s.iter().position(|&x| x == Sign::Zero) {
        None => {
            let mut start = None;
            let mut end = None;
            for i in 0..3 {
                match (s[i], s[(i + 1) % 3]) {
                    (Sign::Positive, Sign::Negative) => start = Some(crossing(i)),
                    (Sign::Negative, Sign::Positive) => end = Some(crossing(i)),
                    _ => {}
                }
            }
            (start?, end?)
        }
        Some(k) => {
            // The other two vertices carry + and -; the edge between them
            // (corner k+1 -> k+2) is crossed, the zero vertex is the other end.
            let i = (k + 1) % 3;
            let zero = (CutPoint::AtVertex(tri[k]), [tri[k]; 2]);
            if s[i] == Sign::Positive {
                (crossing(i), zero)
            } else {
                (zero, crossing(i))
            }
        }
    };
    Some((
        Segment {
            from: start.0,
            to: end.0,
            via: Via::Face(f),
        },
        [start.1, end.1],
    ))
}

/// The S_O segments that lie on in-plane edges: transversal edges, and
/// region boundary edges shared with S_O.
pub fn edge_segments(edges: &[InPlaneEdge]) -> impl Iterator<Item = Segment> + '_ {
    edges.iter().filter_map(|e| {
        let (from, to) = match e.class {
            EdgeClass::Transversal { from, to } => (from, to),
            EdgeClass::RegionBoundary {
                so: Some((from, to)),
                ..
            } => (from, to),
            _ => return None,
        };
        Some(Segment {
            from: CutPoint::AtVertex(from),
            to: CutPoint::AtVertex(to),
            via: Via::Edge(e.edge),
        })
    })
}
