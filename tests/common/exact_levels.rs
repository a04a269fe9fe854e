//! An independent, plain exact classification of a mesh's level sets,
//! written from SPEC sections 3 to 6 alone for the tests of the random
//! families: big-rational coordinates, no slicer code, no perturbation
//! machinery, no nesting.
//!
//! - At a level `c`: the face regions (faces with three vertices on the
//!   plane, joined through shared edges), their facing and areas; the
//!   S_NO edges and the number of maximal polylines they form; the
//!   extrema; S_O as pieces (crossed faces, transversal in-plane edges,
//!   region edges with material on both sides) with directions from the
//!   face orientation, the branches at each vertex and the saddles; S_O
//!   chained by the fan-order parentheses of SPEC 5 to count its loops;
//!   its total signed area as the sum of the pieces' shoelace terms.
//! - At a regular level (no vertex on the plane): the contour's loops are
//!   the connected components of the crossed edges (each crossed face
//!   joins its two), each with its exact signed area.
//! - L- and L+ at `c`: the loops of the regular levels just below (above)
//!   `c`, with their limit areas: the cross-section area of a loop is a
//!   quadratic in the level between consecutive vertex heights (SPEC 7,
//!   invariant 6), so three regular levels give it exactly at `c`; a loop
//!   whose limit area is 0 has collapsed.
#![allow(dead_code)]

use num_traits::{One, Signed, Zero};
use std::cmp::Ordering;
use std::collections::{BTreeMap, HashMap};
use wmslice::exact::rational::rat_from_f64;
use wmslice::exact::Rat;
use wmslice::Mesh;

/// The faces holding an edge, each with its opposite vertex and the
/// edge as directed in that face.
type EdgeFaces = Vec<(usize, usize, (usize, usize))>;

/// A mesh in exact rational coordinates with its edge table.
pub struct ExactMesh {
    pub pos: Vec<[Rat; 3]>,
    pub faces: Vec<[usize; 3]>,
    /// Sorted vertex pair -> the faces holding it, each with its opposite
    /// vertex and the pair as directed in that face.
    edges: HashMap<(usize, usize), EdgeFaces>,
    /// Vertex -> its neighbours in fan order (for a face `(v, a, b)`, `a`
    /// comes just before `b`).
    fans: Vec<Vec<usize>>,
    /// Distinct vertex heights, ascending.
    pub heights: Vec<Rat>,
}

/// The classification at one level.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Classified {
    pub f_regions: usize,
    pub f_up: usize,
    pub f_down: usize,
    pub f_area: Rat,
    pub f_up_area: Rat,
    pub f_down_area: Rat,
    pub s_no_ridges: usize,
    pub s_no_valleys: usize,
    pub p_min: usize,
    pub p_max: usize,
    /// m of every vertex with 2m >= 4 S_O branches, ascending.
    pub saddles: Vec<u64>,
    pub s_o_loops: usize,
    pub s_o_area: Rat,
}

impl Classified {
    /// F, S_NO, P or a saddle.
    pub fn is_critical(&self) -> bool {
        self.f_regions + self.s_no_ridges + self.s_no_valleys + self.p_min + self.p_max > 0
            || !self.saddles.is_empty()
    }
}

/// A one-sided limit: loops, how many collapsed, total limit area.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Limit {
    pub loops: usize,
    pub collapsed: usize,
    pub area: Rat,
}

/// A point of a level set: an edge crossing or a vertex on the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Element {
    Edge(usize, usize),
    Vertex(usize),
}

/// The nearest multiple of `q` (no ties occur in the tests' meshes).
fn snap_to(x: &Rat, q: &Rat) -> Rat {
    let k = x / q;
    let r = k.round();
    assert_ne!(
        (&k - k.floor()) * Rat::from_integer(2.into()),
        Rat::one(),
        "a tie"
    );
    r * q
}

fn cross(a: &[Rat; 2], b: &[Rat; 2]) -> Rat {
    &a[0] * &b[1] - &a[1] * &b[0]
}

