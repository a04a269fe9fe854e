//! Input: a mesh as loaded (or snapped). Output: the same surface with
//! every degenerate face that edge flips can remove removed ([`Repaired`]:
//! the mesh and each flip made), SPEC section 1.
//!
//! A face is degenerate when its three vertices are collinear (exact
//! orient2d in the three coordinate planes). When they are at three
//! distinct positions, exactly one of them, the *apex* `c`, lies strictly
//! inside the segment of the other two, the face's long edge `a-b` (exact
//! comparisons of coordinates, no arithmetic). With the face written
//! `(a, b, c)` in its own order and the face beyond the long edge
//! `(b, a, d)`, the flip replaces both by `(a, d, c)` and `(d, b, c)`:
//! they split `(b, a, d)` at `c`, a point of its edge, so the two faces'
//! union is the same point set and the surface does not move; each new
//! face turns the way `(b, a, d)` turns (orientation kept); edge `a-b` is
//! replaced by edge `c-d` and every other edge keeps its two faces, so a
//! closed oriented 2-manifold stays one (the links of `a` and `b` lose a
//! neighbour, those of `c` and `d` gain one, each still one cycle) as long
//! as `c-d` was not an edge already. Face and vertex ids are kept: the two
//! new faces take the two old faces' places, `(a, d, c)` that of the
//! degenerate face.
//!
//! A flip is made only when all of these hold (else the face stays, and
//! validation refuses it by name, [`Unflippable`]): the six directed edges
//! of the two faces are each used by that face alone, `b -> a` being the
//! other face's; `d != c`; `c-d` is not an edge yet; and the face beyond is
//! either not degenerate, or degenerate with its own apex `d` strictly
//! inside the same edge `a-b` (at a position other than `c`'s).
//!
//! Termination. Let `D` be the number of degenerate faces and `S` the sum
//! of their long edges' lengths. A flip with a non-degenerate face beyond
//! leaves two non-degenerate faces (`d` is off the line `a b`, `c` on it
//! and distinct from `a` and `b`), so `D` drops by one. A flip with a
//! degenerate face beyond keeps `D` (the four points are on one line) and
//! replaces two long edges `a-b` by the long edges of `{a, c, d}` and of
//! `{b, c, d}`, both strictly shorter as `c` and `d` lie strictly inside
//! `a-b`: `S` drops. So `(D, S)` decreases strictly (lexicographically) at
//! every flip; the faces are always triples of the same finitely many
//! vertices, so no state repeats and the flips stop. At most `D` flips of
//! the first kind are made.
//!
//! Deterministic: candidates are taken in ascending face order, in rounds,
//! until a round flips nothing; the result is the same on every machine
//! and thread count (the degenerate faces are found in parallel, then
//! sorted).

use crate::exact::predicates::is_degenerate_triangle;
use crate::ids::{FaceId, VertexId};
use crate::mesh::Mesh;
use crate::par;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::borrow::Cow;
use std::fmt;

/// How a face's three collinear vertices lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Degeneracy {
    /// Two of its vertices are at one position.
    Coincident {
        /// One of them.
        a: VertexId,
        /// The other.
        b: VertexId,
    },
    /// The face is `(a, b, apex)` in its own (cyclic) order, and `apex`
    /// lies strictly inside the segment `a-b`.
    OnEdge {
        /// The long edge's first end (the edge runs `a -> b` in the face).
        a: VertexId,
        /// The long edge's second end.
        b: VertexId,
        /// The vertex inside the long edge.
        apex: VertexId,
    },
}

