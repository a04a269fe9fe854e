//! The bounding volumes of the broad phase: boxes ([`Bounds`]), a leaf's
//! triangles as columns ([`Leaf`]), and extents along the six diagonals
//! ([`Slabs`]), all as `f32` bounds that hold the exact ones.

use super::frame::{down32, up32};
use super::{LEAF, NO_GROUP};

#[inline]
pub(super) fn min3(a: f64, b: f64, c: f64) -> f64 {
    let m = if b < a { b } else { a };
    if c < m {
        c
    } else {
        m
    }
}

#[inline]
pub(super) fn max3(a: f64, b: f64, c: f64) -> f64 {
    let m = if b > a { b } else { a };
    if c > m {
        c
    } else {
        m
    }
}

/// A closed box, its bounds holding the exact ones.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bounds {
    pub(super) lo: [f32; 3],
    pub(super) hi: [f32; 3],
}

impl Bounds {
    pub(super) const EMPTY: Bounds = Bounds {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    /// Whether the closed boxes meet (all six comparisons, without
    /// branches: the answer is rarely predictable).
    #[inline]
    pub(super) fn meets(&self, o: &Bounds) -> bool {
        (self.lo[0] <= o.hi[0])
            & (o.lo[0] <= self.hi[0])
            & (self.lo[1] <= o.hi[1])
            & (o.lo[1] <= self.hi[1])
            & (self.lo[2] <= o.hi[2])
            & (o.lo[2] <= self.hi[2])
    }

    /// The longest of the box's sides (rounded).
    pub(super) fn longest_side(&self) -> f32 {
        (0..3).fold(0f32, |m, k| m.max(self.hi[k] - self.lo[k]))
    }

    /// Whether on two axes or three the boxes overlap over at least half
    /// the smaller side (a heuristic: when two strips' boxes do, a plane
    /// between them is worth trying).
    pub(super) fn overlaps_deeply(&self, o: &Bounds) -> bool {
        (0..3)
            .filter(|&k| {
                let least = (self.hi[k] - self.lo[k]).min(o.hi[k] - o.lo[k]);
                self.hi[k].min(o.hi[k]) - self.lo[k].max(o.lo[k]) >= 0.5 * least
            })
            .count()
            >= 2
    }

    #[inline]
    pub(super) fn union(&self, o: &Bounds) -> Bounds {
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
pub(super) struct Leaf {
    pub(super) lo: [[f32; LEAF]; 3],
    pub(super) hi: [[f32; LEAF]; 3],
    pub(super) v: [[u32; LEAF]; 3],
    pub(super) group: [u32; LEAF],
    pub(super) face: [u32; LEAF],
}

impl Leaf {
    pub(super) const EMPTY: Leaf = Leaf {
        lo: [[f32::INFINITY; LEAF]; 3],
        hi: [[f32::NEG_INFINITY; LEAF]; 3],
        v: [[u32::MAX; LEAF]; 3],
        group: [NO_GROUP; LEAF],
        face: [u32::MAX; LEAF],
    };

    /// The box of slot `s`.
    #[inline(always)]
    pub(super) fn bounds(&self, s: usize) -> Bounds {
        Bounds {
            lo: std::array::from_fn(|k| self.lo[k][s]),
            hi: std::array::from_fn(|k| self.hi[k][s]),
        }
    }

    /// Whether the box of slot `t` meets `b` (six comparisons, no branch).
    #[inline(always)]
    pub(super) fn slot_meets(&self, t: usize, b: &Bounds) -> bool {
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
    pub(super) fn meeting(&self, b: &Bounds) -> u32 {
        (0..LEAF).fold(0, |mask, t| mask | u32::from(self.slot_meets(t, b)) << t)
    }

    /// Bit `t` set for each slot `t` whose box meets `b`, that shares no
    /// vertex id with `v` and is in another group than `group` (or either
    /// is in none). Written lane by lane, without branches, so that the
    /// compiler turns it into a few vector comparisons.
    #[inline(always)]
    pub(super) fn candidates(&self, b: &Bounds, v: [u32; 3], group: u32) -> u32 {
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
pub(super) struct Slabs {
    pub(super) lo: [f32; 6],
    pub(super) hi: [f32; 6],
}

impl Slabs {
    pub(super) const EMPTY: Slabs = Slabs {
        lo: [f32::INFINITY; 6],
        hi: [f32::NEG_INFINITY; 6],
    };

    /// The diagonal coordinates of `q`, each rounded once.
    #[inline(always)]
    pub(super) fn diagonals(q: [f64; 3]) -> [f64; 6] {
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
    pub(super) fn of(p: [[f64; 3]; 3], e: f64) -> Slabs {
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
    pub(super) fn around(ps: impl Iterator<Item = [f64; 3]>, e: f64) -> Slabs {
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
    pub(super) fn meets(&self, o: &Slabs) -> bool {
        (0..6).all(|k| (self.lo[k] <= o.hi[k]) & (o.lo[k] <= self.hi[k]))
    }

    #[inline]
    pub(super) fn union(&self, o: &Slabs) -> Slabs {
        Slabs {
            lo: std::array::from_fn(|k| self.lo[k].min(o.lo[k])),
            hi: std::array::from_fn(|k| self.hi[k].max(o.hi[k])),
        }
    }
}
