//! Input: vertex signs, the edge table and the face regions.
//! Output: the class of every in-plane edge (both ends on the plane),
//! decided once per edge from the signs of its two opposite vertices
//! (SPEC section 3, edge table).

use super::faces::{Facing, Region};
use super::Signs;
use crate::exact::Sign;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;
use rustc_hash::FxHashMap as HashMap;

/// Ridge or valley: the two kinds of 1D extremum S_NO.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RidgeKind {
    /// Both neighbours below: a local maximum along the edge.
    Ridge,
    /// Both neighbours above: a local minimum.
    Valley,
}

/// The class of an in-plane edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeClass {
    /// Both faces in F (then in one region): interior, not reported.
    Interior,
    /// S_NO: a ridge or valley.
    Extremal(RidgeKind),
    /// S_O lying on the edge, running `from -> to` (material on its left).
    Transversal {
        /// Start.
        from: VertexId,
        /// End.
        to: VertexId,
    },
    /// A boundary edge of face region `region` (dF). When material lies on
    /// both sides of the plane next to it, it is also in S_O, running as
    /// `so` says.
    RegionBoundary {
        /// The region's index.
        region: u32,
        /// The S_O direction `(from, to)` when the edge is shared with S_O.
        so: Option<(VertexId, VertexId)>,
    },
}

/// An in-plane edge with its class.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InPlaneEdge {
    /// The edge.
    pub edge: EdgeId,
    /// Its class.
    pub class: EdgeClass,
}

/// Classifies the in-plane edges `candidates` (edges whose two ends have
/// sign zero).
pub fn classify_edges(
    topo: &Topology,
    signs: &Signs<'_>,
    candidates: &[EdgeId],
    regions: &[Region],
    region_of: &HashMap<FaceId, u32>,
) -> Vec<InPlaneEdge> {
    let mut out = Vec::with_capacity(candidates.len());
    for &e in candidates {
        let edge = topo.edge(e);
        let [a, b] = edge.v;
        let r0 = region_of.get(&edge.faces[0]).copied();
        let r1 = region_of.get(&edge.faces[1]).copied();
        let s0 = signs.of(edge.opposite[0]);
        let s1 = signs.of(edge.opposite[1]);
        let class = match (r0, r1) {
            (Some(_), Some(_)) => EdgeClass::Interior,
            (Some(r), None) | (None, Some(r)) => {
                // The region face is faces[k]; it runs (a -> b) when k = 0.
                let (k, other_sign) = if r0.is_some() { (0, s1) } else { (1, s0) };
                let (from, to) = if k == 0 { (a, b) } else { (b, a) };
                let so = match (regions[r as usize].facing, other_sign) {
                    // Up face (material below) with material also above:
                    // S_O runs opposite to dF.
                    (Facing::Up, Sign::Positive) => Some((to, from)),
                    // Down face (material above) with its neighbour below:
                    // S_O runs with dF.
                    (Facing::Down, Sign::Negative) => Some((from, to)),
                    _ => None,
                };
                EdgeClass::RegionBoundary { region: r, so }
            }
            (None, None) => match (s0, s1) {
                (Sign::Negative, Sign::Negative) => EdgeClass::Extremal(RidgeKind::Ridge),
                (Sign::Positive, Sign::Positive) => EdgeClass::Extremal(RidgeKind::Valley),
                // The transversal edge runs the way the face whose opposite
                // vertex is above traverses it (SPEC section 4; derived from
                // the face-walk rule under either perturbation).
                (Sign::Positive, Sign::Negative) => EdgeClass::Transversal { from: a, to: b },
                (Sign::Negative, Sign::Positive) => EdgeClass::Transversal { from: b, to: a },
                // An opposite vertex on the plane puts its face in F.
                _ => EdgeClass::Interior,
            },
        };
        out.push(InPlaneEdge { edge: e, class });
    }
    out
}