/// Why a degenerate face was not flipped away (validation reports it with
/// the face as [`crate::mesh::validate::Defect::DegenerateFace`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Unflippable {
    /// Two of its vertices are at one position: no flip removes it.
    CoincidentVertices {
        /// One vertex.
        a: VertexId,
        /// The other, at the same position.
        b: VertexId,
    },
    /// The long edge, or another edge of the two faces, is not used once
    /// in each direction (an open or non-manifold edge).
    NoFaceBeyond {
        /// The vertex inside the long edge.
        apex: VertexId,
        /// The long edge.
        edge: [VertexId; 2],
    },
    /// The face beyond the long edge has the same three vertices.
    SameTriangleBeyond {
        /// The vertex inside the long edge.
        apex: VertexId,
        /// The long edge.
        edge: [VertexId; 2],
        /// The face beyond.
        beyond: FaceId,
    },
    /// The face beyond is degenerate too, and its apex is not strictly
    /// inside the same edge at another position.
    DegenerateBeyond {
        /// The vertex inside the long edge.
        apex: VertexId,
        /// The long edge.
        edge: [VertexId; 2],
        /// The face beyond.
        beyond: FaceId,
    },
    /// The flip would make edge `apex-opposite`, which exists already (the
    /// mesh would stop being a 2-manifold).
    EdgeExists {
        /// The vertex inside the long edge.
        apex: VertexId,
        /// The long edge.
        edge: [VertexId; 2],
        /// The face beyond.
        beyond: FaceId,
        /// The third vertex of the face beyond.
        opposite: VertexId,
    },
    /// A flip would remove it: the mesh was not repaired
    /// ([`repair_degenerate`]; the command line repairs every mesh).
    Flippable {
        /// The vertex inside the long edge.
        apex: VertexId,
        /// The long edge.
        edge: [VertexId; 2],
        /// The face beyond.
        beyond: FaceId,
    },
}

impl fmt::Display for Unflippable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Unflippable::CoincidentVertices { a, b } => {
                write!(f, "vertices {a} and {b} are at one position, so no edge flip removes it (--weld merges them, and --drop-collapsed then removes the faces that repeat a vertex)")
            }
            Unflippable::NoFaceBeyond { apex, edge: [a, b] } => write!(
                f,
                "vertex {apex} lies inside edge {a}-{b}, and the two faces there do not form a closed manifold patch to flip"
            ),
            Unflippable::SameTriangleBeyond { apex, edge: [a, b], beyond } => write!(
                f,
                "vertex {apex} lies inside edge {a}-{b}, and the face beyond it, {beyond}, is the same triangle reversed"
            ),
            Unflippable::DegenerateBeyond { apex, edge: [a, b], beyond } => write!(
                f,
                "vertex {apex} lies inside edge {a}-{b}, and the face beyond it, {beyond}, is degenerate along another edge"
            ),
            Unflippable::EdgeExists { apex, edge: [a, b], beyond, opposite } => write!(
                f,
                "vertex {apex} lies inside edge {a}-{b}; flipping it with face {beyond} would make edge {apex}-{opposite}, which exists already"
            ),
            Unflippable::Flippable { apex, edge: [a, b], beyond } => write!(
                f,
                "vertex {apex} lies inside edge {a}-{b}; flipping that edge with face {beyond} removes it (wmslice::mesh::flip::repair_degenerate, which the command line runs)"
            ),
        }
    }
}

/// One edge flip: the degenerate `face` `(a, b, apex)` and the face
/// `beyond` `(b, a, opposite)` became `(a, opposite, apex)` and
/// `(opposite, b, apex)`, in the same places.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Flip {
    /// The degenerate face.
    pub face: FaceId,
    /// The face beyond its long edge.
    pub beyond: FaceId,
    /// The long edge `[a, b]`, removed.
    pub edge: [VertexId; 2],
    /// The vertex inside it.
    pub apex: VertexId,
    /// The third vertex of the face beyond; `apex-opposite` is the new edge.
    pub opposite: VertexId,
}

impl fmt::Display for Flip {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b] = self.edge;
        write!(
            f,
            "{} ({} inside {a}-{b}) with {} (new edge {}-{})",
            self.face, self.apex, self.beyond, self.apex, self.opposite
        )
    }
}

/// A mesh after [`repair_degenerate`].
#[derive(Clone, Debug)]
pub struct Repaired<'a> {
    /// The mesh as sliced: borrowed unchanged when nothing was flipped.
    pub mesh: Cow<'a, Mesh>,
    /// The flips, in the order made.
    pub flips: Vec<Flip>,
}

