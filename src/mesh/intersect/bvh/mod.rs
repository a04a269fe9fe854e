//! Input: a mesh with finite coordinates and triangles over its vertices
//! (its faces, or its edges as triangles `(a, b, b)`), optionally each in a
//! group. Output: every pair of triangles with no shared vertex id, not in
//! one group, whose closed bounding volumes meet, handed to a test, but
//! those of two fans or two strips that a plane sets apart (below).
//!
//! The broad phase of the self-intersection test: a bounding-volume
//! hierarchy over the triangles, in the Morton order of their centroids (a
//! heuristic: it shapes the tree, never the answer), with leaves of
//! [`LEAF`] triangles in a complete binary tree, tested against itself node
//! pair by node pair.
//!
//! A group is a set of triangles whose pairs need no test (a certified
//! patch, `patch.rs`). Its triangles are kept together in the order (at the
//! place of the group's first triangle), and a node that holds triangles of
//! one group only is tagged with it, so that two nodes of one group, or a
//! node of one group on its own, are not descended at all.
//!
//! A triangle's volume is its box and its extent along the six diagonals
//! `x +- y`, `x +- z`, `y +- z` (which sharpen the boxes of long faces lying
//! across the axes, like the radial faces of a flat ring), all as `f32`
//! bounds that hold the exact ones ([`down32`], [`up32`]), so two faces that
//! touch have volumes that touch (closed bounds: touching counts). A leaf
//! holds its triangles' boxes and vertex ids as columns, so that one
//! triangle is compared with a whole leaf in a few vector instructions;
//! the diagonal extents are computed only for the pairs that pass (on a
//! smooth surface, almost every pair of boxes that meet belongs to faces
//! sharing a vertex, which are tested elsewhere).
//! Coordinates beyond the `f32` range give infinite bounds, which only
//! makes volumes larger. All volumes are built in one frame per mesh
//! ([`VolumeFrame`]): moved and scaled exactly, and turned onto the mesh's
//! own axes when one plane dominates it off the axes (`turn.rs`).
//!
//! A node also keeps the union of its triangles' diagonal extents and its
//! *hub*, a vertex id all its triangles have, if any. Two nodes apart along
//! a diagonal, or with one hub, hold no pair to test, and are not
//! descended: the pairs tested are the same, but fans (the faces around a
//! cone's apex, which all share it, and those of its base, apart from the
//! cone's along the diagonals) no longer make the search quadratic, as
//! their boxes alone, which all hold the axis, would. Two nodes whose hubs
//! are two vertices (one each, or two that every triangle of a node has
//! one of, as where the Morton order mixes the two caps of a thin disc)
//! are not descended either when a plane through both hubs has every
//! other vertex of one strictly on one side and of the other strictly on
//! the other ([`Bvh::fans_apart`], exact signs): then no triangle of one
//! meets one of the other but at a vertex both have, and the side and
//! base of a cone, or the caps of a disc, turned away from the axes, which
//! the diagonals cannot set apart, are not compared face by face. Nor are
//! two *strips*, nodes whose triangles reach across them (the sides of a
//! tall cylinder turned away from the axes, every face from end to end,
//! whose boxes and diagonal extents all meet), when a plane along them
//! sets them apart ([`Bvh::strips_apart`]).
//!
//! The parts: where the volumes are built (`frame.rs`), the volumes
//! themselves (`volumes.rs`), the order of the triangles (`order.rs`),
//! and the planes that set two fans or two strips apart (`apart.rs`).

mod apart;
mod frame;
mod order;
#[cfg(test)]
mod tests;
mod volumes;

use super::{Found, Stop};
use crate::ids::{FaceId, VertexId};
use crate::mesh::Mesh;
use apart::Hubs;
use frame::{down32, up32, VolumeFrame};
use order::{grouped_order, morton_order, spread};
use rayon::prelude::*;
use volumes::{max3, min3, Bounds, Leaf, Slabs};

/// The group of a triangle in no group.
pub(super) const NO_GROUP: u32 = u32::MAX;

/// The hub of a node whose triangles share no vertex id.
const NO_HUB: u32 = u32::MAX;

/// Faces per leaf (fewer than 32: a leaf's slots are the bits of a `u32`).
const LEAF: usize = 8;
const _: () = assert!(LEAF < 32);

/// Heights (a node there holds `2^height` leaves) at and above which the
/// halves of a node are tested on separate rayon tasks.
const PAR_HEIGHT: u32 = 9;

