//! Input: a closed, oriented, manifold [`Mesh`] with finite coordinates and
//! its [`Topology`]. Output: its self-intersections (SPEC section 1): the
//! pairs of faces that meet anywhere but in the vertices and edges they
//! share, decided exactly.
//!
//! Two faces are tested by the ids they share:
//!
//! - an edge: the edge table's two faces ([`edge_overlaps`]); a fold
//!   (both proper, in one plane, on one side) is reported by validation as
//!   `Defect::Fold`, the rest (two zero-area faces running on along the
//!   edge's line) as self-intersections;
//! - one vertex: the non-neighbouring faces of its fan (`fan.rs`), skipped
//!   for a fan that projects as a star;
//! - none: the pairs whose closed bounding boxes meet (`bvh/`; along
//!   the mesh's own axes when one plane dominates it off the axes,
//!   `turn.rs`), each tested exactly (`narrow.rs`); touching counts, so
//!   two bodies that touch at a point without sharing a vertex id
//!   self-intersect. Pairs within one certified flat patch (`patch.rs`: a
//!   planar region whose faces are proven not to overlap from its
//!   boundary) are skipped, once the fans have shown that faces sharing a
//!   vertex meet properly.
//!
//! Every decision is exact, with no tolerance: signs come from the exact
//! predicates, or from floating-point filters only where their proven
//! error bound shows the sign ([`crate::exact::orient_filter`]); the
//! broad phase's `f32` bounds are rounded outward, so they can only let
//! more pairs through to the exact tests, never fewer.
//!
//! Every pair is found once, by exactly one of these. Work is spread over
//! rayon's pool for large meshes (see `crate::par`); the answer does not
//! depend on it: pairs are listed in ascending order, the first `keep`
//! listed and the rest counted. A search may be told to stop counting
//! once it has found so many pairs ([`Tally::AtLeast`]): a soup of
//! crossing faces has pairs by the million (a fuzzed 300 KB file, 8.8
//! million, 29 s to count), and so has a fan of a few thousand faces
//! around one vertex folded every which way; the first `keep` are then
//! found face by face, ascending (each face against the later faces that
//! share one vertex with it or whose volumes meet its own), so the
//! listing is the same as a whole count would give.

mod bvh;
mod fan;
mod narrow;
mod patch;
#[cfg(test)]
mod patch_tests;
#[cfg(test)]
mod tests;
mod turn;

pub use narrow::EdgeOverlap;

use crate::exact::orient_filter::Filter;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::par;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Face pairs, ascending, each `(a, b)` with `a < b`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FacePairs {
    /// The first pairs in ascending order.
    pub pairs: Vec<(FaceId, FaceId)>,
    /// How many more pairs there are (or at least, see `tally`).
    pub unlisted: usize,
    /// Whether `unlisted` is the count or a lower bound.
    pub tally: Tally,
}

/// What a count of unlisted pairs is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Tally {
    /// Every pair was counted.
    #[default]
    Exact,
    /// The search stopped counting: there are at least that many.
    AtLeast,
}

/// A count of the pairs found, shared by the tasks of one search, and the
/// count at which the search stops.
pub(crate) struct Stop {
    found: AtomicUsize,
    at: usize,
}

impl Stop {
    pub(crate) fn at(at: usize) -> Stop {
        Stop {
            found: AtomicUsize::new(0),
            at,
        }
    }

    /// A stop that is never reached.
    pub(crate) fn never() -> Stop {
        Stop::at(usize::MAX)
    }

    /// One more pair found.
    #[inline]
    pub(crate) fn count(&self) {
        self.found.fetch_add(1, Ordering::Relaxed);
    }

    /// Whether `at` pairs have been found.
    #[inline]
    pub(crate) fn reached(&self) -> bool {
        self.found.load(Ordering::Relaxed) >= self.at
    }
}

/// Pairs being collected: the `keep` smallest seen, and a count of the
/// others.
#[derive(Debug)]
pub(crate) struct Found {
    pairs: Vec<(FaceId, FaceId)>,
    dropped: usize,
    pub(crate) keep: usize,
}

impl Found {
    pub(crate) fn new(keep: usize) -> Found {
        Found {
            pairs: Vec::new(),
            dropped: 0,
            keep,
        }
    }

