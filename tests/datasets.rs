//! Built-in datasets: every mesh is a valid closed outward-oriented manifold
//! with the hand-derived volume, genus and degeneracies, and the
//! hand-derived level sets of `wmslice::datasets::expected` agree with a
//! small brute-force evaluation of the `SPEC.md` rules written here from
//! scratch (no slicer code is used: classification per face and per edge,
//! chaining by mesh element with the section 5 pairing, exact rationals).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use num_bigint::BigInt;
use num_rational::BigRational as Q;
use num_traits::{One, Signed, Zero};
use wmslice::datasets::expected::{expected, solids, Expected};
use wmslice::datasets::{self, Dataset};
use wmslice::Mesh;

// ---------------------------------------------------------------------------
// Exact mesh

fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite coordinate")
}

fn ratio((n, d): (i128, u128)) -> Q {
    Q::new(BigInt::from(n), BigInt::from(d))
}

fn level((n, d): (i64, u64)) -> Q {
    Q::new(BigInt::from(n), BigInt::from(d))
}

fn show(x: &Q) -> String {
    if x.denom().is_one() {
        x.numer().to_string()
    } else {
        format!("{}/{}", x.numer(), x.denom())
    }
}

struct Exact {
    p: Vec<[Q; 3]>,
    f: Vec<[usize; 3]>,
}

impl Exact {
    fn new(m: &Mesh) -> Self {
        let p = m.positions.iter().map(|v| v.map(q)).collect();
        let f = m.faces.iter().map(|t| t.map(|v| v.idx())).collect();
        Exact { p, f }
    }
}

fn sub(a: &[Q; 3], b: &[Q; 3]) -> [Q; 3] {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn cross(a: &[Q; 3], b: &[Q; 3]) -> [Q; 3] {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

fn dot(a: &[Q; 3], b: &[Q; 3]) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn signed_volume(m: &Exact) -> Q {
    let mut v = Q::zero();
    for t in &m.f {
        v += dot(&m.p[t[0]], &cross(&m.p[t[1]], &m.p[t[2]]));
    }
    v / Q::from_integer(BigInt::from(6))
}

/// Twice the signed area of a face's (x, y) projection.
fn projected2(m: &Exact, t: &[usize; 3]) -> Q {
    let [a, b, c] = t.map(|i| &m.p[i]);
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

// ---------------------------------------------------------------------------
// Topology: written locally so that this test depends on nothing but `Mesh`.

struct Topo {
    /// For every directed edge (a, b) of a face: (face, opposite vertex).
    half: HashMap<(usize, usize), (usize, usize)>,
    /// Undirected edges, each once as (min, max).
    edges: BTreeSet<(usize, usize)>,
    /// Neighbours of each vertex in fan order (for a face (v, a, b), a
    /// comes just before b).
    fan: Vec<Vec<usize>>,
}

/// Checks closedness, orientation and manifoldness; returns the topology.
fn topology(m: &Exact) -> Result<Topo, String> {
    let n = m.p.len();
    let mut half = HashMap::new();
    for (fi, t) in m.f.iter().enumerate() {
        if t.iter().any(|&v| v >= n) {
            return Err(format!("face {fi} has an index out of range"));
        }
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return Err(format!("face {fi} repeats a vertex"));
        }
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            if half.insert(e, (fi, t[(k + 2) % 3])).is_some() {
                return Err(format!("directed edge {e:?} appears twice"));
            }
        }
    }
    let mut edges = BTreeSet::new();
    for &(a, b) in half.keys() {
        if !half.contains_key(&(b, a)) {
            return Err(format!(
                "edge ({a}, {b}) has no opposite half (open or flipped)"
            ));
        }
        edges.insert((a.min(b), a.max(b)));
    }
    let mut next: Vec<BTreeMap<usize, usize>> = vec![BTreeMap::new(); n];
    for t in &m.f {
        for k in 0..3 {
            next[t[k]].insert(t[(k + 1) % 3], t[(k + 2) % 3]);
        }
    }
    let mut fan = Vec::with_capacity(n);
    for (v, nx) in next.iter().enumerate() {
        let Some((&start, _)) = nx.iter().next() else {
            return Err(format!("vertex {v} is in no face"));
        };
        let mut cycle = vec![start];
        let mut cur = nx[&start];
        while cur != start {
            if cycle.len() > nx.len() {
                return Err(format!("vertex {v}: link is not a cycle"));
            }
            cycle.push(cur);
            cur = *nx.get(&cur).ok_or(format!("vertex {v}: link is open"))?;
        }
        if cycle.len() != nx.len() {
            return Err(format!("vertex {v}: link has several cycles (bowtie)"));
        }
        fan.push(cycle);
    }
    Ok(Topo { half, edges, fan })
}

/// Sign changes of `z(neighbour) - z(v)` around the link of `v`.
fn link_sign_changes(m: &Exact, t: &Topo, v: usize) -> usize {
    let s: Vec<i32> = t.fan[v]
        .iter()
        .map(|&u| cmp_sign(&m.p[u][2], &m.p[v][2]))
        .filter(|&s| s != 0)
        .collect();
    (0..s.len())
        .filter(|&i| s[i] != s[(i + 1) % s.len()])
        .count()
}

fn cmp_sign(a: &Q, b: &Q) -> i32 {
    match a.cmp(b) {
        std::cmp::Ordering::Less => -1,
        std::cmp::Ordering::Equal => 0,
        std::cmp::Ordering::Greater => 1,
    }
}

// ---------------------------------------------------------------------------
// Brute-force level set, straight from SPEC.md sections 3 to 6.

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug, Hash)]
enum Pt {
    V(usize),
    E(usize, usize),
}