/// The hierarchy: a complete binary tree in heap order (node `n` has
/// children `2 n` and `2 n + 1`, the root is 1), whose `2^height` leaves
/// (nodes `2^height ..`) hold [`LEAF`] triangles each in Morton order
/// (empty leaves at the end have empty boxes).
pub(super) struct Bvh<'m> {
    mesh: &'m Mesh,
    frame: VolumeFrame,
    /// The triangles, in leaves.
    leaves: Vec<Leaf>,
    /// How many triangles there are.
    len: usize,
    nodes: Vec<Bounds>,
    /// Per node, its triangles' diagonal extents ([`Slabs::around`]): two
    /// nodes whose extents are apart along one diagonal hold no pair of
    /// faces that meet, so they are not descended.
    slabs: Vec<Slabs>,
    /// Per leaf, the sum of its triangles' corners (rounded, for the
    /// heuristics of [`Bvh::fans_apart`] and [`Bvh::strips_apart`] only).
    corner_sums: Vec<[f64; 3]>,
    /// Per node, the group all its triangles are in, or [`NO_GROUP`].
    tags: Vec<u32>,
    /// Per node, its [`Hubs`].
    hubs: Vec<Hubs>,
    /// Per node, whether it is a strip: its box is not flat (no side below
    /// `2^-10` of the longest: walls meeting at a corner are not strips)
    /// and every triangle's box has a side of at least three quarters of
    /// the longest (not so a node of CAD faces with one sliver across it)
    /// ([`Bvh::strips_apart`]).
    strips: Vec<bool>,
    height: u32,
    parallel: bool,
}