    pub(crate) fn push(&mut self, a: FaceId, b: FaceId) {
        self.pairs.push(if a < b { (a, b) } else { (b, a) });
        if self.pairs.len() > self.keep.saturating_mul(2).max(64) {
            self.trim();
        }
    }

    /// Adds another collection's pairs and count.
    pub(crate) fn absorb(&mut self, other: Found) {
        let me = std::mem::replace(self, Found::new(self.keep));
        *self = me.merged(other);
    }

    pub(crate) fn merged(mut self, mut other: Found) -> Found {
        if self.pairs.len() < other.pairs.len() {
            std::mem::swap(&mut self.pairs, &mut other.pairs);
        }
        self.pairs.append(&mut other.pairs);
        self.dropped += other.dropped;
        if self.pairs.len() > self.keep {
            self.trim();
        }
        self
    }

    /// Whether no pair was seen.
    fn is_empty(&self) -> bool {
        self.pairs.is_empty() && self.dropped == 0
    }

    /// Keeps the `keep` smallest pairs.
    fn trim(&mut self) {
        if self.pairs.len() > self.keep {
            if self.keep > 0 {
                self.pairs.select_nth_unstable(self.keep - 1);
            }
            self.dropped += self.pairs.len() - self.keep;
            self.pairs.truncate(self.keep);
        }
    }

    fn finish(mut self) -> FacePairs {
        self.trim();
        self.pairs.sort_unstable();
        FacePairs {
            pairs: self.pairs,
            unlisted: self.dropped,
            tally: Tally::Exact,
        }
    }
}

/// Every edge's faces, tested: the improper edges (each edge whose two
/// faces meet beyond it, with how, never [`EdgeOverlap::Proper`], in edge
/// order), and per edge whether its faces are flat neighbours
/// ([`narrow::edge_faces`]: the joints of the flat patches).
fn edge_pass(
    filter: Filter,
    mesh: &Mesh,
    topo: &Topology,
) -> (Vec<(EdgeId, EdgeOverlap)>, Vec<bool>) {
    let tested: Vec<(EdgeOverlap, bool)> = topo
        .edges
        .par_iter()
        .with_min_len(par::MIN_LEN)
        .map(|e| {
            narrow::edge_faces(
                filter,
                mesh.pos(e.v[0]),
                mesh.pos(e.v[1]),
                mesh.pos(e.opposite[0]),
                mesh.pos(e.opposite[1]),
            )
        })
        .collect();
    let improper = tested
        .iter()
        .enumerate()
        .filter(|(_, (kind, _))| *kind != EdgeOverlap::Proper)
        .map(|(k, &(kind, _))| (EdgeId::from_idx(k), kind))
        .collect();
    (improper, tested.into_iter().map(|(_, flat)| flat).collect())
}

/// The improper edges: each edge whose two faces meet beyond it, with how
/// (never [`EdgeOverlap::Proper`]), in edge order.
///
/// `topo` must be the topology of `mesh` with no issue (closed, oriented,
/// manifold) and `mesh`'s coordinates finite.
pub fn edge_overlaps(mesh: &Mesh, topo: &Topology) -> Vec<(EdgeId, EdgeOverlap)> {
    edge_pass(Filter::for_points(&mesh.positions), mesh, topo).0
}

