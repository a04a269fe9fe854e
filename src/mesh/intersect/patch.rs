//! Input: a closed, oriented, manifold mesh with finite coordinates, its
//! topology, and the knowledge that its faces sharing one vertex id meet
//! properly (the fan pass found no pair). Output: its *certified patches*,
//! sets of faces no two of which, sharing no vertex id, meet: the broad
//! phase (`bvh/`) skips those pairs.
//!
//! Flat regions of CAD parts are fans and strips of long thin faces in one
//! plane (the radial faces of an annulus). Their boxes overlap many
//! neighbours, and the finer the ring the more: the pairs a box test passes
//! grow faster than the faces. Their faces do not overlap for a reason that
//! boxes cannot see, and that is proven here once per region.
//!
//! A *patch* is a set of proper faces in one plane, facing one way, joined
//! through edges whose two faces are both such (flat neighbours,
//! [`super::narrow::edge_faces`], exact).
//! Let `P` be one with at least [`MIN_FACES`] faces, and project it one to
//! one onto two coordinate axes (where its plane does not stand upright:
//! every orientation keeps its sign, one for all faces). `P` is
//! *certified* when
//!
//! 1. every vertex lies on at most two of `P`'s boundary edges (those with
//!    one face in `P`), so `P` is a compact surface with boundary and its
//!    boundary a union of closed polygons, and
//! 2. two boundary edges with no shared vertex id do not meet (closed
//!    segments, exact: [`closed_segments_meet_2d`]).
//!
//! **Claim.** In a certified patch, two faces with no shared vertex id do
//! not meet. *Proof.* The projection `phi` of `P` is locally one to one:
//! inside a face (proper), across an inner edge (the two faces lie on its
//! two sides), and at a vertex (its faces in `P` share the vertex, and the
//! fan pass found that such faces meet only in shared elements). Two
//! boundary edges sharing a vertex `v` meet only at `v`: running on along
//! one line, the faces of `P` between them at `v` would turn by a multiple
//! of a full turn, and two of them, sharing only `v`, would meet beyond it.
//! With 2, `phi` is one to one on the boundary: the images are disjoint
//! simple polygons. For a point `p` off them, the number of faces over `p`
//! (each face counted where its interior covers `p`) is the winding number
//! of the boundary about `p`: the sum, over the polygons, of `+1` or `-1`
//! for each whose inside holds `p`. A local homeomorphism from a compact
//! orientable surface into the plane turns its boundary, in total, by its
//! Euler characteristic `2 - 2g - b` (`b` polygons); a simple polygon turns
//! by `+1` or `-1` as it runs counter-clockwise or clockwise, so exactly
//! `1 - g` polygons run counter-clockwise, and `g = 0` since some point is
//! covered. Hence at most one polygon adds `+1`, so at most one face covers
//! any point off the boundary. Two faces sharing no vertex id that met at a
//! point `q` would be two distinct points of `P` over `q`; both inside `P`,
//! their neighbourhoods would cover points near `q` twice; one on the
//! boundary and one inside, points on one side of the boundary near `q`
//! twice; both on the boundary, `phi` would not be one to one there. `QED`
//!
//! Patches that fail a test are not certified, and their pairs are tested
//! like any others; so is every patch when the fan pass found a pair (the
//! mesh is refused, and every pair is listed).

