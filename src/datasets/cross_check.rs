//! Input: an accepted mesh and exact levels. Output: `Ok` when the slicer
//! agrees with itself under transformations whose effect is known
//! exactly, or the first disagreement, named:
//!
//! - a z-mirror ([`check_mirror`]): mirroring the mesh in z (faces turned
//!   to stay outward) turns the material just above `c` into the material
//!   just below `-c`. So the mirror's L- at `-c` is the original's L+ at
//!   `c` and its L+ the original's L-, loop for loop (same mesh elements
//!   in the same order, roles, parents, collapse, exact areas). Its S_O is
//!   the original's loop for loop where no saddle lies on the plane, and
//!   has the same steps and total area where one does (SPEC 5 pairs a
//!   saddle's branches across the sectors below, and below is mirrored).
//!   Faces up become faces down (same faces, same area, boundaries
//!   reversed), ridges become valleys, minima maxima; saddles keep their
//!   branches.
//! - an x-mirror ([`check_x_mirror`]): every loop reversed, nothing else
//!   changed; it runs the number paths on the other side of zero.
//! - the neighbouring regular levels ([`check_neighbours`]): L+ at `c`
//!   crosses exactly the edges, in the same order, of the contour at every
//!   regular level just above (L- likewise below), with the same roles and
//!   parents, and each loop's exact area is the limit at `c` of that
//!   loop's area, a quadratic in the level there (extrapolated exactly
//!   from three levels).
//! - four transformations of the mesh, each sliced once a level beside
//!   the original ([`check_transformed`]):
//!   - a relabelling: the same surface with its vertices and faces
//!     renumbered and each face's corners rotated. Every decision the
//!     slicer makes is geometric, so with the new ids mapped back
//!     everything is the same: S_O, L- and L+ loop for loop (saddles
//!     included), regions, ridges, extrema and saddles. A tie broken by
//!     element ids would show here.
//!   - a quarter turn about z: `(x, y)` becomes `(-y, x)`, exactly; every
//!     loop, area, region, ridge, extremum and saddle the same. What
//!     looks along one axis (the nesting's rays and sweep) meets the
//!     other axis's ties.
//!   - a far translation: the mesh moved by `2^k` in x and z and by
//!     `-2^k` in y, with `k` as large as keeps every coordinate exact
//!     (far beyond the part when its coordinates' bits span under 51,
//!     less when they span more). Nothing but the heights changes: every
//!     loop loop for loop with the same exact area (a polygon's area does
//!     not depend on where it lies), the same regions, ridges, extrema
//!     and saddles. The float filters see coordinates with no room to
//!     spare and must fall back to exact arithmetic whenever they cannot
//!     decide.
//!   - scales to the ends of the double range: the mesh scaled by `2^k`
//!     so that its lowest bit becomes the least subnormal, and again so
//!     that its highest becomes `2^1023`; sliced at `c 2^k`, the same
//!     loops, regions, ridges, extrema and saddles, every exact area
//!     `4^k` times the original's.
//!
//! Loops are compared by mesh element ids (vertices and edges, an edge by
//! its two vertex ids), never by coordinates. Shared by `tests/limits.rs`
//! (datasets and random slabs) and `examples/heldout_cross.rs` (meshes
//! you did not make).

use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::crossing::two_sum;
use crate::exact::rational::{rat_times_pow2, Rat};
use crate::exact::scale::{spread, times_pow2};
use crate::levelset::{total_area, LevelSet, Loop, Slicer};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::nest::Role;
use crate::segment::CutPoint;

/// The mesh mirrored in z, faces turned so that they stay outward. Exact:
/// a coordinate's negation is a double.
pub fn mirrored(mesh: &Mesh) -> Mesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        p[2] = -p[2];
    }
    for f in &mut m.faces {
        f.swap(1, 2);
    }
    m
}

/// A cut by the mesh's elements that do not depend on edge numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Element {
    /// A vertex on the plane, by id.
    Vertex(u32),
    /// A crossed edge, by its vertex ids (smaller first).
    Edge(u32, u32),
}

/// The element a cut lies on.
fn element(topo: &Topology, c: &CutPoint) -> Element {
    match c {
        CutPoint::AtVertex(v) => Element::Vertex(v.0),
        CutPoint::OnEdge(e) => {
            let [a, b] = topo.edge(*e).v;
            Element::Edge(a.0.min(b.0), a.0.max(b.0))
        }
    }
}

/// A cyclic sequence as its least rotation (one that starts at a least
/// element; a loop's elements are nearly all distinct, so this is about
/// linear).
fn canonical<T: Ord + Clone>(seq: &[T]) -> Vec<T> {
    let Some(least) = seq.iter().min() else {
        return Vec::new();
    };
    (0..seq.len())
        .filter(|&r| &seq[r] == least)
        .map(|r| {
            seq[r..]
                .iter()
                .chain(&seq[..r])
                .cloned()
                .collect::<Vec<_>>()
        })
        .min()
        .unwrap_or_default()
}

