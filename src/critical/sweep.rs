//! Input: a validated mesh, its topology and the snap unit. Output: the
//! critical levels and the Reeb graph (see [`super`] for the definitions).
//!
//! The sweep visits the distinct vertex heights in ascending order. Just
//! below a height `c` it holds the contour at `c - epsilon` as cyclic
//! sequences of crossed edges ([`Sequences`]), each tagged with the Reeb
//! arc it belongs to. At `c`:
//!
//! 1. every vertex at `c` is classified from its link ([`classify_vertex`]);
//! 2. the level set's components are found with a union-find over the
//!    vertices at `c`, the contours at `c - epsilon` and `c + epsilon` they
//!    touch, and the in-plane edges: two vertices at `c` lie in one
//!    component exactly when in-plane edges or contour pieces at `c` join
//!    them, and a piece of contour at `c` between two vertices is the
//!    limit of a piece of one contour at `c - epsilon` (and of one at
//!    `c + epsilon`) between edges of their lower (upper) stars;
//! 3. the contours are carried from `c - epsilon` to `c + epsilon` one
//!    vertex at a time (vertices at `c` in id order, each counting its
//!    neighbours at `c` with smaller ids as below: an internal order of
//!    updates only; the contour at `c + epsilon` is determined by the set
//!    of crossed edges, so it does not depend on that order);
//! 4. a component holding a critical element becomes a node: the arcs of
//!    its lower contours end there and each upper contour starts a new
//!    arc. Any other component is one regular contour passing `c`: exactly
//!    one contour below and one above (checked), which keep their arc.
//!
//! `epsilon` is symbolic, as in SPEC 6: "the contour at `c - epsilon`"
//! is the set of edges crossed by every level just below `c`, and no
//! number is ever added to a height or compared against a tolerance.
//!
//! Carrying the contours across a vertex `v` (step 3): with `v`'s
//! neighbours in fan order split into maximal runs of lower (`R_k`) and
//! upper (`U_k`) neighbours, alternating `R_1 U_1 R_2 U_2 ...`, the contour
//! just below `v` crosses the lower-star edges of each `R_k` in fan order,
//! entering from the link edge `L'_{k-1}` (between `U_{k-1}` and `R_k`)
//! and leaving by `L_k` (between `R_k` and `U_k`), so each run is a
//! contiguous piece of one sequence. Just above `v` the contour crosses
//! the upper-star edges of each `U_k` in reverse fan order, from `L'_k`
//! to `L_k` (both follow from the face-walk rule of SPEC section 4). So the
//! pieces `R_k` are cut out, leaving paths from some `L_k` to some
//! `L'_j`, and the paths are joined through the reversed `U` pieces. Each
//! step is checked against the mesh (a piece holds exactly its run's
//! edges, a path starts and ends at the expected link edges); a failed
//! check is an internal error.
//!
//! With one run of each (`R_1 U_1`: every regular vertex with no
//! neighbour at its height, nearly all of a mesh), the path is the rest of
//! the contour, unchanged: `R_1` is replaced by `U_1` reversed in place
//! ([`Sequences::replace_run`], checked to be consecutive in fan order),
//! and the contour keeps its tree and its arc. Only the heights that hold
//! a vertex with another link pattern, or with a neighbour at its height,
//! go through classification, components and the general splice.

use super::link::{classify_vertex, face_edge, AtLevel, InPlane};
use super::reeb::{NodeKind, ReebGraph, ReebNode};
use super::sequences::{ReplaceError, Sequences, NIL};
use super::{CriticalError, CriticalLevel};
use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::rational::{rat_from_f64, rat_to_string, Rat};
use crate::exact::Sign;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::levelset::ridges::join_ridges;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use rustc_hash::FxHashMap as HashMap;

/// A union-find over `0..n` that grows on demand and is reset, not
/// reallocated, at each height (petgraph's `UnionFind` has a fixed size).
#[derive(Default)]
struct Dsu {
    parent: Vec<u32>,
}

impl Dsu {
    fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }
    fn add(&mut self) -> u32 {
        let i = self.parent.len() as u32;
        self.parent.push(i);
        i
    }
    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let g = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = g;
            x = g;
        }
        x
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // The smaller index stays the root (deterministic).
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi as usize] = lo;
        }
    }
}

/// A run of consecutive lower or upper neighbours in a fan (cyclic).
#[derive(Clone, Copy, Debug)]
struct Run {
    start: usize,
    len: usize,
}

