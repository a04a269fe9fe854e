//! Input: a mesh with finite coordinates. Output: every pair of faces with
//! no shared vertex id whose closed bounding boxes meet, handed to a test.
//!
//! The broad phase of the self-intersection test: a bounding-volume
//! hierarchy over the faces, in the order of the Morton codes of their box
//! centres (a heuristic: it shapes the tree, never the answer), leaves of
//! [`LEAF`] faces, each level pairing the nodes of the one below; the tree
//! is then tested against itself.
//!
//! Boxes are `f32`, each bound rounded outwards from the exact `f64`
//! coordinates, so a box holds its face's exact box, and two faces whose
//! exact boxes touch have boxes that touch (closed boxes: touching counts).
//! Coordinates beyond the `f32` range give infinite bounds, which only
//! makes boxes larger.

use super::Found;
use crate::ids::FaceId;
use crate::mesh::Mesh;
use rayon::prelude::*;

/// Faces per leaf.
const LEAF: usize = 8;

/// Levels at and above which the two halves of a node are tested on
/// separate rayon tasks (a node there holds at least `LEAF * 2^level`
/// faces).
const PAR_LEVEL: usize = 8;

/// A closed box, bounds rounded outwards to `f32`.
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

    #[inline]
    fn meets(&self, o: &Bounds) -> bool {
        self.lo[0] <= o.hi[0]
            && o.lo[0] <= self.hi[0]
            && self.lo[1] <= o.hi[1]
            && o.lo[1] <= self.hi[1]
            && self.lo[2] <= o.hi[2]
            && o.lo[2] <= self.hi[2]
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

/// The largest `f32` not above `x`.
#[inline]
fn f32_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x {
        y.next_down()
    } else {
        y
    }
}

/// The smallest `f32` not below `x`.
#[inline]
fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x {
        y.next_up()
    } else {
        y
    }
}

/// A face in the tree: its box, id and vertex ids.
#[derive(Clone, Copy, Debug)]
struct Item {
    bounds: Bounds,
    face: u32,
    v: [u32; 3],
}

impl Item {
    #[inline]
    fn shares_vertex(&self, o: &Item) -> bool {
        self.v.iter().any(|x| o.v.contains(x))
    }
}

/// The hierarchy: faces in leaf order, and the boxes of each level
/// (`levels[0]`: leaves; node `i` of level `l + 1` holds nodes `2 i` and
/// `2 i + 1` of level `l`).
pub(super) struct Bvh {
    items: Vec<Item>,
    levels: Vec<Vec<Bounds>>,
    parallel: bool,
}

/// Spreads the low 21 bits of `x` to every third bit.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f00000000ffff;
    x = (x | x << 16) & 0x1f0000ff0000ff;
    x = (x | x << 8) & 0x100f00f00f00f00f;
    x = (x | x << 4) & 0x10c30c30c30c30c3;
    x = (x | x << 2) & 0x1249249249249249;
    x
}

impl Bvh {
    /// Builds the tree over every face (coordinates finite, indices in
    /// range).
    pub(super) fn build(mesh: &Mesh, parallel: bool) -> Bvh {
        let min_len = if parallel {
            crate::par::MIN_LEN
        } else {
            usize::MAX
        };
        let mut items: Vec<(u64, Item)> = {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in &mesh.positions {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let scale: [f64; 3] = std::array::from_fn(|k| {
                let w = hi[k] - lo[k];
                if w > 0.0 {
                    ((1u64 << 21) - 1) as f64 / w
                } else {
                    0.0
                }
            });
            mesh.faces
                .par_iter()
                .with_min_len(min_len)
                .enumerate()
                .map(|(f, tri)| {
                    let p = tri.map(|v| mesh.pos(v));
                    let mut b = Bounds::EMPTY;
                    let mut code = 0u64;
                    for k in 0..3 {
                        let l = p[0][k].min(p[1][k]).min(p[2][k]);
                        let h = p[0][k].max(p[1][k]).max(p[2][k]);
                        b.lo[k] = f32_down(l);
                        b.hi[k] = f32_up(h);
                        // The centre's cell (a heuristic; saturating casts).
                        let c = (0.5 * l + 0.5 * h - lo[k]) * scale[k];
                        code |= spread(c as u64) << k;
                    }
                    let item = Item {
                        bounds: b,
                        face: f as u32,
                        v: tri.map(|v| v.0),
                    };
                    (code, item)
                })
                .collect()
        };
        if parallel {
            items.par_sort_unstable_by_key(|&(code, it)| (code, it.face));
        } else {
            items.sort_unstable_by_key(|&(code, it)| (code, it.face));
        }
        let items: Vec<Item> = items.into_iter().map(|(_, it)| it).collect();
        let leaves: Vec<Bounds> = items
            .par_chunks(LEAF)
            .with_min_len(min_len / LEAF)
            .map(|c| c.iter().fold(Bounds::EMPTY, |b, it| b.union(&it.bounds)))
            .collect();
        let mut levels = vec![leaves];
        while levels.last().is_some_and(|l| l.len() > 1) {
            let below = levels.last().map(Vec::as_slice).unwrap_or_default();
            let up: Vec<Bounds> = below
                .par_chunks(2)
                .with_min_len(min_len / LEAF)
                .map(|c| c.iter().fold(Bounds::EMPTY, |b, n| b.union(n)))
                .collect();
            levels.push(up);
        }
        Bvh {
            items,
            levels,
            parallel,
        }
    }

    /// Calls `test` on every pair of faces with no shared vertex id whose
    /// boxes meet, and collects the pairs it accepts.
    pub(super) fn pairs<T>(&self, test: &T, keep: usize) -> Found
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        match self.levels.len() {
            0 => Found::new(keep),
            n => self.within(n - 1, 0, test, keep),
        }
    }

