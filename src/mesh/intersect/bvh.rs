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

use super::turn::Turn;
use super::{Found, Stop};
use crate::exact::orient_filter::orient3d_filter;
use crate::exact::predicates::{orient3d, Sign};
use crate::exact::rational::decompose;
use crate::exact::scale::{leading_exponent, times_pow2};
use crate::ids::{FaceId, VertexId};
use crate::mesh::Mesh;
use rayon::prelude::*;

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

/// `2^-22` and `2^-140`: the margins of [`down32`] and [`up32`].
const REL: f64 = 1.0 / 4_194_304.0;
const ABS: f64 = 7.174648137343064e-43;

/// The dot product (rounded; for heuristics).
pub(super) fn dot(u: [f64; 3], v: [f64; 3]) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// The cross product (rounded; for heuristics).
pub(super) fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|c| {
        let (k, l) = ((c + 1) % 3, (c + 2) % 3);
        u[k] * v[l] - u[l] * v[k]
    })
}

/// An `f32` not above any value within `e` of `x` (`x` may be infinite,
/// not NaN; `e >= 0` finite).
///
/// `m = (|x| + e) 2^-22 + 2^-140 + e` is subtracted in `f64` and the
/// result rounded to the nearest `f32`: computing `m` and subtracting it
/// err by at most `2^-52 (|x| + m)`, the conversion by at most
/// `2^-24 |z| + 2^-150` (`z` its input, `2^-150` half the smallest
/// subnormal `f32`), together less than `2^-23 (|x| + m) + 2^-150`, which
/// is below `m - e = (|x| + e) 2^-22 + 2^-140` (as `|x| + m` is below
/// `(|x| + e)(1 + 2^-21) + 2^-139`). Beyond the `f32` range the
/// conversion gives an infinity (and `x = inf` a NaN), which `min` turns
/// into `f32::MAX`, below such an `x`; `-inf` stays. With `e = 0` (every
/// frame but a turned one) this is `x - (|x| 2^-22 + 2^-140)`, as it
/// always was.
#[inline]
fn down32(x: f64, e: f64) -> f32 {
    ((x - ((x.abs() + e) * REL + ABS + e)) as f32).min(f32::MAX)
}

/// An `f32` not below any value within `e` of `x` (`x` may be infinite,
/// not NaN); see [`down32`].
#[inline]
fn up32(x: f64, e: f64) -> f32 {
    ((x + ((x.abs() + e) * REL + ABS + e)) as f32).max(f32::MIN)
}

#[inline]
fn min3(a: f64, b: f64, c: f64) -> f64 {
    let m = if b < a { b } else { a };
    if c < m {
        c
    } else {
        m
    }
}

#[inline]
fn max3(a: f64, b: f64, c: f64) -> f64 {
    let m = if b > a { b } else { a };
    if c > m {
        c
    } else {
        m
    }
}

/// The largest coordinate magnitudes (after the shift) at which
/// [`VolumeFrame`] does not scale: `2^-60` to `2^60`.
const UNSCALED: std::ops::RangeInclusive<i32> = -60..=60;

/// Where the volumes are built: each coordinate `x` of axis `k` as
/// `(x - shift[k]) 2^s`.
///
/// The shift is the axis' lowest coordinate when the axis' coordinates lie
/// farther from zero than they span and every difference from the lowest
/// is exact (the coordinates are multiples of `2^q` and span less than
/// `2^(q + 52)`), else zero; then `s` brings the largest magnitude to
/// `[1, 2)` when its leading exponent lies outside [`UNSCALED`], else
/// `s = 0`. Without them, a part far from the origin (at `1e9`, where an
/// `f32` is 64 apart) or a mesh near `1e-300` (every bound rounded to
/// `+-2^-140`) or `1e300` (every bound infinite) would have volumes that
/// all meet, and every pair of faces would be tested (quadratic time).
///
/// Which closed volumes meet is the same in every such frame: the shift
/// is an exact translation, and `times_pow2` is exact but where a product
/// underflows (a coordinate far below the largest one), then off by at
/// most `2^-1074`, far inside the `2^-140` margin of [`down32`] and
/// [`up32`]; the diagonal sums stay finite (every magnitude is below 4).
///
/// Then, when a plane dominates the mesh off the axes, the frame is also
/// *turned* ([`Turn`]): each coordinate becomes a rounded dot product
/// with a row of a rotation, and every bound is widened by `margin`, a
/// proven bound on that rounding (see [`VolumeFrame::of`]). Two faces
/// that meet have a common point, and so have their images under any
/// linear map: their turned volumes meet. Which volumes meet may change
/// (that is the point), which pairs the exact tests find does not.
#[derive(Clone, Copy, Debug)]
struct VolumeFrame {
    shift: [f64; 3],
    s: i32,
    turn: Option<Turn>,
    /// How far a turned coordinate, or the sum of two, may lie from the
    /// exact one (zero when not turned).
    margin: f64,
}

impl VolumeFrame {
    /// The frame of `mesh` (its triangles `tris`), whose coordinates lie
    /// in `lo ..= hi` per axis.
    fn of(mesh: &Mesh, tris: &[[VertexId; 3]], lo: [f64; 3], hi: [f64; 3]) -> VolumeFrame {
        let shift = std::array::from_fn(|k| {
            let span = hi[k] - lo[k];
            if !(lo[k] > span || -hi[k] > span) {
                // Near the origin (or empty): a shift would gain little.
                return 0.0;
            }
            let grid = mesh
                .positions
                .iter()
                .filter_map(|p| decompose(p[k]))
                .map(|(_, e)| e)
                .min();
            match grid {
                Some(q) if q <= 1023 - 52 && span < pow2_any(q + 52) => lo[k],
                _ => 0.0,
            }
        });
        let top = (0..3)
            .flat_map(|k| [lo[k] - shift[k], hi[k] - shift[k]])
            .filter(|x| x.is_finite())
            .map(f64::abs)
            .fold(0.0, f64::max);
        let s = match leading_exponent(top) {
            Some(e) if !UNSCALED.contains(&e) => -e,
            _ => 0,
        };
        let mut frame = VolumeFrame {
            shift,
            s,
            turn: None,
            margin: 0.0,
        };
        let placed = |v: usize| frame.place_all([mesh.positions[v]])[0];
        let turn = if turning() {
            Turn::of(tris, placed)
        } else {
            None
        };
        if let Some(turn) = turn {
            // Every placed coordinate is at most `q = top 2^s` in
            // magnitude. A turned one, the dot product `(r0 x0 + r1 x1) +
            // r2 x2` in doubles, lies within `3u / (1 - 3u) < 2^-51` of
            // `|r0 x0| + |r1 x1| + |r2 x2| <= row_norm q` of the exact value
            // (the inner-product bound, Higham, "Accuracy and Stability of
            // Numerical Algorithms", 3.1), plus `2^-1075` for each of the
            // three products that underflows: within `turn_error`, twice
            // that bound (its own rounding is a relative `2^-51` at most).
            // The sum of two turned coordinates is within twice that.
            frame.margin = 2.0 * turn_error(&turn, times_pow2(top, s));
            frame.turn = Some(turn);
        }
        frame
    }

    /// Points in this frame (a triangle's corners, read before any
    /// arithmetic so that their loads overlap; as they are in the frame of
    /// most meshes, which neither shifts nor scales).
    #[inline(always)]
    fn place_all<const N: usize>(&self, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        if let Some(t) = &self.turn {
            self.turned(t, ps)
        } else if self.shift == [0.0; 3] && self.s == 0 {
            ps
        } else {
            self.moved(ps)
        }
    }

    /// Points shifted and scaled (not turned).
    #[inline(always)]
    fn moved<const N: usize>(&self, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        ps.map(|p| std::array::from_fn(|k| times_pow2(p[k] - self.shift[k], self.s)))
    }

    /// Points shifted, scaled and turned by `t` (kept out of line: most
    /// meshes are not turned).
    #[inline(never)]
    fn turned<const N: usize>(&self, t: &Turn, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        self.moved(ps).map(|p| t.apply(p))
    }
}

