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

/// Chains segments into closed loops. Each loop lists segment indices in
/// order; loops come out in order of their smallest segment index, and each
/// loop starts at its smallest segment index, so the result is canonical.
pub fn chain_loops(topo: &Topology, segments: &[Segment]) -> Result<Vec<Vec<usize>>, ChainError> {
    let unbalanced = |at: CutPoint| ChainError::Unbalanced {
        at,
        incoming: segments.iter().filter(|s| s.to == at).count(),
        outgoing: segments.iter().filter(|s| s.from == at).count(),
    };
    let mut next = vec![usize::MAX; segments.len()];
    let mut ins: Vec<(CutPoint, usize)> = Vec::new();
    let mut outs: Vec<(CutPoint, usize)> = Vec::new();
    // An edge crossing has one segment in and one out: looked up by edge
    // in this thread's table (every slot `FREE` between calls).
    LEAVING
        .with_borrow_mut(|leaving| {
            if leaving.len() < topo.num_edges() {
                leaving.resize(topo.num_edges(), FREE);
            }
            let linked = link_edges(leaving, segments, &mut next, &mut ins, &mut outs);
            for s in segments {
                if let CutPoint::OnEdge(e) = s.from {
                    leaving[e.idx()] = FREE;
                }
            }
            linked
        })
        .map_err(unbalanced)?;
    // At vertices, arrivals and departures sorted by vertex (then segment
    // index) are two runs per vertex, read side by side. Only vertices are
    // in these lists: one integer key sorts them as the pairs would.
    let order = |&(c, i): &(CutPoint, usize)| match c {
        CutPoint::AtVertex(v) => (u64::from(v.0) << 32) | i as u64,
        CutPoint::OnEdge(_) => u64::MAX,
    };
    ins.sort_unstable_by_key(order);
    outs.sort_unstable_by_key(order);
    let (mut a, mut b) = (0, 0);
    loop {
        let p = match (ins.get(a), outs.get(b)) {
            (Some(x), Some(y)) => x.0.min(y.0),
            (Some(x), None) => x.0,
            (None, Some(y)) => y.0,
            (None, None) => break,
        };
        let run = |v: &[(CutPoint, usize)], from: usize| {
            from + v[from..].iter().take_while(|e| e.0 == p).count()
        };
        let (a_end, b_end) = (run(&ins, a), run(&outs, b));
        let (incoming, outgoing) = (&ins[a..a_end], &outs[b..b_end]);
        (a, b) = (a_end, b_end);
        match (p, incoming.len()) {
            (_, k) if k != outgoing.len() => return Err(unbalanced(p)),
            (_, 1) => next[incoming[0].1] = outgoing[0].1,
            (CutPoint::AtVertex(v), _) => {
                pair_at_vertex(topo, segments, v, incoming, outgoing, &mut next)?
            }
            (CutPoint::OnEdge(_), _) => return Err(unbalanced(p)),
        }
    }
    let mut seen = vec![false; segments.len()];
    let mut loops = Vec::new();
    for start in 0..segments.len() {
        if seen[start] {
            continue;
        }
        // Walked twice, to count and then to list: each loop is allocated
        // once, at its length, instead of growing step by step. (The count
        // is only a capacity: bounded, it cannot loop.)
        let mut len = 1;
        let mut i = start;
        while let Some(&j) = next.get(i) {
            if j == start || len >= segments.len() {
                break;
            }
            len += 1;
            i = j;
        }
        let mut lp = Vec::with_capacity(len);
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

/// A slot of the edge table with no segment leaving its edge.
const FREE: u32 = u32::MAX;
/// A slot whose leaving segment has been arrived at.
const TAKEN: u32 = u32::MAX - 1;

std::thread_local! {
    /// Per edge, the segment leaving its crossing (or `FREE`, `TAKEN`):
    /// kept by each thread across calls, so no level allocates or hashes
    /// for it.
    static LEAVING: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Links each segment arriving at an edge crossing to the one leaving it
/// (`next`), and lists the arrivals at and departures from vertices. On
/// an edge crossing without exactly one segment in and one out, that cut
/// point (the first found, or the smallest edge left without an arrival).
fn link_edges(
    leaving: &mut [u32],
    segments: &[Segment],
    next: &mut [usize],
    ins: &mut Vec<(CutPoint, usize)>,
    outs: &mut Vec<(CutPoint, usize)>,
) -> Result<(), CutPoint> {
    for (i, s) in segments.iter().enumerate() {
        match s.from {
            CutPoint::OnEdge(e) => {
                // At most one segment per face: indices stay below TAKEN.
                let slot = &mut leaving[e.idx()];
                if *slot != FREE {
                    return Err(s.from);
                }
                *slot = i as u32;
            }
            CutPoint::AtVertex(_) => outs.push((s.from, i)),
        }
        if let CutPoint::AtVertex(_) = s.to {
            ins.push((s.to, i));
        }
    }
    // Each departure is taken once (marked `TAKEN`); a second arrival,
    // or a departure never arrived at, is unbalanced.
    for (i, s) in segments.iter().enumerate() {
        if let CutPoint::OnEdge(e) = s.to {
            match leaving.get_mut(e.idx()) {
                Some(j) if *j != TAKEN && *j != FREE => {
                    next[i] = *j as usize;
                    *j = TAKEN;
                }
                _ => return Err(s.to),
            }
        }
    }
    let left = segments
        .iter()
        .filter_map(|s| match s.from {
            CutPoint::OnEdge(e) if leaving[e.idx()] != TAKEN => Some(e),
            _ => None,
        })
        .min();
    match left {
        Some(e) => Err(CutPoint::OnEdge(e)),
        None => Ok(()),
    }
}

/// Pairs the branches at vertex `v` by the fan-order parentheses rule.
fn pair_at_vertex(
    topo: &Topology,
    segments: &[Segment],
    v: VertexId,
    incoming: &[(CutPoint, usize)],
    outgoing: &[(CutPoint, usize)],
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
    for (i, incoming) in incoming
        .iter()
        .map(|&(_, i)| (i, true))
        .chain(outgoing.iter().map(|&(_, i)| (i, false)))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ids::{EdgeId, FaceId};
    use crate::Slicer;

    fn seg(from: u32, to: u32) -> Segment {
        Segment {
            from: CutPoint::OnEdge(EdgeId(from)),
            to: CutPoint::OnEdge(EdgeId(to)),
            via: Via::Face(FaceId(0)),
        }
    }

    #[test]
    fn edge_crossings_chain_and_unbalanced_ends_are_errors() {
        let mesh = crate::datasets::by_name("unit_cube").unwrap().build();
        let slicer = Slicer::new(&mesh).unwrap();
        let topo = slicer.topology();
        // 0 -> 1 -> 2 -> 0 and 3 -> 4 -> 3, given out of order.
        let ok = [seg(1, 2), seg(3, 4), seg(0, 1), seg(4, 3), seg(2, 0)];
        assert_eq!(
            chain_loops(topo, &ok).unwrap(),
            vec![vec![0, 4, 2], vec![1, 3]]
        );
        let unbalanced = |segments: &[Segment]| match chain_loops(topo, segments) {
            Err(ChainError::Unbalanced { at, .. }) => at,
            other => panic!("expected an unbalanced point, got {other:?}"),
        };
        // Edge 2 is arrived at but never left.
        assert_eq!(
            unbalanced(&[seg(0, 1), seg(1, 2)]),
            CutPoint::OnEdge(EdgeId(2))
        );
        // Edge 0 is arrived at twice and edge 2 never: the counts balance
        // but the ends do not.
        let twice = unbalanced(&[seg(0, 1), seg(1, 0), seg(2, 0)]);
        assert_eq!(twice, CutPoint::OnEdge(EdgeId(0)));
        // Edge 5 is left twice.
        assert_eq!(
            unbalanced(&[seg(5, 6), seg(5, 7)]),
            CutPoint::OnEdge(EdgeId(5))
        );
    }
}