/// How the vertices of `face` lie, when they are three distinct vertices
/// at collinear positions; `None` otherwise. Exact.
///
/// # Panics
///
/// On an index out of range or a non-finite coordinate (validation names
/// both; [`repair_degenerate`] leaves such meshes alone).
pub fn degeneracy(mesh: &Mesh, face: FaceId) -> Option<Degeneracy> {
    let t = mesh.faces[face.idx()];
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return None;
    }
    let p = t.map(|v| mesh.pos(v));
    if !is_degenerate_triangle(p[0], p[1], p[2]) {
        return None;
    }
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        if p[i] == p[j] {
            return Some(Degeneracy::Coincident { a: t[i], b: t[j] });
        }
    }
    // Three distinct collinear positions: exactly one is strictly between
    // the other two.
    (0..3)
        .map(|k| (t[k], t[(k + 1) % 3], t[(k + 2) % 3]))
        .find(|&(a, b, c)| strictly_inside(mesh.pos(c), mesh.pos(a), mesh.pos(b)))
        .map(|(a, b, apex)| Degeneracy::OnEdge { a, b, apex })
}

/// Whether `p`, collinear with `a` and `b` (all distinct), lies strictly
/// between them: on every axis between their coordinates (on a line,
/// betweenness on one axis where they differ is betweenness on all).
fn strictly_inside(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| a[k].min(b[k]) <= p[k] && p[k] <= a[k].max(b[k]))
}

/// A face on a directed edge, or [`SHARED`] when several are.
type Slot = u32;
const SHARED: Slot = u32::MAX;

/// The faces on each directed edge.
struct Edges {
    map: FxHashMap<(VertexId, VertexId), Slot>,
}

impl Edges {
    fn new(mesh: &Mesh) -> Edges {
        let mut map = FxHashMap::default();
        map.reserve(3 * mesh.num_faces());
        for (f, t) in mesh.faces.iter().enumerate() {
            for k in 0..3 {
                map.entry((t[k], t[(k + 1) % 3]))
                    .and_modify(|s| *s = SHARED)
                    .or_insert(f as Slot);
            }
        }
        Edges { map }
    }

    /// The one face on directed edge `a -> b`.
    fn single(&self, a: VertexId, b: VertexId) -> Option<FaceId> {
        self.map
            .get(&(a, b))
            .filter(|&&s| s != SHARED)
            .map(|&s| FaceId(s))
    }

    fn exists(&self, a: VertexId, b: VertexId) -> bool {
        self.map.contains_key(&(a, b)) || self.map.contains_key(&(b, a))
    }

    fn set(&mut self, t: [VertexId; 3], f: FaceId, present: bool) {
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            if present {
                self.map.insert(e, f.0);
            } else {
                self.map.remove(&e);
            }
        }
    }
}

/// What to do with a degenerate face: flip it with the face beyond, or why
/// not.
fn plan(mesh: &Mesh, edges: &Edges, face: FaceId, how: Degeneracy) -> Result<Flip, Unflippable> {
    let (a, b, apex) = match how {
        Degeneracy::Coincident { a, b } => return Err(Unflippable::CoincidentVertices { a, b }),
        Degeneracy::OnEdge { a, b, apex } => (a, b, apex),
    };
    let edge = [a, b];
    let no_patch = Unflippable::NoFaceBeyond { apex, edge };
    if edges.single(a, b) != Some(face) {
        return Err(no_patch);
    }
    let beyond = edges.single(b, a).ok_or(no_patch)?;
    let u = mesh.faces[beyond.idx()];
    let k = u.iter().position(|&v| v == b).ok_or(no_patch)?;
    if u[(k + 1) % 3] != a {
        return Err(no_patch);
    }
    let opposite = u[(k + 2) % 3];
    if opposite == apex {
        return Err(Unflippable::SameTriangleBeyond { apex, edge, beyond });
    }
    let t = mesh.faces[face.idx()];
    let own =
        |f: FaceId, t: [VertexId; 3]| (0..3).all(|k| edges.single(t[k], t[(k + 1) % 3]) == Some(f));
    if !own(face, t) || !own(beyond, u) {
        return Err(no_patch);
    }
    match degeneracy(mesh, beyond) {
        None => {}
        Some(Degeneracy::OnEdge { apex: d, .. })
            if d == opposite
                && strictly_inside(mesh.pos(d), mesh.pos(a), mesh.pos(b))
                && mesh.pos(d) != mesh.pos(apex) => {}
        Some(_) => return Err(Unflippable::DegenerateBeyond { apex, edge, beyond }),
    }
    if edges.exists(apex, opposite) {
        return Err(Unflippable::EdgeExists {
            apex,
            edge,
            beyond,
            opposite,
        });
    }
    Ok(Flip {
        face,
        beyond,
        edge,
        apex,
        opposite,
    })
}