/// One component of the level set at the current height.
#[derive(Default)]
struct Component {
    vertices: Vec<u32>,
    lower_arcs: Vec<u32>,
    upper_roots: Vec<u32>,
}

struct Sweep<'a> {
    mesh: &'a Mesh,
    topo: &'a Topology,
    unit: &'a Rat,
    /// Position of each used vertex in the height order.
    rank: Vec<u32>,
    seq: Sequences,
    /// Arcs as `[lower node, upper node]` (`NIL` until the arc ends).
    arcs: Vec<[u32; 2]>,
    nodes: Vec<ReebNode>,
    levels: Vec<CriticalLevel>,
    /// The current height (for error messages).
    z: f64,
    // Scratch, reused across heights.
    signs: Vec<Sign>,
    scratch: Vec<u32>,
    pass_scratch: PassScratch,
}

/// Buffers of one pass across a vertex, reused.
#[derive(Default)]
struct PassScratch {
    lower: Vec<bool>,
    upper: Vec<bool>,
    r_runs: Vec<Run>,
    u_runs: Vec<Run>,
    runs: Vec<(Run, Run)>,
    /// Lower pieces: (root, position, run).
    pieces: Vec<(u32, u32, usize)>,
    path_after: Vec<u32>,
    next_piece: Vec<usize>,
    done: Vec<bool>,
    /// The edges a single run replaces, and those it puts in their place.
    old: Vec<EdgeId>,
    new: Vec<EdgeId>,
}

impl<'a> Sweep<'a> {
    fn internal(&self, what: String) -> CriticalError {
        CriticalError::Internal {
            level: rat_to_string(&self.exact(self.z)),
            what,
        }
    }

    /// A stored height (or coordinate) in the mesh's units, exactly.
    fn exact(&self, x: f64) -> Rat {
        rat_from_f64(x) * self.unit
    }

    fn is_lower(&self, w: VertexId, v: VertexId) -> bool {
        self.rank[w.idx()] < self.rank[v.idx()]
    }

    /// Maximal runs of the fan entries where `pick` holds (cyclic).
    fn runs_of(flags: &[bool], out: &mut Vec<Run>) {
        out.clear();
        let k = flags.len();
        let Some(s) = (0..k).find(|&i| flags[i] && !flags[(i + k - 1) % k]) else {
            if flags.iter().all(|&f| f) && k > 0 {
                out.push(Run { start: 0, len: k });
            }
            return;
        };
        let mut j = 0;
        while j < k {
            if flags[(s + j) % k] {
                let start = (s + j) % k;
                let mut len = 0;
                while j < k && flags[(s + j) % k] {
                    len += 1;
                    j += 1;
                }
                out.push(Run { start, len });
            } else {
                j += 1;
            }
        }
    }

    /// The link edge of fan entry `i` of `v`: `{n_i, n_{i+1}}`.
    fn link_edge(&self, v: VertexId, i: usize) -> Option<EdgeId> {
        let fan = self.topo.fan(v);
        let k = fan.len();
        face_edge(
            self.mesh,
            self.topo,
            fan[i].face,
            fan[i].neighbour,
            fan[(i + 1) % k].neighbour,
        )
    }

    /// Carries the contours across `v` (see the module documentation).
    fn pass(&mut self, v: VertexId) -> Result<(), CriticalError> {
        let mut sc = std::mem::take(&mut self.pass_scratch);
        self.lower_flags(v, &mut sc.lower);
        let result = self.pass_with(v, &mut sc);
        self.pass_scratch = sc;
        result
    }

    /// Which neighbours of `v` in fan order come before it in the sweep.
    fn lower_flags(&self, v: VertexId, out: &mut Vec<bool>) {
        out.clear();
        out.extend(
            self.topo
                .fan(v)
                .iter()
                .map(|e| self.is_lower(e.neighbour, v)),
        );
    }

