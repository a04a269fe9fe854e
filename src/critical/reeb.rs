//! Input: the nodes and arcs the sweep found. Output: the Reeb graph as a
//! value ([`ReebGraph`]) with its exact invariants (components, cycles),
//! and the genus and components of the surface itself, from its Euler
//! characteristic.

use crate::exact::rational::Rat;
use crate::ids::VertexId;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use petgraph::unionfind::UnionFind;

/// What a node of the Reeb graph holds (see [`super`] for the rules).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NodeKind {
    /// An isolated minimum (the node is that vertex).
    Min,
    /// An isolated maximum (the node is that vertex).
    Max,
    /// Saddle vertices only.
    Saddle,
    /// Face regions in the plane, nothing else critical.
    Plateau,
    /// Ridge polylines only.
    Ridge,
    /// Valley polylines only.
    Valley,
    /// Critical elements of more than one of the kinds above.
    Mixed,
}

impl NodeKind {
    /// The lower-case name used in JSON and text.
    pub fn name(self) -> &'static str {
        match self {
            NodeKind::Min => "min",
            NodeKind::Max => "max",
            NodeKind::Saddle => "saddle",
            NodeKind::Plateau => "plateau",
            NodeKind::Ridge => "ridge",
            NodeKind::Valley => "valley",
            NodeKind::Mixed => "mixed",
        }
    }
}

/// A node: one connected component of a critical level set that holds a
/// critical element.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReebNode {
    /// Its exact height, in the mesh's units.
    pub z: Rat,
    /// Index of its height in [`super::CriticalReport::levels`].
    pub level: usize,
    /// What it holds.
    pub kind: NodeKind,
    /// Its smallest vertex id (names the node).
    pub vertex: VertexId,
    /// Mesh vertices at its height in it.
    pub vertices: usize,
    /// Face regions facing up.
    pub faces_up: usize,
    /// Face regions facing down.
    pub faces_down: usize,
    /// Ridge polylines.
    pub ridges: usize,
    /// Valley polylines.
    pub valleys: usize,
    /// Isolated minima.
    pub minima: usize,
    /// Isolated maxima.
    pub maxima: usize,
    /// `m` of each saddle in it, by ascending vertex id.
    pub saddles: Vec<u32>,
    /// Arcs that end here from below (loops of L- touching it).
    pub below: usize,
    /// Arcs that start here going up (loops of L+ touching it).
    pub above: usize,
    /// Genus of a small neighbourhood of the node in the surface (0 unless
    /// several saddles in one level-set component make a handle).
    pub genus: u64,
    /// Exact bounding box `[[x_min, y_min], [x_max, y_max]]` of its
    /// vertices, in the mesh's units.
    pub bbox: [[Rat; 2]; 2],
}

/// The unperturbed Reeb graph: nodes by ascending height (then by smallest
/// vertex id), arcs as `[lower node, upper node]`, sorted; parallel arcs
/// are listed once each.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReebGraph {
    /// The nodes.
    pub nodes: Vec<ReebNode>,
    /// The arcs, `[lower, upper]` node indices, `z(lower) < z(upper)`.
    pub arcs: Vec<[usize; 2]>,
}

impl ReebGraph {
    /// Connected components of the graph.
    pub fn components(&self) -> usize {
        let mut sets = UnionFind::<usize>::new(self.nodes.len());
        let joined = self.arcs.iter().filter(|&&[a, b]| sets.union(a, b)).count();
        self.nodes.len() - joined
    }

    /// Independent cycles (first Betti number): `arcs - nodes + components`.
    pub fn cycles(&self) -> u64 {
        (self.arcs.len() + self.components()) as u64 - self.nodes.len() as u64
    }

    /// The arcs crossing a height strictly between two node heights: those
    /// with `z(lower) < z < z(upper)`. Equals the number of contour loops
    /// at every regular height `z` (checked by the tests).
    pub fn arcs_across(&self, z: &Rat) -> usize {
        self.arcs
            .iter()
            .filter(|&&[a, b]| &self.nodes[a].z < z && z < &self.nodes[b].z)
            .count()
    }
}

/// The total genus and the number of connected components of a closed,
/// orientable surface, from `V - E + F` per component (used vertices only).
pub(super) fn surface_genus(mesh: &Mesh, topo: &Topology) -> (u64, usize) {
    let n = mesh.num_vertices();
    let mut sets = UnionFind::<u32>::new(n);
    for e in &topo.edges {
        sets.union(e.v[0].0, e.v[1].0);
    }
    // chi per component (indexed by its root): +1 per used vertex, -1 per
    // edge, +1 per face.
    let mut chi: Vec<i64> = vec![0; n];
    let mut roots = Vec::new();
    for v in (0..n as u32).filter(|&v| !topo.fan(VertexId(v)).is_empty()) {
        let r = sets.find_mut(v);
        if r == v {
            roots.push(r);
        }
        chi[r as usize] += 1;
    }
    for e in &topo.edges {
        chi[sets.find_mut(e.v[0].0) as usize] -= 1;
    }
    for f in &mesh.faces {
        chi[sets.find_mut(f[0].0) as usize] += 1;
    }
    // A closed orientable surface has chi = 2 - 2g <= 2.
    let genus = roots
        .iter()
        .map(|&r| u64::try_from((2 - chi[r as usize]) / 2).unwrap_or(0))
        .sum();
    (genus, roots.len())
}
