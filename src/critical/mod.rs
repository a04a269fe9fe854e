//! Input: a validated mesh (a [`Slicer`]). Output: its critical values
//! `C` (the heights whose level set holds a face in the plane, a ridge or
//! valley edge, an isolated extremum or a saddle), what each holds and how
//! the contour changes across it, the unperturbed Reeb graph, and layer
//! plans that put every flat on a layer boundary ([`fit`]).
//!
//! Everything is exact and decided without slicing at every vertex
//! height: each vertex is classified from its link at its own height
//! (`link.rs`, the rules of SPEC section 3), and one sweep over the vertices
//! in height order keeps the contours as cyclic sequences of crossed edges
//! in balanced trees (`sequences.rs`), in `O(n log n)` expected time for
//! the whole mesh. Vertices at one height are processed together: a node
//! of the Reeb graph is a whole connected component of a critical level
//! set, never split by a tie-break (no simulation of simplicity).
//!
//! Definitions (used by the code, the JSON and the tests):
//!
//! - **Critical element** at a height `c`: a face in the plane (F), an S_NO
//!   edge (ridge or valley), an isolated extremum (P: min or max) or a
//!   saddle (a vertex with `2m >= 4` S_O branches), as SPEC section 3
//!   defines them. `c` is a **critical height** when its level set holds
//!   one. A vertex on transversal in-plane edges, or with 2 branches, is
//!   regular.
//! - **Node**: a connected component of the level set at a critical height
//!   (faces, edges, vertices and contour pieces in the plane, joined
//!   through the mesh) that holds a critical element. A component that
//!   holds none is a regular contour, not a node.
//! - **Arc**: a connected component of the surface minus the nodes: a
//!   family of regular contours (an open cylinder) from its lower node to
//!   its upper node. It crosses every height strictly between them in
//!   exactly one contour loop, so the loops of L- at `c` are the arcs with
//!   `z(lower) < c <= z(upper)`, those of L+ the arcs with
//!   `z(lower) <= c < z(upper)`.
//! - **Node kind** ([`NodeKind`]), from the critical elements it holds:
//!   `min` / `max`: an isolated extremum (then it is that vertex alone);
//!   `plateau`: face regions and nothing else critical; `ridge`, `valley`:
//!   S_NO polylines of that kind only; `saddle`: saddle vertices only;
//!   `mixed`: elements of more than one of these kinds (for example a
//!   plateau with a ridge leaving it, or a saddle on a valley).
//! - **Node genus**: the genus of a small neighbourhood of the node in the
//!   surface (`(2 - b - chi) / 2` for its `b` incident arcs and the Euler
//!   characteristic `chi` of the node). It is 0 for every node with at
//!   most one saddle; it can be positive where several saddles lie in one
//!   level-set component. Then, exactly, for a surface of total genus `g`:
//!   `cycles(Reeb) + sum(node genus) = g`, and the Reeb graph has one
//!   connected component per component of the mesh. [`analyze`] checks
//!   both identities on every run.

pub mod brute_force;
pub mod fit;
mod link;
mod reeb;
mod sequences;
mod sweep;

pub use reeb::{NodeKind, ReebGraph, ReebNode};

use crate::exact::rational::{rat_to_string, Rat};
use crate::levelset::Slicer;

/// One critical height: what its level set holds and how the contour
/// changes across it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CriticalLevel {
    /// The exact height, in the mesh's units.
    pub z: Rat,
    /// Face regions F facing up (material below).
    pub faces_up: usize,
    /// Face regions F facing down (material above).
    pub faces_down: usize,
    /// S_NO polylines of kind ridge.
    pub ridges: usize,
    /// S_NO polylines of kind valley.
    pub valleys: usize,
    /// Isolated minima (P).
    pub minima: usize,
    /// Isolated maxima (P).
    pub maxima: usize,
    /// `m` of each saddle (`2m` S_O branches), by ascending vertex id.
    pub saddles: Vec<u32>,
    /// Loops of L- (the contour just below), collapsed ones included.
    pub below: usize,
    /// Loops of L+ (the contour just above), collapsed ones included.
    pub above: usize,
}

/// The critical values of a mesh, with its Reeb graph.
#[derive(Clone, Debug, PartialEq)]
pub struct CriticalReport {
    /// The critical heights, ascending.
    pub levels: Vec<CriticalLevel>,
    /// The Reeb graph; its nodes lie at the heights of `levels`.
    pub reeb: ReebGraph,
    /// Total genus of the surface: the sum over components of
    /// `(2 - chi) / 2`.
    pub genus: u64,
    /// Connected components of the surface.
    pub components: usize,
}

/// Why the analysis failed: always an internal error (a bug), for a mesh
/// that validation accepted.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CriticalError {
    /// A consistency check of the sweep failed.
    #[error("critical values at z = {level}: {what} (internal error, please report)")]
    Internal {
        /// The height being processed, as `p/q`.
        level: String,
        /// What failed.
        what: String,
    },
}

/// The critical heights of the mesh, what each holds, its L-/L+ loop
/// counts and the unperturbed Reeb graph (see the module documentation).
///
/// Exact: every decision is a comparison of two stored doubles or an exact
/// orientation; heights are reported as exact rationals in the mesh's
/// units. `O(n log n)` expected time.
///
/// ```
/// use wmslice::{critical, datasets, Slicer};
/// use wmslice::critical::NodeKind;
/// let mesh = datasets::by_name("upright_torus").unwrap().build();
/// let report = critical::analyze(&Slicer::new(&mesh).unwrap()).unwrap();
/// // min (-3), saddles (-1, 1), max (3); z = -2, 0, 2 are regular.
/// let zs: Vec<String> = report.levels.iter().map(|l| l.z.to_string()).collect();
/// assert_eq!(zs, ["-3", "-1", "1", "3"]);
/// // Across the hole's bottom the contour splits: 1 loop below, 2 above.
/// assert_eq!((report.levels[1].below, report.levels[1].above), (1, 2));
/// assert_eq!(report.levels[1].saddles, [2]);
/// // The Reeb graph: 4 nodes, 4 arcs, one cycle = the genus.
/// let kinds: Vec<NodeKind> = report.reeb.nodes.iter().map(|n| n.kind).collect();
/// assert_eq!(kinds, [NodeKind::Min, NodeKind::Saddle, NodeKind::Saddle, NodeKind::Max]);
/// assert_eq!(report.reeb.arcs, [[0, 1], [1, 2], [1, 2], [2, 3]]);
/// assert_eq!((report.reeb.cycles(), report.genus), (1, 1));
/// ```
pub fn analyze(slicer: &Slicer<'_>) -> Result<CriticalReport, CriticalError> {
    let (levels, reeb) = sweep::sweep(slicer.mesh(), slicer.topology(), slicer.unit())?;
    let (genus, components) = reeb::surface_genus(slicer.mesh(), slicer.topology());
    let node_genus: u64 = reeb.nodes.iter().map(|n| n.genus).sum();
    let internal = |what: String| CriticalError::Internal {
        level: levels
            .last()
            .map(|l| rat_to_string(&l.z))
            .unwrap_or_default(),
        what,
    };
    if reeb.components() != components {
        return Err(internal(format!(
            "the Reeb graph has {} components, the mesh {components}",
            reeb.components()
        )));
    }
    if reeb.cycles() + node_genus != genus {
        return Err(internal(format!(
            "the Reeb graph has {} cycles and its nodes genus {node_genus}, the mesh genus {genus}",
            reeb.cycles()
        )));
    }
    Ok(CriticalReport {
        levels,
        reeb,
        genus,
        components,
    })
}
