//! Input: the S_NO edges (ridge or valley in-plane edges). Output: maximal
//! polylines, split where more than two S_NO edges meet or where the kind
//! changes; each open (with its borders) or closed. Not oriented.

use crate::classify::RidgeKind;
use crate::ids::{EdgeId, VertexId};
use rustc_hash::FxHashMap as HashMap;

/// A maximal S_NO polyline (topology only; points are added by the caller).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RidgePath {
    /// Ridge or valley.
    pub kind: RidgeKind,
    /// A cycle through no junction.
    pub closed: bool,
    /// Vertices in order (a closed path does not repeat its first vertex;
    /// an open path that returns to its junction lists it at both ends).
    pub vertices: Vec<VertexId>,
}

/// Joins S_NO edges `(edge, [a, b], kind)` into maximal polylines, in a
/// canonical order (by smallest edge id).
pub fn join_ridges(edges: &[(EdgeId, [VertexId; 2], RidgeKind)]) -> Vec<RidgePath> {
    let mut at: HashMap<VertexId, Vec<usize>> = HashMap::default();
    for (i, (_, v, _)) in edges.iter().enumerate() {
        at.entry(v[0]).or_default().push(i);
        at.entry(v[1]).or_default().push(i);
    }
    let is_junction = |v: VertexId| -> bool {
        let inc = &at[&v];
        inc.len() != 2 || edges[inc[0]].2 != edges[inc[1]].2
    };
    let mut used = vec![false; edges.len()];
    let mut paths = Vec::new();
    let walk =
        |start: VertexId, first: usize, used: &mut Vec<bool>| -> (Vec<VertexId>, RidgeKind) {
            let kind = edges[first].2;
            let mut verts = vec![start];
            let mut cur = start;
            let mut e = first;
            loop {
                used[e] = true;
                let [a, b] = edges[e].1;
                cur = if a == cur { b } else { a };
                verts.push(cur);
                if is_junction(cur) {
                    break;
                }
                match at[&cur].iter().copied().find(|&j| !used[j]) {
                    Some(j) => e = j,
                    None => break,
                }
            }
            (verts, kind)
        };
    // Open paths start at junctions, in edge order for determinism.
    let mut order: Vec<usize> = (0..edges.len()).collect();
    order.sort_unstable_by_key(|&i| edges[i].0);
    for &i in &order {
        if used[i] {
            continue;
        }
        let [a, b] = edges[i].1;
        let start = if is_junction(a) {
            Some(a)
        } else if is_junction(b) {
            Some(b)
        } else {
            None
        };
        if let Some(s) = start {
            let (vertices, kind) = walk(s, i, &mut used);
            paths.push(RidgePath {
                kind,
                closed: false,
                vertices,
            });
        }
    }
    // What remains are cycles through non-junction vertices.
    for &i in &order {
        if used[i] {
            continue;
        }
        let s = edges[i].1[0];
        let (mut vertices, kind) = walk(s, i, &mut used);
        vertices.pop();
        paths.push(RidgePath {
            kind,
            closed: true,
            vertices,
        });
    }
    paths
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(id: u32, a: u32, b: u32) -> (EdgeId, [VertexId; 2], RidgeKind) {
        (EdgeId(id), [VertexId(a), VertexId(b)], RidgeKind::Ridge)
    }

    #[test]
    fn cycle_is_closed_and_star_is_split() {
        let ring = join_ridges(&[e(0, 0, 1), e(1, 1, 2), e(2, 0, 2)]);
        assert_eq!(ring.len(), 1);
        assert!(ring[0].closed);
        assert_eq!(ring[0].vertices.len(), 3);
        // Three edges meeting at vertex 0: three open paths.
        let star = join_ridges(&[e(0, 0, 1), e(1, 0, 2), e(2, 0, 3)]);
        assert_eq!(star.len(), 3);
        assert!(star.iter().all(|p| !p.closed && p.vertices.len() == 2));
    }

    #[test]
    fn loop_back_to_a_junction_is_open() {
        // A triangle 0-1-2 with a tail 0-3: vertex 0 is a junction (degree 3).
        let p = join_ridges(&[e(0, 0, 1), e(1, 1, 2), e(2, 2, 0), e(3, 0, 3)]);
        assert_eq!(p.len(), 2);
        let lp = p.iter().find(|p| p.vertices.len() == 4).unwrap();
        assert!(!lp.closed);
        assert_eq!(lp.vertices.first(), lp.vertices.last());
    }
}
