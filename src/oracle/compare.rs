//! Input: a mesh, an exact level (or several), the Rust level set and the
//! CGAL oracle's answer. Output: every element-by-element disagreement
//! between them, as readable lines (empty when they agree): vertex signs,
//! faces in the plane (and facing), the class of every in-plane edge,
//! extremal vertices, S_O branch counts and saddles, and the exact contour
//! segments of `CGAL::Polygon_mesh_slicer`. Shared by `tests/oracle.rs` and
//! the `slice_oracle` fuzz target.
//!
//! How CGAL 5.5's slicer output is compared (see the header comment of
//! `cpp-oracle/oracle.cpp`, read from CGAL's source): its polylines are
//! unoriented and mix S_O, S_NO, all of dF (an edge shared by S_O and dF
//! appears once) and one-point polylines for the extrema P; interior edges
//! of F never appear. So the CGAL polylines are cut into undirected exact
//! segments; one copy of every S_NO edge and every dF edge not in S_O (per
//! the oracle's own edge classes) is removed, and must be there to remove;
//! the one-point polylines must be exactly the points of P; what is left
//! must equal, as a multiset, the undirected segments of Rust's S_O loops.
//!
//! [`compare_self_intersections`] compares validation's self-intersection
//! verdict and face pairs with CGAL's (shared by
//! `tests/self_intersection_oracle.rs`, whose doc says what each side
//! counts, and `examples/heldout_oracle.rs`).

use super::{oracle_classify, oracle_self_intersections, ExactXY, OracleEdgeClass, OracleResult};
use crate::classify::{vertex_signs, ExtremumKind, Facing, RidgeKind};
use crate::datasets::slab::{heights_and_midpoints, Slab};
use crate::exact::predicates::is_degenerate_triangle;
use crate::exact::rational::{rat_from_f64, rat_to_string, Rat};
use crate::exact::{Level, Point2, Sign};
use crate::ids::{FaceId, VertexId};
use crate::levelset::{LevelSet, Slicer};
use crate::mesh::intersect::self_intersections;
use crate::mesh::topology::Topology;
use crate::mesh::validate::{validate, Defect};
use crate::mesh::Mesh;
use crate::segment::CutPoint;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

type Seg = (ExactXY, ExactXY);
type EdgeKey = (VertexId, VertexId);

fn key(a: VertexId, b: VertexId) -> EdgeKey {
    (a.min(b), a.max(b))
}

fn xy(p: &Point2) -> ExactXY {
    (p.x.clone(), p.y.clone())
}

fn vertex_xy(mesh: &Mesh, v: VertexId) -> ExactXY {
    let p = mesh.pos(v);
    (rat_from_f64(p[0]), rat_from_f64(p[1]))
}

fn seg(p: ExactXY, q: ExactXY) -> Seg {
    if p <= q {
        (p, q)
    } else {
        (q, p)
    }
}

fn show_xy(p: &ExactXY) -> String {
    format!("({}, {})", rat_to_string(&p.0), rat_to_string(&p.1))
}

fn show_seg(s: &Seg) -> String {
    format!("{} -- {}", show_xy(&s.0), show_xy(&s.1))
}

/// Adds `n` to a multiset.
fn bump<K: Ord>(m: &mut BTreeMap<K, i64>, k: K, n: i64) {
    let e = m.entry(k).or_insert(0);
    *e += n;
}

/// The Rust answer, reduced to the oracle's per-element form.
struct RustView {
    signs: Vec<Sign>,
    in_plane_faces: BTreeMap<FaceId, Facing>,
    edges: BTreeMap<EdgeKey, OracleEdgeClass>,
    extrema: BTreeMap<VertexId, ExtremumKind>,
    branches: BTreeMap<VertexId, u32>,
    so_segments: BTreeMap<Seg, i64>,
}