/// One loop as comparable facts: its canonical element sequence, role,
/// parent's sequence, collapse and exact area.
pub type LoopFacts = (Vec<Element>, Role, Option<Vec<Element>>, bool, Rat);

/// A family as comparable facts, sorted by sequence; `seq` gives a loop's
/// elements.
fn shape(loops: &[Loop], seq: impl Fn(&Loop) -> Vec<Element>) -> Vec<LoopFacts> {
    let keys: Vec<Vec<Element>> = loops.iter().map(|l| canonical(&seq(l))).collect();
    let mut out: Vec<LoopFacts> = loops
        .iter()
        .zip(&keys)
        .map(|(l, k)| {
            (
                k.clone(),
                l.role,
                l.parent.map(|p| keys[p].clone()),
                l.collapsed,
                l.area(),
            )
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// A family by the elements its points lie on.
pub fn limit_shape(topo: &Topology, loops: &[Loop]) -> Vec<LoopFacts> {
    shape(loops, |l| l.cuts.iter().map(|c| element(topo, c)).collect())
}

/// The first difference between two families, if any.
fn same_family(what: &str, c: &Rat, a: &[LoopFacts], b: &[LoopFacts]) -> Result<(), String> {
    if a.len() != b.len() {
        return Err(format!(
            "{what} at {c}: {} loops against {}",
            a.len(),
            b.len()
        ));
    }
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        if x != y {
            let field = if x.0 != y.0 {
                "elements"
            } else if x.1 != y.1 {
                "role"
            } else if x.2 != y.2 {
                "parent"
            } else if x.3 != y.3 {
                "collapse"
            } else {
                "area"
            };
            return Err(format!(
                "{what} at {c}: loop {i} (of {}, ordered by elements) differs in its {field}",
                a.len()
            ));
        }
    }
    Ok(())
}

/// A family's steps from element to element, sorted: what its loops are
/// made of, however they pair the branches at a saddle. S_O pairs them
/// across the sectors below the plane (SPEC 5), the mirror's across the
/// original's sectors above, so at a saddle the two S_O differ in their
/// loops but not in their steps.
fn steps(topo: &Topology, loops: &[Loop]) -> Vec<(Element, Element)> {
    let mut out: Vec<_> = loops
        .iter()
        .flat_map(|l| {
            let seq: Vec<Element> = l.cuts.iter().map(|c| element(topo, c)).collect();
            let n = seq.len();
            (0..n).map(move |i| (seq[i], seq[(i + 1) % n]))
        })
        .collect();
    out.sort();
    out
}

/// A path of vertex ids independent of its direction and, when closed, of
/// its start.
fn undirected(ids: &[u32], closed: bool) -> Vec<u32> {
    let rev: Vec<u32> = ids.iter().rev().copied().collect();
    if closed {
        canonical(ids).min(canonical(&rev))
    } else {
        ids.to_vec().min(rev)
    }
}

/// Which mirror a level set is seen through.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mirror {
    /// As it is.
    None,
    /// In z: up and down, ridges and valleys, minima and maxima exchanged,
    /// boundaries reversed.
    Z,
    /// In x: boundaries reversed, nothing exchanged.
    X,
}

/// Everything but the loops of a level set, seen through `mirror`:
/// regions with their facing, faces, area and boundaries; ridges and
/// valleys; minima and maxima; saddles.
type Rest = (
    Vec<(Facing, Vec<u32>, Rat, Vec<Vec<Element>>)>,
    Vec<(RidgeKind, bool, Vec<u32>)>,
    Vec<(u32, ExtremumKind)>,
    Vec<(u32, u32)>,
);

fn rest(topo: &Topology, ls: &LevelSet, mirror: Mirror) -> Rest {
    let swap = mirror == Mirror::Z;
    let facing = |f: Facing| match (f, swap) {
        (Facing::Up, true) => Facing::Down,
        (Facing::Down, true) => Facing::Up,
        (f, _) => f,
    };
    let mut regions: Vec<_> = ls
        .regions
        .iter()
        .map(|r| {
            let mut boundary: Vec<Vec<Element>> = r
                .boundary
                .iter()
                .map(|l| {
                    let mut seq: Vec<Element> = l.cuts.iter().map(|c| element(topo, c)).collect();
                    if mirror != Mirror::None {
                        seq.reverse();
                    }
                    canonical(&seq)
                })
                .collect();
            boundary.sort();
            let mut faces: Vec<u32> = r.faces.iter().map(|f| f.0).collect();
            faces.sort_unstable();
            (facing(r.facing), faces, r.area.clone(), boundary)
        })
        .collect();
    regions.sort_by(|a, b| a.1.cmp(&b.1));
    let mut ridges: Vec<_> = ls
        .ridges
        .iter()
        .map(|r| {
            let kind = match (r.kind, swap) {
                (RidgeKind::Ridge, true) => RidgeKind::Valley,
                (RidgeKind::Valley, true) => RidgeKind::Ridge,
                (k, _) => k,
            };
            let ids: Vec<u32> = r.vertices.iter().map(|v| v.0).collect();
            (kind, r.closed, undirected(&ids, r.closed))
        })
        .collect();
    ridges.sort_by(|a, b| a.2.cmp(&b.2));
    let mut extrema: Vec<_> = ls
        .extrema
        .iter()
        .map(|p| {
            let kind = match (p.kind, swap) {
                (ExtremumKind::Min, true) => ExtremumKind::Max,
                (ExtremumKind::Max, true) => ExtremumKind::Min,
                (k, _) => k,
            };
            (p.vertex.0, kind)
        })
        .collect();
    extrema.sort_by_key(|e| e.0);
    let mut saddles: Vec<_> = ls
        .saddles
        .iter()
        .map(|s| (s.vertex.0, s.branches))
        .collect();
    saddles.sort();
    (regions, ridges, extrema, saddles)
}

/// The z-mirror check at each of `levels` (in the mesh's units): slices
/// `mesh` at `c` and its mirror at `-c` and compares them as the module
/// documentation says. `Err` names the level and what differs; a slicing
/// error is an `Err` too.
pub fn check_mirror(mesh: &Mesh, levels: &[Rat]) -> Result<(), String> {
    let m = mirrored(mesh);
    let a = Slicer::new(mesh).map_err(|e| format!("the mesh: {e}"))?;
    let b = Slicer::new(&m).map_err(|e| format!("the mirror: {e}"))?;
    let (ta, tb) = (a.topology(), b.topology());
    for c in levels {
        let up = a.slice_at(c).map_err(|e| format!("at {c}: {e}"))?;
        let down = b
            .slice_at(&-c.clone())
            .map_err(|e| format!("the mirror at {}: {e}", -c.clone()))?;
        let pairs = [
            ("L+ (the mirror's L-)", &up.above, &down.below),
            ("L- (the mirror's L+)", &up.below, &down.above),
        ];
        for (what, x, y) in pairs {
            same_family(what, c, &limit_shape(ta, x), &limit_shape(tb, y))?;
        }
        if up.saddles.is_empty() && down.saddles.is_empty() {
            same_family(
                "S_O",
                c,
                &limit_shape(ta, &up.contours),
                &limit_shape(tb, &down.contours),
            )?;
        } else if steps(ta, &up.contours) != steps(tb, &down.contours)
            || total_area(&up.contours) != total_area(&down.contours)
        {
            return Err(format!(
                "S_O at {c} (a saddle level): its steps or its total area differ from the mirror's"
            ));
        }
        same_rest(
            c,
            rest(ta, &up, Mirror::None),
            rest(tb, &down, Mirror::Z),
            "the mirror",
        )?;
    }
    Ok(())
}

/// The first difference between two level sets' [`Rest`], if any; `other`
/// names the second ("the mirror").
fn same_rest(c: &Rat, r: Rest, s: Rest, other: &str) -> Result<(), String> {
    let names = ["face regions", "ridges", "extrema", "saddles"];
    let differs = [r.0 != s.0, r.1 != s.1, r.2 != s.2, r.3 != s.3];
    match differs.iter().position(|&d| d) {
        Some(i) => Err(format!("{} at {c} differ from {other}'s", names[i])),
        None => Ok(()),
    }
}

/// The mesh mirrored in x, faces turned so that they stay outward.
pub fn x_mirrored(mesh: &Mesh) -> Mesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        p[0] = -p[0];
    }
    for f in &mut m.faces {
        f.swap(1, 2);
    }
    m
}