fn on_edge(a: usize, b: usize) -> Pt {
    Pt::E(a.min(b), a.max(b))
}

/// Where a branch sits around its vertex: along the edge to a neighbour, or
/// inside the face sector that starts at a neighbour (fan order).
#[derive(Clone, Copy, Debug)]
enum Slot {
    Nbr(usize),
    Sector(usize),
}

struct Seg {
    from: Pt,
    to: Pt,
    from_slot: Option<Slot>,
    to_slot: Option<Slot>,
}

#[derive(Default, Debug, PartialEq)]
struct Found {
    outer: usize,
    hole: usize,
    up: usize,
    down: usize,
    flat: usize,
    ridges_open: usize,
    ridges_closed: usize,
    valleys_open: usize,
    valleys_closed: usize,
    minima: usize,
    maxima: usize,
    saddles: Vec<u32>,
    area_contours: Q,
    area_up: Q,
    area_down: Q,
}

struct Slicer<'a> {
    m: &'a Exact,
    t: &'a Topo,
}

impl Slicer<'_> {
    fn signs(&self, c: &Q) -> Vec<i32> {
        self.m.p.iter().map(|p| cmp_sign(&p[2], c)).collect()
    }

    fn point(&self, pt: Pt, c: &Q) -> (Q, Q) {
        match pt {
            Pt::V(v) => (self.m.p[v][0].clone(), self.m.p[v][1].clone()),
            Pt::E(a, b) => {
                let (pa, pb) = (&self.m.p[a], &self.m.p[b]);
                let t = (c - &pa[2]) / (&pb[2] - &pa[2]);
                (
                    &pa[0] + (&pb[0] - &pa[0]) * &t,
                    &pa[1] + (&pb[1] - &pa[1]) * &t,
                )
            }
        }
    }

    /// The S_O segment of a face with a strict sign change: walking the face
    /// in its order, from the point where the walk passes from + to - to the
    /// point where it passes from - to + (section 4).
    fn face_segment(&self, t: &[usize; 3], s: &[i32]) -> Option<Seg> {
        let (mut p2m, mut m2p) = (None, None);
        for i in 0..3 {
            let (p, q, r) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
            if s[p] > 0 && s[q] < 0 {
                p2m = Some((on_edge(p, q), None));
            }
            if s[p] < 0 && s[q] > 0 {
                m2p = Some((on_edge(p, q), None));
            }
            if s[q] == 0 {
                // The face seen from q is (q, r, p): its sector starts at r.
                if s[p] > 0 && s[r] < 0 {
                    p2m = Some((Pt::V(q), Some(Slot::Sector(r))));
                }
                if s[p] < 0 && s[r] > 0 {
                    m2p = Some((Pt::V(q), Some(Slot::Sector(r))));
                }
            }
        }
        let ((from, from_slot), (to, to_slot)) = (p2m?, m2p?);
        Some(Seg {
            from,
            to,
            from_slot,
            to_slot,
        })
    }

    /// Signed area of the contour at a level with no vertex on it.
    fn regular_area(&self, c: &Q) -> Q {
        let s = self.signs(c);
        assert!(
            s.iter().all(|&x| x != 0),
            "level {} is not regular",
            show(c)
        );
        let mut area = Q::zero();
        for t in &self.m.f {
            if let Some(seg) = self.face_segment(t, &s) {
                let (a, b) = (self.point(seg.from, c), self.point(seg.to, c));
                area += &a.0 * &b.1 - &a.1 * &b.0;
            }
        }
        area / Q::from_integer(BigInt::from(2))
    }

    fn heights(&self) -> Vec<Q> {
        let set: BTreeSet<Q> = self.m.p.iter().map(|p| p[2].clone()).collect();
        set.into_iter().collect()
    }

    /// The one-sided limit of the cross-section area at `c` from below
    /// (`dir = -1`) or above (`dir = 1`): the area is a quadratic in z
    /// between consecutive vertex heights, so three samples inside the
    /// adjacent interval extrapolate to `c` exactly.
    fn one_sided_area(&self, c: &Q, dir: i32) -> Q {
        let hs = self.heights();
        let other = if dir < 0 {
            hs.iter().rev().find(|h| *h < c)
        } else {
            hs.iter().find(|h| *h > c)
        };
        let Some(other) = other else {
            return Q::zero();
        };
        let four = Q::from_integer(BigInt::from(4));
        let zs: Vec<Q> = (1..=3)
            .map(|k| c + (other - c) * Q::from_integer(BigInt::from(k)) / &four)
            .collect();
        let ys: Vec<Q> = zs.iter().map(|z| self.regular_area(z)).collect();
        let mut value = Q::zero();
        for i in 0..3 {
            let mut w = Q::one();
            for j in 0..3 {
                if i != j {
                    w *= (c - &zs[j]) / (&zs[i] - &zs[j]);
                }
            }
            value += w * &ys[i];
        }
        value
    }

    fn level_set(&self, c: &Q) -> Found {
        let m = self.m;
        let s = self.signs(c);
        let mut found = Found::default();
        let mut segs: Vec<Seg> = Vec::new();
        let in_f: Vec<bool> = m.f.iter().map(|t| t.iter().all(|&v| s[v] == 0)).collect();

        // Faces: F, or one crossing segment.
        for (fi, t) in m.f.iter().enumerate() {
            if !in_f[fi] {
                segs.extend(self.face_segment(t, &s));
            }
        }

        // Edges in the plane (section 3, edge table).
        let mut sno: [Vec<(usize, usize)>; 2] = [Vec::new(), Vec::new()]; // ridge, valley
        for &(a, b) in &self.t.edges {
            if s[a] != 0 || s[b] != 0 {
                continue;
            }
            let (f1, o1) = self.t.half[&(a, b)];
            let (f2, o2) = self.t.half[&(b, a)];
            let so_dir = match (in_f[f1], in_f[f2]) {
                (true, true) => None,
                (false, false) if s[o1] == s[o2] => {
                    sno[usize::from(s[o1] > 0)].push((a, b));
                    None
                }
                // Transversal: the direction of the face whose opposite
                // vertex is above.
                (false, false) => Some(if s[o1] > 0 { (a, b) } else { (b, a) }),
                (flat1, _) => {
                    let (ff, (nf_dir, on)) = if flat1 {
                        (f1, ((b, a), o2))
                    } else {
                        (f2, ((a, b), o1))
                    };
                    let up = projected2(m, &m.f[ff]).is_positive();
                    let down = projected2(m, &m.f[ff]).is_negative();
                    if (up && s[on] > 0) || (down && s[on] < 0) {
                        Some(if s[on] > 0 {
                            nf_dir
                        } else {
                            (nf_dir.1, nf_dir.0)
                        })
                    } else {
                        None
                    }
                }
            };
            if let Some((x, y)) = so_dir {
                segs.push(Seg {
                    from: Pt::V(x),
                    to: Pt::V(y),
                    from_slot: Some(Slot::Nbr(y)),
                    to_slot: Some(Slot::Nbr(x)),
                });
            }
        }

        // F regions: faces joined by shared in-plane edges.
        let mut parent: Vec<usize> = (0..m.f.len()).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for &(a, b) in &self.t.edges {
            let (f1, _) = self.t.half[&(a, b)];
            let (f2, _) = self.t.half[&(b, a)];
            if in_f[f1] && in_f[f2] {
                let (r1, r2) = (root(&mut parent, f1), root(&mut parent, f2));
                parent[r1] = r2;
            }
        }
        let mut regions: BTreeMap<usize, (Q, BTreeSet<i32>)> = BTreeMap::new();
        for (fi, t) in m.f.iter().enumerate() {
            if in_f[fi] {
                let a2 = projected2(m, t);
                let r = root(&mut parent, fi);
                let e = regions.entry(r).or_insert((Q::zero(), BTreeSet::new()));
                e.1.insert(if a2.is_positive() {
                    1
                } else if a2.is_negative() {
                    -1
                } else {
                    0
                });
                e.0 += a2;
            }
        }
        found.area_up = Q::zero();
        found.area_down = Q::zero();
        for (a2, facings) in regions.values() {
            let nonzero: Vec<i32> = facings.iter().copied().filter(|&x| x != 0).collect();
            assert!(nonzero.len() <= 1, "an F region mixes facings (a fold)");
            match nonzero.first() {
                Some(1) => {
                    found.up += 1;
                    found.area_up += a2 / Q::from_integer(BigInt::from(2));
                }
                Some(_) => {
                    found.down += 1;
                    found.area_down -= a2 / Q::from_integer(BigInt::from(2));
                }
                None => found.flat += 1,
            }
        }

        // S_NO polylines, split where more than two S_NO edges meet.
        for (kind, list) in sno.iter().enumerate() {
            let mut adj: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
            for &(a, b) in list {
                adj.entry(a).or_default().push(b);
                adj.entry(b).or_default().push(a);
            }
            let mut seen = BTreeSet::new();
            let (mut open, mut closed) = (0, 0);
            for &start in adj.keys() {
                if !seen.insert(start) {
                    continue;
                }
                let mut comp = vec![start];
                let mut stack = vec![start];
                while let Some(x) = stack.pop() {
                    for &y in &adj[&x] {
                        if seen.insert(y) {
                            comp.push(y);
                            stack.push(y);
                        }
                    }
                }
                let special: usize = comp.iter().map(|x| adj[x].len()).filter(|&d| d != 2).sum();
                if special == 0 {
                    closed += 1;
                } else {
                    open += special / 2;
                }
            }
            if kind == 0 {
                (found.ridges_open, found.ridges_closed) = (open, closed);
            } else {
                (found.valleys_open, found.valleys_closed) = (open, closed);
            }
        }

        // P and saddles.
        let mut branches = vec![0u32; m.p.len()];
        for sg in &segs {
            for pt in [sg.from, sg.to] {
                if let Pt::V(v) = pt {
                    branches[v] += 1;
                }
            }
        }
        for v in 0..m.p.len() {
            if s[v] != 0 {
                continue;
            }
            let fan = &self.t.fan[v];
            if fan.iter().all(|&u| s[u] > 0) {
                found.minima += 1;
            } else if fan.iter().all(|&u| s[u] < 0) {
                found.maxima += 1;
            } else if branches[v] >= 4 {
                found.saddles.push(branches[v]);
            }
        }
        found.saddles.sort_unstable();

        // Chaining (section 5): one in, one out at an edge crossing; at a
        // vertex, branches in fan order read as balanced parentheses.
        let mut next = vec![usize::MAX; segs.len()];
        let mut at: BTreeMap<Pt, (Vec<usize>, Vec<usize>)> = BTreeMap::new();
        for (i, sg) in segs.iter().enumerate() {
            at.entry(sg.to).or_default().0.push(i);
            at.entry(sg.from).or_default().1.push(i);
        }
        for (pt, (ins, outs)) in &at {
            assert_eq!(ins.len(), outs.len(), "unbalanced branches at {pt:?}");
            match *pt {
                Pt::E(..) => {
                    assert_eq!(ins.len(), 1, "edge crossing {pt:?} used twice");
                    next[ins[0]] = outs[0];
                }
                Pt::V(v) => {
                    let fan = &self.t.fan[v];
                    let pos = |slot: Slot| match slot {
                        Slot::Nbr(u) => 2 * fan.iter().position(|&x| x == u).unwrap(),
                        Slot::Sector(u) => 2 * fan.iter().position(|&x| x == u).unwrap() + 1,
                    };
                    let mut list: Vec<(usize, bool, usize)> = ins
                        .iter()
                        .map(|&i| (pos(segs[i].to_slot.unwrap()), true, i))
                        .chain(
                            outs.iter()
                                .map(|&i| (pos(segs[i].from_slot.unwrap()), false, i)),
                        )
                        .collect();
                    list.sort_unstable();
                    // Start just after the lowest prefix sum: then every
                    // outgoing branch finds an open incoming one.
                    let (mut sum, mut low, mut start) = (0i64, 0i64, 0usize);
                    for (k, &(_, incoming, _)) in list.iter().enumerate() {
                        sum += if incoming { 1 } else { -1 };
                        if sum < low {
                            (low, start) = (sum, k + 1);
                        }
                    }
                    let mut open = Vec::new();
                    for k in 0..list.len() {
                        let (_, incoming, i) = list[(start + k) % list.len()];
                        if incoming {
                            open.push(i);
                        } else {
                            next[open.pop().expect("balanced")] = i;
                        }
                    }
                }
            }
        }
        let mut done = vec![false; segs.len()];
        found.area_contours = Q::zero();
        for i in 0..segs.len() {
            if done[i] {
                continue;
            }
            let mut area = Q::zero();
            let mut j = i;
            while !done[j] {
                done[j] = true;
                let (a, b) = (self.point(segs[j].from, c), self.point(segs[j].to, c));
                area += &a.0 * &b.1 - &a.1 * &b.0;
                j = next[j];
            }
            assert_eq!(j, i, "chaining did not close a loop");
            let area = area / Q::from_integer(BigInt::from(2));
            assert!(!area.is_zero(), "S_O loop of zero area at {}", show(c));
            if area.is_positive() {
                found.outer += 1;
            } else {
                found.hole += 1;
            }
            found.area_contours += area;
        }
        found
    }
}