/// Derives the per-element classification from a Rust level set. Every
/// structural impossibility (an edge reported twice, a dF loop through a
/// crossing) is an error.
fn rust_view(mesh: &Mesh, c: &Rat, ls: &LevelSet, errs: &mut Vec<String>) -> RustView {
    let signs = vertex_signs(mesh, &Level::new(c.clone()));
    let mut in_plane_faces = BTreeMap::new();
    for r in &ls.regions {
        for &f in &r.faces {
            if in_plane_faces.insert(f, r.facing).is_some() {
                errs.push(format!("face {} is in two regions", f.0));
            }
        }
    }
    // dF edges.
    let mut boundary: BTreeMap<EdgeKey, i64> = BTreeMap::new();
    for (ri, r) in ls.regions.iter().enumerate() {
        for l in &r.boundary {
            let n = l.cuts.len();
            for i in 0..n {
                match (l.cuts[i], l.cuts[(i + 1) % n]) {
                    (CutPoint::AtVertex(a), CutPoint::AtVertex(b)) => {
                        bump(&mut boundary, key(a, b), 1)
                    }
                    other => errs.push(format!("region {ri}: dF piece {other:?} is not an edge")),
                }
            }
        }
    }
    // S_O: in-plane pieces, branches and segments.
    let mut so_edges: BTreeMap<EdgeKey, i64> = BTreeMap::new();
    let mut branches: BTreeMap<VertexId, u32> = (0..mesh.num_vertices())
        .filter(|&v| signs[v] == Sign::Zero)
        .map(|v| (VertexId::from_idx(v), 0))
        .collect();
    let mut so_segments = BTreeMap::new();
    for (li, l) in ls.contours.iter().enumerate() {
        let n = l.cuts.len();
        if l.points.len() != n {
            errs.push(format!(
                "S_O loop {li}: {} cuts but {} points",
                n,
                l.points.len()
            ));
            continue;
        }
        for i in 0..n {
            let j = (i + 1) % n;
            if let CutPoint::AtVertex(v) = l.cuts[i] {
                *branches.entry(v).or_insert(0) += 2;
            }
            if let (CutPoint::AtVertex(a), CutPoint::AtVertex(b)) = (l.cuts[i], l.cuts[j]) {
                bump(&mut so_edges, key(a, b), 1);
            }
            let [p, q] = [i, j].map(|k| xy(&l.points[k].exact()));
            bump(&mut so_segments, seg(p, q), 1);
        }
    }
    let mut edges = BTreeMap::new();
    let mut put = |errs: &mut Vec<String>, k: EdgeKey, class: OracleEdgeClass| {
        if let Some(old) = edges.insert(k, class) {
            errs.push(format!("edge {k:?} reported as {old:?} and as {class:?}"));
        }
    };
    for r in &ls.ridges {
        let n = r.vertices.len();
        let class = match r.kind {
            RidgeKind::Ridge => OracleEdgeClass::Ridge,
            RidgeKind::Valley => OracleEdgeClass::Valley,
        };
        let pairs = if r.closed { n } else { n.saturating_sub(1) };
        for i in 0..pairs {
            put(errs, key(r.vertices[i], r.vertices[(i + 1) % n]), class);
        }
    }
    for (&k, &cnt) in &boundary {
        if cnt != 1 {
            errs.push(format!("dF edge {k:?} appears {cnt} times"));
        }
        put(
            errs,
            k,
            OracleEdgeClass::Boundary {
                so: so_edges.contains_key(&k),
            },
        );
    }
    for (&k, &cnt) in &so_edges {
        if cnt != 1 {
            errs.push(format!("S_O edge {k:?} appears {cnt} times"));
        }
        if !boundary.contains_key(&k) {
            put(errs, k, OracleEdgeClass::Transversal);
        }
    }
    for &f in in_plane_faces.keys() {
        let t = mesh.faces[f.idx()];
        for i in 0..3 {
            let k = key(t[i], t[(i + 1) % 3]);
            if !boundary.contains_key(&k) {
                edges.entry(k).or_insert(OracleEdgeClass::Interior);
            }
        }
    }
    let mut extrema = BTreeMap::new();
    for e in &ls.extrema {
        if extrema.insert(e.vertex, e.kind).is_some() {
            errs.push(format!("extremum {} reported twice", e.vertex.0));
        }
        if xy(&e.point) != vertex_xy(mesh, e.vertex) {
            errs.push(format!("extremum {} has a wrong point", e.vertex.0));
        }
    }
    RustView {
        signs,
        in_plane_faces,
        edges,
        extrema,
        branches,
        so_segments,
    }
}