impl ExactMesh {
    /// The mesh's exact coordinates, snapped to `snap` when given.
    pub fn new(mesh: &Mesh, snap: Option<&Rat>) -> Self {
        let pos: Vec<[Rat; 3]> = mesh
            .positions
            .iter()
            .map(|p| {
                p.map(|x| {
                    let r = rat_from_f64(x);
                    match snap {
                        Some(q) => snap_to(&r, q),
                        None => r,
                    }
                })
            })
            .collect();
        let faces: Vec<[usize; 3]> = mesh.faces.iter().map(|f| f.map(|v| v.idx())).collect();
        let mut edges: HashMap<(usize, usize), EdgeFaces> = HashMap::new();
        let mut next: Vec<BTreeMap<usize, usize>> = vec![BTreeMap::new(); pos.len()];
        for (fi, f) in faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b, o) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((fi, o, (a, b)));
                // Face (v, a, b) seen from v = f[k]: a = f[k+1] before b = f[k+2].
                next[a].insert(b, o);
            }
        }
        let fans = next
            .iter()
            .map(|n| {
                let Some((&first, _)) = n.iter().next() else {
                    return Vec::new();
                };
                let mut cycle = vec![first];
                let mut at = n[&first];
                while at != first {
                    cycle.push(at);
                    at = n[&at];
                }
                assert_eq!(cycle.len(), n.len(), "a vertex link is one cycle");
                cycle
            })
            .collect();
        let mut heights: Vec<Rat> = pos.iter().map(|p| p[2].clone()).collect();
        heights.sort();
        heights.dedup();
        ExactMesh {
            pos,
            faces,
            edges,
            fans,
            heights,
        }
    }

    fn sign(&self, v: usize, c: &Rat) -> Ordering {
        self.pos[v][2].cmp(c)
    }

    fn xy(&self, v: usize) -> [Rat; 2] {
        [self.pos[v][0].clone(), self.pos[v][1].clone()]
    }

    /// The exact point of an element at level `c`.
    fn point(&self, e: Element, c: &Rat) -> [Rat; 2] {
        match e {
            Element::Vertex(v) => self.xy(v),
            Element::Edge(a, b) => {
                let (pa, pb) = (&self.pos[a], &self.pos[b]);
                let t = (c - &pa[2]) / (&pb[2] - &pa[2]);
                [
                    &pa[0] + (&pb[0] - &pa[0]) * &t,
                    &pa[1] + (&pb[1] - &pa[1]) * &t,
                ]
            }
        }
    }

    fn edge(a: usize, b: usize) -> Element {
        Element::Edge(a.min(b), a.max(b))
    }

    /// The S_O segment of a face with both signs: from where the walk in
    /// the face's own vertex order passes from + to - to where it passes
    /// from - to + (SPEC 4); through an edge crossing or a vertex on the
    /// plane. `None` when the face has no strict sign change.
    fn face_piece(&self, f: usize, c: &Rat) -> Option<(Element, Element, usize)> {
        let t = self.faces[f];
        let s = t.map(|v| self.sign(v, c));
        if !(s.contains(&Ordering::Greater) && s.contains(&Ordering::Less)) {
            return None;
        }
        let passage = |from: Ordering, to: Ordering| -> Element {
            for k in 0..3 {
                let (a, b, d) = (k, (k + 1) % 3, (k + 2) % 3);
                if s[a] == from && s[b] == to {
                    return Self::edge(t[a], t[b]);
                }
                if s[a] == from && s[b] == Ordering::Equal && s[d] == to {
                    return Element::Vertex(t[b]);
                }
            }
            unreachable!("a face with both signs passes both ways")
        };
        Some((
            passage(Ordering::Greater, Ordering::Less),
            passage(Ordering::Less, Ordering::Greater),
            f,
        ))
    }

    /// Faces in the plane `z = c`.
    fn in_plane(&self, f: usize, c: &Rat) -> bool {
        self.faces[f].iter().all(|&v| self.pos[v][2] == *c)
    }

    /// Twice the signed projected area of a face.
    fn face_area2(&self, f: usize) -> Rat {
        let [a, b, d] = self.faces[f].map(|v| self.xy(v));
        let u = [&b[0] - &a[0], &b[1] - &a[1]];
        let w = [&d[0] - &a[0], &d[1] - &a[1]];
        cross(&u, &w)
    }

    /// The classification at level `c`.
    pub fn classify(&self, c: &Rat) -> Classified {
        let mut out = Classified {
            f_area: Rat::zero(),
            f_up_area: Rat::zero(),
            f_down_area: Rat::zero(),
            s_o_area: Rat::zero(),
            ..Classified::default()
        };
        let nf = self.faces.len();
        let in_f: Vec<bool> = (0..nf).map(|f| self.in_plane(f, c)).collect();
        // F: faces joined through edges both of whose faces are in F.
        let mut parent: Vec<usize> = (0..nf).collect();
        fn find(p: &mut [usize], x: usize) -> usize {
            let mut r = x;
            while p[r] != r {
                r = p[r];
            }
            let mut y = x;
            while p[y] != r {
                let n = p[y];
                p[y] = r;
                y = n;
            }
            r
        }
        for list in self.edges.values() {
            if let [(f, _, _), (g, _, _)] = list[..] {
                if in_f[f] && in_f[g] {
                    let (rf, rg) = (find(&mut parent, f), find(&mut parent, g));
                    parent[rf] = rg;
                }
            }
        }
        let mut regions: BTreeMap<usize, (Ordering, Rat)> = BTreeMap::new();
        for f in (0..nf).filter(|&f| in_f[f]) {
            let a2 = self.face_area2(f);
            let facing = a2.cmp(&Rat::zero());
            let r = find(&mut parent, f);
            let e = regions.entry(r).or_insert((facing, Rat::zero()));
            assert!(
                e.0 == facing || facing == Ordering::Equal || e.0 == Ordering::Equal,
                "one facing per region (no folds)"
            );
            if e.0 == Ordering::Equal {
                e.0 = facing;
            }
            e.1 += a2.abs() / Rat::from_integer(2.into());
        }
        for (facing, area) in regions.values() {
            out.f_regions += 1;
            out.f_area += area;
            match facing {
                Ordering::Greater => {
                    out.f_up += 1;
                    out.f_up_area += area;
                }
                Ordering::Less => {
                    out.f_down += 1;
                    out.f_down_area += area;
                }
                Ordering::Equal => {}
            }
        }
        // In-plane edges: S_NO edges, S_O pieces along edges.
        let mut pieces: Vec<(Element, Element, Position)> = Vec::new();
        let mut s_no: BTreeMap<usize, Vec<(usize, bool)>> = BTreeMap::new();
        for (&(a, b), list) in &self.edges {
            if self.pos[a][2] != *c || self.pos[b][2] != *c {
                continue;
            }
            let [(f, o1, d1), (g, o2, _)] = list[..] else {
                panic!("an edge in two faces");
            };
            if in_f[f] && in_f[g] {
                continue;
            }
            let (s1, s2) = (self.sign(o1, c), self.sign(o2, c));
            if s1 == s2 {
                // Both off the plane on one side: a ridge (below) or valley.
                let ridge = s1 == Ordering::Less;
                s_no.entry(a).or_default().push((b, ridge));
                s_no.entry(b).or_default().push((a, ridge));
                continue;
            }
            // Transversal, or a region edge: S_O when the faces off the
            // plane put material on both sides. The direction from a face
            // off the plane: its own direction of the edge when its
            // opposite vertex is above, reversed when below.
            let off: Vec<(usize, (usize, usize))> = [(f, o1, d1), (g, o2, list[1].2)]
                .into_iter()
                .filter(|&(face, _, _)| !in_f[face])
                .map(|(_, o, d)| (o, d))
                .collect();
            let dir = |(o, (p, q)): (usize, (usize, usize))| {
                if self.sign(o, c) == Ordering::Greater {
                    (p, q)
                } else {
                    (q, p)
                }
            };
            let so = if off.len() == 2 {
                let (x, y) = (dir(off[0]), dir(off[1]));
                assert_eq!(x, y, "both faces direct a transversal edge alike");
                Some(x)
            } else {
                // A region edge: S_O when an up face's neighbour is above
                // or a down face's is below.
                let fin = if in_f[f] { f } else { g };
                let up = self.face_area2(fin) > Rat::zero();
                let above = self.sign(off[0].0, c) == Ordering::Greater;
                (up == above).then(|| dir(off[0]))
            };
            if let Some((p, q)) = so {
                pieces.push((
                    Element::Vertex(p),
                    Element::Vertex(q),
                    Position::Along(p, q),
                ));
            }
        }
        let (ridges, valleys) = count_polylines(&s_no);
        out.s_no_ridges = ridges;
        out.s_no_valleys = valleys;
        // P.
        for v in 0..self.pos.len() {
            if self.pos[v][2] != *c {
                continue;
            }
            let signs: Vec<Ordering> = self.fans[v].iter().map(|&w| self.sign(w, c)).collect();
            if signs.iter().all(|&s| s == Ordering::Greater) {
                out.p_min += 1;
            } else if signs.iter().all(|&s| s == Ordering::Less) {
                out.p_max += 1;
            }
        }
        // Face pieces.
        for (f, &flat) in in_f.iter().enumerate().take(nf) {
            if flat {
                continue;
            }
            if let Some((s, e, f)) = self.face_piece(f, c) {
                pieces.push((s, e, Position::Inside(f)));
            }
        }
        // Area: the shoelace terms of all pieces.
        let two = Rat::from_integer(2.into());
        for (s, e, _) in &pieces {
            out.s_o_area += cross(&self.point(*s, c), &self.point(*e, c)) / &two;
        }
        // Branches and chaining.
        let mut at_vertex: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        let mut starts_at_edge: HashMap<Element, usize> = HashMap::new();
        for (i, (s, e, _)) in pieces.iter().enumerate() {
            for el in [s, e] {
                if let Element::Vertex(v) = el {
                    at_vertex.entry(*v).or_default().push(i);
                }
            }
            if let Element::Edge(..) = s {
                assert!(
                    starts_at_edge.insert(*s, i).is_none(),
                    "one piece out of a crossing"
                );
            }
        }
        let mut next: Vec<Option<usize>> = vec![None; pieces.len()];
        for (i, (_, e, _)) in pieces.iter().enumerate() {
            if let Element::Edge(..) = e {
                next[i] = Some(starts_at_edge[e]);
            }
        }
        for (&v, list) in &at_vertex {
            if list.len() >= 4 {
                out.saddles.push(list.len() as u64 / 2);
            }
            // Fan-order positions: 2k at the k-th neighbour, 2k + 1 in the
            // sector after it.
            let fan = &self.fans[v];
            let index: HashMap<usize, usize> =
                fan.iter().enumerate().map(|(k, &w)| (w, k)).collect();
            let mut branches: Vec<(usize, bool, usize)> = list
                .iter()
                .map(|&i| {
                    let (s, _, pos) = &pieces[i];
                    let incoming = *s != Element::Vertex(v);
                    let at = match *pos {
                        Position::Along(p, q) => 2 * index[&if p == v { q } else { p }],
                        Position::Inside(f) => {
                            let t = self.faces[f];
                            let k = t.iter().position(|&x| x == v).expect("v in its face");
                            2 * index[&t[(k + 1) % 3]] + 1
                        }
                    };
                    (at, incoming, i)
                })
                .collect();
            branches.sort();
            // Parentheses, going round twice from the start.
            let mut open: Vec<usize> = Vec::new();
            let mut paired = vec![false; branches.len()];
            for k in 0..2 * branches.len() {
                let b = k % branches.len();
                if paired[b] {
                    continue;
                }
                if branches[b].1 {
                    if !open.contains(&b) {
                        open.push(b);
                    }
                } else if let Some(o) = open.pop() {
                    paired[o] = true;
                    paired[b] = true;
                    next[branches[o].2] = Some(branches[b].2);
                }
            }
            assert!(
                paired.iter().all(|&p| p),
                "every branch at vertex {v} pairs"
            );
        }
        out.saddles.sort_unstable();
        // Loops: the cycles of `next`.
        let mut seen = vec![false; pieces.len()];
        for i in 0..pieces.len() {
            if seen[i] {
                continue;
            }
            out.s_o_loops += 1;
            let mut j = i;
            while !seen[j] {
                seen[j] = true;
                j = next[j].expect("S_O is closed");
            }
            assert_eq!(j, i, "S_O pieces form cycles");
        }
        out
    }

    /// The loops of a regular level `t` (no vertex at `t`): each crossed
    /// edge's component, with its exact signed area.
    pub fn regular(&self, t: &Rat) -> BTreeMap<(usize, usize), Rat> {
        assert!(self.heights.binary_search(t).is_err(), "a regular level");
        let mut parent: HashMap<(usize, usize), (usize, usize)> = HashMap::new();
        fn find(
            p: &mut HashMap<(usize, usize), (usize, usize)>,
            x: (usize, usize),
        ) -> (usize, usize) {
            let mut r = x;
            while p[&r] != r {
                r = p[&r];
            }
            r
        }
        let mut segments = Vec::new();
        for f in 0..self.faces.len() {
            if let Some((Element::Edge(a, b), Element::Edge(d, e), _)) = self.face_piece(f, t) {
                for k in [(a, b), (d, e)] {
                    parent.entry(k).or_insert(k);
                }
                let (ra, rb) = (find(&mut parent, (a, b)), find(&mut parent, (d, e)));
                parent.insert(ra, rb);
                segments.push(((a, b), Element::Edge(a, b), Element::Edge(d, e)));
            }
        }
        let two = Rat::from_integer(2.into());
        let mut areas: BTreeMap<(usize, usize), Rat> = BTreeMap::new();
        for (key, s, e) in segments {
            let r = find(&mut parent, key);
            *areas.entry(r).or_insert_with(Rat::zero) +=
                cross(&self.point(s, t), &self.point(e, t)) / &two;
        }
        areas
    }

    /// L- (`below`) or L+ at `c`: the loops of the regular levels beside
    /// `c` and their limit areas at `c`.
    pub fn limit(&self, c: &Rat, below: bool) -> Limit {
        let other = if below {
            self.heights.iter().rev().find(|h| *h < c)
        } else {
            self.heights.iter().find(|h| *h > c)
        };
        let Some(other) = other else {
            return Limit {
                area: Rat::zero(),
                ..Limit::default()
            };
        };
        let four = Rat::from_integer(4.into());
        let ts: Vec<Rat> = (1..=3)
            .map(|k| c + (other - c) * Rat::from_integer(k.into()) / &four)
            .collect();
        let samples: Vec<BTreeMap<(usize, usize), Rat>> =
            ts.iter().map(|t| self.regular(t)).collect();
        let keys: Vec<_> = samples[0].keys().copied().collect();
        assert!(
            samples
                .iter()
                .all(|s| s.keys().copied().eq(keys.iter().copied())),
            "the same loops across a regular interval"
        );
        let mut out = Limit {
            loops: keys.len(),
            collapsed: 0,
            area: Rat::zero(),
        };
        for k in keys {
            let ys: Vec<&Rat> = samples.iter().map(|s| &s[&k]).collect();
            let a = lagrange(&ts, &ys, c);
            if a.is_zero() {
                out.collapsed += 1;
            }
            out.area += a;
        }
        out
    }
}

