//! Input: a validated mesh, its edge table and an exact level. Output: what
//! the level set must be, derived here from SPEC sections 3, 4 and 6 alone
//! (not by the slicer's classification, segment or chaining code): vertex
//! signs, in-plane face components with their facing, the multiset of
//! oriented S_O pieces, the S_NO edges, the extrema, the saddle branch
//! counts, and the pieces of L- and L+.
//!
//! A piece is a pair of mesh elements `(from, to)` ([`On`]): the edge a
//! crossing lies on or the vertex on the plane. Every decision is an exact
//! sign (`Level::sign_of`, `orient2d_xy`); no coordinate arithmetic happens
//! here except the exact face areas.

use super::doc::On;
use crate::exact::predicates::orient2d_xy;
use crate::exact::rational::{rat_from_f64, Rat};
use crate::exact::{Level, Sign};
use crate::ids::VertexId;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use num_traits::{Signed, Zero};
use petgraph::unionfind::UnionFind;
use std::collections::{BTreeMap, HashMap};

/// "No component": the face is not in the plane.
pub(super) const NONE: u32 = u32::MAX;

/// A multiset of oriented pieces.
pub(super) type Pieces = HashMap<(On, On), u32>;

/// The facing of an in-plane face or component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Facing {
    /// Counter-clockwise in (x, y).
    Up,
    /// Clockwise.
    Down,
    /// Zero area.
    Flat,
}

impl Facing {
    pub(super) fn name(self) -> &'static str {
        match self {
            Facing::Up => "up",
            Facing::Down => "down",
            Facing::Flat => "flat",
        }
    }

    pub(super) fn parse(s: &str) -> Option<Facing> {
        match s {
            "up" => Some(Facing::Up),
            "down" => Some(Facing::Down),
            "flat" => Some(Facing::Flat),
            _ => None,
        }
    }
}

/// Ridge (neighbours below) or valley (neighbours above).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RidgeKind {
    /// Both opposite vertices below.
    Ridge,
    /// Both above.
    Valley,
}

impl RidgeKind {
    pub(super) fn name(self) -> &'static str {
        match self {
            RidgeKind::Ridge => "ridge",
            RidgeKind::Valley => "valley",
        }
    }
}

/// Min (every neighbour above) or max (every neighbour below).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Extremum {
    /// Minimum.
    Min,
    /// Maximum.
    Max,
}

impl Extremum {
    pub(super) fn name(self) -> &'static str {
        match self {
            Extremum::Min => "min",
            Extremum::Max => "max",
        }
    }
}

/// Which one-sided limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    /// L-: a vertex on the plane counts as above.
    Below,
    /// L+: a vertex on the plane counts as below.
    Above,
}

/// Everything the level set at one level must contain.
pub(super) struct Facts {
    /// `sign(h(v) - c)`.
    pub signs: Vec<Sign>,
    /// In-plane component of each face, or [`NONE`].
    pub component: Vec<u32>,
    /// Facing of each component (its non-flat faces'), and whether it mixes
    /// up and down faces.
    pub facing: Vec<(Facing, bool)>,
    /// In-plane faces, ascending.
    pub in_plane: Vec<u32>,
    /// S_O pieces.
    pub so: Pieces,
    /// S_O pieces ending at each vertex (saddle branches).
    pub branches: HashMap<u32, usize>,
    /// S_NO edges and their kind.
    pub sno: BTreeMap<u32, RidgeKind>,
    /// Isolated extrema on the plane.
    pub extrema: BTreeMap<u32, Extremum>,
}

/// The S_O piece of a face walked in its vertex order under signs `s`:
/// from where the walk passes from + to -, to where it passes from - to +
/// (SPEC section 4); a zero vertex between a + and a - corner is where the
/// walk passes. `None` unless the face has both a + and a - corner.
pub(super) fn face_piece(s: [Sign; 3], tri: [u32; 3], edges: [u32; 3]) -> Option<(On, On)> {
    if !(s.contains(&Sign::Positive) && s.contains(&Sign::Negative)) {
        return None;
    }
    let (mut from, mut to) = (None, None);
    for i in 0..3 {
        let next = s[(i + 1) % 3];
        let prev = s[(i + 2) % 3];
        match (s[i], next) {
            (Sign::Positive, Sign::Negative) => from = Some(On::Edge(edges[i].into())),
            (Sign::Negative, Sign::Positive) => to = Some(On::Edge(edges[i].into())),
            _ => {}
        }
        if s[i] == Sign::Zero {
            match (prev, next) {
                (Sign::Positive, Sign::Negative) => from = Some(On::Vertex(tri[i].into())),
                (Sign::Negative, Sign::Positive) => to = Some(On::Vertex(tri[i].into())),
                _ => {}
            }
        }
    }
    Some((from?, to?))
}