/// The x-mirror check at each of `levels`: the mirror's level set at `c`
/// is the original's with every loop (S_O, L-, L+, dF) reversed, the same
/// roles, parents, collapse and exact areas (a loop's points are mirrored
/// and its direction reversed: the signed area is unchanged), and the
/// same regions' facing, ridges, extrema and saddles. Nothing is
/// exchanged, and a saddle's branches pair the same way (its fan order and
/// the directions at it are both reversed), so S_O is compared loop for
/// loop at a saddle too. Every x coordinate and crossing changes sign:
/// the number paths are run on the other side of zero.
pub fn check_x_mirror(mesh: &Mesh, levels: &[Rat]) -> Result<(), String> {
    let m = x_mirrored(mesh);
    let a = Slicer::new(mesh).map_err(|e| format!("the mesh: {e}"))?;
    let b = Slicer::new(&m).map_err(|e| format!("the x-mirror: {e}"))?;
    let (ta, tb) = (a.topology(), b.topology());
    let reversed =
        |l: &Loop| -> Vec<Element> { l.cuts.iter().rev().map(|c| element(ta, c)).collect() };
    for c in levels {
        let p = a.slice_at(c).map_err(|e| format!("at {c}: {e}"))?;
        let q = b
            .slice_at(c)
            .map_err(|e| format!("the x-mirror at {c}: {e}"))?;
        let families = [
            ("S_O (x-mirror)", &p.contours, &q.contours),
            ("L- (x-mirror)", &p.below, &q.below),
            ("L+ (x-mirror)", &p.above, &q.above),
        ];
        for (what, x, y) in families {
            same_family(what, c, &shape(x, reversed), &limit_shape(tb, y))?;
        }
        same_rest(
            c,
            rest(ta, &p, Mirror::X),
            rest(tb, &q, Mirror::None),
            "the x-mirror",
        )?;
    }
    Ok(())
}