    fn pass_with(&mut self, v: VertexId, sc: &mut PassScratch) -> Result<(), CriticalError> {
        let fan = self.topo.fan(v);
        let k = fan.len();
        let nl = sc.lower.iter().filter(|&&l| l).count();
        if nl == 0 {
            // A minimum of the sweep order: a new contour around v.
            return match self.seq.build((0..k).rev().map(|i| fan[i].edge)) {
                Some(_) => Ok(()),
                None => Err(self.internal(format!("a new contour at {v} reuses an edge"))),
            };
        }
        if nl == k {
            // A maximum: the contour around v is exactly its star's edges.
            let e0 = fan[0].edge;
            if !self.seq.contains(e0) {
                return Err(self.internal(format!("no contour reaches the top of {v}")));
            }
            let (root, pos) = self.seq.locate(e0);
            let mut got = std::mem::take(&mut self.scratch);
            got.clear();
            self.seq.collect(root, &mut got);
            let ok = got.len() == k && (0..k).all(|i| got[(pos as usize + i) % k] == fan[i].edge.0);
            self.scratch = got;
            if !ok {
                return Err(self.internal(format!("the contour closing at {v} is not its star")));
            }
            let mut scratch = std::mem::take(&mut self.scratch);
            self.seq.release(root, &mut scratch);
            self.scratch = scratch;
            return Ok(());
        }
        // Runs R_j (lower) and U_j (upper, right after R_j).
        Self::runs_of(&sc.lower, &mut sc.r_runs);
        sc.upper.clear();
        sc.upper.extend(sc.lower.iter().map(|&l| !l));
        Self::runs_of(&sc.upper, &mut sc.u_runs);
        let (r_runs, u_runs) = (&sc.r_runs, &mut sc.u_runs);
        let r = r_runs.len();
        if u_runs.len() != r {
            return Err(self.internal(format!("unbalanced runs at {v}")));
        }
        if r == 1 {
            return self.replace(v, r_runs[0], u_runs[0], sc);
        }
        // Align: U_j starts right after R_j ends.
        let first_u_start = (r_runs[0].start + r_runs[0].len) % k;
        let shift = u_runs
            .iter()
            .position(|u| u.start == first_u_start)
            .ok_or_else(|| self.internal(format!("runs do not alternate at {v}")))?;
        u_runs.rotate_left(shift);
        sc.runs.clear();
        sc.runs
            .extend(sc.r_runs.iter().copied().zip(sc.u_runs.iter().copied()));
        self.reconnect(v, sc)
    }

    /// One run of lower and one of upper neighbours: the contour below `v`
    /// crosses the lower edges in fan order, and just above `v` the upper
    /// edges in reverse fan order take their place; the rest of the
    /// contour, and its arc, stay as they are.
    fn replace(
        &mut self,
        v: VertexId,
        lower: Run,
        upper: Run,
        sc: &mut PassScratch,
    ) -> Result<(), CriticalError> {
        let fan = self.topo.fan(v);
        let k = fan.len();
        sc.old.clear();
        sc.old
            .extend((0..lower.len).map(|i| fan[(lower.start + i) % k].edge));
        sc.new.clear();
        sc.new.extend(
            (0..upper.len)
                .rev()
                .map(|i| fan[(upper.start + i) % k].edge),
        );
        self.seq.replace_run(&sc.old, &sc.new).map_err(|e| match e {
            ReplaceError::NotARun => self.internal(format!(
                "the contour below {v} does not cross its lower edges in fan order"
            )),
            ReplaceError::InUse => self.internal(format!("an upper edge of {v} is in use")),
        })
    }