/// Twice the exact signed (x, y) area of a face, in stored units.
pub(super) fn twice_area(mesh: &Mesh, f: usize) -> Rat {
    let [a, b, c] = mesh.faces[f].map(|v| mesh.pos(v).map(rat_from_f64));
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

impl Facts {
    /// Derives the facts at `level` (in the mesh's stored units).
    pub(super) fn new(mesh: &Mesh, topo: &Topology, level: &Level) -> Facts {
        let signs: Vec<Sign> = mesh.positions.iter().map(|p| level.sign_of(p[2])).collect();
        let zero = |v: VertexId| signs[v.idx()] == Sign::Zero;
        let nf = mesh.num_faces();

        // F: faces with three zero corners, joined across shared edges.
        let mut component = vec![NONE; nf];
        let in_plane: Vec<u32> = (0..nf)
            .filter(|&f| mesh.faces[f].iter().all(|&v| zero(v)))
            .map(|f| f as u32)
            .collect();
        let mut sets = UnionFind::<u32>::new(nf);
        for &f in &in_plane {
            component[f as usize] = 0;
        }
        for e in &topo.edges {
            let [f0, f1] = e.faces.map(|f| f.0);
            if component[f0 as usize] != NONE && component[f1 as usize] != NONE {
                sets.union(f0, f1);
            }
        }
        let mut facing: Vec<(Facing, bool)> = Vec::new();
        let mut id_of_root: HashMap<u32, u32> = HashMap::new();
        for &f in &in_plane {
            let root = sets.find_mut(f);
            let id = *id_of_root.entry(root).or_insert_with(|| {
                facing.push((Facing::Flat, false));
                (facing.len() - 1) as u32
            });
            component[f as usize] = id;
            let [a, b, c] = mesh.faces[f as usize].map(|v| mesh.pos(v));
            let this = match orient2d_xy(a, b, c) {
                Sign::Positive => Facing::Up,
                Sign::Negative => Facing::Down,
                Sign::Zero => Facing::Flat,
            };
            let slot = &mut facing[id as usize];
            match (slot.0, this) {
                (_, Facing::Flat) => {}
                (Facing::Flat, t) => slot.0 = t,
                (s, t) if s != t => slot.1 = true,
                _ => {}
            }
        }

        // S_O: crossed faces.
        let mut so: Pieces = HashMap::new();
        for f in 0..nf {
            let tri = mesh.faces[f].map(|v| v.0);
            let s = tri.map(|v| signs[v as usize]);
            let edges = topo.face_edges[f].map(|e| e.0);
            if let Some(p) = face_piece(s, tri, edges) {
                *so.entry(p).or_default() += 1;
            }
        }

        // In-plane edges, decided by the edge table (SPEC section 3).
        let mut sno = BTreeMap::new();
        for (id, e) in topo.edges.iter().enumerate() {
            if !(zero(e.v[0]) && zero(e.v[1])) {
                continue;
            }
            let [a, b] = e.v.map(|v| On::Vertex(v.0.into()));
            let c = e.faces.map(|f| component[f.idx()]);
            let s = e.opposite.map(|v| signs[v.idx()]);
            let piece = match (c[0] != NONE, c[1] != NONE) {
                (true, true) => None,
                (true, false) | (false, true) => {
                    // dF runs as the in-plane face traverses the edge.
                    let k = if c[0] != NONE { 0 } else { 1 };
                    let (from, to) = if k == 0 { (a, b) } else { (b, a) };
                    match (facing[c[k] as usize].0, s[1 - k]) {
                        (Facing::Up, Sign::Positive) => Some((to, from)),
                        (Facing::Down, Sign::Negative) => Some((from, to)),
                        _ => None,
                    }
                }
                (false, false) => match (s[0], s[1]) {
                    (Sign::Negative, Sign::Negative) => {
                        sno.insert(id as u32, RidgeKind::Ridge);
                        None
                    }
                    (Sign::Positive, Sign::Positive) => {
                        sno.insert(id as u32, RidgeKind::Valley);
                        None
                    }
                    // The face whose opposite vertex is above gives the
                    // direction (material on the left).
                    (Sign::Positive, Sign::Negative) => Some((a, b)),
                    (Sign::Negative, Sign::Positive) => Some((b, a)),
                    _ => None,
                },
            };
            if let Some(p) = piece {
                *so.entry(p).or_default() += 1;
            }
        }

        let mut branches: HashMap<u32, usize> = HashMap::new();
        for (&(from, to), &n) in &so {
            for end in [from, to] {
                if let On::Vertex(v) = end {
                    *branches.entry(v as u32).or_default() += n as usize;
                }
            }
        }

        let mut extrema = BTreeMap::new();
        for v in 0..mesh.num_vertices() {
            if signs[v] != Sign::Zero {
                continue;
            }
            let fan = topo.fan(VertexId::from_idx(v));
            let mut sides = fan.iter().map(|e| signs[e.neighbour.idx()]);
            let Some(first) = sides.next() else { continue };
            if first != Sign::Zero && sides.all(|s| s == first) {
                let kind = if first == Sign::Positive {
                    Extremum::Min
                } else {
                    Extremum::Max
                };
                extrema.insert(v as u32, kind);
            }
        }

        Facts {
            signs,
            component,
            facing,
            in_plane,
            so,
            branches,
            sno,
            extrema,
        }
    }

    /// The exact unsigned area of faces, in stored units squared.
    pub(super) fn area_of(mesh: &Mesh, faces: impl Iterator<Item = usize>) -> Rat {
        let twice = faces.fold(Rat::zero(), |acc, f| acc + twice_area(mesh, f).abs());
        twice / Rat::from_integer(2.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: Sign = Sign::Positive;
    const N: Sign = Sign::Negative;
    const Z: Sign = Sign::Zero;

    #[test]
    fn face_walk_runs_from_plus_to_minus_crossing() {
        let tri = [10, 11, 12];
        let edges = [20, 21, 22]; // 10->11, 11->12, 12->10
        assert_eq!(
            face_piece([P, N, N], tri, edges),
            Some((On::Edge(20), On::Edge(22)))
        );
        assert_eq!(
            face_piece([Z, P, N], tri, edges),
            Some((On::Edge(21), On::Vertex(10)))
        );
        assert_eq!(
            face_piece([Z, N, P], tri, edges),
            Some((On::Vertex(10), On::Edge(21)))
        );
        assert_eq!(face_piece([Z, Z, P], tri, edges), None);
        assert_eq!(face_piece([P, P, Z], tri, edges), None);
    }
}
