//! Input: a mesh's positions (doubles) and exact levels. Output: the
//! positions as integers on one binary grid, when they fit, and the exact
//! crossings and vertex points computed on that grid.
//!
//! Every double is `k 2^e` with an integer `k`. When a mesh's coordinates
//! span at most 62 bits of one grid `2^e` (every `f32` mesh whose smallest
//! non-zero coordinate is not more than about `2^-38` times its largest,
//! and many `f64` CAD meshes), each position is three `i64` on that grid.
//! A crossing then needs no alignment of exponents: in grid units the
//! level is `p / q`, once per level, and the crossing of edge `(a, b)` is
//! `((ax w + (bx - ax) s) / w, (ay w + (by - ay) s) / w)` with
//! `w = q (bz - az)` and `s = p - q az`, in `i128`. The bit lengths of the
//! grid and of the level bound every product, so a level is accepted only
//! when none can overflow, and then no product is checked.

use super::level::Level;
use super::point::LoopPoint;
use super::rational::decompose;
use crate::ids::VertexId;

/// Every position of a mesh as integers on one binary grid:
/// `position = k 2^e`, exactly.
#[derive(Clone, Debug)]
pub struct MeshGrid {
    k: Vec<[i64; 3]>,
    e: i32,
    /// The largest bit length of any `|k|`.
    bits: u32,
}

/// A level in the grid's units, `p / q` (`q > 0`), accepted only when no
/// crossing at it can overflow `i128`.
#[derive(Clone, Copy, Debug)]
pub struct GridLevel {
    p: i128,
    q: i128,
}

fn bits(v: i128) -> u32 {
    128 - v.unsigned_abs().leading_zeros()
}

impl MeshGrid {
    /// The positions on the finest grid that holds them all, or `None`
    /// when some coordinate is not finite or they span more than 62 bits.
    pub fn new(positions: &[[f64; 3]]) -> Option<MeshGrid> {
        let mut e = i32::MAX;
        for p in positions {
            for &c in p {
                if !c.is_finite() {
                    return None;
                }
                if let Some((_, ce)) = decompose(c) {
                    e = e.min(ce);
                }
            }
        }
        if e == i32::MAX {
            e = 0;
        }
        let mut bits_max = 0;
        let mut k = Vec::with_capacity(positions.len());
        for p in positions {
            let mut row = [0i64; 3];
            for (r, &c) in row.iter_mut().zip(p) {
                if let Some((m, ce)) = decompose(c) {
                    let shift = u32::try_from(ce - e).ok().filter(|&s| s <= 62)?;
                    let v = i128::from(m) << shift;
                    let b = bits(v);
                    if b > 62 {
                        return None;
                    }
                    bits_max = bits_max.max(b);
                    *r = v as i64;
                }
            }
            k.push(row);
        }
        Some(MeshGrid {
            k,
            e,
            bits: bits_max,
        })
    }

    /// The level in grid units, when every crossing at it fits in `i128`
    /// (else the caller computes crossings another way).
    pub fn level(&self, level: &Level) -> Option<GridLevel> {
        let (p, q) = level.small()?;
        // c / 2^e = p / (q 2^e).
        let (p, q) = if self.e >= 0 {
            (p, shl(q, self.e.unsigned_abs())?)
        } else {
            (shl(p, self.e.unsigned_abs())?, q)
        };
        let b = self.bits;
        // |dz| < 2^(b+1); |w| < 2^(bits q + b + 1); |s| < 2^(max + 1);
        // each product of a crossing below 2^(x_bits - 1), their sum below
        // 2^x_bits.
        let w_bits = bits(q) + b + 1;
        let s_bits = bits(p).max(bits(q) + b) + 1;
        let x_bits = (b + w_bits).max(b + 1 + s_bits) + 1;
        (x_bits <= 126).then_some(GridLevel { p, q })
    }

    /// The exact `(x, y)` of vertex `v`.
    pub fn point(&self, v: VertexId) -> LoopPoint {
        let [x, y, _] = self.k[v.idx()].map(i128::from);
        LoopPoint::from_integers(x, y, 1, self.e).expect("w = 1 is in range")
    }

