//! Input: a [`Mesh`] whose faces have in-range, distinct vertex ids.
//! Output: its [`Topology`]: the edge table (each undirected edge with its
//! faces and their opposite vertices) and every vertex's fan (neighbours
//! and faces in the cyclic order the surface orientation gives).
//!
//! Pure topology: no coordinate is read here. Building sorts the half-edges
//! once (`O(n log n)`); the tables take about 60 bytes per triangle.

use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::Mesh;

/// Sentinel for "no face" in a [`Edge`] of a defective mesh.
pub const NO_FACE: FaceId = FaceId(u32::MAX);

/// An undirected edge `{v[0], v[1]}` with `v[0] < v[1]`.
///
/// `faces[0]` traverses it as `v[0] -> v[1]`, `faces[1]` as `v[1] -> v[0]`;
/// `opposite[k]` is the vertex of `faces[k]` not on the edge. In a valid
/// closed mesh both faces exist.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Endpoints, smaller id first.
    pub v: [VertexId; 2],
    /// The face running `v[0] -> v[1]`, then the one running `v[1] -> v[0]`.
    pub faces: [FaceId; 2],
    /// The vertex opposite the edge in `faces[0]` and in `faces[1]`.
    pub opposite: [VertexId; 2],
}

/// One entry of a vertex fan: neighbour `n_k` and the face `(v, n_k, n_{k+1})`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FanEntry {
    /// The neighbour vertex `n_k`.
    pub neighbour: VertexId,
    /// The edge `{v, n_k}`.
    pub edge: EdgeId,
    /// The face whose corner at `v` runs from `n_k` to `n_{k+1}`.
    pub face: FaceId,
}

/// Edge table and vertex fans of a closed, oriented, manifold mesh.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// All undirected edges.
    pub edges: Vec<Edge>,
    /// For each face, the edge from corner `i` to corner `i + 1`.
    pub face_edges: Vec<[EdgeId; 3]>,
    fan_start: Vec<u32>,
    fan: Vec<FanEntry>,
}

/// A problem found while building the tables; validation turns these into
/// named defects.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TopologyIssue {
    /// An undirected edge used by a number of half-edges other than two
    /// opposite ones. `faces` lists every face on it.
    BadEdge {
        /// Endpoints, smaller first.
        v: [VertexId; 2],
        /// Faces running `v[0] -> v[1]`.
        forward: Vec<FaceId>,
        /// Faces running `v[1] -> v[0]`.
        backward: Vec<FaceId>,
    },
    /// A vertex whose faces form more than one cycle (or an open fan).
    Bowtie {
        /// The vertex.
        vertex: VertexId,
        /// Number of separate face cycles or fans around it.
        cycles: usize,
    },
}

impl Topology {
    /// Builds the tables. Faces must have in-range, pairwise distinct vertex
    /// ids (validation checks this first). Defective edges and vertices are
    /// returned as issues; tables are then only partially meaningful.
    pub fn build(mesh: &Mesh) -> (Topology, Vec<TopologyIssue>) {
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
            by_first.sort_unstable_by_key(|&j| local[j as usize].0);
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

    /// The fan of `v`: neighbours in the order the surface orientation
    /// gives (seen from outside, counter-clockwise), each with the face that
    /// follows it.
    #[inline]
    pub fn fan(&self, v: VertexId) -> &[FanEntry] {
        let s = self.fan_start[v.idx()] as usize;
        let e = self.fan_start[v.idx() + 1] as usize;
        &self.fan[s..e]
    }

    /// Number of undirected edges.
    pub fn num_edges(&self) -> usize {
        self.edges.len()
    }

    /// The edge record.
    #[inline]
    pub fn edge(&self, e: EdgeId) -> &Edge {
        &self.edges[e.idx()]
    }

    /// Approximate heap size of the tables in bytes.
    pub fn heap_bytes(&self) -> usize {
        self.edges.capacity() * std::mem::size_of::<Edge>()
            + self.face_edges.capacity() * std::mem::size_of::<[EdgeId; 3]>()
            + self.fan_start.capacity() * 4
            + self.fan.capacity() * std::mem::size_of::<FanEntry>()
    }
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

/// Checks the structural invariants of a valid mesh's tables: every edge has
/// two faces that really traverse it in opposite directions, opposite
/// vertices are right, every fan is a closed cycle covering the vertex's
/// corners exactly once, and V - E + F is even per the counts. Shared by
/// tests and fuzz targets. Returns a description of the first violation.
pub fn check_invariants(mesh: &Mesh, topo: &Topology) -> Result<(), String> {
    for (k, e) in topo.edges.iter().enumerate() {
        if e.v[0] >= e.v[1] {
            return Err(format!("edge e{k} endpoints not ordered"));
        }
        for s in 0..2 {
            let f = e.faces[s];
            if f == NO_FACE || f.idx() >= mesh.num_faces() {
                return Err(format!("edge e{k} misses face {s}"));
            }
            let tri = mesh.faces[f.idx()];
            let (from, to) = if s == 0 {
                (e.v[0], e.v[1])
            } else {
                (e.v[1], e.v[0])
            };
            let c = (0..3).find(|&c| tri[c] == from && tri[(c + 1) % 3] == to);
            match c {
                None => return Err(format!("face {f} does not run {from}->{to} of e{k}")),
                Some(c) => {
                    if tri[(c + 2) % 3] != e.opposite[s] {
                        return Err(format!("wrong opposite vertex on e{k}"));
                    }
                    if topo.face_edges[f.idx()][c] != EdgeId::from_idx(k) {
                        return Err(format!("face_edges of {f} does not point to e{k}"));
                    }
                }
            }
        }
    }
    let mut seen = vec![0u8; mesh.num_faces()];
    for v in 0..mesh.num_vertices() {
        let vid = VertexId::from_idx(v);
        let fan = topo.fan(vid);
        for (k, entry) in fan.iter().enumerate() {
            let next = fan[(k + 1) % fan.len()].neighbour;
            let tri = mesh.faces[entry.face.idx()];
            let ok = (0..3).any(|c| {
                tri[c] == vid && tri[(c + 1) % 3] == entry.neighbour && tri[(c + 2) % 3] == next
            });
            if !ok {
                return Err(format!("fan of {vid} is not a cycle at {}", entry.face));
            }
            let e = topo.edge(entry.edge);
            if !(e.v.contains(&vid) && e.v.contains(&entry.neighbour)) {
                return Err(format!(
                    "fan edge of {vid} does not join {}",
                    entry.neighbour
                ));
            }
            seen[entry.face.idx()] += 1;
        }
    }
    if seen.iter().any(|&c| c != 3) {
        return Err("some face is not in exactly three fans".into());
    }
    if 2 * topo.edges.len() != 3 * mesh.num_faces() {
        return Err("2E != 3F".into());
    }
    Ok(())
}