/// A renumbering of `n` ids: `i -> (i k + n / 2) mod n` with `k` the
/// first number from about `0.618 n` up that is prime to `n`, so that
/// neighbours in the old order are scattered and no order is kept or
/// simply reversed.
fn scattered(n: usize) -> Vec<u32> {
    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    let mut k = (n * 618 / 1000).max(1);
    while gcd(k, n.max(1)) != 1 {
        k += 1;
    }
    let (k, n) = (k as u128, n as u128);
    (0..n).map(|i| ((i * k + n / 2) % n) as u32).collect()
}

/// The same surface renumbered: vertex `v` becomes `vertices[v]`, face `f`
/// becomes face `faces[f]` with its corners rotated by `f mod 3` (which
/// keeps its orientation). Returns the mesh and, for each new vertex and
/// face id, the old one.
pub fn relabelled(mesh: &Mesh) -> (Mesh, Vec<u32>, Vec<u32>) {
    let vertices = scattered(mesh.positions.len());
    let faces = scattered(mesh.faces.len());
    let mut old_vertex = vec![0; vertices.len()];
    let mut positions = vec![[0.0; 3]; vertices.len()];
    for (v, &new) in vertices.iter().enumerate() {
        old_vertex[new as usize] = v as u32;
        positions[new as usize] = mesh.positions[v];
    }
    let mut old_face = vec![0; faces.len()];
    let mut triples = vec![[0; 3]; faces.len()];
    for (f, &new) in faces.iter().enumerate() {
        old_face[new as usize] = f as u32;
        let corners = mesh.faces[f].map(|v| vertices[v.0 as usize]);
        triples[new as usize] = std::array::from_fn(|i| corners[(i + f % 3) % 3]);
    }
    (Mesh::from_raw(positions, triples), old_vertex, old_face)
}

/// An element with its vertex ids renamed by `old`.
fn renamed_element(e: Element, old: &[u32]) -> Element {
    match e {
        Element::Vertex(v) => Element::Vertex(old[v as usize]),
        Element::Edge(a, b) => {
            let (a, b) = (old[a as usize], old[b as usize]);
            Element::Edge(a.min(b), a.max(b))
        }
    }
}

/// A loop's elements renamed by `old`, as its least rotation.
fn renamed_seq(seq: &[Element], old: &[u32]) -> Vec<Element> {
    canonical(
        &seq.iter()
            .map(|&e| renamed_element(e, old))
            .collect::<Vec<_>>(),
    )
}

