//! Input: vertex signs and the edge table. Output: the face regions F
//! (faces with all three vertices in the plane, joined across in-plane
//! edges), each with its facing, exact area and boundary half-edges dF.

use super::Signs;
use crate::exact::face_area::{twice_area_xy, MagnitudeSum};
use crate::exact::predicates::orient2d_xy;
use crate::exact::rational::Rat;
use crate::exact::Sign;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;

/// Which way an in-plane region faces (SPEC section 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Facing {
    /// Counter-clockwise in `(x, y)`: outward normal `+z`, material below.
    Up,
    /// Clockwise: outward normal `-z`, material above.
    Down,
    /// Every face of the region has zero area.
    Flat,
}

/// A boundary half-edge of a region: runs `from -> to` as its region face
/// traverses it (the direction dF follows).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// The undirected edge.
    pub edge: EdgeId,
    /// Start vertex (in the region face's order).
    pub from: VertexId,
    /// End vertex.
    pub to: VertexId,
    /// The region face that owns the half-edge.
    pub face: FaceId,
}

/// A connected region of in-plane faces (faces sharing in-plane edges).
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// Faces, ascending.
    pub faces: Vec<FaceId>,
    /// Facing of its non-zero-area faces.
    pub facing: Facing,
    /// Exact area (unsigned), in the mesh's units squared.
    pub area: Rat,
    /// Boundary half-edges dF, unordered (chained later).
    pub boundary: Vec<BoundaryEdge>,
}

/// The facing of one in-plane face, from the exact orientation of its
/// `(x, y)` projection.
pub fn face_facing(mesh: &Mesh, f: FaceId) -> Facing {
    let [a, b, c] = mesh.faces[f.idx()].map(|v| mesh.pos(v));
    Facing::of_orientation(orient2d_xy(a, b, c))
}

impl Facing {
    /// The facing of a face whose `(x, y)` projection has this orientation.
    fn of_orientation(s: Sign) -> Facing {
        match s {
            Sign::Positive => Facing::Up,
            Sign::Negative => Facing::Down,
            Sign::Zero => Facing::Flat,
        }
    }
}

/// Finds the face regions among `in_plane` faces (all three signs zero).
/// `region_of` is filled with each in-plane face's region index.
pub fn face_regions(
    mesh: &Mesh,
    topo: &Topology,
    signs: &Signs<'_>,
    in_plane: &[FaceId],
    region_of: &mut rustc_hash::FxHashMap<FaceId, u32>,
) -> Vec<Region> {
    region_of.clear();
    let is_in_plane = |f: FaceId| mesh.faces[f.idx()].iter().all(|&v| signs.is_zero(v));
    let mut regions = Vec::new();
    let mut sorted: Vec<FaceId> = in_plane.to_vec();
    sorted.sort_unstable();
    for &seed in &sorted {
        if region_of.contains_key(&seed) {
            continue;
        }
        let r = regions.len() as u32;
        let mut faces = vec![seed];
        region_of.insert(seed, r);
        let mut stack = vec![seed];
        let mut boundary = Vec::new();
        while let Some(f) = stack.pop() {
            let tri = mesh.faces[f.idx()];
            for c in 0..3 {
                let e = topo.face_edges[f.idx()][c];
                let edge = topo.edge(e);
                let other = if edge.faces[0] == f {
                    edge.faces[1]
                } else {
                    edge.faces[0]
                };
                if is_in_plane(other) {
                    if let std::collections::hash_map::Entry::Vacant(slot) = region_of.entry(other)
                    {
                        slot.insert(r);
                        faces.push(other);
                        stack.push(other);
                    }
                } else {
                    boundary.push(BoundaryEdge {
                        edge: e,
                        from: tri[c],
                        to: tri[(c + 1) % 3],
                        face: f,
                    });
                }
            }
        }
        faces.sort_unstable();
        let mut facing = Facing::Flat;
        let mut twice = MagnitudeSum::default();
        for &f in &faces {
            let [a, b, c] = mesh.faces[f.idx()].map(|v| mesh.pos(v));
            // A slicer's mesh is validated: every coordinate is finite,
            // so no face is skipped here.
            let Some(area) = twice_area_xy(a, b, c) else {
                continue;
            };
            if facing == Facing::Flat {
                facing = Facing::of_orientation(area.sign());
            }
            twice.add_abs(&area);
        }
        boundary.sort_unstable_by_key(|b| b.edge);
        regions.push(Region {
            faces,
            facing,
            area: twice.to_rat_times_pow2(-1),
            boundary,
        });
    }
    regions
}