/// Lists the keys where two maps differ.
fn diff_maps<K: Ord + std::fmt::Debug, V: PartialEq + std::fmt::Debug>(
    what: &str,
    rust: &BTreeMap<K, V>,
    oracle: &BTreeMap<K, V>,
    errs: &mut Vec<String>,
) {
    let keys: BTreeSet<&K> = rust.keys().chain(oracle.keys()).collect();
    for k in keys {
        let (r, o) = (rust.get(k), oracle.get(k));
        if r != o {
            errs.push(format!("{what} {k:?}: rust {r:?}, oracle {o:?}"));
        }
    }
}

/// What the comparisons covered (so a vacuous run is noticed).
#[derive(Clone, Debug, Default)]
pub struct Coverage {
    /// Levels compared.
    pub levels: usize,
    /// Faces in the plane, summed over the levels.
    pub in_plane_faces: usize,
    /// In-plane edges by class (`Debug` of [`OracleEdgeClass`]).
    pub edges: BTreeMap<String, usize>,
    /// Extremal vertices.
    pub extrema: usize,
    /// Saddles by branch count.
    pub saddles_by_branches: BTreeMap<u32, usize>,
    /// Rust S_O segments.
    pub so_segments: usize,
    /// CGAL polylines.
    pub cgal_polylines: usize,
}

impl Coverage {
    /// Counts what the oracle's answer `o` contains.
    pub fn add(&mut self, o: &OracleResult) {
        self.levels += 1;
        self.in_plane_faces += o.in_plane_faces.len();
        for c in o.edges.values() {
            *self.edges.entry(format!("{c:?}")).or_default() += 1;
        }
        self.extrema += o.extrema.len();
        for &b in o.branches.values().filter(|&&b| b >= 4) {
            *self.saddles_by_branches.entry(b).or_default() += 1;
        }
        self.cgal_polylines += o.polylines.len();
    }
}

/// Compares Rust and the oracle on one mesh at one level; returns every
/// disagreement found (a failure of either side is one).
pub fn compare_level(mesh: &Mesh, slicer: &Slicer<'_>, c: &Rat, cov: &mut Coverage) -> Vec<String> {
    let ls = match slicer.slice_at(c) {
        Ok(ls) => ls,
        Err(e) => return vec![format!("Rust failed: {e}")],
    };
    let oracle: OracleResult = match oracle_classify(mesh, c) {
        Ok(o) => o,
        Err(e) => return vec![format!("oracle failed: {e}")],
    };
    cov.add(&oracle);
    cov.so_segments += ls.contours.iter().map(|l| l.cuts.len()).sum::<usize>();
    compare_answers(mesh, c, &ls, &oracle)
}

