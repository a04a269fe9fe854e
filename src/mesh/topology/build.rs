//! Input: a [`Mesh`] whose faces have in-range, distinct vertex ids.
//! Output: its [`Topology`] tables and the defects met while building them.
//!
//! No global sort: the corners are grouped by vertex once (a counting
//! sort), and everything else is read from a vertex's own corners. The
//! undirected edge `{lo, hi}` (`lo < hi`) is found among the corners at
//! `lo`: the face runs `lo -> hi` where `hi` follows `lo`, and `hi -> lo`
//! where `hi` precedes it. Enumerating each vertex's higher neighbours in
//! increasing order, vertex after vertex, numbers the edges in `(lo, hi)`
//! order. Blocks of vertices are independent, so edges and fans are built
//! on the caller's rayon pool; the tables do not depend on the number of
//! threads.

use rayon::prelude::*;
use std::ops::Range;

use super::{Edge, FanEntry, Topology, TopologyIssue, NO_FACE};
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::Mesh;
use crate::par;

/// The corner of `face` at some vertex `v`: the face runs `v -> next -> prev`.
#[derive(Clone, Copy, Debug, Default)]
struct Corner {
    next: VertexId,
    prev: VertexId,
    face: FaceId,
}

/// Vertices per parallel task.
const BLOCK: usize = 8192;

/// Fans up to this many corners find successors by a linear search.
const SMALL_FAN: usize = 16;

/// See [`Topology::build`].
pub(super) fn build(mesh: &Mesh) -> (Topology, Vec<TopologyIssue>) {
    let nv = mesh.num_vertices();
    let (fan_start, corners) = corners_by_vertex(mesh);
    let blocks: Vec<Range<usize>> = (0..nv.div_ceil(BLOCK))
        .map(|b| b * BLOCK..((b + 1) * BLOCK).min(nv))
        .collect();
    let per_block: Vec<BlockEdges> = blocks
        .par_iter()
        .map(|vs| block_edges(vs.clone(), &fan_start, &corners))
        .collect();
    let (edges, edge_start, mut issues) = join_blocks(per_block, mesh);
    let face_edges = face_edges(mesh, &edges, &edge_start);
    let (fan, bowties) = fans(mesh, &blocks, &fan_start, &corners, &face_edges);
    issues.extend(bowties);
    (
        Topology {
            edges,
            face_edges,
            fan_start,
            fan,
        },
        issues,
    )
}

/// The blocks' edges in order, where each vertex's edges start (`nv + 1`
/// entries), and the bad edges. The edges are copied block by block in
/// parallel, each into its own part of the table.
fn join_blocks(
    per_block: Vec<BlockEdges>,
    mesh: &Mesh,
) -> (Vec<Edge>, Vec<u32>, Vec<TopologyIssue>) {
    let mut edge_start = Vec::with_capacity(mesh.num_vertices() + 1);
    edge_start.push(0u32);
    let mut issues = Vec::new();
    for b in &per_block {
        for &n in &b.counts {
            let last = *edge_start.last().unwrap_or(&0);
            edge_start.push(last + n);
        }
        issues.extend_from_slice(&b.issues);
    }
    let total = per_block.iter().map(|b| b.edges.len()).sum();
    let mut edges: Vec<Edge> = Vec::with_capacity(total);
    let mut rest = &mut edges.spare_capacity_mut()[..total];
    let mut parts = Vec::with_capacity(per_block.len());
    for b in &per_block {
        let (part, tail) = rest.split_at_mut(b.edges.len());
        parts.push((part, &b.edges));
        rest = tail;
    }
    let copy = |(part, block): (&mut [std::mem::MaybeUninit<Edge>], &Vec<Edge>)| {
        for (slot, e) in part.iter_mut().zip(block) {
            slot.write(*e);
        }
    };
    if total >= par::MIN_LEN {
        parts.into_par_iter().for_each(copy);
    } else {
        parts.into_iter().for_each(copy);
    }
    // SAFETY: the parts cover `0..total` exactly, and every slot of each
    // part was written from its block (equal lengths).
    unsafe { edges.set_len(total) };
    (edges, edge_start, issues)
}

