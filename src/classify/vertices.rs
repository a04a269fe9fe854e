//! Input: vertex signs and fans. Output: the isolated extremal vertices P
//! (all neighbours strictly above: minimum; all strictly below: maximum).

use super::Signs;
use crate::exact::Sign;
use crate::ids::VertexId;
use crate::mesh::topology::Topology;

/// Minimum or maximum.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ExtremumKind {
    /// Every neighbour strictly above.
    Min,
    /// Every neighbour strictly below.
    Max,
}

/// An isolated extremal vertex on the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Extremum {
    /// The vertex.
    pub vertex: VertexId,
    /// Its kind.
    pub kind: ExtremumKind,
}

/// The extremum kind of an on-plane vertex, if any. Vertices with an empty
/// fan (unused) are never extrema.
pub fn extremum_kind(topo: &Topology, signs: &Signs<'_>, v: VertexId) -> Option<ExtremumKind> {
    let fan = topo.fan(v);
    let first = signs.of(fan.first()?.neighbour);
    if first == Sign::Zero || fan.iter().any(|e| signs.of(e.neighbour) != first) {
        return None;
    }
    Some(match first {
        Sign::Positive => ExtremumKind::Min,
        _ => ExtremumKind::Max,
    })
}