#[cfg(test)]
std::thread_local! {
    /// Whether frames may be turned: always, but in the tests of this
    /// module that count or compare volumes along the axes.
    static TURNING: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Whether frames may be turned (always, but where a test of this module
/// has switched it off: `TURNING`).
fn turning() -> bool {
    #[cfg(test)]
    return TURNING.with(|t| t.get());
    #[cfg(not(test))]
    true
}

/// A bound on how far `turn.apply(x)` lies from the exact dot products
/// for any point `x` whose coordinates are at most `q` in magnitude (see
/// [`VolumeFrame::of`]).
fn turn_error(turn: &Turn, q: f64) -> f64 {
    turn.row_norm() * q * pow2_any(-50) + pow2_any(-1000)
}

/// `2^k` for any `k` up to 1023 (zero below the subnormals).
fn pow2_any(k: i32) -> f64 {
    times_pow2(1.0, k.max(-1100))
}

/// A closed box, its bounds holding the exact ones.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    /// Whether the closed boxes meet (all six comparisons, without
    /// branches: the answer is rarely predictable).
    #[inline]
    fn meets(&self, o: &Bounds) -> bool {
        (self.lo[0] <= o.hi[0])
            & (o.lo[0] <= self.hi[0])
            & (self.lo[1] <= o.hi[1])
            & (o.lo[1] <= self.hi[1])
            & (self.lo[2] <= o.hi[2])
            & (o.lo[2] <= self.hi[2])
    }

    /// The longest of the box's sides (rounded).
    fn longest_side(&self) -> f32 {
        (0..3).fold(0f32, |m, k| m.max(self.hi[k] - self.lo[k]))
    }

    /// Whether on two axes or three the boxes overlap over at least half
    /// the smaller side (a heuristic: when two strips' boxes do, a plane
    /// between them is worth trying).
    fn overlaps_deeply(&self, o: &Bounds) -> bool {
        (0..3)
            .filter(|&k| {
                let least = (self.hi[k] - self.lo[k]).min(o.hi[k] - o.lo[k]);
                self.hi[k].min(o.hi[k]) - self.lo[k].max(o.lo[k]) >= 0.5 * least
            })
            .count()
            >= 2
    }

    #[inline]
    fn union(&self, o: &Bounds) -> Bounds {
        let mut b = *self;
        for k in 0..3 {
            b.lo[k] = b.lo[k].min(o.lo[k]);
            b.hi[k] = b.hi[k].max(o.hi[k]);
        }
        b
    }
}

/// [`LEAF`] triangles of the tree as columns, so that one triangle is
/// tested against all of a leaf at once: their boxes, vertex ids, groups
/// and positions in the input. A slot past the last triangle (in the last
/// leaf only) has an empty box, and is masked out before any test.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Leaf {
    lo: [[f32; LEAF]; 3],
    hi: [[f32; LEAF]; 3],
    v: [[u32; LEAF]; 3],
    group: [u32; LEAF],
    face: [u32; LEAF],
}

impl Leaf {
    const EMPTY: Leaf = Leaf {
        lo: [[f32::INFINITY; LEAF]; 3],
        hi: [[f32::NEG_INFINITY; LEAF]; 3],
        v: [[u32::MAX; LEAF]; 3],
        group: [NO_GROUP; LEAF],
        face: [u32::MAX; LEAF],
    };

    /// The box of slot `s`.
    #[inline(always)]
    fn bounds(&self, s: usize) -> Bounds {
        Bounds {
            lo: std::array::from_fn(|k| self.lo[k][s]),
            hi: std::array::from_fn(|k| self.hi[k][s]),
        }
    }

    /// Whether the box of slot `t` meets `b` (six comparisons, no branch).
    #[inline(always)]
    fn slot_meets(&self, t: usize, b: &Bounds) -> bool {
        (b.lo[0] <= self.hi[0][t])
            & (self.lo[0][t] <= b.hi[0])
            & (b.lo[1] <= self.hi[1][t])
            & (self.lo[1][t] <= b.hi[1])
            & (b.lo[2] <= self.hi[2][t])
            & (self.lo[2][t] <= b.hi[2])
    }

    /// Bit `t` set for each slot `t` whose box meets `b` (vector
    /// comparisons, as in [`Leaf::candidates`]).
    #[inline(always)]
    fn meeting(&self, b: &Bounds) -> u32 {
        (0..LEAF).fold(0, |mask, t| mask | u32::from(self.slot_meets(t, b)) << t)
    }

    /// Bit `t` set for each slot `t` whose box meets `b`, that shares no
    /// vertex id with `v` and is in another group than `group` (or either
    /// is in none). Written lane by lane, without branches, so that the
    /// compiler turns it into a few vector comparisons.
    #[inline(always)]
    fn candidates(&self, b: &Bounds, v: [u32; 3], group: u32) -> u32 {
        let mut mask = 0u32;
        for t in 0..LEAF {
            let meets = self.slot_meets(t, b);
            let shares = (0..3).fold(false, |acc, k| {
                acc | (self.v[k][t] == v[0]) | (self.v[k][t] == v[1]) | (self.v[k][t] == v[2])
            });
            let grouped = (group != NO_GROUP) & (self.group[t] == group);
            mask |= u32::from(meets & !shares & !grouped) << t;
        }
        mask
    }
}

/// A face's extent along the diagonals `x + y`, `x - y`, `x + z`, `x - z`,
/// `y + z`, `y - z` (lows, then highs): each sum is computed in `f64`
/// (relative error at most `2^-53`, or an infinity beyond the range, far
/// inside the margin of [`down32`] and [`up32`]), so the bounds hold the
/// exact extent, and two faces whose extents along one diagonal are apart
/// do not meet. Kept per node (the union of its faces'), and computed for
/// a pair of faces only when their boxes meet (few pairs beside the faces
/// sharing a vertex, which are not tested here).
#[derive(Clone, Copy, Debug)]
struct Slabs {
    lo: [f32; 6],
    hi: [f32; 6],
}

impl Slabs {
    const EMPTY: Slabs = Slabs {
        lo: [f32::INFINITY; 6],
        hi: [f32::NEG_INFINITY; 6],
    };

    /// The diagonal coordinates of `q`, each rounded once.
    #[inline(always)]
    fn diagonals(q: [f64; 3]) -> [f64; 6] {
        [
            q[0] + q[1],
            q[0] - q[1],
            q[0] + q[2],
            q[0] - q[2],
            q[1] + q[2],
            q[1] - q[2],
        ]
    }

    /// The extents of the triangle `p`, whose coordinates are each
    /// within `e / 2` of the exact ones (so the sums within `e`).
    fn of(p: [[f64; 3]; 3], e: f64) -> Slabs {
        let [d0, d1, d2] = p.map(Slabs::diagonals);
        Slabs {
            lo: std::array::from_fn(|k| down32(min3(d0[k], d1[k], d2[k]), e)),
            hi: std::array::from_fn(|k| up32(max3(d0[k], d1[k], d2[k]), e)),
        }
    }

    /// The extents of the triangles with corners `ps` (at least one
    /// point): the lowest and highest rounded sums, widened once, which
    /// hold the exact extents as [`Slabs::of`] does (and are the union of
    /// the triangles' [`Slabs::of`] but where a widening near `2^-140`
    /// rounds differently, which would only skip pairs that do not meet).
    fn around(ps: impl Iterator<Item = [f64; 3]>, e: f64) -> Slabs {
        let (lo, hi) = ps.map(Slabs::diagonals).fold(
            ([f64::INFINITY; 6], [f64::NEG_INFINITY; 6]),
            |(lo, hi), d| {
                (
                    std::array::from_fn(|k| if d[k] < lo[k] { d[k] } else { lo[k] }),
                    std::array::from_fn(|k| if d[k] > hi[k] { d[k] } else { hi[k] }),
                )
            },
        );
        Slabs {
            lo: lo.map(|x| down32(x, e)),
            hi: hi.map(|x| up32(x, e)),
        }
    }