/// Compares a Rust level set with the oracle's answer element by element.
pub fn compare_answers(mesh: &Mesh, c: &Rat, ls: &LevelSet, oracle: &OracleResult) -> Vec<String> {
    let mut errs = Vec::new();
    let rv = rust_view(mesh, c, ls, &mut errs);

    // Signs.
    for (v, (r, o)) in rv.signs.iter().zip(&oracle.signs).enumerate() {
        if r != o {
            errs.push(format!("sign of vertex {v}: rust {r:?}, oracle {o:?}"));
        }
    }
    // Faces in the plane; a region's facing is that of its non-flat faces.
    let face_set = |m: &BTreeMap<FaceId, Facing>| m.keys().copied().collect::<BTreeSet<_>>();
    let (rf, of) = (
        face_set(&rv.in_plane_faces),
        face_set(&oracle.in_plane_faces),
    );
    if rf != of {
        errs.push(format!(
            "in-plane faces: rust only {:?}, oracle only {:?}",
            rf.difference(&of).collect::<Vec<_>>(),
            of.difference(&rf).collect::<Vec<_>>()
        ));
    }
    for (f, region_facing) in &rv.in_plane_faces {
        if let Some(&own) = oracle.in_plane_faces.get(f) {
            if own != Facing::Flat && own != *region_facing {
                errs.push(format!(
                    "face {}: region facing {region_facing:?}, own facing {own:?}",
                    f.0
                ));
            }
        }
    }
    // Edge classes, extrema, branch counts.
    diff_maps("in-plane edge", &rv.edges, &oracle.edges, &mut errs);
    diff_maps("extremum", &rv.extrema, &oracle.extrema, &mut errs);
    diff_maps(
        "branches at vertex",
        &rv.branches,
        &oracle.branches,
        &mut errs,
    );
    for (v, &b) in &oracle.branches {
        if b % 2 != 0 {
            errs.push(format!("oracle: odd branch count {b} at vertex {}", v.0));
        }
    }
    let oracle_saddles: BTreeSet<(VertexId, u32)> = oracle
        .branches
        .iter()
        .filter(|&(_, &b)| b >= 4)
        .map(|(&v, &b)| (v, b))
        .collect();
    let rust_saddles: BTreeSet<(VertexId, u32)> =
        ls.saddles.iter().map(|s| (s.vertex, s.branches)).collect();
    if oracle_saddles != rust_saddles {
        errs.push(format!(
            "saddles: rust {rust_saddles:?}, oracle {oracle_saddles:?}"
        ));
    }

    // CGAL's polylines.
    let mut cgal: BTreeMap<Seg, i64> = BTreeMap::new();
    let mut singles = BTreeSet::new();
    for pl in &oracle.polylines {
        match pl.len() {
            0 => errs.push("CGAL returned an empty polyline".into()),
            1 => {
                singles.insert(pl[0].clone());
            }
            _ => {
                for w in pl.windows(2) {
                    bump(&mut cgal, seg(w[0].clone(), w[1].clone()), 1);
                }
            }
        }
    }
    let extremal_points: BTreeSet<ExactXY> =
        oracle.extrema.keys().map(|&v| vertex_xy(mesh, v)).collect();
    if singles != extremal_points {
        errs.push(format!(
            "CGAL one-point polylines {:?} are not the extrema {:?}",
            singles.iter().map(show_xy).collect::<Vec<_>>(),
            extremal_points.iter().map(show_xy).collect::<Vec<_>>()
        ));
    }
    for (&(a, b), class) in &oracle.edges {
        let s = seg(vertex_xy(mesh, a), vertex_xy(mesh, b));
        let keep = match class {
            OracleEdgeClass::Ridge
            | OracleEdgeClass::Valley
            | OracleEdgeClass::Boundary { so: false } => true,
            OracleEdgeClass::Interior
            | OracleEdgeClass::Transversal
            | OracleEdgeClass::Boundary { so: true } => continue,
        };
        if keep {
            bump(&mut cgal, s.clone(), -1);
            if cgal[&s] < 0 {
                errs.push(format!(
                    "CGAL lacks the {class:?} edge ({}, {}): {}",
                    a.0,
                    b.0,
                    show_seg(&s)
                ));
            }
        }
    }
    cgal.retain(|_, n| *n != 0);
    if cgal != rv.so_segments {
        let mut d: BTreeMap<Seg, i64> = cgal.clone();
        for (s, n) in &rv.so_segments {
            bump(&mut d, s.clone(), -n);
        }
        for (s, n) in d.iter().filter(|(_, n)| **n != 0) {
            let who = if *n > 0 { "only CGAL" } else { "only Rust S_O" };
            errs.push(format!(
                "contour segment {} ({who}, x{})",
                show_seg(s),
                n.abs()
            ));
        }
    }
    errs
}

/// The mesh as pasteable Rust (`Mesh::from_raw(vec![..], vec![..])`).
pub fn pasteable_mesh(mesh: &Mesh) -> String {
    let mut s = String::from("Mesh::from_raw(\n    vec![");
    for p in &mesh.positions {
        let _ = write!(s, "[{:?}, {:?}, {:?}], ", p[0], p[1], p[2]);
    }
    s.push_str("],\n    vec![");
    for f in &mesh.faces {
        let _ = write!(s, "[{}, {}, {}], ", f[0].0, f[1].0, f[2].0);
    }
    s.push_str("],\n)");
    s
}

/// Compares Rust and the oracle on `mesh` at every level of `levels`, in
/// order; the report of the first level where they disagree (at most 40
/// disagreements, then the mesh as pasteable Rust).
pub fn compare_levels(mesh: &Mesh, levels: &[Rat], cov: &mut Coverage) -> Result<(), String> {
    let slicer = Slicer::new(mesh).map_err(|e| format!("Rust rejected the mesh: {e}"))?;
    for c in levels {
        let errs = compare_level(mesh, &slicer, c, cov);
        if !errs.is_empty() {
            let mut msg = format!("Rust and CGAL disagree at z = {}:\n", rat_to_string(c));
            for e in errs.iter().take(40) {
                let _ = writeln!(msg, "  - {e}");
            }
            let _ = writeln!(msg, "mesh:\n{}", pasteable_mesh(mesh));
            return Err(msg);
        }
    }
    Ok(())
}

