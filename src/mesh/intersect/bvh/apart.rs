//! Two nodes no pair of whose triangles needs a test although their
//! volumes meet: fans around two hubs, or strips, that a plane sets apart
//! (exact signs; the plane itself is a heuristic).

use super::super::turn::{cross, dot};
use super::volumes::Leaf;
use super::{Bvh, NO_HUB};
use crate::exact::orient_filter::orient3d_filter;
use crate::exact::predicates::{orient3d, Sign};

impl Bvh<'_> {
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
    pub(super) fn fans_apart(&self, i: usize, j: usize, h: u32) -> bool {
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
    pub(super) fn strips_apart(&self, i: usize, j: usize, h: u32) -> bool {
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
    pub(super) fn apart_by(&self, plane: &Plane, a: Side, b: Side) -> bool {
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
}

/// A plane through three points: which side of it a point lies on, exact.
pub(super) struct Plane(pub(super) [[f64; 3]; 3]);

impl Plane {
    /// The exact sign of `orient3d` of the plane's points and `x`.
    fn sign(&self, x: [f64; 3]) -> Sign {
        let [a, b, c] = self.0;
        orient3d_filter(a, b, c, x).unwrap_or_else(|| orient3d(a, b, c, x))
    }

    /// The side of `x` when the plane's points are finite and `x` is off
    /// the plane.
    pub(super) fn side_of(&self, x: [f64; 3]) -> Option<Sign> {
        let finite = self.0.iter().flatten().chain(&x).all(|v| v.is_finite());
        finite.then(|| self.sign(x)).filter(|&s| s != Sign::Zero)
    }
}

/// One of two nodes a plane may set apart: its leaves (the `nearest` to
/// the other node tried first), its hubs (on the plane), and the side its
/// vertices should be on.
pub(super) struct Side {
    pub(super) leaves: std::ops::Range<usize>,
    pub(super) nearest: usize,
    pub(super) hubs: Hubs,
    pub(super) want: Sign,
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
pub(super) struct Hubs([u32; 2]);

impl Hubs {
    pub(super) const NONE: Hubs = Hubs([NO_HUB; 2]);

    /// The hubs of the first `n` triangles of `leaf`: one when they have
    /// one, else two that every triangle has one of, when there are such:
    /// of those, the pair whose rarer vertex is in the most triangles of
    /// the mesh (`valence`), so that two leaves of the same two fans get
    /// the same hubs (a heuristic: any pair is true of the leaf).
    pub(super) fn of_leaf(leaf: &Leaf, n: usize, valence: &[u16]) -> Hubs {
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
    pub(super) fn union(self, o: Hubs) -> Hubs {
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
    pub(super) fn one(self) -> u32 {
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