// ---------------------------------------------------------------------------
// Tests

fn expected_solid(name: &str) -> &'static wmslice::datasets::expected::Solid {
    solids()
        .iter()
        .find(|s| s.dataset == name)
        .unwrap_or_else(|| panic!("no solid row for {name}"))
}

fn vertex_at(m: &Exact, p: [i64; 3]) -> usize {
    let p = p.map(|x| Q::from_integer(BigInt::from(x)));
    m.p.iter()
        .position(|v| *v == p)
        .unwrap_or_else(|| panic!("no vertex at {p:?}"))
}

#[test]
fn names_are_unique_snake_case_and_found_by_name() {
    let all = datasets::all();
    assert_eq!(all.len(), 13);
    let names: BTreeSet<&str> = all.iter().map(|d| d.name).collect();
    assert_eq!(names.len(), all.len());
    for d in all {
        assert!(d
            .name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'));
        assert!(!d.summary.is_empty() && !d.summary.contains('\n'));
        assert_eq!(datasets::by_name(d.name).map(|x| x.name), Some(d.name));
        assert!(!d.degenerate_levels.is_empty());
    }
    assert!(datasets::by_name("no_such_dataset").is_none());
}

#[test]
fn every_dataset_is_a_closed_oriented_manifold_without_degenerate_faces() {
    for d in datasets::all() {
        let m = Exact::new(&d.build());
        let t = topology(&m).unwrap_or_else(|e| panic!("{}: {e}", d.name));
        for (fi, f) in m.f.iter().enumerate() {
            let n = cross(&sub(&m.p[f[1]], &m.p[f[0]]), &sub(&m.p[f[2]], &m.p[f[0]]));
            assert!(
                n.iter().any(|x| !x.is_zero()),
                "{}: face {fi} has zero area",
                d.name
            );
        }
        // No fold: two faces on one edge, in one plane, on the same side.
        for &(a, b) in &t.edges {
            let (_, c) = t.half[&(a, b)];
            let (_, e) = t.half[&(b, a)];
            let ab = sub(&m.p[b], &m.p[a]);
            let (ac, ae) = (sub(&m.p[c], &m.p[a]), sub(&m.p[e], &m.p[a]));
            let coplanar = dot(&cross(&ab, &ac), &ae).is_zero();
            let same_side = dot(&cross(&ab, &ac), &cross(&ab, &ae)).is_positive();
            assert!(
                !(coplanar && same_side),
                "{}: fold at edge ({a}, {b})",
                d.name
            );
        }
        // Exactly representable, small coordinates.
        for p in &d.build().positions {
            assert!(p
                .iter()
                .all(|x| x.is_finite() && x.abs() < f64::from(1u32 << 20)));
        }
    }
}

#[test]
fn volumes_counts_and_euler_characteristics_match_the_hand_derivation() {
    assert_eq!(solids().len(), datasets::all().len());
    for d in datasets::all() {
        let mesh = d.build();
        let m = Exact::new(&mesh);
        let t = topology(&m).unwrap();
        let s = expected_solid(d.name);
        assert_eq!(mesh.positions.len(), s.vertices, "{}: vertices", d.name);
        assert_eq!(mesh.faces.len(), s.faces, "{}: faces", d.name);
        let vol = signed_volume(&m);
        assert!(
            vol.is_positive(),
            "{}: volume {} not positive",
            d.name,
            show(&vol)
        );
        assert_eq!(vol, ratio(s.volume), "{}: volume {}", d.name, show(&vol));
        let chi = m.p.len() as i64 - t.edges.len() as i64 + m.f.len() as i64;
        assert_eq!(chi, s.euler, "{}: Euler characteristic", d.name);
    }
}

#[test]
fn every_declared_degenerate_level_has_a_vertex_on_it() {
    for d in datasets::all() {
        let m = Exact::new(&d.build());
        let mut last: Option<Q> = None;
        for &l in d.degenerate_levels {
            let c = level(l);
            assert!(
                m.p.iter().any(|p| p[2] == c),
                "{}: no vertex at z = {}",
                d.name,
                show(&c)
            );
            if let Some(prev) = &last {
                assert!(*prev < c, "{}: levels not increasing", d.name);
            }
            last = Some(c);
        }
    }
}

#[test]
fn monkey_saddle_link_alternates_six_times() {
    let m = Exact::new(&datasets::by_name("double_torus").unwrap().build());
    let t = topology(&m).unwrap();
    let v = vertex_at(&m, [0, 0, 2]);
    assert_eq!(t.fan[v].len(), 6);
    assert_eq!(link_sign_changes(&m, &t, v), 6);
}

#[test]
fn saddle8_link_alternates_eight_times() {
    let m = Exact::new(&datasets::by_name("saddle8").unwrap().build());
    let t = topology(&m).unwrap();
    let v = vertex_at(&m, [0, 0, 2]);
    assert_eq!(t.fan[v].len(), 8);
    assert_eq!(link_sign_changes(&m, &t, v), 8);
}

#[test]
fn upright_torus_hole_top_and_bottom_are_ordinary_saddles() {
    let m = Exact::new(&datasets::by_name("upright_torus").unwrap().build());
    let t = topology(&m).unwrap();
    for z in [1, -1] {
        let v = vertex_at(&m, [0, 0, z]);
        assert_eq!(link_sign_changes(&m, &t, v), 4, "z = {z}");
    }
}

#[test]
fn builds_are_deterministic() {
    for d in datasets::all() {
        assert_eq!(d.build(), d.build(), "{}", d.name);
    }
}

#[test]
fn expectation_table_covers_every_degenerate_level_and_a_regular_neighbour() {
    for row in expected() {
        assert!(
            datasets::by_name(row.dataset).is_some(),
            "unknown {}",
            row.dataset
        );
        assert_eq!(row.faces_flat, 0);
        assert!(!row.why.is_empty());
    }
    for d in datasets::all() {
        let m = Exact::new(&d.build());
        let heights: BTreeSet<Q> = m.p.iter().map(|p| p[2].clone()).collect();
        let rows: Vec<&Expected> = expected().iter().filter(|r| r.dataset == d.name).collect();
        let levels: Vec<Q> = rows.iter().map(|r| level(r.level)).collect();
        assert!(
            levels.windows(2).all(|w| w[0] < w[1]),
            "{}: rows not sorted",
            d.name
        );
        for &l in d.degenerate_levels {
            let c = level(l);
            assert!(levels.contains(&c), "{}: no row at {}", d.name, show(&c));
            let below = heights.iter().rev().find(|h| **h < c);
            let above = heights.iter().find(|h| **h > c);
            let regular_next = levels.iter().any(|z| {
                !heights.contains(z)
                    && ((below.is_some_and(|b| b < z) && *z < c)
                        || (above.is_some_and(|a| z < a) && *z > c))
            });
            assert!(
                regular_next,
                "{}: no regular row next to {}",
                d.name,
                show(&c)
            );
        }
    }
}

fn check_row(d: &Dataset, sl: &Slicer<'_>, row: &Expected) -> Vec<String> {
    let c = level(row.level);
    let f = sl.level_set(&c);
    let below = sl.one_sided_area(&c, -1);
    let above = sl.one_sided_area(&c, 1);
    let mut bad = Vec::new();
    let mut cmp = |what: &str, got: String, want: String| {
        if got != want {
            bad.push(format!(
                "{} z={}: {what}: computed {got}, table {want}",
                d.name,
                show(&c)
            ));
        }
    };
    cmp(
        "outer loops",
        f.outer.to_string(),
        row.contours_outer.to_string(),
    );
    cmp(
        "hole loops",
        f.hole.to_string(),
        row.contours_hole.to_string(),
    );
    cmp("up regions", f.up.to_string(), row.faces_up.to_string());
    cmp(
        "down regions",
        f.down.to_string(),
        row.faces_down.to_string(),
    );
    cmp(
        "flat regions",
        f.flat.to_string(),
        row.faces_flat.to_string(),
    );
    cmp(
        "open ridges",
        f.ridges_open.to_string(),
        row.ridges_open.to_string(),
    );
    cmp(
        "closed ridges",
        f.ridges_closed.to_string(),
        row.ridges_closed.to_string(),
    );
    cmp(
        "open valleys",
        f.valleys_open.to_string(),
        row.valleys_open.to_string(),
    );
    cmp(
        "closed valleys",
        f.valleys_closed.to_string(),
        row.valleys_closed.to_string(),
    );
    cmp("minima", f.minima.to_string(), row.minima.to_string());
    cmp("maxima", f.maxima.to_string(), row.maxima.to_string());
    cmp(
        "saddles",
        format!("{:?}", f.saddles),
        format!("{:?}", row.saddles),
    );
    cmp(
        "S_O area",
        show(&f.area_contours),
        show(&ratio(row.area_contours)),
    );
    cmp("L- area", show(&below), show(&ratio(row.area_below)));
    cmp("L+ area", show(&above), show(&ratio(row.area_above)));
    cmp("up area", show(&f.area_up), show(&ratio(row.area_faces_up)));
    cmp(
        "down area",
        show(&f.area_down),
        show(&ratio(row.area_faces_down)),
    );
    bad
}

#[test]
fn hand_derived_level_sets_agree_with_a_brute_force_evaluation_of_the_spec() {
    let mut bad = Vec::new();
    for d in datasets::all() {
        let m = Exact::new(&d.build());
        let t = topology(&m).unwrap();
        let sl = Slicer { m: &m, t: &t };
        for row in expected().iter().filter(|r| r.dataset == d.name) {
            bad.extend(check_row(d, &sl, row));
        }
    }
    assert!(
        bad.is_empty(),
        "{} mismatches:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn cross_sections_integrate_to_the_volume() {
    // SPEC.md section 7.6: Simpson's rule between consecutive vertex heights.
    for d in datasets::all() {
        let m = Exact::new(&d.build());
        let t = topology(&m).unwrap();
        let sl = Slicer { m: &m, t: &t };
        let hs = sl.heights();
        let mut total = Q::zero();
        for w in hs.windows(2) {
            let mid = (&w[0] + &w[1]) / Q::from_integer(BigInt::from(2));
            let a0 = sl.one_sided_area(&w[0], 1);
            let a1 = sl.one_sided_area(&w[1], -1);
            let am = sl.regular_area(&mid);
            total += (&w[1] - &w[0]) * (a0 + am * Q::from_integer(BigInt::from(4)) + a1)
                / Q::from_integer(BigInt::from(6));
        }
        assert_eq!(total, signed_volume(&m), "{}", d.name);
    }
}

#[test]
fn datasets_md_has_a_section_and_a_table_row_for_every_expectation() {
    let md = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/DATASETS.md"))
        .expect("DATASETS.md at the crate root");
    for d in datasets::all() {
        let head = format!("\n## {}\n", d.name);
        let start = md
            .find(&head)
            .unwrap_or_else(|| panic!("no section for {}", d.name));
        let rest = &md[start + head.len()..];
        let section = &rest[..rest.find("\n## ").unwrap_or(rest.len())];
        for row in expected().iter().filter(|r| r.dataset == d.name) {
            let z = show(&level(row.level));
            let line = format!("\n| {z} | {}/{} |", row.contours_outer, row.contours_hole);
            assert!(
                section.contains(&line),
                "{}: no table row for z = {z}",
                d.name
            );
        }
    }
}