/// For each face, the edge from corner `i` to corner `i + 1`: found among
/// the edges of its lower endpoint, which are sorted by their higher one
/// (by bisection: a vertex of a fan of 50 000 faces made the linear
/// search take 1.8 s).
fn face_edges(mesh: &Mesh, edges: &[Edge], edge_start: &[u32]) -> Vec<[EdgeId; 3]> {
    mesh.faces
        .par_iter()
        .with_min_len(par::MIN_LEN)
        .map(|tri| {
            std::array::from_fn(|c| {
                let (a, b) = (tri[c], tri[(c + 1) % 3]);
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                let start = edge_start[lo.idx()] as usize;
                let block = &edges[start..edge_start[lo.idx() + 1] as usize];
                let k = block.partition_point(|e| e.v[1] < hi);
                match block.get(k) {
                    Some(e) if e.v[1] == hi => EdgeId::from_idx(start + k),
                    _ => EdgeId(u32::MAX),
                }
            })
        })
        .collect()
}

/// The fan table, each block of vertices filling its own part, and the
/// bowtie vertices.
fn fans(
    mesh: &Mesh,
    blocks: &[Range<usize>],
    fan_start: &[u32],
    corners: &[Corner],
    face_edges: &[[EdgeId; 3]],
) -> (Vec<FanEntry>, Vec<TopologyIssue>) {
    let blank = FanEntry {
        neighbour: VertexId(0),
        edge: EdgeId(0),
        face: FaceId(0),
    };
    let mut fan = par::filled(blank, corners.len());
    let mut parts = Vec::with_capacity(blocks.len());
    let mut rest = fan.as_mut_slice();
    for vs in blocks {
        let len = (fan_start[vs.end] - fan_start[vs.start]) as usize;
        let (part, tail) = rest.split_at_mut(len);
        parts.push((vs.clone(), part));
        rest = tail;
    }
    let bowties: Vec<Vec<TopologyIssue>> = parts
        .into_par_iter()
        .map(|(vs, out)| block_fans(mesh, vs, fan_start, corners, face_edges, out))
        .collect();
    (fan, bowties.into_iter().flatten().collect())
}

/// The corners grouped by vertex, each vertex's in face order, and where
/// each vertex's group starts (`nv + 1` entries).
fn corners_by_vertex(mesh: &Mesh) -> (Vec<u32>, Vec<Corner>) {
    let nv = mesh.num_vertices();
    let mut start = vec![0u32; nv + 1];
    for tri in &mesh.faces {
        for v in tri {
            start[v.idx() + 1] += 1;
        }
    }
    for k in 0..nv {
        start[k + 1] += start[k];
    }
    let mut corners = par::filled(Corner::default(), 3 * mesh.num_faces());
    let mut fill = start.clone();
    for (f, tri) in mesh.faces.iter().enumerate() {
        for c in 0..3 {
            let slot = &mut fill[tri[c].idx()];
            corners[*slot as usize] = Corner {
                next: tri[(c + 1) % 3],
                prev: tri[(c + 2) % 3],
                face: FaceId::from_idx(f),
            };
            *slot += 1;
        }
    }
    (start, corners)
}

/// The edges whose lower endpoint is in one block of vertices.
struct BlockEdges {
    /// In `(lo, hi)` order.
    edges: Vec<Edge>,
    /// Edges per vertex of the block.
    counts: Vec<u32>,
    /// Edges not used by exactly one face each way.
    issues: Vec<TopologyIssue>,
}

/// A half-edge between `lo` and a higher neighbour, seen from `lo`.
#[derive(Clone, Copy)]
struct HalfEdge {
    hi: VertexId,
    face: FaceId,
    /// The face runs `lo -> hi` (else `hi -> lo`).
    forward: bool,
    /// The face's third vertex.
    opposite: VertexId,
}