    fn reconnect(&mut self, v: VertexId, sc: &mut PassScratch) -> Result<(), CriticalError> {
        let fan = self.topo.fan(v);
        let k = fan.len();
        let PassScratch {
            runs,
            pieces,
            path_after,
            next_piece,
            done,
            ..
        } = sc;
        let runs: &[(Run, Run)] = runs;
        let r = runs.len();
        // Locate each lower piece: (root, position, run).
        pieces.clear();
        for (j, (rr, _)) in runs.iter().enumerate() {
            let e = fan[rr.start].edge;
            if !self.seq.contains(e) {
                return Err(self.internal(format!("edge {e} below {v} is on no contour")));
            }
            let (root, pos) = self.seq.locate(e);
            pieces.push((root, pos, j));
        }
        pieces.sort_unstable();
        path_after.clear();
        path_after.resize(r, NIL);
        next_piece.clear();
        next_piece.resize(r, usize::MAX);
        let mut g = 0;
        while g < pieces.len() {
            let root = pieces[g].0;
            let mut h = g;
            while h < pieces.len() && pieces[h].0 == root {
                h += 1;
            }
            let group = &pieces[g..h];
            let base = group[0].1;
            let total = self.seq.len(root);
            // Rotate so that the first piece starts the sequence.
            let (a, b) = self.seq.split(root, base);
            let mut rest = self.seq.concat(b, a);
            for (t, &(_, pos, j)) in group.iter().enumerate() {
                let run = runs[j].0;
                let (piece, after) = self.seq.split(rest, run.len as u32);
                let mut got = std::mem::take(&mut self.scratch);
                got.clear();
                self.seq.collect(piece, &mut got);
                let ok = got.len() == run.len
                    && (0..run.len).all(|i| got[i] == fan[(run.start + i) % k].edge.0);
                self.seq.release(piece, &mut got);
                self.scratch = got;
                if !ok {
                    return Err(self.internal(format!(
                        "the contour below {v} does not cross its lower edges in fan order"
                    )));
                }
                let path_len = if t + 1 < group.len() {
                    group[t + 1].1 - (pos + run.len as u32)
                } else {
                    total - (pos - base) - run.len as u32
                };
                let (path, next_rest) = self.seq.split(after, path_len);
                if path == NIL {
                    return Err(self.internal(format!("an empty contour path at {v}")));
                }
                path_after[j] = path;
                next_piece[j] = group[(t + 1) % group.len()].2;
                rest = next_rest;
            }
            if rest != NIL {
                return Err(self.internal(format!("a contour piece left over at {v}")));
            }
            g = h;
        }
        // Join: the path after R_j ends before R_m, at L'_{m-1}; then comes
        // U_{m-1} reversed, then L_{m-1}, which starts the path after R_{m-1}.
        done.clear();
        done.resize(r, false);
        for j0 in 0..r {
            if done[j0] {
                continue;
            }
            let mut t = NIL;
            let mut j = j0;
            loop {
                done[j] = true;
                let path = path_after[j];
                let (rr, _) = runs[j];
                let l_j = self.link_edge(v, (rr.start + rr.len - 1) % k);
                if l_j.map(|e| e.0) != Some(self.seq.first(path)) {
                    return Err(self.internal(format!(
                        "a contour leaves the lower star of {v} by an unexpected edge"
                    )));
                }
                let m = next_piece[j];
                let up = (m + r - 1) % r;
                let (_, ur) = runs[up];
                let l_prime = self.link_edge(v, (ur.start + ur.len - 1) % k);
                if l_prime.map(|e| e.0) != Some(self.seq.last(path)) {
                    return Err(self.internal(format!(
                        "a contour enters the lower star of {v} by an unexpected edge"
                    )));
                }
                t = self.seq.concat(t, path);
                let upper = (0..ur.len).rev().map(|i| fan[(ur.start + i) % k].edge);
                let piece = self
                    .seq
                    .build(upper)
                    .ok_or_else(|| self.internal(format!("an upper edge of {v} is in use")))?;
                t = self.seq.concat(t, piece);
                j = up;
                if j == j0 {
                    break;
                }
                if done[j] {
                    return Err(self.internal(format!("contour pieces at {v} do not close")));
                }
            }
        }
        Ok(())
    }
}

/// Per-node tallies while a height is processed.
#[derive(Default, Clone)]
struct Tally {
    faces_up: usize,
    faces_down: usize,
    ridges: usize,
    valleys: usize,
    minima: usize,
    maxima: usize,
    saddles: Vec<(VertexId, u32)>,
    /// Euler characteristic of the node: vertices - in-plane edges -
    /// face branches / 2 + faces (times 2, to stay integral).
    chi2: i64,
}

