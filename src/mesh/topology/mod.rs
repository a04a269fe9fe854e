//! Input: a [`Mesh`] whose faces have in-range, distinct vertex ids.
//! Output: its [`Topology`]: the edge table (each undirected edge with its
//! faces and their opposite vertices) and every vertex's fan (neighbours
//! and faces in the cyclic order the surface orientation gives).
//!
//! Pure topology: no coordinate is read here. Building groups the corners
//! by vertex (linear time; `build.rs` says how edges and fans follow from
//! that, in parallel); the tables take about 60 bytes per triangle.

use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::Mesh;

mod build;

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
    ///
    /// Edges are numbered in `(lower, higher)` endpoint order; a vertex
    /// whose corners do not form one cycle has its fan split into cycles,
    /// each successor being the first unused corner (in face order) that
    /// continues the previous one. Runs on the caller's rayon pool; the
    /// tables do not depend on the number of threads.
    pub fn build(mesh: &Mesh) -> (Topology, Vec<TopologyIssue>) {
        build::build(mesh)
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