/// The degenerate faces (three distinct vertices, collinear), ascending.
fn degenerate_faces(mesh: &Mesh) -> Vec<FaceId> {
    (0..mesh.num_faces())
        .into_par_iter()
        .with_min_len(par::MIN_LEN)
        .map(FaceId::from_idx)
        .filter(|&f| degeneracy(mesh, f).is_some())
        .collect()
}

/// Removes every degenerate face that edge flips can remove, repeatedly
/// (see the module doc for the rule, the proof that it stops and why the
/// surface does not move). Exact and deterministic; face and vertex ids
/// are kept. A mesh with an index out of range, a repeated vertex in a
/// face or a non-finite coordinate is returned unchanged (validation
/// refuses it); so is a mesh without degenerate faces (borrowed, not
/// copied). Degenerate faces that remain are named by validation with
/// the reason ([`Unflippable`]).
pub fn repair_degenerate(mesh: &Mesh) -> Repaired<'_> {
    let unchanged = |mesh| Repaired {
        mesh: Cow::Borrowed(mesh),
        flips: Vec::new(),
    };
    let nv = mesh.num_vertices();
    let sound = mesh.positions.iter().flatten().all(|x| x.is_finite())
        && mesh.faces.iter().flatten().all(|v| v.idx() < nv);
    if !sound {
        return unchanged(mesh);
    }
    // Found where the predicates need not scale (the flips below, on the
    // few faces found, use the mesh as it is).
    let mut pending = degenerate_faces(&mesh.in_predicate_frame());
    if pending.is_empty() {
        return unchanged(mesh);
    }
    let mut out = mesh.clone();
    let mut edges = Edges::new(&out);
    let mut flips = Vec::new();
    loop {
        let before = flips.len();
        for &f in &pending {
            let Some(how) = degeneracy(&out, f) else {
                continue;
            };
            let Ok(flip) = plan(&out, &edges, f, how) else {
                continue;
            };
            let (t, u) = (out.faces[f.idx()], out.faces[flip.beyond.idx()]);
            edges.set(t, f, false);
            edges.set(u, flip.beyond, false);
            let [a, b] = flip.edge;
            let (c, d) = (flip.apex, flip.opposite);
            out.faces[f.idx()] = [a, d, c];
            out.faces[flip.beyond.idx()] = [d, b, c];
            edges.set([a, d, c], f, true);
            edges.set([d, b, c], flip.beyond, true);
            flips.push(flip);
        }
        if flips.len() == before {
            break;
        }
        // The faces still degenerate (the new ones of a flip along a
        // degenerate face beyond are), in ascending order.
        let mut next: Vec<FaceId> = pending
            .iter()
            .copied()
            .chain(flips[before..].iter().map(|x| x.beyond))
            .filter(|&f| degeneracy(&out, f).is_some())
            .collect();
        next.sort_unstable();
        next.dedup();
        pending = next;
    }
    Repaired {
        mesh: if flips.is_empty() {
            Cow::Borrowed(mesh)
        } else {
            Cow::Owned(out)
        },
        flips,
    }
}

/// Why each of `faces` that is degenerate (three distinct collinear
/// vertices; validation passes those it finds) is not flipped away.
///
/// # Panics
///
/// As [`degeneracy`].
pub fn diagnose(mesh: &Mesh, faces: &[FaceId]) -> Vec<(FaceId, Unflippable)> {
    if faces.is_empty() {
        return Vec::new();
    }
    let edges = Edges::new(mesh);
    faces
        .iter()
        .filter_map(|&f| {
            let why = match plan(mesh, &edges, f, degeneracy(mesh, f)?) {
                Ok(flip) => Unflippable::Flippable {
                    apex: flip.apex,
                    edge: flip.edge,
                    beyond: flip.beyond,
                },
                Err(why) => why,
            };
            Some((f, why))
        })
        .collect()
}