    /// The exact crossing of edge `(a, b)` with the level; the caller
    /// guarantees `h(a) != h(b)`.
    #[inline]
    pub fn crossing(&self, a: VertexId, b: VertexId, level: &GridLevel) -> LoopPoint {
        let [ax, ay, az] = self.k[a.idx()].map(i128::from);
        let [bx, by, bz] = self.k[b.idx()].map(i128::from);
        let w = level.q * (bz - az);
        let s = level.p - level.q * az;
        let x = ax * w + (bx - ax) * s;
        let y = ay * w + (by - ay) * s;
        let (x, y, w) = if w < 0 { (-x, -y, -w) } else { (x, y, w) };
        LoopPoint::from_integers(x, y, w, self.e).expect("0 < w < 2^126 by the level's bound")
    }
}

fn shl(v: i128, s: u32) -> Option<i128> {
    (s < 127 && bits(v) + s <= 126).then(|| v << s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;
    use crate::exact::point::Point2;
    use crate::exact::rational::{rat_from_f64, Rat};

    proptest::proptest! {
        /// Crossings and vertex points on the grid equal the big-rational
        /// reference: integer, dyadic and decimal coordinates (`f32` and
        /// `f64`), levels strictly between the ends.
        #[test]
        fn grid_crossings_equal_the_reference(
            a in proptest::array::uniform3(-1000i32..1000), b in proptest::array::uniform3(-1000i32..1000),
            scale in -30i32..10, kind in 0u8..3, t in 1i64..1000, den in 1i64..1001
        ) {
            let f = |v: [i32; 3]| v.map(|x| match kind {
                0 => f64::from(x) * 2f64.powi(scale),
                1 => f64::from((f64::from(x) * 0.1) as f32),
                _ => f64::from(x) * 0.1,
            });
            let (a, b) = (f(a), f(b));
            proptest::prop_assume!(a[2] != b[2]);
            let za = rat_from_f64(a[2]);
            let zb = rat_from_f64(b[2]);
            let level = Level::new(&za + (zb - &za) * Rat::new(t.into(), (den + t).into()));
            let grid = MeshGrid::new(&[a, b]).unwrap();
            let (va, vb) = (VertexId(0), VertexId(1));
            proptest::prop_assert_eq!(grid.point(va).exact().into_owned(), Point2::of_vertex(a));
            if let Some(lv) = grid.level(&level) {
                let p = grid.crossing(va, vb, &lv);
                let reference = Point2::on_edge_reference(a, b, &level);
                proptest::prop_assert_eq!(p.exact().into_owned(), reference.clone());
                proptest::prop_assert_eq!(p.to_f64(), reference.to_f64());
                proptest::prop_assert_eq!(grid.crossing(vb, va, &lv), p);
            }
        }
    }

    #[test]
    fn grids_that_do_not_fit_are_refused() {
        assert!(MeshGrid::new(&[[1e-30, 0.0, 0.0], [1e30, 0.0, 0.0]]).is_none());
        assert!(MeshGrid::new(&[[f64::NAN, 0.0, 0.0]]).is_none());
        // 2^-62 and 1 differ by 62 bits: refused; 2^-61 and 1 fit.
        assert!(MeshGrid::new(&[[2f64.powi(-62), 0.0, 1.0]]).is_none());
        let grid = MeshGrid::new(&[[2f64.powi(-61), 0.0, 1.0], [0.0, 0.0, 0.0]]).unwrap();
        assert_eq!(grid.bits, 62);
        // A level needing more than i128 is refused, a simple one accepted.
        assert!(grid
            .level(&Level::new(parse_rational("1/3").unwrap()))
            .is_none());
        let small = MeshGrid::new(&[[1.0, 2.0, 3.0], [0.5, 0.0, 0.0]]).unwrap();
        let lv = small
            .level(&Level::new(parse_rational("1/3").unwrap()))
            .unwrap();
        let p = small.crossing(VertexId(0), VertexId(1), &lv);
        assert_eq!(
            p.exact().into_owned(),
            Point2::on_edge_reference(
                [1.0, 2.0, 3.0],
                [0.5, 0.0, 0.0],
                &Level::new(parse_rational("1/3").unwrap())
            )
        );
    }
}