/// A family's facts with vertex ids renamed by `old`, sorted again.
fn renamed_family(family: Vec<LoopFacts>, old: &[u32]) -> Vec<LoopFacts> {
    let mut out: Vec<LoopFacts> = family
        .into_iter()
        .map(|(seq, role, parent, collapsed, area)| {
            let parent = parent.map(|p| renamed_seq(&p, old));
            (renamed_seq(&seq, old), role, parent, collapsed, area)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// A [`Rest`] with vertex ids renamed by `old_vertex` and face ids by
/// `old_face`, every list sorted again (a region's faces too), as
/// [`rest`] sorts them.
fn renamed_rest(r: Rest, old_vertex: &[u32], old_face: &[u32]) -> Rest {
    let (regions, ridges, extrema, saddles) = r;
    let mut regions: Vec<_> = regions
        .into_iter()
        .map(|(facing, faces, area, boundary)| {
            let mut faces: Vec<u32> = faces.iter().map(|&f| old_face[f as usize]).collect();
            faces.sort_unstable();
            let mut boundary: Vec<_> = boundary
                .iter()
                .map(|l| renamed_seq(l, old_vertex))
                .collect();
            boundary.sort();
            (facing, faces, area, boundary)
        })
        .collect();
    regions.sort_by(|a, b| a.1.cmp(&b.1));
    let mut ridges: Vec<_> = ridges
        .into_iter()
        .map(|(kind, closed, ids)| {
            let ids: Vec<u32> = ids.iter().map(|&v| old_vertex[v as usize]).collect();
            (kind, closed, undirected(&ids, closed))
        })
        .collect();
    ridges.sort_by(|a, b| a.2.cmp(&b.2));
    let mut extrema: Vec<_> = extrema
        .into_iter()
        .map(|(v, kind)| (old_vertex[v as usize], kind))
        .collect();
    extrema.sort_by_key(|e| e.0);
    let mut saddles: Vec<_> = saddles
        .into_iter()
        .map(|(v, branches)| (old_vertex[v as usize], branches))
        .collect();
    saddles.sort();
    (regions, ridges, extrema, saddles)
}

/// How the other mesh's level set is brought back to the original's.
#[derive(Clone, Copy)]
enum Back<'a> {
    /// As it is (the mesh moved or turned: same ids, same areas).
    AsIs,
    /// Vertex and face ids mapped back (new id to old).
    Renamed { vertex: &'a [u32], face: &'a [u32] },
    /// Every area divided by this factor (the mesh scaled).
    Shrunk(&'a Rat),
}

impl Back<'_> {
    fn family(self, family: Vec<LoopFacts>) -> Vec<LoopFacts> {
        match self {
            Back::AsIs => family,
            Back::Renamed { vertex, .. } => renamed_family(family, vertex),
            Back::Shrunk(f) => family
                .into_iter()
                .map(|(seq, role, parent, collapsed, area)| {
                    (seq, role, parent, collapsed, area / f)
                })
                .collect(),
        }
    }

    fn rest(self, r: Rest) -> Rest {
        match self {
            Back::AsIs => r,
            Back::Renamed { vertex, face } => renamed_rest(r, vertex, face),
            Back::Shrunk(f) => {
                let (regions, ridges, extrema, saddles) = r;
                let regions = regions
                    .into_iter()
                    .map(|(facing, faces, area, boundary)| (facing, faces, area / f, boundary))
                    .collect();
                (regions, ridges, extrema, saddles)
            }
        }
    }
}

/// One level set `p` against another's `q` that must be equal to it once
/// brought `back`: S_O, L- and L+ loop for loop (elements in order,
/// roles, parents, collapse, exact areas), and the same regions (faces,
/// facing, exact area, boundaries), ridges, extrema and saddles. `other`
/// names `q`'s mesh.
fn same_level_set(
    c: &Rat,
    (ta, p): (&Topology, &LevelSet),
    (tb, q): (&Topology, &LevelSet),
    other: &str,
    back: Back<'_>,
) -> Result<(), String> {
    let families = [
        ("S_O", &p.contours, &q.contours),
        ("L-", &p.below, &q.below),
        ("L+", &p.above, &q.above),
    ];
    for (what, x, y) in families {
        let theirs = back.family(limit_shape(tb, y));
        let what = format!("{what} (against {other})");
        same_family(&what, c, &limit_shape(ta, x), &theirs)?;
    }
    let theirs = back.rest(rest(tb, q, Mirror::None));
    same_rest(c, rest(ta, p, Mirror::None), theirs, other)
}

/// `(L, H)` of the mesh's nonzero coordinates ([`spread`]): `L` the
/// least exponent of a set bit, every magnitude below `2^H`.
fn bit_range(mesh: &Mesh) -> Option<(i32, i32)> {
    spread(mesh.positions.as_flattened())
}

/// The mesh with every coordinate `v` on axis `k` replaced by `f(k, v)`, if
/// each is a double.
fn each_coordinate(mesh: &Mesh, f: impl Fn(usize, f64) -> Option<f64>) -> Option<Mesh> {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        for (k, v) in p.iter_mut().enumerate() {
            *v = f(k, *v)?;
        }
    }
    Some(m)
}

/// `a + b` when it is exactly a double (its [`two_sum`] error is zero).
fn exact_sum(a: f64, b: f64) -> Option<f64> {
    let (s, err) = two_sum(a, b);
    (err == 0.0 && s.is_finite()).then_some(s)
}

/// The largest power of two `t` (below `2^1023`) that moves `mesh` by
/// `(t, -t, t)` with every coordinate still exact, with the moved mesh:
/// `2^(lo + 51)` when every coordinate's bits span under 51 (`lo` the
/// lowest set bit's exponent), smaller when they span more (a coordinate
/// `3.6e-16` beside `40` allows `2^-24`), `None` when not even
/// `2^lo` keeps them exact.
pub fn far_offset(mesh: &Mesh) -> Option<(f64, Mesh)> {
    let (lo, _) = bit_range(mesh).unwrap_or((0, 0));
    (lo..=(lo + 51).min(1022)).rev().find_map(|k| {
        let t = 2f64.powi(k);
        Some((t, translated(mesh, t)?))
    })
}

/// `mesh` moved by `(t, -t, t)`, if every coordinate stays exact.
pub fn translated(mesh: &Mesh, t: f64) -> Option<Mesh> {
    each_coordinate(mesh, |k, v| exact_sum(v, if k == 1 { -t } else { t }))
}

/// `mesh` turned a quarter about the z axis: `(x, y, z) -> (-y, x, z)`.
/// Exact (a negation is a double) and orientation-preserving, so faces
/// stay outward.
pub fn quarter_turned(mesh: &Mesh) -> Mesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        *p = [-p[1], p[0], p[2]];
    }
    m
}