impl<'m> Bvh<'m> {
    /// Builds the tree over `tris` (coordinates finite, indices in range),
    /// `groups[t]` the group of triangle `t` (`None`: no groups).
    pub(super) fn build(
        mesh: &'m Mesh,
        tris: &[[VertexId; 3]],
        groups: Option<&[u32]>,
        parallel: bool,
    ) -> Bvh<'m> {
        let min_len = if parallel {
            crate::par::MIN_LEN
        } else {
            usize::MAX
        };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        // Coordinates moved and scaled so that `f32` bounds stay apart,
        // and turned when a plane dominates off the axes (see
        // `VolumeFrame`): faces that meet have volumes that meet.
        let frame = VolumeFrame::of(mesh, tris, lo, hi);
        let [lo, hi] = match frame.turn {
            None => frame.place_all([lo, hi]),
            // The turned box of the points (for the Morton codes only).
            Some(_) => mesh.positions.iter().fold(
                [lo.map(|_| f64::INFINITY), hi.map(|_| f64::NEG_INFINITY)],
                |[lo, hi], &p| {
                    let p = frame.place_all([p])[0];
                    [
                        std::array::from_fn(|k| lo[k].min(p[k])),
                        std::array::from_fn(|k| hi[k].max(p[k])),
                    ]
                },
            ),
        };
        let e = frame.margin;
        let scale: [f64; 3] = std::array::from_fn(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 {
                1023.0 / w
            } else {
                0.0
            }
        });
        // Each triangle's box, and the Morton code of its centroid's cell
        // (a heuristic that shapes the tree only; the casts saturate), in
        // input order: one pass over the triangles as they are stored.
        let (boxes, codes): (Vec<Bounds>, Vec<u32>) = tris
            .par_iter()
            .with_min_len(min_len)
            .map(|tri| {
                let p = frame.place_all(tri.map(|v| mesh.pos(v)));
                let mut code = 0u32;
                for k in 0..3 {
                    let m = (p[0][k] + p[1][k] + p[2][k]) * (1.0 / 3.0);
                    code |= spread(((m - lo[k]) * scale[k]) as u32) << k;
                }
                let b = Bounds {
                    lo: std::array::from_fn(|k| down32(min3(p[0][k], p[1][k], p[2][k]), e)),
                    hi: std::array::from_fn(|k| up32(max3(p[0][k], p[1][k], p[2][k]), e)),
                };
                (b, code)
            })
            .unzip();
        let order = match groups {
            None => morton_order(&codes),
            Some(g) => grouped_order(&codes, g),
        };
        drop(codes);
        let group = |t: usize| groups.map_or(NO_GROUP, |g| g[t]);
        let n_leaves = order.len().div_ceil(LEAF).max(1);
        let height = n_leaves.next_power_of_two().trailing_zeros();
        let first = 1usize << height;
        let mut leaves = vec![Leaf::EMPTY; n_leaves];
        let mut slabs = vec![Slabs::EMPTY; 2 * first];
        let mut corner_sums = vec![[0.0; 3]; n_leaves];
        leaves
            .par_iter_mut()
            .zip(&mut slabs[first..first + n_leaves])
            .zip(&mut corner_sums)
            .with_min_len(min_len / LEAF)
            .zip(order.par_chunks(LEAF))
            .for_each(|(((leaf, d), sum), ts)| {
                for (s, &t) in ts.iter().enumerate() {
                    let b = &boxes[t as usize];
                    for (k, v) in tris[t as usize].iter().enumerate() {
                        leaf.lo[k][s] = b.lo[k];
                        leaf.hi[k][s] = b.hi[k];
                        leaf.v[k][s] = v.0;
                    }
                    leaf.group[s] = group(t as usize);
                    leaf.face[s] = t;
                }
                let corners = || {
                    ts.iter()
                        .flat_map(|&t| tris[t as usize].map(|v| mesh.pos(v)))
                };
                *d = Slabs::around(corners().map(|p| frame.place_all([p])[0]), e);
                *sum = corners().fold([0.0; 3], |s, p| std::array::from_fn(|c| s[c] + p[c]));
            });
        drop(boxes);
        // How many triangles have each vertex (saturating): which hubs a
        // leaf is given when several pairs would do (a heuristic).
        let mut valence = vec![0u16; mesh.positions.len()];
        for v in tris.iter().flatten() {
            valence[v.idx()] = valence[v.idx()].saturating_add(1);
        }
        let mut nodes = vec![Bounds::EMPTY; 2 * first];
        let mut tags = vec![NO_GROUP; 2 * first];
        let mut hubs = vec![Hubs::NONE; 2 * first];
        // Per node, the shortest of its triangles' boxes' longest sides.
        let mut reach = vec![f32::INFINITY; 2 * first];
        nodes[first..first + n_leaves]
            .par_iter_mut()
            .zip(&mut tags[first..first + n_leaves])
            .zip(&mut hubs[first..first + n_leaves])
            .zip(&mut reach[first..first + n_leaves])
            .with_min_len(min_len / LEAF)
            .zip(leaves.par_iter().zip(order.par_chunks(LEAF)))
            .for_each(|((((n, tag), hub), reach), (leaf, ts))| {
                *n = (0..ts.len()).fold(Bounds::EMPTY, |b, s| b.union(&leaf.bounds(s)));
                *reach =
                    (0..ts.len()).fold(f32::INFINITY, |r, s| r.min(leaf.bounds(s).longest_side()));
                if leaf.group[..ts.len()].iter().all(|&g| g == leaf.group[0]) {
                    *tag = leaf.group[0];
                }
                *hub = Hubs::of_leaf(leaf, ts.len(), &valence);
            });
        for n in (1..first).rev() {
            nodes[n] = nodes[2 * n].union(&nodes[2 * n + 1]);
            slabs[n] = slabs[2 * n].union(&slabs[2 * n + 1]);
            if tags[2 * n] == tags[2 * n + 1] {
                tags[n] = tags[2 * n];
            }
            hubs[n] = hubs[2 * n].union(hubs[2 * n + 1]);
            reach[n] = reach[2 * n].min(reach[2 * n + 1]);
        }
        let strips = nodes
            .iter()
            .zip(&reach)
            .map(|(b, &r)| {
                let longest = b.longest_side();
                4.0 * r >= 3.0 * longest && (0..3).all(|k| 1024.0 * (b.hi[k] - b.lo[k]) >= longest)
            })
            .collect();
        Bvh {
            mesh,
            frame,
            leaves,
            len: order.len(),
            nodes,
            slabs,
            corner_sums,
            tags,
            hubs,
            strips,
            height,
            parallel,
        }
    }

    /// Whether the volumes are built in a turned frame.
    #[cfg(test)]
    pub(super) fn is_turned(&self) -> bool {
        self.frame.turn.is_some()
    }

    /// Calls `test` on every pair of triangles (each named by its position
    /// in the input, as a [`FaceId`]) with no shared vertex id, not in one
    /// group, whose volumes meet, but the pairs of fans and strips set
    /// apart ([`Bvh::fans_apart`], [`Bvh::strips_apart`]), and collects
    /// the pairs it accepts, each counted on `stop`; once `stop` is
    /// reached, stops early (the pairs collected are then some of them).
    #[inline(never)]
    pub(super) fn pairs<T>(&self, test: &T, keep: usize, stop: &Stop) -> Found
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        let mut found = Found::new(keep);
        self.within(1, self.height, &Search { test, stop }, &mut found);
        found
    }

    /// Where each triangle is: its leaf and slot, by its position in the
    /// input.
    pub(super) fn places(&self) -> Vec<(usize, usize)> {
        let mut place = vec![(0, 0); self.len];
        for (i, leaf) in self.leaves.iter().enumerate() {
            for s in 0..self.filled(i) {
                place[leaf.face[s] as usize] = (i, s);
            }
        }
        place
    }

    /// Adds to `out` the triangles after `a` in the input that
    /// [`Bvh::pairs`] would hand its test with `a` (found by descending
    /// the tree), and those it skips as fans or strips set apart (no plane
    /// is tried here; such pairs do not meet), in no particular order;
    /// `place` is [`Bvh::places`].
    pub(super) fn later_partners(&self, place: &[(usize, usize)], a: FaceId, out: &mut Vec<u32>) {
        let (i, s) = place[a.idx()];
        let leaf = &self.leaves[i];
        let probe = Probe {
            bounds: leaf.bounds(s),
            slabs: self.slabs(leaf, s),
            v: [0, 1, 2].map(|k| leaf.v[k][s]),
            group: leaf.group[s],
            face: leaf.face[s],
        };
        self.later_in_node(1, self.height, &probe, out);
    }

    /// [`Bvh::later_partners`] of the triangle `probe`, in node `n` of
    /// height `h`.
    fn later_in_node(&self, n: usize, h: u32, probe: &Probe, out: &mut Vec<u32>) {
        if !self.nodes[n].meets(&probe.bounds)
            || !self.slabs[n].meets(&probe.slabs)
            || (probe.group != NO_GROUP && self.tags[n] == probe.group)
            || probe.v.contains(&self.hubs[n].one())
        {
            return;
        }
        if h > 0 {
            self.later_in_node(2 * n, h - 1, probe, out);
            self.later_in_node(2 * n + 1, h - 1, probe, out);
            return;
        }
        let i = n - (1 << self.height);
        let Some(other) = self.leaves.get(i) else {
            return;
        };
        let mut mask =
            other.candidates(&probe.bounds, probe.v, probe.group) & Self::slots(self.filled(i));
        while mask != 0 {
            let t = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if other.face[t] > probe.face && probe.slabs.meets(&self.slabs(other, t)) {
                out.push(other.face[t]);
            }
        }
    }

    /// How many slots of leaf `i` hold a triangle (none for a padding
    /// leaf of the complete tree).
    #[inline]
    fn filled(&self, i: usize) -> usize {
        self.len.saturating_sub(i * LEAF).min(LEAF)
    }

    /// The bits of the first `n` slots of a leaf.
    #[inline]
    fn slots(n: usize) -> u32 {
        (1u32 << n) - 1
    }

    #[inline]
    fn par(&self, h: u32) -> bool {
        self.parallel && h >= PAR_HEIGHT
    }

    /// Pairs within node `n` of height `h`.
    fn within<T>(&self, n: usize, h: u32, search: &Search<T>, found: &mut Found)
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        if self.tags[n] != NO_GROUP || self.hubs[n].one() != NO_HUB || search.stop.reached() {
            return;
        }
        if h == 0 {
            let i = n - (1 << self.height);
            let Some(leaf) = self.leaves.get(i) else {
                return;
            };
            let n = self.filled(i);
            for s in 0..n {
                let later = !0u32 << (s + 1) & Self::slots(n);
                let v = [0, 1, 2].map(|k| leaf.v[k][s]);
                let mask = leaf.candidates(&leaf.bounds(s), v, leaf.group[s]) & later;
                self.visit(leaf, s, leaf, mask, search, found);
            }
            return;
        }
        let (a, b) = (2 * n, 2 * n + 1);
        if self.par(h) {
            let keep = found.keep;
            let (mut x, mut y, mut z) = (Found::new(keep), Found::new(keep), Found::new(keep));
            rayon::join(
                || self.within(a, h - 1, search, &mut x),
                || {
                    rayon::join(
                        || self.within(b, h - 1, search, &mut y),
                        || self.across(a, b, h - 1, search, &mut z),
                    )
                },
            );
            found.absorb(x);
            found.absorb(y);
            found.absorb(z);
        } else {
            self.within(a, h - 1, search, found);
            self.within(b, h - 1, search, found);
            self.across(a, b, h - 1, search, found);
        }
    }

    /// Pairs with one face in node `i` and one in node `j`, both of height
    /// `h`.
    fn across<T>(&self, i: usize, j: usize, h: u32, search: &Search<T>, found: &mut Found)
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        let (bi, bj) = (&self.nodes[i], &self.nodes[j]);
        if !bi.meets(bj)
            || (self.tags[i] != NO_GROUP && self.tags[i] == self.tags[j])
            || (self.hubs[i].one() != NO_HUB && self.hubs[i].one() == self.hubs[j].one())
            || !self.slabs[i].meets(&self.slabs[j])
            || search.stop.reached()
            || (h > 0 && (self.fans_apart(i, j, h) || self.strips_apart(i, j, h)))
        {
            return;
        }
        if h == 0 {
            let first = 1 << self.height;
            return self.leaf_pair(i - first, j - first, [bi, bj], search, found);
        }
        let (i0, i1, j0, j1) = (2 * i, 2 * i + 1, 2 * j, 2 * j + 1);
        if self.par(h) {
            let keep = found.keep;
            let mut parts = [(); 4].map(|_| Found::new(keep));
            let [p0, p1, p2, p3] = &mut parts;
            rayon::join(
                || {
                    rayon::join(
                        || self.across(i0, j0, h - 1, search, p0),
                        || self.across(i0, j1, h - 1, search, p1),
                    )
                },
                || {
                    rayon::join(
                        || self.across(i1, j0, h - 1, search, p2),
                        || self.across(i1, j1, h - 1, search, p3),
                    )
                },
            );
            for p in parts {
                found.absorb(p);
            }
        } else {
            self.across(i0, j0, h - 1, search, found);
            self.across(i0, j1, h - 1, search, found);
            self.across(i1, j0, h - 1, search, found);
            self.across(i1, j1, h - 1, search, found);
        }
    }

    /// The pairs with one face in leaf `i` (of box `bi`) and one in leaf
    /// `j` (of box `bj`): the faces of each that meet the other's box
    /// (two vector tests; most leaf pairs end here), then each such face
    /// of `i` against those of `j` at once.
    #[inline(always)]
    fn leaf_pair<T>(
        &self,
        i: usize,
        j: usize,
        [bi, bj]: [&Bounds; 2],
        search: &Search<T>,
        found: &mut Found,
    ) where
        T: Fn(FaceId, FaceId) -> bool,
    {
        #[cfg(test)]
        tests::LEAF_PAIRS.with(|c| c.set(c.get() + 1));
        let (Some(li), Some(lj)) = (self.leaves.get(i), self.leaves.get(j)) else {
            return;
        };
        let in_j = lj.meeting(bi) & Self::slots(self.filled(j));
        if in_j == 0 {
            return;
        }
        let mut in_i = li.meeting(bj) & Self::slots(self.filled(i));
        while in_i != 0 {
            let s = in_i.trailing_zeros() as usize;
            in_i &= in_i - 1;
            let v = [0, 1, 2].map(|k| li.v[k][s]);
            let mask = lj.candidates(&li.bounds(s), v, li.group[s]) & in_j;
            self.visit(li, s, lj, mask, search, found);
        }
    }

    /// Tests the triangle in slot `s` of `a` against the triangles in the
    /// slots of `b` whose bits are set in `mask` (boxes that meet, no
    /// shared vertex id, not in one group) when their diagonal extents
    /// meet too.
    #[inline(always)]
    fn visit<T>(
        &self,
        a: &Leaf,
        s: usize,
        b: &Leaf,
        mut mask: u32,
        search: &Search<T>,
        found: &mut Found,
    ) where
        T: Fn(FaceId, FaceId) -> bool,
    {
        if mask == 0 {
            return;
        }
        let sa = self.slabs(a, s);
        while mask != 0 {
            let t = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if sa.meets(&self.slabs(b, t)) {
                let (fa, fb) = (FaceId(a.face[s]), FaceId(b.face[t]));
                if (search.test)(fa, fb) {
                    search.stop.count();
                    found.push(fa, fb);
                }
            }
        }
    }

    /// The diagonal extents of the triangle in slot `t` of `l`.
    #[inline(always)]
    fn slabs(&self, l: &Leaf, t: usize) -> Slabs {
        let v = [0, 1, 2].map(|k| l.v[k][t] as usize);
        Slabs::of(
            self.frame.place_all(v.map(|v| self.mesh.positions[v])),
            self.frame.margin,
        )
    }
}

/// A triangle whose later partners [`Bvh::later_partners`] looks for:
/// its volume, vertex ids, group and position in the input, read once.
struct Probe {
    bounds: Bounds,
    slabs: Slabs,
    v: [u32; 3],
    group: u32,
    face: u32,
}

/// One search of [`Bvh::pairs`]: its test, and the count it stops at.
struct Search<'t, T> {
    test: &'t T,
    stop: &'t Stop,
}