use super::bvh::{Bvh, NO_GROUP};
use super::narrow::{closed_segments_meet_2d, projection, Axes};
use super::Stop;
use crate::exact::orient_filter::Filter;
use crate::ids::{FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::par;
use petgraph::unionfind::UnionFind;
use std::sync::atomic::{AtomicBool, Ordering};

/// The fewest faces a patch needs to be worth certifying: two faces that
/// share an edge are never tested anyway.
pub(super) const MIN_FACES: usize = 16;

/// Per face, its certified patch (numbered from 0), or [`NO_GROUP`];
/// `flat[e]` tells whether the faces of edge `e` are flat neighbours
/// ([`super::narrow::edge_faces`]).
pub(super) fn certified_patches(
    filter: Filter,
    mesh: &Mesh,
    topo: &Topology,
    flat: &[bool],
) -> Vec<u32> {
    let parallel = mesh.num_faces() >= par::MIN_LEN;
    if !flat.contains(&true) {
        return vec![NO_GROUP; mesh.num_faces()];
    }
    let mut sets = UnionFind::<u32>::new(mesh.num_faces());
    for (e, _) in topo.edges.iter().zip(flat).filter(|(_, &f)| f) {
        sets.union(e.faces[0].0, e.faces[1].0);
    }
    let root = sets.into_labeling();
    let mut size = vec![0u32; root.len()];
    for &r in &root {
        size[r as usize] += 1;
    }
    // Candidates numbered in order of their roots.
    let mut number = vec![NO_GROUP; root.len()];
    let mut candidates = 0u32;
    for (r, &s) in size.iter().enumerate() {
        if s as usize >= MIN_FACES {
            number[r] = candidates;
            candidates += 1;
        }
    }
    if candidates == 0 {
        return vec![NO_GROUP; mesh.num_faces()];
    }
    let patch = |f: FaceId| number[root[f.idx()] as usize];
    // Boundary edges of candidates, as (patch, edge index), and the axes
    // each candidate projects on.
    let mut boundary: Vec<(u32, u32)> = Vec::new();
    for (k, e) in topo.edges.iter().enumerate() {
        let [a, b] = e.faces.map(patch);
        for g in [a, b] {
            if g != NO_GROUP && a != b {
                boundary.push((g, k as u32));
            }
        }
    }
    let mut axes: Vec<Option<Axes>> = vec![None; candidates as usize];
    for (f, tri) in mesh.faces.iter().enumerate() {
        let g = patch(FaceId::from_idx(f));
        if g != NO_GROUP && axes[g as usize].is_none() {
            let [a, b, c] = tri.map(|v| mesh.pos(v));
            axes[g as usize] = projection(filter, a, b, c).map(|(ax, _)| ax);
        }
    }
    let failed: Vec<AtomicBool> = (0..candidates).map(|_| AtomicBool::new(false)).collect();
    pinched(&boundary, mesh, topo, &failed);
    // Test 2, by a tree over the boundary edges as triangles (a, b, b).
    let tris: Vec<[VertexId; 3]> = boundary
        .iter()
        .map(|&(_, k)| {
            let [a, b] = topo.edges[k as usize].v;
            [a, b, b]
        })
        .collect();
    let tree = Bvh::build(mesh, &tris, None, parallel);
    let meets = |s: FaceId, t: FaceId| {
        let (g, h) = (boundary[s.idx()].0, boundary[t.idx()].0);
        if g == h && !failed[g as usize].load(Ordering::Relaxed) {
            let p = |i: usize| tris[i].map(|v| mesh.pos(v));
            let ([x, y, _], [u, w, _]) = (p(s.idx()), p(t.idx()));
            // A candidate's faces are proper (each is on a flat edge), so
            // its axes are known; were they not, it would not be certified.
            let meet = axes[g as usize].is_none_or(|ax| closed_segments_meet_2d(ax, x, y, u, w));
            if meet {
                failed[g as usize].store(true, Ordering::Relaxed);
            }
        }
        false
    };
    tree.pairs(&meets, 0, &Stop::never());
    // Certified patches, renumbered from 0.
    let mut renumber = vec![NO_GROUP; candidates as usize];
    let mut next = 0;
    for (g, f) in failed.iter().enumerate() {
        if !f.load(Ordering::Relaxed) {
            renumber[g] = next;
            next += 1;
        }
    }
    (0..mesh.num_faces())
        .map(|f| match patch(FaceId::from_idx(f)) {
            NO_GROUP => NO_GROUP,
            g => renumber[g as usize],
        })
        .collect()
}

/// Marks as failed each candidate with a vertex on more than two of its
/// boundary edges.
fn pinched(boundary: &[(u32, u32)], mesh: &Mesh, topo: &Topology, failed: &[AtomicBool]) {
    // Boundary edges per vertex, over all candidates; only vertices on more
    // than two are looked at per candidate.
    let mut on = vec![0u8; mesh.num_vertices()];
    for &(_, k) in boundary {
        for v in topo.edges[k as usize].v {
            on[v.idx()] = on[v.idx()].saturating_add(1);
        }
    }
    let mut ends: Vec<(u32, u32)> = boundary
        .iter()
        .flat_map(|&(g, k)| topo.edges[k as usize].v.map(|v| (g, v.0)))
        .filter(|&(_, v)| on[v as usize] > 2)
        .collect();
    ends.sort_unstable();
    for run in ends.chunk_by(|x, y| x == y) {
        if run.len() > 2 {
            failed[run[0].0 as usize].store(true, Ordering::Relaxed);
        }
    }
}