    #[inline]
    fn meets(&self, o: &Slabs) -> bool {
        (0..6).all(|k| (self.lo[k] <= o.hi[k]) & (o.lo[k] <= self.hi[k]))
    }

    #[inline]
    fn union(&self, o: &Slabs) -> Slabs {
        Slabs {
            lo: std::array::from_fn(|k| self.lo[k].min(o.lo[k])),
            hi: std::array::from_fn(|k| self.hi[k].max(o.hi[k])),
        }
    }
}

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

/// Spreads the low 10 bits of `x` to every third bit.
fn spread(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | x << 16) & 0x030000ff;
    x = (x | x << 8) & 0x0300f00f;
    x = (x | x << 4) & 0x030c30c3;
    x = (x | x << 2) & 0x09249249;
    x
}

/// The positions `0..codes.len()` in ascending order of their codes, ties
/// by position (a stable least-significant-digit radix sort of `code << 32
/// | position`, four passes of 8 bits).
fn morton_order(codes: &[u32]) -> Vec<u32> {
    let mut keys: Vec<u64> = codes
        .iter()
        .enumerate()
        .map(|(t, &c)| u64::from(c) << 32 | t as u64)
        .collect();
    let mut other = vec![0u64; keys.len()];
    for pass in 0..4 {
        let shift = 32 + 8 * pass;
        let mut count = [0usize; 257];
        for &k in keys.iter() {
            count[((k >> shift) & 0xff) as usize + 1] += 1;
        }
        for d in 0..256 {
            count[d + 1] += count[d];
        }
        for &k in keys.iter() {
            let d = ((k >> shift) & 0xff) as usize;
            other[count[d]] = k;
            count[d] += 1;
        }
        std::mem::swap(&mut keys, &mut other);
    }
    keys.into_iter().map(|k| k as u32).collect()
}