fn block_edges(vs: Range<usize>, start: &[u32], corners: &[Corner]) -> BlockEdges {
    let mut out = BlockEdges {
        edges: Vec::new(),
        counts: Vec::with_capacity(vs.len()),
        issues: Vec::new(),
    };
    let mut half: Vec<HalfEdge> = Vec::new();
    for v in vs {
        let lo = VertexId::from_idx(v);
        half.clear();
        for c in &corners[start[v] as usize..start[v + 1] as usize] {
            if c.next > lo {
                half.push(HalfEdge {
                    hi: c.next,
                    face: c.face,
                    forward: true,
                    opposite: c.prev,
                });
            }
            if c.prev > lo {
                half.push(HalfEdge {
                    hi: c.prev,
                    face: c.face,
                    forward: false,
                    opposite: c.next,
                });
            }
        }
        half.sort_unstable_by_key(|h| (h.hi, h.face));
        let before = out.edges.len();
        for group in half.chunk_by(|a, b| a.hi == b.hi) {
            out.edges.push(edge(lo, group, &mut out.issues));
        }
        out.counts.push((out.edges.len() - before) as u32);
    }
    out
}

/// The edge `{lo, group[0].hi}` from all its half-edges (sorted by face).
fn edge(lo: VertexId, group: &[HalfEdge], issues: &mut Vec<TopologyIssue>) -> Edge {
    let hi = group[0].hi;
    let mut forward = group.iter().filter(|h| h.forward);
    let mut backward = group.iter().filter(|h| !h.forward);
    let (f0, b0) = (forward.next(), backward.next());
    if let (Some(f), Some(b), None, None) = (f0, b0, forward.next(), backward.next()) {
        return Edge {
            v: [lo, hi],
            faces: [f.face, b.face],
            opposite: [f.opposite, b.opposite],
        };
    }
    let faces = |fwd: bool| {
        group
            .iter()
            .filter(|h| h.forward == fwd)
            .map(|h| h.face)
            .collect()
    };
    issues.push(TopologyIssue::BadEdge {
        v: [lo, hi],
        forward: faces(true),
        backward: faces(false),
    });
    Edge {
        v: [lo, hi],
        faces: [
            f0.map_or(NO_FACE, |h| h.face),
            b0.map_or(NO_FACE, |h| h.face),
        ],
        opposite: [f0.map_or(lo, |h| h.opposite), b0.map_or(hi, |h| h.opposite)],
    }
}