/// Runs the sweep.
pub(super) fn sweep(
    mesh: &Mesh,
    topo: &Topology,
    unit: &Rat,
) -> Result<(Vec<CriticalLevel>, ReebGraph), CriticalError> {
    let n = mesh.num_vertices();
    let key = |v: u32| mesh.positions[v as usize][2] + 0.0;
    // Sorted by (height, id), as pairs: no position is read in the sort.
    let mut keyed: Vec<(f64, u32)> = (0..n as u32)
        .filter(|&v| !topo.fan(VertexId(v)).is_empty())
        .map(|v| (key(v), v))
        .collect();
    keyed.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let order: Vec<u32> = keyed.into_iter().map(|(_, v)| v).collect();
    let mut rank = vec![u32::MAX; n];
    for (i, &v) in order.iter().enumerate() {
        rank[v as usize] = i as u32;
    }
    let mut s = Sweep {
        mesh,
        topo,
        unit,
        rank,
        seq: Sequences::new(topo.num_edges()),
        arcs: Vec::new(),
        nodes: Vec::new(),
        levels: Vec::new(),
        z: 0.0,
        signs: Vec::new(),
        scratch: Vec::new(),
        pass_scratch: PassScratch::default(),
    };
    let mut start = 0;
    let mut ctx = LevelScratch::default();
    while start < order.len() {
        let z = key(order[start]);
        let mut end = start + 1;
        while end < order.len() && key(order[end]) == z {
            end += 1;
        }
        s.z = z;
        s.level(&order[start..end], start, &mut ctx)?;
        start = end;
    }
    if let Some(a) = s.arcs.iter().position(|a| a[1] == NIL) {
        return Err(s.internal(format!("arc {a} never ends")));
    }
    // Below / above counts from the arcs: L- at level i holds the arcs with
    // lower level < i <= upper level, L+ those with lower <= i < upper.
    let nl = s.levels.len();
    let mut below = vec![0i64; nl + 1];
    let mut above = vec![0i64; nl + 1];
    for a in &s.arcs {
        let (lo, hi) = (s.nodes[a[0] as usize].level, s.nodes[a[1] as usize].level);
        if lo >= hi {
            return Err(s.internal(format!("an arc runs from level {lo} to {hi}")));
        }
        below[lo + 1] += 1;
        below[hi + 1] -= 1;
        above[lo] += 1;
        above[hi] -= 1;
    }
    let (mut b, mut u) = (0i64, 0i64);
    for i in 0..nl {
        b += below[i];
        u += above[i];
        s.levels[i].below = b as usize;
        s.levels[i].above = u as usize;
    }
    let mut arcs: Vec<[usize; 2]> = s
        .arcs
        .iter()
        .map(|a| [a[0] as usize, a[1] as usize])
        .collect();
    arcs.sort_unstable();
    Ok((
        s.levels,
        ReebGraph {
            nodes: s.nodes,
            arcs,
        },
    ))
}

/// Scratch for one height, reused.
#[derive(Default)]
struct LevelScratch {
    at: Vec<AtLevel>,
    inplane: InPlane,
    dsu: Dsu,
    lower_item: HashMap<u32, u32>,
    upper_item: HashMap<u32, u32>,
    runs: Vec<Run>,
    flags: Vec<bool>,
}