/// The positions ordered as [`morton_order`], except that the triangles of
/// a group follow one another (in that order) at the place of the group's
/// first triangle in it. Groups are numbered from 0.
fn grouped_order(codes: &[u32], groups: &[u32]) -> Vec<u32> {
    let morton = morton_order(codes);
    // Each group's triangles in Morton order, by a counting sort.
    let n_groups = groups
        .iter()
        .filter(|&&g| g != NO_GROUP)
        .max()
        .map_or(0, |&g| g as usize + 1);
    let mut start = vec![0usize; n_groups + 1];
    for &g in groups.iter().filter(|&&g| g != NO_GROUP) {
        start[g as usize + 1] += 1;
    }
    for g in 0..n_groups {
        start[g + 1] += start[g];
    }
    let mut fill = start.clone();
    let mut by_group = vec![0u32; start[n_groups]];
    for &t in &morton {
        let g = groups[t as usize];
        if g != NO_GROUP {
            by_group[fill[g as usize]] = t;
            fill[g as usize] += 1;
        }
    }
    let mut placed = vec![false; n_groups];
    let mut order = Vec::with_capacity(morton.len());
    for &t in &morton {
        match groups[t as usize] {
            NO_GROUP => order.push(t),
            g if !placed[g as usize] => {
                placed[g as usize] = true;
                order.extend_from_slice(&by_group[start[g as usize]..start[g as usize + 1]]);
            }
            _ => {}
        }
    }
    order
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

    /// Whether nodes `i` and `j` of height `h` are fans whose hubs are two
    /// vertices at different points `a`, `b` (one hub each, or two for
    /// either, see [`Hubs`]), that a plane through both sets apart: every
    /// other vertex of `i` strictly on one side, every other vertex of `j`
    /// strictly on the other (exact signs, as in [`Bvh::apart_by`]). Then
    /// each triangle meets the plane only in its hub, and no triangle of
    /// one meets one of the other but at a hub they share. Two fans of one
    /// cone, its side and its base (whose faces, turned away from the
    /// axes, the boxes and diagonals cannot set apart), are so apart
    /// wherever their arcs of the ring do not meet; so are the two caps of
    /// a thin disc, each a fan, where the Morton order mixes them.
    ///
    /// The plane, and the order in which vertices are tried, are
    /// heuristics (from the leaves' corner sums, in floating point): they
    /// decide what is tried and how soon a failure shows, never the
    /// answer. The plane holds the line `ab` and is normal to the
    /// difference of the fans' centroids, less its part along `ab`; the
    /// leaves of each fan nearest the other's centroid are tried first
    /// (where fans whose arcs meet fail).
    fn fans_apart(&self, i: usize, j: usize, h: u32) -> bool {
        let (hi, hj) = (self.hubs[i], self.hubs[j]);
        let Some([ha, hb]) = hi.line_with(hj) else {
            return false;
        };
        let (a, b) = (
            self.mesh.positions[ha as usize],
            self.mesh.positions[hb as usize],
        );
        if a == b {
            return false;
        }
        let (li, lj) = (self.leaves_of(i, h), self.leaves_of(j, h));
        // The hubs' parts of the two centroids differ along `ab` only, which
        // the plane's normal leaves out.
        let (ci, cj) = (self.centroid(li.clone()), self.centroid(lj.clone()));
        let d: [f64; 3] = std::array::from_fn(|c| b[c] - a[c]);
        let w: [f64; 3] = std::array::from_fn(|c| ci[c] - cj[c]);
        let t = dot(w, d) / dot(d, d);
        // The third point `a + d x n`, `n` the part of `w` normal to `d`.
        let n: [f64; 3] = std::array::from_fn(|c| w[c] - t * d[c]);
        let dn = cross(d, n);
        let q: [f64; 3] = std::array::from_fn(|c| a[c] + dn[c]);
        let plane = Plane([a, b, q]);
        // The side of `i`'s rim: that of `ci - cj` seen from the plane.
        let Some(want) = plane.side_of(std::array::from_fn(|c| a[c] + n[c])) else {
            return false;
        };
        let (ni, nj) = (
            self.nearest_leaf(li.clone(), cj),
            self.nearest_leaf(lj.clone(), ci),
        );
        self.apart_by(
            &plane,
            Side {
                leaves: li,
                nearest: ni,
                hubs: hi,
                want,
            },
            Side {
                leaves: lj,
                nearest: nj,
                hubs: hj,
                want: want.flip(),
            },
        )
    }

    /// Whether nodes `i` and `j` of height `h`, two strips (see
    /// [`Bvh::strips`]) whose boxes overlap deeply, neither a fan with one
    /// hub (whose pairs [`Bvh::fans_apart`] tries), are set apart by the
    /// plane between their centroids that holds the longest edge of
    /// either's leaf nearest the other (exact signs, as in
    /// [`Bvh::apart_by`]). Long faces turned away from the axes, such as
    /// the sides of a tall cylinder (every face runs from end to end),
    /// have boxes and diagonal extents that all meet; two strips of such
    /// faces are set apart by a plane along them wherever they share no
    /// vertex. As in [`Bvh::fans_apart`], the plane and the order of the
    /// vertices are heuristics, never the answer.
    fn strips_apart(&self, i: usize, j: usize, h: u32) -> bool {
        let (bi, bj) = (&self.nodes[i], &self.nodes[j]);
        let fan = self.hubs[i].one() != NO_HUB || self.hubs[j].one() != NO_HUB;
        if fan || !(self.strips[i] && self.strips[j] && bi.overlaps_deeply(bj)) {
            return false;
        }
        let (li, lj) = (self.leaves_of(i, h), self.leaves_of(j, h));
        let (ci, cj) = (self.centroid(li.clone()), self.centroid(lj.clone()));
        let (ni, nj) = (
            self.nearest_leaf(li.clone(), cj),
            self.nearest_leaf(lj.clone(), ci),
        );
        let (ei, ej) = (self.longest_edge(ni), self.longest_edge(nj));
        let e = if dot(ei, ei) >= dot(ej, ej) { ei } else { ej };
        let d: [f64; 3] = std::array::from_fn(|c| cj[c] - ci[c]);
        // `n`: the part of `d` normal to `e`, the plane's normal.
        let t = dot(d, e) / dot(e, e);
        let n: [f64; 3] = std::array::from_fn(|c| d[c] - t * e[c]);
        let m: [f64; 3] = std::array::from_fn(|c| 0.5 * (ci[c] + cj[c]));
        let en = cross(e, n);
        let plane = Plane([
            m,
            std::array::from_fn(|c| m[c] + e[c]),
            std::array::from_fn(|c| m[c] + en[c]),
        ]);
        let Some(want) = plane.side_of(ci) else {
            return false;
        };
        self.apart_by(
            &plane,
            Side {
                leaves: li,
                nearest: ni,
                hubs: Hubs::NONE,
                want,
            },
            Side {
                leaves: lj,
                nearest: nj,
                hubs: Hubs::NONE,
                want: want.flip(),
            },
        )
    }

    /// Whether the vertices of each side are on its side of `plane` or on
    /// the plane, no triangle has two vertices on it, and a vertex of one
    /// side on it is at another point than every other vertex of the other
    /// side on it (exact signs; a side's hubs are on the plane, and not
    /// asked). Then the two sides' triangles lie in opposite closed
    /// half-spaces, each meets the plane in at most its one vertex there,
    /// and a triangle of one meets one of the other only at a vertex both
    /// have: never a pair to test. Each side's nearest leaf is tried first.
    fn apart_by(&self, plane: &Plane, a: Side, b: Side) -> bool {
        let mut on = [OnPlane::default(); 2];
        let sides = [&a, &b];
        let first = sides.map(|s| s.nearest..s.nearest + 1);
        let apart = first
            .iter()
            .zip(sides)
            .zip(&mut on)
            .all(|((l, s), on)| self.on_side(plane, l.clone(), s, on))
            && sides
                .iter()
                .zip(&mut on)
                .all(|(s, on)| self.on_side(plane, s.leaves.clone(), s, on));
        let pos = |v: &u32| self.mesh.positions[*v as usize];
        apart
            && on[0]
                .ids()
                .iter()
                .all(|u| on[1].ids().iter().all(|v| u == v || pos(u) != pos(v)))
    }

    /// Whether every vertex of the triangles in `leaves` is on `s.want`'s
    /// side of `plane` or on it, at most one of each triangle on it (each
    /// gathered in `on`, which has room for a few).
    fn on_side(
        &self,
        plane: &Plane,
        leaves: std::ops::Range<usize>,
        s: &Side,
        on: &mut OnPlane,
    ) -> bool {
        leaves.into_iter().all(|l| {
            let leaf = &self.leaves[l];
            (0..self.filled(l)).all(|t| {
                let mut at = NO_HUB;
                (0..3).all(|k| {
                    let v = leaf.v[k][t];
                    let sign = if s.hubs.has(v) {
                        Sign::Zero
                    } else {
                        plane.sign(self.mesh.positions[v as usize])
                    };
                    if sign != Sign::Zero {
                        return sign == s.want;
                    }
                    let first = at == NO_HUB || at == v;
                    at = v;
                    first && on.add(v)
                })
            })
        })
    }

    /// The leaves (filled) under node `n` of height `h`.
    fn leaves_of(&self, n: usize, h: u32) -> std::ops::Range<usize> {
        let first = (n << h) - (1 << self.height);
        first..(first + (1 << h)).min(self.leaves.len())
    }

    /// The leaf among `leaves` whose centroid is nearest `p` (approximate).
    fn nearest_leaf(&self, leaves: std::ops::Range<usize>, p: [f64; 3]) -> usize {
        let start = leaves.start;
        leaves
            .map(|l| {
                let k = 1.0 / (3 * self.filled(l).max(1)) as f64;
                let m: [f64; 3] = std::array::from_fn(|c| self.corner_sums[l][c] * k - p[c]);
                (l, dot(m, m))
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .map_or(start, |(l, _)| l)
    }

    /// The centroid of the corners of the triangles in `leaves`
    /// (approximate).
    fn centroid(&self, leaves: std::ops::Range<usize>) -> [f64; 3] {
        let (sum, faces) = self.corner_sum(leaves);
        sum.map(|x| x / (3 * faces.max(1)) as f64)
    }

    /// The sum of the corners of the triangles in `leaves` (rounded), and
    /// how many triangles there are.
    fn corner_sum(&self, leaves: std::ops::Range<usize>) -> ([f64; 3], usize) {
        let faces = leaves.clone().map(|l| self.filled(l)).sum();
        let sum = leaves.fold([0.0; 3], |s, l| {
            std::array::from_fn(|c| s[c] + self.corner_sums[l][c])
        });
        (sum, faces)
    }

    /// The longest edge (rounded difference of its ends) of the triangles
    /// in leaf `l`.
    fn longest_edge(&self, l: usize) -> [f64; 3] {
        let leaf = &self.leaves[l];
        let pos = |k: usize, t: usize| self.mesh.positions[leaf.v[k][t] as usize];
        (0..self.filled(l))
            .flat_map(|t| (0..3).map(move |k| (t, k)))
            .map(|(t, k)| {
                let (p, q) = (pos(k, t), pos((k + 1) % 3, t));
                std::array::from_fn(|c| q[c] - p[c])
            })
            .max_by(|x: &[f64; 3], y: &[f64; 3]| dot(*x, *x).total_cmp(&dot(*y, *y)))
            .unwrap_or([0.0; 3])
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

/// A plane through three points: which side of it a point lies on, exact.
struct Plane([[f64; 3]; 3]);

impl Plane {
    /// The exact sign of `orient3d` of the plane's points and `x`.
    fn sign(&self, x: [f64; 3]) -> Sign {
        let [a, b, c] = self.0;
        orient3d_filter(a, b, c, x).unwrap_or_else(|| orient3d(a, b, c, x))
    }

    /// The side of `x` when the plane's points are finite and `x` is off
    /// the plane.
    fn side_of(&self, x: [f64; 3]) -> Option<Sign> {
        let finite = self.0.iter().flatten().chain(&x).all(|v| v.is_finite());
        finite.then(|| self.sign(x)).filter(|&s| s != Sign::Zero)
    }
}

/// One of two nodes a plane may set apart: its leaves (the `nearest` to
/// the other node tried first), its hubs (on the plane), and the side its
/// vertices should be on.
struct Side {
    leaves: std::ops::Range<usize>,
    nearest: usize,
    hubs: Hubs,
    want: Sign,
}

/// The vertices of one node on a plane: a few ids, without repeats.
#[derive(Clone, Copy, Default, Debug)]
struct OnPlane {
    ids: [u32; 4],
    len: usize,
}

impl OnPlane {
    /// Adds `v` when it is new; false when there is no room for it.
    fn add(&mut self, v: u32) -> bool {
        if self.ids().contains(&v) {
            return true;
        }
        let room = self.len < self.ids.len();
        if room {
            self.ids[self.len] = v;
            self.len += 1;
        }
        room
    }

    fn ids(&self) -> &[u32] {
        &self.ids[..self.len]
    }
}

/// The hubs of a node: a vertex id every one of its triangles has (the
/// apex of a fan: no two of them, nor two of two nodes with this one hub,
/// are a pair to test), or two ids every triangle has one of (two fans
/// mixed in one node, as the halves of a thin disc's caps are in the
/// Morton order), or none ([`NO_HUB`] in the unused places). Read by
/// [`Bvh::fans_apart`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Hubs([u32; 2]);

impl Hubs {
    const NONE: Hubs = Hubs([NO_HUB; 2]);

    /// The hubs of the first `n` triangles of `leaf`: one when they have
    /// one, else two that every triangle has one of, when there are such:
    /// of those, the pair whose rarer vertex is in the most triangles of
    /// the mesh (`valence`), so that two leaves of the same two fans get
    /// the same hubs (a heuristic: any pair is true of the leaf).
    fn of_leaf(leaf: &Leaf, n: usize, valence: &[u16]) -> Hubs {
        if n == 0 {
            return Hubs::NONE;
        }
        let has = |s: usize, v: u32| (0..3).any(|k| leaf.v[k][s] == v);
        let mut two = (Hubs::NONE, 0);
        for k in 0..3 {
            let a = leaf.v[k][0];
            // The triangles before the first without `a` all have it.
            let Some(s) = (1..n).find(|&s| !has(s, a)) else {
                return Hubs([a, NO_HUB]);
            };
            for b in (0..3).map(|m| leaf.v[m][s]) {
                let rarer = valence[a as usize].min(valence[b as usize]);
                if rarer > two.1 && (s + 1..n).all(|t| has(t, a) || has(t, b)) {
                    two = (Hubs([a, b]), rarer);
                }
            }
        }
        two.0
    }

    /// The hubs of two nodes together: their ids when there are at most
    /// two, and every node has hubs.
    fn union(self, o: Hubs) -> Hubs {
        if self == Hubs::NONE || o == Hubs::NONE {
            return Hubs::NONE;
        }
        let mut out = self;
        for v in o.ids() {
            if !out.has(v) {
                if out.0[1] != NO_HUB {
                    return Hubs::NONE;
                }
                out.0[1] = v;
            }
        }
        out
    }

    /// The hub, when there is one only, else [`NO_HUB`].
    fn one(self) -> u32 {
        if self.0[1] == NO_HUB {
            self.0[0]
        } else {
            NO_HUB
        }
    }

    /// The two ids of the hubs of `self` and `o` together, when there are
    /// two (the line a plane through them holds).
    fn line_with(self, o: Hubs) -> Option<[u32; 2]> {
        let u = self.union(o);
        (u.0[1] != NO_HUB).then_some(u.0)
    }

    fn ids(self) -> impl Iterator<Item = u32> {
        self.0.into_iter().filter(|&v| v != NO_HUB)
    }

    fn has(self, v: u32) -> bool {
        v != NO_HUB && self.0.contains(&v)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::scale::times_pow2;
    use std::cell::Cell;
    use std::sync::Mutex;

    /// Doubles `m 2^e`, from the least subnormal to near the largest.
    fn double() -> impl proptest::strategy::Strategy<Value = f64> {
        use proptest::prelude::*;
        (-(1i64 << 53)..1 << 53, -1126i32..970).prop_map(|(m, e)| times_pow2(m as f64, e))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4096))]
        /// `down32(x, e)` is at most `x - e` and `up32(x, e)` at least
        /// `x + e`, exactly (in rationals), across the range.
        #[test]
        fn bounds_hold_every_value_within_the_margin(x in double(), e in double()) {
            use crate::exact::rational::rat_from_f64;
            let e = e.abs();
            let (lo, hi) = (down32(x, e), up32(x, e));
            let (x, e) = (rat_from_f64(x), rat_from_f64(e));
            if lo.is_finite() {
                proptest::prop_assert!(rat_from_f64(f64::from(lo)) <= &x - &e);
            }
            if hi.is_finite() {
                proptest::prop_assert!(rat_from_f64(f64::from(hi)) >= &x + &e);
            }
        }

        /// A turned coordinate lies within `turn_error` of the exact dot
        /// product (in rationals), for any rows and any point whose
        /// coordinates are at most `q` in magnitude, down to the
        /// subnormals.
        #[test]
        fn turned_coordinates_lie_within_the_turn_error(
            rows in proptest::array::uniform3(proptest::array::uniform3(-1.0f64..1.0)),
            ms in proptest::array::uniform3(-(1i64 << 53)..1 << 53),
            shifts in proptest::array::uniform3(0i32..120),
            top in -1000i32..200,
        ) {
            use crate::exact::rational::rat_from_f64;
            use num_traits::Signed;
            // Coordinates at most 2^top, some far below it.
            let x: [f64; 3] =
                std::array::from_fn(|k| times_pow2(ms[k] as f64, top - 53 - shifts[k]));
            let turn = Turn::from_rows(rows);
            let bound = rat_from_f64(turn_error(&turn, times_pow2(1.0, top)));
            for (row, got) in rows.iter().zip(turn.apply(x)) {
                let exact = (0..3).fold(crate::exact::rational::Rat::from_integer(0.into()), |s, k| {
                    s + rat_from_f64(row[k]) * rat_from_f64(x[k])
                });
                // The proven bound of `VolumeFrame::of` checked in
                // rationals (it widens the broad phase's volumes; no
                // decision compares with it).
                let off = rat_from_f64(got) - exact;
                proptest::prop_assert!(off.abs() <= bound, "{:?}", x);
            }
        }
    }

    thread_local! {
        /// Pairs of leaves compared on this thread (a search with
        /// `parallel` off runs on the calling thread).
        pub(super) static LEAF_PAIRS: Cell<usize> = const { Cell::new(0) };
    }

    /// The tree of `mesh` with its volumes along the axes (never turned):
    /// the tests here count and compare the volumes of that frame.
    fn unturned<'m>(mesh: &'m Mesh, groups: Option<&[u32]>) -> Bvh<'m> {
        TURNING.with(|t| t.set(false));
        let tree = Bvh::build(mesh, &mesh.faces, groups, false);
        TURNING.with(|t| t.set(true));
        tree
    }

    /// The pairs the tree hands to its test, sorted.
    fn candidates(mesh: &Mesh) -> Vec<(FaceId, FaceId)> {
        grouped_candidates(mesh, None)
    }

    /// [`candidates`] with the faces in groups.
    fn grouped_candidates(mesh: &Mesh, groups: Option<&[u32]>) -> Vec<(FaceId, FaceId)> {
        tested_by(&unturned(mesh, groups))
    }

    /// The pairs `tree` hands to its test, sorted.
    fn tested_by(tree: &Bvh<'_>) -> Vec<(FaceId, FaceId)> {
        let seen = Mutex::new(Vec::new());
        tree.pairs(
            &|a: FaceId, b: FaceId| {
                seen.lock().unwrap().push((a.min(b), a.max(b)));
                false
            },
            0,
            &Stop::never(),
        );
        let mut seen = seen.into_inner().unwrap();
        seen.sort_unstable();
        seen
    }

    /// Every pair of faces with no shared vertex id, not in one group,
    /// whose boxes and diagonal extents meet, each face's volume computed
    /// on its own (`mesh` in the frame that neither shifts nor scales).
    fn all_meeting(mesh: &Mesh, groups: Option<&[u32]>) -> Vec<(FaceId, FaceId)> {
        let volume = |f: &[VertexId; 3]| {
            let p = f.map(|v| mesh.pos(v));
            let b = Bounds {
                lo: std::array::from_fn(|k| down32(min3(p[0][k], p[1][k], p[2][k]), 0.0)),
                hi: std::array::from_fn(|k| up32(max3(p[0][k], p[1][k], p[2][k]), 0.0)),
            };
            (b, Slabs::of(p, 0.0))
        };
        let volumes: Vec<_> = mesh.faces.iter().map(volume).collect();
        let group = |t: usize| groups.map_or(NO_GROUP, |g| g[t]);
        let mut out = Vec::new();
        for a in 0..mesh.faces.len() {
            for b in a + 1..mesh.faces.len() {
                let shares = mesh.faces[a].iter().any(|v| mesh.faces[b].contains(v));
                let grouped = group(a) != NO_GROUP && group(a) == group(b);
                let ((ba, sa), (bb, sb)) = (&volumes[a], &volumes[b]);
                if !shares && !grouped && ba.meets(bb) && sa.meets(sb) {
                    out.push((FaceId::from_idx(a), FaceId::from_idx(b)));
                }
            }
        }
        out
    }

    /// A cone over a regular `n`-gon in the plane `z = 0`, its base a fan
    /// around the centre: `n` faces around the apex, then `n` around the
    /// centre. Its coordinates are cosines and sines (no grid).
    fn capped_cone(n: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for i in 0..n {
            let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
            mesh.positions.push([a.cos(), a.sin(), 0.0]);
        }
        mesh.positions.push([0.0, 0.0, 1.0]);
        mesh.positions.push([0.0, 0.0, 0.0]);
        let ring = |i: u32| VertexId(i % n);
        mesh.faces
            .extend((0..n).map(|i| [ring(i), ring(i + 1), VertexId(n)]));
        mesh.faces
            .extend((0..n).map(|i| [ring(i + 1), ring(i), VertexId(n + 1)]));
        mesh
    }

    /// The tree hands its test exactly the pairs whose volumes meet (no
    /// more: its nodes' extents and hubs only skip nodes that hold none),
    /// on a soup, and on a capped cone with its base as one group.
    #[test]
    fn the_pairs_tested_are_those_whose_volumes_meet() {
        let soup = soup_within(16);
        let reference = all_meeting(&soup, None);
        assert!(reference.len() > 100, "{}", reference.len());
        assert_eq!(candidates(&soup), reference);
        let cone = capped_cone(300);
        let groups: Vec<u32> = (0..600)
            .map(|t| if t < 300 { NO_GROUP } else { 0 })
            .collect();
        for groups in [None, Some(&groups[..])] {
            let reference = all_meeting(&cone, groups);
            assert!(!reference.is_empty());
            assert_eq!(grouped_candidates(&cone, groups), reference);
        }
    }

    /// A fan's faces all share its apex, and the faces of a cone and of
    /// its base (a fan in another plane) are apart along the diagonals
    /// but near their ring: comparing the nodes' hubs and extents, the
    /// search of a capped cone compares a number of leaf pairs that grows
    /// with the leaves, not with their square (boxes alone: every pair of
    /// the cone's leaves, about `250^2 / 2` here).
    #[test]
    fn a_capped_cone_compares_few_pairs_of_leaves() {
        let n = 1000;
        let cone = capped_cone(n);
        let groups: Vec<u32> = (0..2 * n)
            .map(|t| if t < n { NO_GROUP } else { 0 })
            .collect();
        let leaves = (2 * n as usize).div_ceil(LEAF);
        LEAF_PAIRS.with(|c| c.set(0));
        let pairs = grouped_candidates(&cone, Some(&groups));
        let compared = LEAF_PAIRS.with(Cell::get);
        assert!(compared < 8 * leaves, "{compared} pairs of {leaves} leaves");
        assert_eq!(pairs, all_meeting(&cone, Some(&groups)));
    }

    /// `mesh` turned by the rotation of cosine 3/5 about the axis `(1, 2,
    /// 2) / 3`: its entries are not dyadic, so the coordinates are
    /// rounded, and no face lies in a coordinate plane or along a diagonal.
    fn turned(mesh: &Mesh) -> Mesh {
        rotated(mesh, [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0], 0.6, 0.8)
    }

    /// `mesh` turned about the unit axis `k` by the angle of cosine `c`
    /// and sine `s` (Rodrigues' formula, rounded).
    fn rotated(mesh: &Mesh, k: [f64; 3], c: f64, s: f64) -> Mesh {
        let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let cross = match (i, j) {
                    (0, 1) => -k[2],
                    (0, 2) => k[1],
                    (1, 0) => k[2],
                    (1, 2) => -k[0],
                    (2, 0) => -k[1],
                    (2, 1) => k[0],
                    _ => 0.0,
                };
                let id = if i == j { c } else { 0.0 };
                id + s * cross + (1.0 - c) * k[i] * k[j]
            })
        });
        let mut m = mesh.clone();
        for p in &mut m.positions {
            let q = *p;
            *p = std::array::from_fn(|i| r[i][0] * q[0] + r[i][1] * q[1] + r[i][2] * q[2]);
        }
        m
    }

    /// The pairs the tree hands its test on `mesh`, and how many pairs of
    /// faces have volumes that meet, after checking that the first are
    /// among the second and that none of the others (those a plane set
    /// apart) meets (exact test).
    fn tested_and_meeting(mesh: &Mesh) -> (Vec<(FaceId, FaceId)>, usize) {
        let tested = candidates(mesh);
        let meeting = all_meeting(mesh, None);
        assert!(tested.iter().all(|p| meeting.binary_search(p).is_ok()));
        let face = |f: FaceId| mesh.faces[f.idx()].map(|v| mesh.pos(v));
        let filter = crate::exact::orient_filter::Filter::CHECKING;
        for &(a, b) in meeting.iter().filter(|p| tested.binary_search(p).is_err()) {
            assert!(
                !super::super::narrow::faces_meet(filter, face(a), face(b)),
                "{a:?} {b:?}"
            );
        }
        (tested, meeting.len())
    }

    /// `a` and `b` side by side in one mesh, `b` moved by `d`.
    fn joined(a: &Mesh, b: &Mesh, d: [f64; 3]) -> Mesh {
        let mut m = a.clone();
        let n = a.positions.len() as u32;
        m.positions.extend(
            b.positions
                .iter()
                .map(|p| std::array::from_fn(|k| p[k] + d[k])),
        );
        m.faces
            .extend(b.faces.iter().map(|t| t.map(|v| VertexId(v.0 + n))));
        m
    }

    /// The pairs of faces of `mesh` (closed, manifold) that meet improperly
    /// as the search finds them, checked against testing every pair.
    fn found_by_search_and_by_all_pairs(mesh: &Mesh) -> Vec<(FaceId, FaceId)> {
        let (topo, issues) = crate::mesh::topology::Topology::build(mesh);
        assert!(issues.is_empty(), "{issues:?}");
        let every = super::super::tests::all_pairs(mesh);
        assert_eq!(super::super::self_intersections(mesh, &topo), every);
        every
    }

    /// A flat plate of long thin faces (twenty cells of 40 x 1, split
    /// across), turned off the axes: along the axes each face's box holds
    /// much of the plate, and the other cap's faces meet it; in the turned
    /// frame (the plate's own axes) the boxes are thin again. The pairs
    /// tested fall from 972 to 92 (asserted: below a fifth), and the
    /// search still finds what testing every pair finds (none: the plate
    /// is closed and proper).
    #[test]
    fn a_turned_plate_of_slivers_is_searched_along_its_own_axes() {
        let n = 21 * 5;
        let mut plate = crate::datasets::slab::Slab {
            nx: 20,
            ny: 4,
            bot: vec![0; n],
            thick: vec![1; n],
            diag: (0..80).map(|c| c % 3 == 0).collect(),
            rot: 0,
        }
        .mesh();
        for p in &mut plate.positions {
            p[0] *= 40.0;
        }
        let mesh = turned(&plate);
        let tree = Bvh::build(&mesh, &mesh.faces, None, false);
        assert!(tree.is_turned());
        let (along_axes, along_plate) = (candidates(&mesh).len(), tested_by(&tree).len());
        assert!(
            5 * along_plate < along_axes,
            "{along_plate} pairs tested turned, {along_axes} along the axes"
        );
        assert!(found_by_search_and_by_all_pairs(&mesh).is_empty());
        // On the axes, the same plate is not turned.
        assert!(!Bvh::build(&plate, &plate.faces, None, false).is_turned());
    }

    /// A capped cone turned away from the axes: every face's box holds a
    /// stretch of the axis, and so do the diagonals, so boxes and extents
    /// meet for most pairs of a side face and a base face. The fans' plane
    /// sets their nodes apart wherever their arcs of the ring do not meet.
    /// The pairs so skipped are among those whose volumes meet, and none
    /// meets (exact test); and the pairs tested no longer grow with the
    /// square of the faces (which boxes and extents alone make them do:
    /// about 49 000 at 2 000 sections, 793 000 at 8 000; with the fans'
    /// plane 21 000 and 164 000).
    #[test]
    fn a_turned_capped_cone_tests_few_pairs() {
        let tested = |n: u32| candidates(&turned(&capped_cone(n)));
        let (few, meeting) = tested_and_meeting(&turned(&capped_cone(2000)));
        assert!(2 * few.len() < meeting, "{} of {meeting}", few.len());
        let more = tested(8000).len();
        assert!(
            more < 10 * few.len(),
            "{more} pairs at 8 000 sections, {} at 2 000",
            few.len()
        );
    }

    /// Two turned cones, the second moved through the first: fans that
    /// cross are not set apart, and the search finds every pair that
    /// testing all pairs finds.
    #[test]
    fn crossing_fans_are_not_set_apart() {
        let one = capped_cone(64);
        let two = turned(&joined(&one, &one, [0.5, 0.25, 0.5]));
        let every = found_by_search_and_by_all_pairs(&two);
        assert!(every.len() > 50, "{}", every.len());
    }

    /// A cylinder of radius 1 and height `height` over a regular `n`-gon
    /// in the plane `z = 0`: `2 n` side faces, each from end to end, then
    /// each end a fan of `n` faces around its centre. Its coordinates are
    /// cosines and sines (no grid).
    fn capped_cylinder(n: u32, height: f64) -> Mesh {
        let mut mesh = Mesh::default();
        for z in [0.0, height] {
            for i in 0..n {
                let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
                mesh.positions.push([a.cos(), a.sin(), z]);
            }
        }
        mesh.positions.push([0.0, 0.0, 0.0]);
        mesh.positions.push([0.0, 0.0, height]);
        let (low, high) = (|i: u32| VertexId(i % n), |i: u32| VertexId(n + i % n));
        for i in 0..n {
            mesh.faces.push([low(i), low(i + 1), high(i + 1)]);
            mesh.faces.push([low(i), high(i + 1), high(i)]);
        }
        mesh.faces
            .extend((0..n).map(|i| [low(i + 1), low(i), VertexId(2 * n)]));
        mesh.faces
            .extend((0..n).map(|i| [high(i), high(i + 1), VertexId(2 * n + 1)]));
        mesh
    }

    /// A tall cylinder turned away from the axes: every side face runs
    /// from end to end, so its box and diagonal extents hold most of the
    /// others'. The plane along the strips sets apart the nodes of strips
    /// that share no vertex: the pairs so skipped are among those whose
    /// volumes meet, and none meets (exact test); and the pairs tested no
    /// longer grow with the square of the faces (with boxes and extents
    /// alone, every pair of side faces that share no vertex is tested:
    /// 1 995 000 at 1 000 sections; with the plane 374 000, and 1 592 000
    /// at 4 000). Turned instead so that its axis is nearly in the plane
    /// `y = 0` (`(0.6, 0.01, 0.8)`, normalized: every node's box is thin
    /// along y, and the leaves in Morton order hold arcs from both sides
    /// of the circle), fewer pairs meet and the plane sets fewer apart
    /// (669 000 of 1 258 000), but the growth is still far from square
    /// (3 473 000 at 4 000 sections).
    #[test]
    fn a_turned_tall_cylinder_tests_few_pairs() {
        let (k, c): ([f64; 3], f64) = ([-0.01, 0.6, 0.0], 0.8 / 1.00005f64.sqrt());
        let norm = dot(k, k).sqrt();
        let nearly = |m: &Mesh| rotated(m, k.map(|x| x / norm), c, (1.0 - c * c).sqrt());
        for (turn, part) in [(&turned as &dyn Fn(&Mesh) -> Mesh, 5), (&nearly, 1)] {
            let tested = |n: u32| candidates(&turn(&capped_cylinder(n, 100.0)));
            let (few, meeting) = tested_and_meeting(&turn(&capped_cylinder(1000, 100.0)));
            assert!(part * few.len() < meeting, "{} of {meeting}", few.len());
            let more = tested(4000).len();
            assert!(
                more < 8 * few.len(),
                "{more} pairs at 4 000 sections, {} at 1 000",
                few.len()
            );
        }
    }

    /// A thin disc turned away from the axes, each cap a fan of slivers
    /// from its centre to the rim: every sliver's box holds the centre, so
    /// boxes and extents meet for most pairs of a sliver of one cap and
    /// one of the other, and the Morton order mixes the two caps in its
    /// nodes. A node whose triangles each have one of the two centres has
    /// both as hubs, and the plane through them sets such nodes apart
    /// wherever their arcs of the rim do not meet. The pairs so skipped
    /// are among those whose volumes meet, and none meets (exact test);
    /// and the pairs tested grow 6.9-fold from 1 000 to 4 000 sections
    /// (62 500 to 431 000; with one hub a node, 131 800 and 1 797 000, all
    /// the pairs whose volumes meet).
    #[test]
    fn a_turned_thin_disc_tests_fewer_pairs() {
        let disc = |n: u32| turned(&capped_cylinder(n, 0.01));
        let (few, meeting) = tested_and_meeting(&disc(1000));
        assert!(2 * few.len() < meeting, "{} of {meeting}", few.len());
        let more = candidates(&disc(4000)).len();
        assert!(
            more < 9 * few.len(),
            "{more} pairs at 4 000 sections, {} at 1 000",
            few.len()
        );
    }

    /// Two leaves of eight triangles, one at `x < 0` and one at `x > 0`
    /// (and higher: in Morton order, the first eight apart from the rest),
    /// the first corner of the first triangle of each moved to `p` and
    /// `q`; [`Bvh::apart_by`] with the plane `x = 0`.
    fn apart_at(p: [f64; 3], q: [f64; 3]) -> bool {
        apart_after(|mesh| {
            mesh.positions[0] = p;
            mesh.positions[24] = q;
        })
    }

    /// [`apart_at`]'s leaves, after `edit`: 16 triangles of three corners
    /// each (vertex `3 t + k` is corner `k` of triangle `t`).
    fn apart_after(edit: impl Fn(&mut Mesh)) -> bool {
        let mut mesh = Mesh::default();
        for t in 0..16u32 {
            let (x, z) = if t < 8 { (-2.0, 0.0) } else { (2.0, 4.0) };
            let y = z + f64::from(t % 8) / 8.0;
            for c in [[x, y, z], [x + 0.5, y, z + 1.0], [x, y + 0.1, z + 1.0]] {
                mesh.positions.push(c);
            }
            mesh.faces.push([3 * t, 3 * t + 1, 3 * t + 2].map(VertexId));
        }
        edit(&mut mesh);
        let tree = unturned(&mesh, None);
        let place = tree.places();
        let (a, b) = (place[0].0, place[8].0);
        assert_ne!(a, b);
        let plane = Plane([[0.0; 3], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let want = plane.side_of([-1.0, 0.0, 0.0]).unwrap();
        let side = |l: usize, want| Side {
            leaves: l..l + 1,
            nearest: l,
            hubs: Hubs::NONE,
            want,
        };
        tree.apart_by(&plane, side(a, want), side(b, want.flip()))
    }

    /// A plane sets two leaves apart when each is on its side, and the
    /// points of one on the plane are none, or one point that is not the
    /// other's one point; not when they touch the plane at one point, or
    /// a vertex is on the wrong side.
    #[test]
    fn a_plane_sets_apart_what_touches_it_at_different_points() {
        let (off_a, off_b) = ([-2.0, 0.0, 0.0], [2.0, 4.0, 4.0]);
        assert!(apart_at(off_a, off_b));
        let (on, elsewhere) = ([0.0, 1.0, 2.0], [0.0, 3.0, 2.0]);
        assert!(apart_at(on, off_b));
        assert!(apart_at(off_a, on));
        assert!(apart_at(on, elsewhere));
        assert!(!apart_at(on, on));
        assert!(!apart_at([0.5, 1.0, 2.0], off_b));
        assert!(!apart_at(off_a, [-0.5, 1.0, 2.0]));
    }

    /// Each triangle may touch the plane at one vertex: a side may touch
    /// it at several points, and at a vertex the other side has too (a
    /// triangle of one meets one of the other there only when both have
    /// that vertex: not a pair to test); not at a point where the other
    /// side has another vertex, nor along an edge.
    #[test]
    fn a_plane_sets_apart_what_touches_it_at_shared_vertices() {
        let on = |y: f64| [0.0, y, 2.0];
        // Triangles 0 and 1 (left) and 8 (right) touch the plane.
        let several = |m: &mut Mesh| {
            (m.positions[0], m.positions[3], m.positions[24]) = (on(1.0), on(3.0), on(5.0));
        };
        assert!(apart_after(several));
        // Triangle 8's first corner is triangle 0's, on the plane.
        let shared = |m: &mut Mesh| {
            m.positions[0] = on(1.0);
            m.faces[8][0] = VertexId(0);
        };
        assert!(apart_after(shared));
        assert!(apart_after(|m| {
            several(m);
            shared(m);
        }));
        // Triangle 8's first corner moved to triangle 1's, a vertex apart.
        assert!(!apart_after(|m| {
            several(m);
            m.positions[24] = on(3.0);
        }));
        // Triangle 0's edge from its first to its second corner on it.
        assert!(!apart_after(|m| {
            (m.positions[0], m.positions[1]) = (on(1.0), on(1.5));
        }));
    }

    /// Two turned tall cylinders, the second moved through the first:
    /// strips that cross are not set apart, and the search finds every
    /// pair that testing all pairs finds.
    #[test]
    fn crossing_strips_are_not_set_apart() {
        let one = capped_cylinder(48, 20.0);
        let two = turned(&joined(&one, &one, [0.5, 0.25, 0.5]));
        let every = found_by_search_and_by_all_pairs(&two);
        assert!(every.len() > 50, "{}", every.len());
    }

    /// 300 small triangles (sides up to 4/64) at random places on the
    /// `1/64` grid in `[0, 1.5]^3`, no vertex shared.
    fn soup() -> Mesh {
        soup_within(92)
    }

    /// 300 small triangles (sides up to 4/64) at random places on the
    /// `1/64` grid, their lowest corner in `[0, cells / 64)^3`, no vertex
    /// shared.
    fn soup_within(cells: u64) -> Mesh {
        let mut state = 7u64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let mut mesh = Mesh::default();
        for t in 0..300u32 {
            let base: [u64; 3] = std::array::from_fn(|_| next(cells));
            for _ in 0..3 {
                let p: [f64; 3] = std::array::from_fn(|k| (base[k] + next(5)) as f64 / 64.0);
                mesh.positions.push(p);
            }
            mesh.faces.push([3 * t, 3 * t + 1, 3 * t + 2].map(VertexId));
        }
        // The span is at least 1: the leading exponent of the volumes'
        // largest magnitude is 0 in every frame below.
        mesh.positions.push([1.5, 0.0, 0.0]);
        mesh
    }

    /// The same soup far from the origin (at `2^30`, where `f32` are 128
    /// apart), near `2^-1000`, among the subnormals (`2^-1060`) and near
    /// `2^1000`: the tree hands its test exactly the pairs it hands it for
    /// the soup as made, which are far fewer than all pairs. Before the
    /// frame, every `f32` volume of these met every other.
    #[test]
    fn far_tiny_subnormal_and_huge_copies_test_the_same_pairs() {
        let mesh = soup();
        let reference = candidates(&mesh);
        let n = mesh.faces.len();
        assert!(!reference.is_empty());
        assert!(reference.len() < n * (n - 1) / 20, "{}", reference.len());
        let moved = |f: &dyn Fn(f64) -> f64| Mesh {
            positions: mesh.positions.iter().map(|p| p.map(f)).collect(),
            faces: mesh.faces.clone(),
        };
        for (name, copy) in [
            ("far", moved(&|x| x + times_pow2(1.0, 30))),
            ("tiny", moved(&|x| times_pow2(x, -1000))),
            ("subnormal", moved(&|x| times_pow2(x, -1060))),
            ("huge", moved(&|x| times_pow2(x, 1000))),
        ] {
            assert_eq!(candidates(&copy), reference, "{name}");
        }
    }

    /// `later_partners`, over every triangle, gives the pairs `pairs`
    /// hands to its test, each once, smaller face first (on a soup, where
    /// no two nodes are fans).
    #[test]
    fn the_later_partners_are_the_pairs_tested() {
        let mesh = soup_within(16);
        let reference = candidates(&mesh);
        assert!(reference.len() > 100, "{}", reference.len());
        let tree = unturned(&mesh, None);
        let place = tree.places();
        let mut all = Vec::new();
        for a in 0..mesh.faces.len() {
            let mut later = Vec::new();
            tree.later_partners(&place, FaceId::from_idx(a), &mut later);
            later.sort_unstable();
            all.extend(later.into_iter().map(|b| (FaceId::from_idx(a), FaceId(b))));
        }
        assert_eq!(all, reference);
    }

    /// `mesh` turned by `angle` about `axis` made unit length (rounded:
    /// test input, any axis will do), or about z when it is zero.
    fn turned_about(mesh: &Mesh, axis: [f64; 3], angle: f64) -> Mesh {
        let norm = dot(axis, axis).sqrt();
        let k = if norm > 0.0 {
            axis.map(|x| x / norm)
        } else {
            [0.0, 0.0, 1.0]
        };
        rotated(mesh, k, angle.cos(), angle.sin())
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(40))]

        /// Two tall cylinders, each turned about a random axis, the second
        /// moved by a small offset (often through the first, or touching
        /// it along a side): the search, whose strips a plane may set
        /// apart, finds exactly the pairs that testing every pair finds.
        #[test]
        fn strips_hide_no_pair(
            sections in proptest::array::uniform2(12u32..48),
            heights in proptest::array::uniform2(4.0f64..40.0),
            axes in proptest::array::uniform2(proptest::array::uniform3(-1.0f64..1.0)),
            angles in proptest::array::uniform2(0.1f64..3.0),
            d in proptest::array::uniform3(-2.5f64..2.5),
        ) {
            let turn = |m: usize| {
                turned_about(&capped_cylinder(sections[m], heights[m]), axes[m], angles[m])
            };
            found_by_search_and_by_all_pairs(&joined(&turn(0), &turn(1), d));
        }

        /// Two thin discs (caps that are fans, mixed in the tree's nodes),
        /// every other vertex of the top rim lowered by a random amount
        /// (often through the bottom cap), each turned about a random
        /// axis, the second moved by a small offset (often through the
        /// first): the search, whose fans a plane through their hubs may
        /// set apart, finds exactly the pairs that testing every pair
        /// finds.
        #[test]
        fn fans_hide_no_pair(
            sections in proptest::array::uniform2(16u32..160),
            heights in proptest::array::uniform2(0.001f64..0.2),
            lowered in proptest::array::uniform2(0.0f64..0.3),
            axes in proptest::array::uniform2(proptest::array::uniform3(-1.0f64..1.0)),
            angles in proptest::array::uniform2(0.1f64..3.0),
            d in proptest::array::uniform3(-0.3f64..0.3),
        ) {
            let turn = |m: usize| {
                let n = sections[m] as usize;
                let mut disc = capped_cylinder(sections[m], heights[m]);
                for p in disc.positions[n..2 * n].iter_mut().step_by(2) {
                    p[2] -= lowered[m];
                }
                turned_about(&disc, axes[m], angles[m])
            };
            found_by_search_and_by_all_pairs(&joined(&turn(0), &turn(1), d));
        }
    }

    /// `pairs` collects every accepted pair, counted on its stop, and
    /// stops early once the stop is reached.
    #[test]
    fn the_search_counts_on_its_stop() {
        let mesh = soup_within(16);
        let n = candidates(&mesh).len();
        let tree = unturned(&mesh, None);
        let all = |_: FaceId, _: FaceId| true;
        let stop = Stop::at(n + 1);
        let found = tree.pairs(&all, 10, &stop).finish();
        assert_eq!((found.pairs.len(), found.unlisted), (10, n - 10));
        assert!(!stop.reached());
        let stop = Stop::at(n / 2);
        let found = tree.pairs(&all, 10, &stop).finish();
        assert!(stop.reached());
        assert!(found.pairs.len() + found.unlisted < n, "{n}");
    }
}
