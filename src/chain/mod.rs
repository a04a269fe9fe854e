//! Input: oriented segments that end on mesh elements. Output: closed
//! loops, as lists of segment indices, joined by topology alone.
//!
//! The project's one tie-break for chaining (SPEC section 5) lives here:
//! at an edge crossing there is one segment in and one out; at a vertex
//! with several branches, the branches are listed in fan order and read as
//! balanced parentheses (incoming opens, outgoing closes the latest open
//! one), and each closed pair joins. No coordinate is compared.

use crate::ids::VertexId;
use crate::mesh::topology::Topology;
use crate::segment::{CutPoint, Segment, Via};
use rustc_hash::FxHashMap as HashMap;

/// A chaining failure: the segments do not form closed loops. This is an
/// internal error (a bug in classification), never a user error.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ChainError {
    /// Different numbers of segments arrive at and leave a cut point.
    #[error("{incoming} segments arrive at {at:?} but {outgoing} leave it (internal error, please report)")]
    Unbalanced {
        /// The cut point.
        at: CutPoint,
        /// Arriving segments.
        incoming: usize,
        /// Leaving segments.
        outgoing: usize,
    },
    /// A branch at a vertex is not on any face or edge of its fan.
    #[error("a branch at {vertex} is not in its fan (internal error, please report)")]
    NotInFan {
        /// The vertex.
        vertex: VertexId,
    },
}

#[derive(Default)]
struct Ends {
    incoming: Vec<usize>,
    outgoing: Vec<usize>,
}

/// Chains segments into closed loops. Each loop lists segment indices in
/// order; loops come out in order of their smallest segment index, and each
/// loop starts at its smallest segment index, so the result is canonical.
pub fn chain_loops(topo: &Topology, segments: &[Segment]) -> Result<Vec<Vec<usize>>, ChainError> {
    let mut at: HashMap<CutPoint, Ends> =
        HashMap::with_capacity_and_hasher(segments.len(), Default::default());
    for (i, s) in segments.iter().enumerate() {
        at.entry(s.from).or_default().outgoing.push(i);
        at.entry(s.to).or_default().incoming.push(i);
    }
    let mut next = vec![usize::MAX; segments.len()];
    let mut points: Vec<(&CutPoint, &Ends)> = at.iter().collect();
    points.sort_unstable_by_key(|(p, _)| **p);
    for (p, ends) in points {
        if ends.incoming.len() != ends.outgoing.len() {
            return Err(ChainError::Unbalanced {
                at: *p,
                incoming: ends.incoming.len(),
                outgoing: ends.outgoing.len(),
            });
        }
        match (*p, ends.incoming.len()) {
            (_, 1) => next[ends.incoming[0]] = ends.outgoing[0],
            (CutPoint::AtVertex(v), _) => pair_at_vertex(topo, segments, v, ends, &mut next)?,
            (CutPoint::OnEdge(_), _) => {
                return Err(ChainError::Unbalanced {
                    at: *p,
                    incoming: ends.incoming.len(),
                    outgoing: ends.outgoing.len(),
                })
            }
        }
    }
    let mut seen = vec![false; segments.len()];
    let mut loops = Vec::new();
    for start in 0..segments.len() {
        if seen[start] {
            continue;
        }
        let mut lp = Vec::new();
        let mut i = start;
        while !seen[i] {
            seen[i] = true;
            lp.push(i);
            i = next[i];
        }
        loops.push(lp);
    }
    Ok(loops)
}

/// Pairs the branches at vertex `v` by the fan-order parentheses rule.
fn pair_at_vertex(
    topo: &Topology,
    segments: &[Segment],
    v: VertexId,
    ends: &Ends,
    next: &mut [usize],
) -> Result<(), ChainError> {
    // Position in the fan: 2k for the edge to neighbour n_k, 2k + 1 for the
    // face (v, n_k, n_{k+1}).
    let fan = topo.fan(v);
    let mut position: HashMap<Via, usize> =
        HashMap::with_capacity_and_hasher(2 * fan.len(), Default::default());
    for (k, entry) in fan.iter().enumerate() {
        position.insert(Via::Edge(entry.edge), 2 * k);
        position.insert(Via::Face(entry.face), 2 * k + 1);
    }
    let mut branches: Vec<(usize, bool, usize)> = Vec::new();
    for (&i, incoming) in ends
        .incoming
        .iter()
        .map(|i| (i, true))
        .chain(ends.outgoing.iter().map(|i| (i, false)))
    {
        let pos = *position
            .get(&segments[i].via)
            .ok_or(ChainError::NotInFan { vertex: v })?;
        branches.push((pos, incoming, i));
    }
    branches.sort_unstable();
    // Two passes round the cycle match every branch of a balanced list,
    // whatever the start.
    let n = branches.len();
    let mut open: Vec<usize> = Vec::new();
    let mut pushed = vec![false; n];
    let mut matched = vec![false; n];
    for step in 0..2 * n {
        let k = step % n;
        let (_, incoming, seg) = branches[k];
        if incoming {
            if !pushed[k] {
                pushed[k] = true;
                open.push(k);
            }
        } else if !matched[k] {
            if let Some(j) = open.pop() {
                matched[k] = true;
                next[branches[j].2] = seg;
            }
        }
    }
    Ok(())
}