/// `v 2^k` when it is a double ([`times_pow2`] is exact then; it is one
/// when it is finite and scales back to `v`, no bit lost below `2^-1074`).
fn exact_times_pow2(v: f64, k: i32) -> Option<f64> {
    let w = times_pow2(v, k);
    (w.is_finite() && times_pow2(w, -k) == v).then_some(w)
}

/// `mesh` scaled by `2^k`, if every coordinate stays exact.
pub fn scaled(mesh: &Mesh, k: i32) -> Option<Mesh> {
    each_coordinate(mesh, |_, v| exact_times_pow2(v, k))
}

/// The two scales [`check_transformed`] tries: the lowest set bit of any
/// coordinate taken down to `2^-1074` (the least subnormal), and the
/// highest up to `2^1023`, when the mesh has a nonzero coordinate.
pub fn extreme_scales(mesh: &Mesh) -> Vec<i32> {
    bit_range(mesh).map_or(Vec::new(), |(lo, hi)| vec![-1074 - lo, 1024 - hi])
}

/// Where a transformed mesh is sliced for the original's level `c`.
enum At {
    /// At `c` (the mesh renumbered or turned).
    Same,
    /// At `c + t` (the mesh moved by `t` in z).
    Plus(Rat),
    /// At `c 2^k` (the mesh scaled by `2^k`).
    TimesPow2(i32),
}

/// What [`check_transformed`] made besides the renumbering and the turn.
#[derive(Clone, Debug, PartialEq)]
pub struct Transformed {
    /// The far translation `t` ([`far_offset`]), `None` when no offset
    /// keeps every coordinate exact.
    pub moved: Option<f64>,
    /// The scales `2^k` checked ([`extreme_scales`]), by `k`.
    pub scales: Vec<i32>,
}

/// The renumbering, the quarter turn, the far translation and the scales
/// to both ends of the double range, at each of `levels`, the mesh as the
/// slicer holds it sliced once a level and compared with each:
///
/// - [`relabelled`] (degenerate faces already flipped away, so it needs
///   no flip, whose order could depend on ids), its ids mapped back;
/// - [`quarter_turned`] at the same `c` (a rotation keeps every signed
///   area; the nesting's rays and sweep, which look along one axis, meet
///   the other axis's ties);
/// - moved by [`far_offset`]'s `t`, at `c + t`;
/// - scaled by `2^k` for each of [`extreme_scales`], at `c 2^k`, every
///   exact area `4^k` times the original's.
///
/// Each must give equal level sets: S_O, L- and L+ loop for loop
/// (elements, roles, parents, collapse, exact areas), regions, ridges,
/// extrema and saddles. A transformed mesh that is refused is an `Err`
/// too: the surface is the same.
pub fn check_transformed(slicer: &Slicer<'_>, levels: &[Rat]) -> Result<Transformed, String> {
    let mesh = slicer.mesh();
    let (renumbered, old_vertex, old_face) = relabelled(mesh);
    let turned = quarter_turned(mesh);
    let moved = far_offset(mesh);
    let scales: Vec<(i32, Mesh, Rat)> = extreme_scales(mesh)
        .into_iter()
        .filter_map(|k| {
            let area = rat_times_pow2(&Rat::from_integer(1.into()), 2 * k);
            Some((k, scaled(mesh, k)?, area))
        })
        .collect();
    let renamed = Back::Renamed {
        vertex: &old_vertex,
        face: &old_face,
    };
    let mut others = vec![
        (
            "the relabelled mesh".to_string(),
            &renumbered,
            At::Same,
            renamed,
        ),
        ("the turned mesh".to_string(), &turned, At::Same, Back::AsIs),
    ];
    if let Some((t, m)) = &moved {
        let shift = At::Plus(crate::exact::rational::rat_from_f64(*t));
        others.push((format!("the mesh moved by {t:e}"), m, shift, Back::AsIs));
    }
    for (k, m, area) in &scales {
        let name = format!("the mesh scaled by 2^{k}");
        others.push((name, m, At::TimesPow2(*k), Back::Shrunk(area)));
    }
    let others = others
        .into_iter()
        .map(|(name, m, at, back)| {
            let b = Slicer::new(m).map_err(|e| format!("{name}: {e}"))?;
            Ok((name, b, at, back))
        })
        .collect::<Result<Vec<_>, String>>()?;
    for c in levels {
        let p = slicer.slice_at(c).map_err(|e| format!("at {c}: {e}"))?;
        for (name, b, at, back) in &others {
            let at = match at {
                At::Same => c.clone(),
                At::Plus(t) => c + t,
                At::TimesPow2(k) => rat_times_pow2(c, *k),
            };
            let q = b
                .slice_at(&at)
                .map_err(|e| format!("{name} at {at}: {e}"))?;
            let (ta, tb) = (slicer.topology(), b.topology());
            same_level_set(c, (ta, &p), (tb, &q), name, *back)?;
        }
    }
    Ok(Transformed {
        moved: moved.map(|(t, _)| t),
        scales: scales.iter().map(|(k, ..)| *k).collect(),
    })
}