/// The `slice_oracle` fuzz check of one slab: Rust and CGAL agree at every
/// vertex height, every midpoint and every level of `extra`. The error
/// carries the slab as pasteable Rust.
pub fn compare_slab(slab: &Slab, extra: &[Rat], cov: &mut Coverage) -> Result<(), String> {
    let mesh = slab.mesh();
    let mut levels = heights_and_midpoints(&mesh);
    levels.extend(extra.iter().cloned());
    compare_levels(&mesh, &levels, cov).map_err(|e| {
        let mut msg = format!("{e}slab: {}\nextra levels: [", slab.pasteable());
        for c in extra {
            let _ = write!(msg, "\"{}\", ", rat_to_string(c));
        }
        msg.push(']');
        msg
    })
}

/// Compares this crate's exact self-intersection test with CGAL's on a
/// closed, oriented, manifold mesh with finite coordinates: the degenerate
/// faces (CGAL's `(f, f)` pairs), the pairs of proper faces, and the
/// verdict (CGAL's `does_self_intersect` against validation's refusal by
/// a fold, a self-intersection or a degenerate face). `Ok(Some(verdict))`
/// when both agree, `Ok(None)` when the topology has issues (nothing to
/// compare: also when a face names a vertex the mesh does not have or a
/// coordinate is not finite, which the edge tables cannot be built on),
/// else what differs, with the mesh as pasteable Rust.
pub fn compare_self_intersections(m: &Mesh) -> Result<Option<bool>, String> {
    let nv = m.num_vertices();
    let in_range = m.faces.iter().flatten().all(|v| v.idx() < nv);
    let finite = m.positions.iter().flatten().all(|x| x.is_finite());
    if !(in_range && finite) {
        return Ok(None);
    }
    let (topo, issues) = Topology::build(m);
    if !issues.is_empty() {
        return Ok(None);
    }
    let cgal = oracle_self_intersections(m).map_err(|e| format!("oracle: {e}"))?;
    let degenerate: BTreeSet<FaceId> = (0..m.num_faces())
        .map(FaceId::from_idx)
        .filter(|&f| {
            let [a, b, c] = m.faces[f.idx()].map(|v| m.pos(v));
            is_degenerate_triangle(a, b, c)
        })
        .collect();
    let cgal_degenerate: BTreeSet<FaceId> = cgal
        .pairs
        .iter()
        .filter(|(a, b)| a == b)
        .map(|&(a, _)| a)
        .collect();
    if cgal_degenerate != degenerate {
        return Err(format!(
            "degenerate faces: CGAL {cgal_degenerate:?}, ours {degenerate:?}\n{}",
            pasteable_mesh(m)
        ));
    }
    let proper = |p: &&(FaceId, FaceId)| !degenerate.contains(&p.0) && !degenerate.contains(&p.1);
    let theirs: Vec<_> = cgal.pairs.iter().filter(proper).copied().collect();
    let all_ours = self_intersections(m, &topo);
    let ours: Vec<_> = all_ours.iter().filter(proper).copied().collect();
    if theirs != ours {
        return Err(format!(
            "pairs: CGAL {theirs:?}, ours {ours:?}\n{}",
            pasteable_mesh(m)
        ));
    }
    let report = validate(m);
    let refused = report.defects.iter().any(|d| {
        matches!(
            d,
            Defect::SelfIntersection { .. } | Defect::Fold { .. } | Defect::DegenerateFace { .. }
        )
    });
    let some_pair = !cgal.pairs.is_empty();
    if cgal.does_intersect != refused || cgal.does_intersect != some_pair {
        return Err(format!(
            "verdict: CGAL {}, ours {refused} ({report})\n{}",
            cgal.does_intersect,
            pasteable_mesh(m)
        ));
    }
    Ok(Some(cgal.does_intersect))
}