impl Sweep<'_> {
    /// Processes the vertices `group` (all at height `self.z`), whose
    /// ranks start at `first_rank`.
    fn level(
        &mut self,
        group: &[u32],
        first_rank: usize,
        ctx: &mut LevelScratch,
    ) -> Result<(), CriticalError> {
        let g = group.len();
        let local = |rank: &[u32], v: VertexId| rank[v.idx()] as usize - first_rank;
        if self.pass_if_regular(group)? {
            return Ok(());
        }
        // 1. Classify.
        ctx.at.clear();
        ctx.inplane.clear();
        let mut signs = std::mem::take(&mut self.signs);
        for &v in group {
            let at = classify_vertex(
                self.mesh,
                self.topo,
                VertexId(v),
                &mut signs,
                &mut ctx.inplane,
            )
            .map_err(|f| self.internal(format!("in-plane face {} has zero area", f.0)))?;
            ctx.at.push(at);
        }
        self.signs = signs;
        let critical = ctx.at.iter().any(AtLevel::is_critical);
        // 2. Components: vertices, then contours below and above.
        ctx.dsu.reset(g);
        ctx.lower_item.clear();
        ctx.upper_item.clear();
        for (i, &v) in group.iter().enumerate() {
            let v = VertexId(v);
            let fan = self.topo.fan(v);
            ctx.flags.clear();
            ctx.flags
                .extend(fan.iter().map(|e| self.mesh.pos(e.neighbour)[2] < self.z));
            Self::runs_of(&ctx.flags, &mut ctx.runs);
            for run in &ctx.runs {
                let e = fan[run.start].edge;
                if !self.seq.contains(e) {
                    return Err(self.internal(format!("edge {e} below {v} is on no contour")));
                }
                let (root, _) = self.seq.locate(e);
                let arc = self.seq.tag(root);
                if arc == NIL {
                    return Err(self.internal(format!("a contour below {v} has no arc")));
                }
                let item = *ctx.lower_item.entry(arc).or_insert_with(|| ctx.dsu.add());
                ctx.dsu.union(i as u32, item);
            }
        }
        for &(a, b) in &ctx.inplane.edges {
            ctx.dsu
                .union(local(&self.rank, a) as u32, local(&self.rank, b) as u32);
        }
        // 3. Carry the contours across the vertices, in rank order.
        for &v in group {
            self.pass(VertexId(v))?;
        }
        for (i, &v) in group.iter().enumerate() {
            let v = VertexId(v);
            let fan = self.topo.fan(v);
            ctx.flags.clear();
            ctx.flags
                .extend(fan.iter().map(|e| self.mesh.pos(e.neighbour)[2] > self.z));
            Self::runs_of(&ctx.flags, &mut ctx.runs);
            for run in &ctx.runs {
                let e = fan[run.start].edge;
                if !self.seq.contains(e) {
                    return Err(self.internal(format!("edge {e} above {v} is on no contour")));
                }
                let (root, _) = self.seq.locate(e);
                let item = *ctx.upper_item.entry(root).or_insert_with(|| ctx.dsu.add());
                ctx.dsu.union(i as u32, item);
            }
        }
        // 4. Components: nodes and regular contours.
        let mut comp_of_root: HashMap<u32, usize> = HashMap::default();
        let mut comps: Vec<Component> = Vec::new();
        let mut comp_index = |dsu: &mut Dsu, item: u32, comps: &mut Vec<Component>| -> usize {
            let r = dsu.find(item);
            *comp_of_root.entry(r).or_insert_with(|| {
                comps.push(Component::default());
                comps.len() - 1
            })
        };
        for i in 0..g {
            let c = comp_index(&mut ctx.dsu, i as u32, &mut comps);
            comps[c].vertices.push(i as u32);
        }
        let mut lower: Vec<(u32, u32)> = ctx.lower_item.iter().map(|(&a, &it)| (a, it)).collect();
        lower.sort_unstable();
        for (arc, it) in lower {
            let c = comp_index(&mut ctx.dsu, it, &mut comps);
            comps[c].lower_arcs.push(arc);
        }
        let mut upper: Vec<(u32, u32)> = ctx.upper_item.iter().map(|(&r, &it)| (r, it)).collect();
        upper.sort_unstable();
        for (root, it) in upper {
            let c = comp_index(&mut ctx.dsu, it, &mut comps);
            comps[c].upper_roots.push(root);
        }
        // Every component holds a vertex (items were joined to vertices).
        // Regular components keep their arc.
        let mut node_comps: Vec<usize> = Vec::new();
        for (ci, comp) in comps.iter().enumerate() {
            let is_node = comp
                .vertices
                .iter()
                .any(|&i| ctx.at[i as usize].is_critical());
            if is_node {
                node_comps.push(ci);
                continue;
            }
            if comp.lower_arcs.len() != 1 || comp.upper_roots.len() != 1 {
                return Err(self.internal(format!(
                    "a regular contour through v{} meets {} contours below and {} above",
                    group[comp.vertices[0] as usize],
                    comp.lower_arcs.len(),
                    comp.upper_roots.len()
                )));
            }
            self.seq.set_tag(comp.upper_roots[0], comp.lower_arcs[0]);
        }
        if !critical {
            return Ok(());
        }
        self.make_nodes(group, ctx, &comps, &node_comps)
    }

    /// The common case: every vertex of `group` is regular and has no
    /// neighbour at its height. Then each one has exactly one run of lower
    /// and one of upper neighbours, its contour passes in place
    /// ([`Self::replace`]) and keeps its arc, and no components are needed:
    /// the vertices are passed and `true` returned. Otherwise nothing is
    /// done and `false` returned.
    fn pass_if_regular(&mut self, group: &[u32]) -> Result<bool, CriticalError> {
        let mut sc = std::mem::take(&mut self.pass_scratch);
        let regular = group
            .iter()
            .all(|&v| self.regular_alone(VertexId(v), &mut sc.lower));
        let mut result = Ok(regular);
        if regular {
            for &v in group {
                // Alone at its height, the flags of the test are still here.
                if group.len() > 1 {
                    self.regular_alone(VertexId(v), &mut sc.lower);
                }
                if let Err(e) = self.pass_with(VertexId(v), &mut sc) {
                    result = Err(e);
                    break;
                }
            }
        }
        self.pass_scratch = sc;
        result
    }

    /// Whether `v` has no neighbour at its height and is regular: the signs
    /// of its neighbours change exactly twice around it (SPEC section 3:
    /// not in F, on no S_NO edge, no extremum, two S_O branches). Leaves in
    /// `lower` which neighbours are below it, which then are exactly those
    /// before it in the sweep.
    fn regular_alone(&self, v: VertexId, lower: &mut Vec<bool>) -> bool {
        let z = self.z;
        lower.clear();
        for e in self.topo.fan(v) {
            let h = self.mesh.pos(e.neighbour)[2];
            if h == z {
                return false;
            }
            lower.push(h < z);
        }
        let k = lower.len();
        (0..k).filter(|&i| lower[i] != lower[(i + 1) % k]).count() == 2
    }

    /// Creates the nodes of the current height from its critical
    /// components, ends and starts their arcs, and records the level.
    fn make_nodes(
        &mut self,
        group: &[u32],
        ctx: &mut LevelScratch,
        comps: &[Component],
        node_comps: &[usize],
    ) -> Result<(), CriticalError> {
        let level_index = self.levels.len();
        // Nodes ordered by their smallest vertex id.
        let mut order: Vec<(u32, usize)> = node_comps
            .iter()
            .map(|&c| {
                let min_v = comps[c].vertices.iter().map(|&i| group[i as usize]).min();
                (min_v.unwrap_or(u32::MAX), c)
            })
            .collect();
        order.sort_unstable();
        let first_node = self.nodes.len();
        let mut node_of_comp: HashMap<usize, usize> = HashMap::default();
        for (t, &(_, c)) in order.iter().enumerate() {
            node_of_comp.insert(c, first_node + t);
        }
        // The node of each vertex of the group (usize::MAX: regular).
        let mut node_of_vertex = vec![usize::MAX; group.len()];
        for &(_, c) in &order {
            for &i in &comps[c].vertices {
                node_of_vertex[i as usize] = node_of_comp[&c] - first_node;
            }
        }
        let mut tallies = vec![Tally::default(); order.len()];
        let local =
            |v: VertexId| self.rank[v.idx()] as usize - self.rank[group[0] as usize] as usize;
        // Vertices: P, saddles, and chi.
        for (i, at) in ctx.at.iter().enumerate() {
            let t = node_of_vertex[i];
            if t == usize::MAX {
                continue;
            }
            let tally = &mut tallies[t];
            tally.chi2 += 2 - i64::from(at.face_branches);
            match at.extremum {
                Some(ExtremumKind::Min) => tally.minima += 1,
                Some(ExtremumKind::Max) => tally.maxima += 1,
                None => {}
            }
            if at.branches >= 4 {
                tally.saddles.push((VertexId(group[i]), at.branches / 2));
            }
        }
        for &(a, _) in &ctx.inplane.edges {
            let t = node_of_vertex[local(a)];
            if t != usize::MAX {
                tallies[t].chi2 -= 2;
            }
        }
        // Face regions: faces of F joined across in-plane edges.
        let faces = &ctx.inplane.faces;
        let index: HashMap<FaceId, u32> = faces
            .iter()
            .enumerate()
            .map(|(i, &f)| (f, i as u32))
            .collect();
        let mut dsu = Dsu::default();
        dsu.reset(faces.len());
        for (i, &f) in faces.iter().enumerate() {
            for &e in &self.topo.face_edges[f.idx()] {
                let edge = self.topo.edge(e);
                let other = if edge.faces[0] == f {
                    edge.faces[1]
                } else {
                    edge.faces[0]
                };
                if let Some(&j) = index.get(&other) {
                    dsu.union(i as u32, j);
                }
            }
        }
        // Each region's facing is that of its smallest face.
        let mut region_face: HashMap<u32, FaceId> = HashMap::default();
        for (i, &f) in faces.iter().enumerate() {
            let r = dsu.find(i as u32);
            let slot = region_face.entry(r).or_insert(f);
            if f < *slot {
                *slot = f;
            }
        }
        for &f in faces {
            let t = node_of_vertex[local(self.mesh.faces[f.idx()][0])];
            if t != usize::MAX {
                tallies[t].chi2 += 2;
            }
        }
        let mut regions: Vec<FaceId> = region_face.into_values().collect();
        regions.sort_unstable();
        for f in regions {
            let t = node_of_vertex[local(self.mesh.faces[f.idx()][0])];
            if t == usize::MAX {
                return Err(self.internal(format!("face {f} in the plane is in no node")));
            }
            match crate::classify::faces::face_facing(self.mesh, f) {
                Facing::Up => tallies[t].faces_up += 1,
                Facing::Down => tallies[t].faces_down += 1,
                Facing::Flat => {
                    return Err(self.internal(format!("in-plane face {f} has zero area")));
                }
            }
        }
        // S_NO polylines, split as the slicer splits them.
        for p in join_ridges(&ctx.inplane.sno) {
            let t = node_of_vertex[local(p.vertices[0])];
            if t == usize::MAX {
                return Err(self.internal("a ridge is in no node".into()));
            }
            match p.kind {
                RidgeKind::Ridge => tallies[t].ridges += 1,
                RidgeKind::Valley => tallies[t].valleys += 1,
            }
        }
        // Nodes, arcs.
        let z = self.exact(self.z);
        let mut level = CriticalLevel {
            z: z.clone(),
            faces_up: 0,
            faces_down: 0,
            ridges: 0,
            valleys: 0,
            minima: 0,
            maxima: 0,
            saddles: Vec::new(),
            below: 0,
            above: 0,
        };
        let mut saddles: Vec<(VertexId, u32)> = Vec::new();
        for (t, &(min_v, c)) in order.iter().enumerate() {
            let node = first_node + t;
            let comp = &comps[c];
            for &arc in &comp.lower_arcs {
                let slot = &mut self.arcs[arc as usize][1];
                if *slot != NIL {
                    return Err(self.internal(format!("arc {arc} ends twice")));
                }
                *slot = node as u32;
            }
            for &root in &comp.upper_roots {
                let arc = self.arcs.len() as u32;
                self.arcs.push([node as u32, NIL]);
                self.seq.set_tag(root, arc);
            }
            let tally = &mut tallies[t];
            tally.saddles.sort_unstable();
            let b = (comp.lower_arcs.len() + comp.upper_roots.len()) as i64;
            // 2 - 2 genus - b = chi.
            let twice_genus = 2 - b - tally.chi2 / 2;
            if tally.chi2 % 2 != 0 || twice_genus < 0 || twice_genus % 2 != 0 {
                return Err(self.internal(format!(
                    "node at v{min_v}: Euler characteristic {}/2 with {b} arcs",
                    tally.chi2
                )));
            }
            let kind = node_kind(tally);
            let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for &i in &comp.vertices {
                let p = self.mesh.positions[group[i as usize] as usize];
                for a in 0..2 {
                    lo[a] = lo[a].min(p[a]);
                    hi[a] = hi[a].max(p[a]);
                }
            }
            self.nodes.push(ReebNode {
                z: z.clone(),
                level: level_index,
                kind,
                vertex: VertexId(min_v),
                vertices: comp.vertices.len(),
                faces_up: tally.faces_up,
                faces_down: tally.faces_down,
                ridges: tally.ridges,
                valleys: tally.valleys,
                minima: tally.minima,
                maxima: tally.maxima,
                saddles: tally.saddles.iter().map(|s| s.1).collect(),
                below: comp.lower_arcs.len(),
                above: comp.upper_roots.len(),
                genus: (twice_genus / 2) as u64,
                bbox: [
                    [self.exact(lo[0]), self.exact(lo[1])],
                    [self.exact(hi[0]), self.exact(hi[1])],
                ],
            });
            level.faces_up += tally.faces_up;
            level.faces_down += tally.faces_down;
            level.ridges += tally.ridges;
            level.valleys += tally.valleys;
            level.minima += tally.minima;
            level.maxima += tally.maxima;
            saddles.extend(tally.saddles.iter().copied());
        }
        saddles.sort_unstable();
        level.saddles = saddles.into_iter().map(|s| s.1).collect();
        self.levels.push(level);
        Ok(())
    }
}

/// The kind of a node from what it holds (see [`super`]).
fn node_kind(t: &Tally) -> NodeKind {
    let plateau = t.faces_up + t.faces_down > 0;
    let kinds = [
        (t.minima > 0, NodeKind::Min),
        (t.maxima > 0, NodeKind::Max),
        (!t.saddles.is_empty(), NodeKind::Saddle),
        (plateau, NodeKind::Plateau),
        (t.ridges > 0, NodeKind::Ridge),
        (t.valleys > 0, NodeKind::Valley),
    ];
    let mut present = kinds.iter().filter(|k| k.0).map(|k| k.1);
    match (present.next(), present.next()) {
        (Some(k), None) => k,
        _ => NodeKind::Mixed,
    }
}