/// L+ at `c` (L- when `below`) against the contours at `c + k d` for
/// k = 1, 2, 3, which must all be regular and lie before the next vertex
/// height in that direction (`d < 0` below): same edges in the same
/// order, same roles and parents, and the limit's exact area equal to the
/// quadratic extrapolation `3 A(1) - 3 A(2) + A(3)` of each loop's area.
pub fn check_neighbours(slicer: &Slicer<'_>, c: &Rat, d: &Rat, below: bool) -> Result<(), String> {
    let topo = slicer.topology();
    let slice = |z: &Rat| slicer.slice_at(z).map_err(|e| format!("at {z}: {e}"));
    let ls = slice(c)?;
    let limit = if below { &ls.below } else { &ls.above };
    let which = if below { "L-" } else { "L+" };
    let near = (1..=3)
        .map(|k| slice(&(c + d * Rat::from_integer(k.into()))))
        .collect::<Result<Vec<_>, _>>()?;
    let crossed = |l: &Loop| -> Vec<Element> {
        if l.crossings.is_empty() {
            l.cuts.iter().map(|c| element(topo, c)).collect()
        } else {
            l.crossings
                .iter()
                .map(|&e| element(topo, &CutPoint::OnEdge(e)))
                .collect()
        }
    };
    let ours = shape(limit, crossed);
    let theirs: Vec<_> = near
        .iter()
        .map(|n| limit_shape(topo, &n.contours))
        .collect();
    if ours.len() != theirs[0].len() {
        return Err(format!(
            "{which} at {c}: {} loops, the regular level beside it {}",
            ours.len(),
            theirs[0].len()
        ));
    }
    // Three levels in one regular interval: one structure.
    let structure = |s: &[LoopFacts]| s.iter().map(|l| l.0.clone()).collect::<Vec<_>>();
    if theirs[1..]
        .iter()
        .any(|t| structure(t) != structure(&theirs[0]))
    {
        return Err(format!(
            "the regular levels beside {c} ({which} side) differ among themselves"
        ));
    }
    let three = Rat::from_integer(3.into());
    for (i, o) in ours.iter().enumerate() {
        let n = &theirs[0][i];
        let field = if o.0 != n.0 {
            Some("crossed edges")
        } else if o.1 != n.1 {
            Some("role")
        } else if o.2 != n.2 {
            Some("parent")
        } else {
            let a = |k: usize| &theirs[k][i].4;
            let limit_area = &three * a(0) - &three * a(1) + a(2);
            (o.4 != limit_area).then_some("area (not the limit of the regular areas)")
        };
        if let Some(field) = field {
            return Err(format!(
                "{which} at {c}: loop {i} differs from the regular level beside it in its {field}"
            ));
        }
    }
    Ok(())
}

