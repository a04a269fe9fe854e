//! Input: a vertex `v`, its fan, and the vertex heights. Output: what `v`
//! holds in the level set at its own height `c = z(v)` (SPEC section 3),
//! read from its link alone: whether a face of its fan lies in the plane
//! (F), its ridge and valley edges (S_NO), whether it is an isolated
//! extremum (P), and its number of S_O branches (`2m`; a saddle when
//! `m >= 2`).
//!
//! Exact: heights are compared as the doubles they are (`-0 == +0`), and
//! the facing of an in-plane face is the exact orientation of its
//! projection. Nothing is rounded.
//!
//! With `s_i` the sign of `z(n_i) - c` for the neighbours `n_0 .. n_{k-1}`
//! in fan order (face `i` is `(v, n_i, n_{i+1})`), the branches at `v` are
//! the S_O segments that end there, exactly as the slicer makes them:
//! - a face with `{s_i, s_{i+1}} = {+, -}` (its segment runs from `v` to the
//!   opposite edge);
//! - a transversal edge `(v, n_i)`: `s_i = 0` with `s_{i-1}`, `s_{i+1}`
//!   strictly opposite;
//! - a boundary edge of F shared with S_O: `s_i = 0`, exactly one of the two
//!   faces at the edge in F, the F face `up` with the other face's third
//!   vertex above, or `down` with it below.

use crate::classify::faces::face_facing;
use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::Sign;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;

/// The exact sign of `a - b` for finite doubles.
#[inline]
pub(super) fn height_sign(a: f64, b: f64) -> Sign {
    if a < b {
        Sign::Negative
    } else if a > b {
        Sign::Positive
    } else {
        Sign::Zero
    }
}

/// What a vertex holds at its own height.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct AtLevel {
    /// A face of its fan lies in the plane.
    pub in_face: bool,
    /// Its S_NO edges (ridge or valley).
    pub sno_edges: u32,
    /// P: every neighbour strictly above (min) or below (max).
    pub extremum: Option<ExtremumKind>,
    /// S_O branches `2m` (segments of S_O that end at the vertex).
    pub branches: u32,
    /// The branches that are face segments (not in-plane edges).
    pub face_branches: u32,
}

impl AtLevel {
    /// Whether the vertex is a critical element: in F, on S_NO, in P, or a
    /// saddle (`2m >= 4`).
    pub(super) fn is_critical(&self) -> bool {
        self.in_face || self.sno_edges > 0 || self.extremum.is_some() || self.branches >= 4
    }
}

/// The in-plane elements a vertex contributes, each reported by exactly
/// one of its vertices.
#[derive(Default)]
pub(super) struct InPlane {
    /// Faces of F, each from its smallest vertex.
    pub faces: Vec<FaceId>,
    /// S_NO edges, each from its smaller end, with its ends (smaller first).
    pub sno: Vec<(EdgeId, [VertexId; 2], RidgeKind)>,
    /// In-plane edges `(v, w)`, each from its smaller end `v`.
    pub edges: Vec<(VertexId, VertexId)>,
}

impl InPlane {
    pub(super) fn clear(&mut self) {
        self.faces.clear();
        self.sno.clear();
        self.edges.clear();
    }
}

/// The reason a vertex cannot be classified: an in-plane face of zero
/// area, which validation refuses (its three vertices are collinear).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FlatFace(pub FaceId);

/// Classifies `v` at its own height from its link (see the module
/// documentation), and appends its in-plane elements to `out`.
pub(super) fn classify_vertex(
    mesh: &Mesh,
    topo: &Topology,
    v: VertexId,
    signs: &mut Vec<Sign>,
    out: &mut InPlane,
) -> Result<AtLevel, FlatFace> {
    let fan = topo.fan(v);
    let k = fan.len();
    let c = mesh.pos(v)[2];
    signs.clear();
    signs.extend(fan.iter().map(|e| height_sign(mesh.pos(e.neighbour)[2], c)));
    let s = |i: usize| signs[i % k];
    let mut at = AtLevel::default();
    if k == 0 {
        return Ok(at);
    }
    if s(0) != Sign::Zero && signs.iter().all(|&x| x == s(0)) {
        at.extremum = Some(if s(0) == Sign::Positive {
            ExtremumKind::Min
        } else {
            ExtremumKind::Max
        });
        return Ok(at);
    }
    let facing = |f: FaceId| -> Result<Facing, FlatFace> {
        match face_facing(mesh, f) {
            Facing::Flat => Err(FlatFace(f)),
            x => Ok(x),
        }
    };
    for i in 0..k {
        let (prev, cur, next) = (s(i + k - 1), s(i), s(i + 1));
        let entry = fan[i];
        // Face i = (v, n_i, n_{i+1}).
        if cur == Sign::Zero && next == Sign::Zero {
            at.in_face = true;
            let tri = mesh.faces[entry.face.idx()];
            if tri.iter().all(|&w| w >= v) {
                out.faces.push(entry.face);
            }
        }
        if cur.flip() == next && cur != Sign::Zero {
            at.branches += 1;
            at.face_branches += 1;
        }
        if cur != Sign::Zero {
            continue;
        }
        // Edge (v, n_i) lies in the plane; its faces are i - 1 and i.
        let w = entry.neighbour;
        if v < w {
            out.edges.push((v, w));
        }
        match (prev, next) {
            (Sign::Zero, Sign::Zero) => {}
            (Sign::Zero, other) | (other, Sign::Zero) => {
                // A boundary edge of F: the F face is i - 1 (prev zero) or i.
                let f = if prev == Sign::Zero {
                    fan[(i + k - 1) % k].face
                } else {
                    entry.face
                };
                let shared = matches!(
                    (facing(f)?, other),
                    (Facing::Up, Sign::Positive) | (Facing::Down, Sign::Negative)
                );
                if shared {
                    at.branches += 1;
                }
            }
            (a, b) if a == b => {
                at.sno_edges += 1;
                if v < w {
                    let kind = if a == Sign::Negative {
                        RidgeKind::Ridge
                    } else {
                        RidgeKind::Valley
                    };
                    out.sno.push((entry.edge, [v, w], kind));
                }
            }
            _ => at.branches += 1,
        }
    }
    Ok(at)
}

/// The edge of face `f` that joins `a` and `b` (its edge opposite the
/// third vertex), if `a -> b` or `b -> a` is one of its edges.
pub(super) fn face_edge(
    mesh: &Mesh,
    topo: &Topology,
    f: FaceId,
    a: VertexId,
    b: VertexId,
) -> Option<EdgeId> {
    let tri = mesh.faces[f.idx()];
    (0..3)
        .find(|&i| {
            let (x, y) = (tri[i], tri[(i + 1) % 3]);
            (x, y) == (a, b) || (x, y) == (b, a)
        })
        .map(|i| topo.face_edges[f.idx()][i])
}