    /// The faces of leaf `i`.
    fn leaf(&self, i: usize) -> &[Item] {
        let s = i * LEAF;
        &self.items[s..(s + LEAF).min(self.items.len())]
    }

    /// The children of node `i` of `level` (> 0) that exist.
    fn children(&self, level: usize, i: usize) -> impl Iterator<Item = usize> {
        let n = self.levels[level - 1].len();
        2 * i..(2 * i + 2).min(n)
    }

    fn par(&self, level: usize) -> bool {
        self.parallel && level >= PAR_LEVEL
    }

    /// Pairs within node `i` of `level`.
    fn within<T>(&self, level: usize, i: usize, test: &T, keep: usize) -> Found
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        if level == 0 {
            let mut found = Found::new(keep);
            let items = self.leaf(i);
            for (k, a) in items.iter().enumerate() {
                for b in &items[k + 1..] {
                    self.visit(a, b, test, &mut found);
                }
            }
            return found;
        }
        let c: Vec<usize> = self.children(level, i).collect();
        match c[..] {
            [a] => self.within(level - 1, a, test, keep),
            [a, b] => {
                let ((x, y), z) = crate::par::join(
                    self.par(level),
                    || {
                        crate::par::join(
                            self.par(level),
                            || self.within(level - 1, a, test, keep),
                            || self.within(level - 1, b, test, keep),
                        )
                    },
                    || self.across(level - 1, a, b, test, keep),
                );
                x.merged(y).merged(z)
            }
            _ => Found::new(keep),
        }
    }

    /// Pairs with one face in node `i` and one in node `j` of `level`.
    fn across<T>(&self, level: usize, i: usize, j: usize, test: &T, keep: usize) -> Found
    where
        T: Fn(FaceId, FaceId) -> bool + Sync,
    {
        let mut found = Found::new(keep);
        if !self.levels[level][i].meets(&self.levels[level][j]) {
            return found;
        }
        if level == 0 {
            let (ls, rs) = (self.leaf(i), self.leaf(j));
            for a in ls {
                if !a.bounds.meets(&self.levels[0][j]) {
                    continue;
                }
                for b in rs {
                    self.visit(a, b, test, &mut found);
                }
            }
            return found;
        }
        let ci: Vec<usize> = self.children(level, i).collect();
        let cj: Vec<usize> = self.children(level, j).collect();
        if self.par(level) {
            let pairs: Vec<(usize, usize)> = ci
                .iter()
                .flat_map(|&a| cj.iter().map(move |&b| (a, b)))
                .collect();
            return pairs
                .into_par_iter()
                .map(|(a, b)| self.across(level - 1, a, b, test, keep))
                .reduce(|| Found::new(keep), Found::merged);
        }
        for &a in &ci {
            for &b in &cj {
                found = found.merged(self.across(level - 1, a, b, test, keep));
            }
        }
        found
    }

    #[inline]
    fn visit<T>(&self, a: &Item, b: &Item, test: &T, found: &mut Found)
    where
        T: Fn(FaceId, FaceId) -> bool,
    {
        if a.bounds.meets(&b.bounds) && !a.shares_vertex(b) {
            let (fa, fb) = (FaceId(a.face), FaceId(b.face));
            if test(fa, fb) {
                found.push(fa, fb);
            }
        }
    }
}