/// [`check_neighbours`] on both sides of each of `levels` that is a vertex
/// height, with `d` a quarter of the gap to the next vertex height there.
pub fn check_all_neighbours(slicer: &Slicer<'_>, levels: &[Rat]) -> Result<(), String> {
    let zs = crate::levelset::check::vertex_heights(slicer.mesh());
    let four = Rat::from_integer(4.into());
    for c in levels {
        let Ok(i) = zs.binary_search(c) else {
            continue;
        };
        if let Some(next) = zs.get(i + 1) {
            check_neighbours(slicer, c, &((next - c) / &four), false)?;
        }
        if i > 0 {
            check_neighbours(slicer, c, &((&zs[i - 1] - c) / &four), true)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scattered_is_a_permutation_that_keeps_no_order() {
        for n in 0..300usize {
            let p = scattered(n);
            let mut sorted = p.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "n = {n}");
            if n >= 3 {
                let reversed: Vec<u32> = (0..n as u32).rev().collect();
                assert!(p != sorted && p != reversed, "n = {n}: {p:?}");
            }
        }
    }

    #[test]
    fn far_offsets_keep_every_coordinate_exact() {
        use crate::exact::rational::rat_from_f64;
        assert_eq!(exact_sum(1.0, 2f64.powi(-60)), None);
        // 1 + 2^-52 is the double after 1: the sum is exact.
        let after_one = f64::from_bits(1.0f64.to_bits() + 1);
        assert_eq!(exact_sum(1.0, 2f64.powi(-52)), Some(after_one));
        assert_eq!(exact_sum(f64::MAX, f64::MAX), None);
        let cube = crate::datasets::by_name("unit_cube").unwrap().build();
        // Small integers: 2^51 above the lowest bit (2^0).
        assert_eq!(far_offset(&cube).map(|(t, _)| t), Some(2f64.powi(51)));
        // An f32 part centred at the origin: 40 beside 3.6e-16 (in
        // [2^-52, 2^-51), 24 bits: its lowest is 2^-75) leaves room for
        // 2^-24 (52 bits from 2^-75 up).
        let mut noisy = cube.clone();
        noisy.positions[0][0] = f64::from(3.6e-16f32);
        noisy.positions[1][1] = 40.0;
        let (t, moved) = far_offset(&noisy).unwrap();
        assert_eq!(t, 2f64.powi(-24));
        for (p, q) in noisy.positions.iter().zip(&moved.positions) {
            for (i, sign) in [1.0, -1.0, 1.0].into_iter().enumerate() {
                assert_eq!(
                    rat_from_f64(q[i]),
                    rat_from_f64(p[i]) + rat_from_f64(sign * t)
                );
            }
        }
    }

    #[test]
    fn scales_to_the_ends_of_the_range_are_exact_or_refused() {
        let tiny = f64::from_bits(1); // 2^-1074
        assert_eq!(exact_times_pow2(1.0, -1074), Some(tiny));
        // 3 2^-1074 is a subnormal; 3 2^-1075 would need a bit below it.
        assert_eq!(exact_times_pow2(3.0, -1074), Some(3.0 * tiny));
        assert_eq!(exact_times_pow2(3.0, -1075), None);
        assert_eq!(exact_times_pow2(1.5, 1023), Some(1.5 * 2f64.powi(1023)));
        assert_eq!(exact_times_pow2(1.0, 1024), None);
        assert_eq!(exact_times_pow2(tiny, 2097), Some(2f64.powi(1023)));
        let cube = crate::datasets::by_name("unit_cube").unwrap().build();
        // Coordinates 0 and 1: the 1 goes to 2^-1074 and to 2^1023.
        assert_eq!(extreme_scales(&cube), vec![-1074, 1023]);
        let up = scaled(&cube, 1023).unwrap();
        assert!(up
            .positions
            .iter()
            .flatten()
            .all(|&x| x == 0.0 || x == 2f64.powi(1023)));
    }

    #[test]
    fn relabelled_keeps_the_surface_and_maps_back() {
        let mesh = crate::datasets::by_name("double_torus").unwrap().build();
        let (m, old_vertex, old_face) = relabelled(&mesh);
        for (new, &old) in old_vertex.iter().enumerate() {
            assert_eq!(m.positions[new], mesh.positions[old as usize]);
        }
        for (new, &old) in old_face.iter().enumerate() {
            let back = m.faces[new].map(|v| old_vertex[v.0 as usize]);
            let orig = mesh.faces[old as usize].map(|v| v.0);
            // The same oriented triangle, its corners rotated.
            assert!((0..3).any(|r| (0..3).all(|i| back[i] == orig[(i + r) % 3])));
        }
        assert_ne!(m.faces, mesh.faces);
    }

    #[test]
    fn a_quarter_turn_is_exact_and_keeps_orientation() {
        let mesh = crate::datasets::by_name("unit_cube").unwrap().build();
        let turned = quarter_turned(&mesh);
        let four = (0..3).fold(turned.clone(), |m, _| quarter_turned(&m));
        assert_eq!(four.positions, mesh.positions);
        assert_eq!(turned.faces, mesh.faces);
        // The cube [0, 1]^3 turned is [-1, 0] x [0, 1] x [0, 1]: at z = 1/2
        // one outer loop, counterclockwise (positive area), of exact area
        // 1, every point in [-1, 0] x [0, 1].
        let half = Rat::new(1.into(), 2.into());
        let slicer = Slicer::new(&turned).unwrap();
        let ls = slicer.slice_at(&half).unwrap();
        let [l] = ls.contours.as_slice() else {
            panic!("{} loops", ls.contours.len())
        };
        assert_eq!(
            (l.role, l.area()),
            (Role::Outer, Rat::from_integer(1.into()))
        );
        for p in &l.points {
            let p = p.exact();
            assert!(p.x <= Rat::from_integer(0.into()) && p.x >= Rat::from_integer((-1).into()));
            assert!(p.y >= Rat::from_integer(0.into()) && p.y <= Rat::from_integer(1.into()));
        }
    }
}