/// Orders the corners around each vertex of a block into its fan, written
/// to `out` (the block's part of the fan table); returns the bowties.
fn block_fans(
    mesh: &Mesh,
    vs: Range<usize>,
    start: &[u32],
    corners: &[Corner],
    face_edges: &[[EdgeId; 3]],
    out: &mut [FanEntry],
) -> Vec<TopologyIssue> {
    let base = start[vs.start] as usize;
    let mut issues = Vec::new();
    let mut used = Vec::new();
    let mut by_next: Vec<u32> = Vec::new();
    for v in vs {
        let range = start[v] as usize..start[v + 1] as usize;
        let local = &corners[range.clone()];
        let vid = VertexId::from_idx(v);
        // Order the corners around v: (a -> b) is followed by the first
        // unused corner (b -> ..), first in corner order. A linear search
        // for small fans; corners sorted by (next vertex, position) for
        // large ones (a vertex may have thousands of faces).
        let small = local.len() <= SMALL_FAN;
        by_next.clear();
        if !small {
            by_next.extend(0..local.len() as u32);
            by_next.sort_unstable_by_key(|&j| (local[j as usize].next, j));
        }
        used.clear();
        used.resize(local.len(), false);
        let mut written = range.start - base;
        let (mut cycles, mut closed, mut scan) = (0, true, 0);
        while written < range.end - base {
            while used[scan] {
                scan += 1;
            }
            cycles += 1;
            let first = local[scan].next;
            let mut k = scan;
            loop {
                used[k] = true;
                let c = local[k];
                let tri = mesh.faces[c.face.idx()];
                let at = (0..3).find(|&i| tri[i] == vid).unwrap_or(0);
                out[written] = FanEntry {
                    neighbour: c.next,
                    edge: face_edges[c.face.idx()][at],
                    face: c.face,
                };
                written += 1;
                let want = c.prev;
                let next = if small {
                    (0..local.len()).find(|&j| !used[j] && local[j].next == want)
                } else {
                    let lo = by_next.partition_point(|&j| local[j as usize].next < want);
                    by_next[lo..]
                        .iter()
                        .take_while(|&&j| local[j as usize].next == want)
                        .map(|&j| j as usize)
                        .find(|&j| !used[j])
                };
                match next {
                    Some(j) => k = j,
                    None => {
                        closed &= want == first;
                        break;
                    }
                }
            }
        }
        // An open fan is a boundary vertex: the open edges report it.
        if cycles > 1 && closed {
            issues.push(TopologyIssue::Bowtie {
                vertex: vid,
                cycles,
            });
        }
    }
    issues
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The previous builder, kept as the reference: one global sort of the
    /// half-edges by `(min, max)` endpoint, fans found per vertex.
    fn reference_build(mesh: &Mesh) -> (Topology, Vec<TopologyIssue>) {
        let nv = mesh.num_vertices();
        let nf = mesh.num_faces();
        let mut issues = Vec::new();

        // Half-edges keyed by (min, max) endpoint, then direction.
        let mut half: Vec<(u64, u32)> = Vec::with_capacity(3 * nf);
        for (f, tri) in mesh.faces.iter().enumerate() {
            for i in 0..3 {
                let a = tri[i].0 as u64;
                let b = tri[(i + 1) % 3].0 as u64;
                let key = if a < b { (a << 32) | b } else { (b << 32) | a };
                half.push((key, (3 * f + i) as u32));
            }
        }
        half.sort_unstable();

        let mut edges = Vec::with_capacity(3 * nf / 2 + 1);
        let mut face_edges = vec![[EdgeId(u32::MAX); 3]; nf];
        let mut i = 0;
        while i < half.len() {
            let key = half[i].0;
            let mut j = i;
            while j < half.len() && half[j].0 == key {
                j += 1;
            }
            let lo = VertexId((key >> 32) as u32);
            let hi = VertexId(key as u32);
            let mut forward = Vec::new();
            let mut backward = Vec::new();
            for &(_, h) in &half[i..j] {
                let f = h / 3;
                let c = (h % 3) as usize;
                if mesh.faces[f as usize][c] == lo {
                    forward.push((FaceId(f), c));
                } else {
                    backward.push((FaceId(f), c));
                }
            }
            let id = EdgeId::from_idx(edges.len());
            let opp = |(f, c): (FaceId, usize)| mesh.faces[f.idx()][(c + 2) % 3];
            if forward.len() == 1 && backward.len() == 1 {
                edges.push(Edge {
                    v: [lo, hi],
                    faces: [forward[0].0, backward[0].0],
                    opposite: [opp(forward[0]), opp(backward[0])],
                });
            } else {
                issues.push(TopologyIssue::BadEdge {
                    v: [lo, hi],
                    forward: forward.iter().map(|x| x.0).collect(),
                    backward: backward.iter().map(|x| x.0).collect(),
                });
                let first = |v: &[(FaceId, usize)]| v.first().copied();
                edges.push(Edge {
                    v: [lo, hi],
                    faces: [
                        first(&forward).map_or(NO_FACE, |x| x.0),
                        first(&backward).map_or(NO_FACE, |x| x.0),
                    ],
                    opposite: [
                        first(&forward).map_or(lo, opp),
                        first(&backward).map_or(hi, opp),
                    ],
                });
            }
            for &(_, h) in &half[i..j] {
                face_edges[(h / 3) as usize][(h % 3) as usize] = id;
            }
            i = j;
        }
        drop(half);

        // Fans: corner (v, a, b) of face f gives the entry (a, f) with
        // successor b. Group corners by vertex, then follow successors.
        let mut count = vec![0u32; nv + 1];
        for tri in &mesh.faces {
            for v in tri {
                count[v.idx() + 1] += 1;
            }
        }
        for k in 0..nv {
            count[k + 1] += count[k];
        }
        let fan_start = count;
        let mut corners: Vec<(VertexId, VertexId, FaceId)> =
            vec![(VertexId(0), VertexId(0), FaceId(0)); 3 * nf];
        let mut fill = fan_start.clone();
        for (f, tri) in mesh.faces.iter().enumerate() {
            for c in 0..3 {
                let v = tri[c];
                let slot = &mut fill[v.idx()];
                corners[*slot as usize] = (tri[(c + 1) % 3], tri[(c + 2) % 3], FaceId::from_idx(f));
                *slot += 1;
            }
        }
        let mut fan = Vec::with_capacity(3 * nf);
        let mut used = Vec::new();
        let mut by_first: Vec<u32> = Vec::new();
        let mut ordered = Vec::new();
        for v in 0..nv {
            let range = fan_start[v] as usize..fan_start[v + 1] as usize;
            let local = &corners[range];
            if local.is_empty() {
                continue;
            }
            // Order the corners around v: (a -> b) is followed by (b -> ..).
            // Corners sorted by their first neighbour find successors in
            // O(log deg); a vertex may have thousands of faces.
            by_first.clear();
            by_first.extend(0..local.len() as u32);
            by_first.sort_unstable_by_key(|&j| (local[j as usize].0, j));
            used.clear();
            used.resize(local.len(), false);
            ordered.clear();
            let mut cycles = 0;
            let mut closed = true;
            let mut scan = 0;
            while ordered.len() < local.len() {
                while used[scan] {
                    scan += 1;
                }
                cycles += 1;
                let first = local[scan].0;
                let mut k = scan;
                loop {
                    used[k] = true;
                    ordered.push(local[k]);
                    let want = local[k].1;
                    let lo = by_first.partition_point(|&j| local[j as usize].0 < want);
                    let next = by_first[lo..]
                        .iter()
                        .take_while(|&&j| local[j as usize].0 == want)
                        .map(|&j| j as usize)
                        .find(|&j| !used[j]);
                    match next {
                        Some(j) => k = j,
                        None => {
                            closed &= want == first;
                            break;
                        }
                    }
                }
            }
            // An open fan is a boundary vertex: the open edges report it.
            if cycles > 1 && closed {
                issues.push(TopologyIssue::Bowtie {
                    vertex: VertexId::from_idx(v),
                    cycles,
                });
            }
            let vid = VertexId::from_idx(v);
            for &(a, _b, f) in &ordered {
                let edge = face_edge_between(mesh, &face_edges, f, vid, a);
                fan.push(FanEntry {
                    neighbour: a,
                    edge,
                    face: f,
                });
            }
        }
        (
            Topology {
                edges,
                face_edges,
                fan_start,
                fan,
            },
            issues,
        )
    }

    fn face_edge_between(
        mesh: &Mesh,
        face_edges: &[[EdgeId; 3]],
        f: FaceId,
        v: VertexId,
        a: VertexId,
    ) -> EdgeId {
        let tri = mesh.faces[f.idx()];
        (0..3)
            .find(|&c| tri[c] == v && tri[(c + 1) % 3] == a)
            .map_or(EdgeId(u32::MAX), |c| face_edges[f.idx()][c])
    }

    fn assert_same(mesh: &Mesh) -> Result<(), TestCaseError> {
        let (t, issues) = build(mesh);
        let (r, want) = reference_build(mesh);
        prop_assert_eq!(&t.edges, &r.edges);
        prop_assert_eq!(&t.face_edges, &r.face_edges);
        prop_assert_eq!(&t.fan_start, &r.fan_start);
        prop_assert_eq!(&t.fan, &r.fan);
        prop_assert_eq!(issues, want);
        Ok(())
    }

    #[test]
    fn datasets_build_as_the_reference_does() {
        for d in crate::datasets::all() {
            assert_same(&d.build()).unwrap();
        }
    }

    proptest! {
        /// Faces on few vertices: edges used by one, three or more faces,
        /// bowties, open fans and unused vertices, over block boundaries
        /// when `nv` is large.
        #[test]
        fn defective_meshes_build_as_the_reference_does(
            nv in 3u32..40,
            spread in prop_oneof![Just(1u32), Just(5000u32)],
            picks in proptest::collection::vec((0u32..40, 0u32..40, 0u32..40), 1..150),
        ) {
            let faces: Vec<[VertexId; 3]> = picks
                .into_iter()
                .map(|(a, b, c)| [a % nv, b % nv, c % nv])
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .map(|t| t.map(|v| VertexId(v * spread)))
                .collect();
            let n = (nv * spread) as usize;
            let mesh = Mesh { positions: vec![[0.0; 3]; n], faces };
            assert_same(&mesh)?;
        }
    }
}