/// The improper edges, as [`edge_overlaps`], and the pairs of faces
/// sharing one vertex id or none that meet anywhere but in that vertex:
/// ascending, the first `keep` listed. The pairs are counted up to
/// `stop_at`: with that many or more, the count is a lower bound
/// ([`Tally::AtLeast`]); the listing is the same either way, and so is
/// whether the count stops (it depends on the number of pairs only).
///
/// `topo` must be the topology of `mesh` with no issue (closed, oriented,
/// manifold) and `mesh`'s coordinates finite.
pub fn face_pairs(
    mesh: &Mesh,
    topo: &Topology,
    keep: usize,
    stop_at: usize,
) -> (Vec<(EdgeId, EdgeOverlap)>, FacePairs) {
    let filter = Filter::for_points(&mesh.positions);
    let parallel = mesh.num_faces() >= par::MIN_LEN;
    let stop = Stop::at(stop_at);
    let (at_vertices, (improper, patches)) = par::join(
        parallel,
        || {
            (0..mesh.num_vertices())
                .into_par_iter()
                .with_min_len(par::MIN_LEN)
                .fold(
                    || Found::new(keep),
                    |mut found, v| {
                        let v = VertexId::from_idx(v);
                        fan::fan_pairs(filter, mesh, v, topo.fan(v), &stop, &mut found);
                        found
                    },
                )
                .reduce(|| Found::new(keep), Found::merged)
        },
        || {
            let (improper, flat) = edge_pass(filter, mesh, topo);
            (
                improper,
                patch::certified_patches(filter, mesh, topo, &flat),
            )
        },
    );
    // The patches' proof rests on the fans' pairs all being proper.
    let groups = at_vertices.is_empty().then_some(&patches[..]);
    let tree = bvh::Bvh::build(mesh, &mesh.faces, groups, parallel);
    let face = |f: FaceId| mesh.faces[f.idx()].map(|v| mesh.pos(v));
    let meet = |a, b| narrow::faces_meet(filter, face(a), face(b));
    let apart = tree.pairs(&meet, keep, &stop);
    if !stop.reached() {
        return (improper, at_vertices.merged(apart).finish());
    }
    let first = first_pairs(keep, mesh, topo, &tree, |p| match p {
        Partner::Apart(a, b) => meet(a, b),
        Partner::AtVertex(p) => fan::meet(filter, mesh, topo, p),
    });
    let stopped = FacePairs {
        unlisted: stop_at.saturating_sub(first.len()),
        pairs: first,
        tally: Tally::AtLeast,
    };
    (improper, stopped)
}

/// A pair of faces to test, the second after the first in the input.
enum Partner<'p> {
    /// Sharing no vertex.
    Apart(FaceId, FaceId),
    /// Sharing one vertex.
    AtVertex(&'p fan::AtVertex),
}

/// The first `keep` pairs in ascending order that `meet` accepts, of the
/// pairs the fans and `tree` test: face by face in ascending order, each
/// against the later faces that share one vertex with it and those
/// [`bvh::Bvh::later_partners`] finds, until `keep` are found. Sequential:
/// for a search that stopped, where pairs abound.
fn first_pairs(
    keep: usize,
    mesh: &Mesh,
    topo: &Topology,
    tree: &bvh::Bvh,
    meet: impl Fn(Partner) -> bool,
) -> Vec<(FaceId, FaceId)> {
    let place = tree.places();
    let mut first = Vec::new();
    let (mut apart, mut at_vertex) = (Vec::new(), Vec::new());
    for a in (0..mesh.num_faces()).map(FaceId::from_idx) {
        apart.clear();
        at_vertex.clear();
        tree.later_partners(&place, a, &mut apart);
        fan::later_partners(mesh, topo, a, &mut at_vertex);
        let mut later: Vec<(FaceId, Partner)> = apart
            .iter()
            .map(|&b| (FaceId(b), Partner::Apart(a, FaceId(b))))
            .chain(at_vertex.iter().map(|p| (p.face, Partner::AtVertex(p))))
            .collect();
        later.sort_unstable_by_key(|&(b, _)| b);
        for (b, p) in later {
            if first.len() >= keep {
                return first;
            }
            if meet(p) {
                first.push((a, b));
            }
        }
    }
    first
}

/// The pairs of [`face_pairs`] (its edge pass too, which the search
/// needs).
pub fn separate_face_pairs(mesh: &Mesh, topo: &Topology, keep: usize, stop_at: usize) -> FacePairs {
    face_pairs(mesh, topo, keep, stop_at).1
}

/// Every improper pair of faces (folds included), ascending, each pair
/// once (two faces folding along all three of their edges, a triangle and
/// its reverse, are one pair, not three): the whole answer, unbounded,
/// for tests and comparisons.
///
/// `topo` must be the topology of `mesh` with no issue and `mesh`'s
/// coordinates finite.
pub fn self_intersections(mesh: &Mesh, topo: &Topology) -> Vec<(FaceId, FaceId)> {
    let (improper, apart) = face_pairs(mesh, topo, usize::MAX, usize::MAX);
    let mut pairs = apart.pairs;
    for (e, _) in improper {
        let [a, b] = topo.edge(e).faces;
        pairs.push(if a < b { (a, b) } else { (b, a) });
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}