/// Where an S_O piece sits around a vertex: along the edge `(p, q)`, or
/// inside face `f`'s sector.
#[derive(Clone, Copy, Debug)]
enum Position {
    Along(usize, usize),
    Inside(usize),
}

/// The value at `x` of the quadratic through three points.
fn lagrange(ts: &[Rat], ys: &[&Rat], x: &Rat) -> Rat {
    let mut sum = Rat::zero();
    for i in 0..3 {
        let mut term = ys[i].clone();
        for j in 0..3 {
            if i != j {
                term = term * (x - &ts[j]) / (&ts[i] - &ts[j]);
            }
        }
        sum += term;
    }
    sum
}

/// Maximal S_NO polylines (ridges, valleys): split at vertices where the
/// count of S_NO edges is not two or where a ridge meets a valley. Each
/// open polyline has two ends at such break vertices; each closed one is
/// a component with no break vertex.
fn count_polylines(s_no: &BTreeMap<usize, Vec<(usize, bool)>>) -> (usize, usize) {
    let is_break = |v: &usize| {
        let list = &s_no[v];
        list.len() != 2 || list[0].1 != list[1].1
    };
    // Ends at break vertices, by kind.
    let mut ends = [0usize; 2];
    for (v, list) in s_no {
        if is_break(v) {
            for &(_, ridge) in list {
                ends[usize::from(ridge)] += 1;
            }
        }
    }
    let mut counts = [ends[0] / 2, ends[1] / 2];
    // Closed cycles: components without a break vertex.
    let mut seen: BTreeMap<usize, bool> = BTreeMap::new();
    for (&v, list) in s_no {
        if seen.contains_key(&v) {
            continue;
        }
        let mut stack = vec![v];
        let mut any_break = false;
        seen.insert(v, true);
        while let Some(x) = stack.pop() {
            any_break |= is_break(&x);
            for &(y, _) in &s_no[&x] {
                if seen.insert(y, true).is_none() {
                    stack.push(y);
                }
            }
        }
        if !any_break {
            counts[usize::from(list[0].1)] += 1;
        }
    }
    (counts[1], counts[0])
}
