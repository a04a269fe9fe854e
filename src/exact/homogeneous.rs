//! Input: exact points held as integers `(x 2^e / w, y 2^e / w)`
//! ([`LoopPoint::as_integers`]). Output: exact comparisons and orientation
//! computed on the integers, with no gcd and no rational normalisation:
//! the exact fallback of the filters when their intervals cannot decide
//! (ties, collinear points), which is common on axis-aligned parts.
//!
//! Points of one mesh grid share `e`, so `e` cancels: `x_a / w_a` against
//! `x_b / w_b` is `x_a w_b` against `x_b w_a` (`w > 0`), a 256-bit product
//! comparison; the orientation is the 3 x 3 determinant of the homogeneous
//! coordinates `(x, y, w)`, whose sign is the orientation's as every `w` is
//! positive. Points with different `e`, or held as reduced rationals, go
//! through [`Point2`] (exact rationals).

use super::point::{LoopPoint, Point2};
use super::predicates::orient2d_rat;
use super::Sign;
use num_bigint::BigInt;
use std::cmp::Ordering;

/// `|a| |b|` as a 256-bit number `(high, low)`.
fn wide_mul(a: u128, b: u128) -> (u128, u128) {
    let mask = u128::from(u64::MAX);
    let (a1, a0) = (a >> 64, a & mask);
    let (b1, b0) = (b >> 64, b & mask);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    // Middle sum below 2^129: split its carry.
    let (mid, carry) = p01.overflowing_add(p10);
    let (low, c0) = p00.overflowing_add(mid << 64);
    let high = p11 + (mid >> 64) + (u128::from(carry) << 64) + u128::from(c0);
    (high, low)
}

/// The exact order of `a b` and `c d`.
pub fn cmp_products(a: i128, b: i128, c: i128, d: i128) -> Ordering {
    let sign = |x: i128, y: i128| (x.signum() * y.signum()) as i8;
    let (s, t) = (sign(a, b), sign(c, d));
    if s != t {
        return s.cmp(&t);
    }
    let m = wide_mul(a.unsigned_abs(), b.unsigned_abs());
    let n = wide_mul(c.unsigned_abs(), d.unsigned_abs());
    match s {
        1 => m.cmp(&n),
        -1 => n.cmp(&m),
        _ => Ordering::Equal,
    }
}

/// The exact order of one coordinate (`axis` 0 for x, 1 for y) of two
/// points.
pub fn cmp_coordinate(a: &LoopPoint, b: &LoopPoint, axis: usize) -> Ordering {
    if std::ptr::eq(a, b) {
        return Ordering::Equal;
    }
    match (a.as_integers(), b.as_integers()) {
        (Some((ax, ay, aw, ae)), Some((bx, by, bw, be))) if ae == be => {
            let (u, v) = if axis == 0 { (ax, bx) } else { (ay, by) };
            cmp_products(u, bw, v, aw)
        }
        _ if a.same_coordinate_by_recipe(b, axis) => Ordering::Equal,
        _ => {
            let (p, q) = (a.exact(), b.exact());
            if axis == 0 {
                p.x.cmp(&q.x)
            } else {
                p.y.cmp(&q.y)
            }
        }
    }
}

/// The exact orientation of three points: positive when counter-clockwise.
pub fn orient(a: &LoopPoint, b: &LoopPoint, c: &LoopPoint) -> Sign {
    let (Some(p), Some(q), Some(r)) = (a.as_integers(), b.as_integers(), c.as_integers()) else {
        return orient_rational(a, b, c);
    };
    if p.3 != q.3 || p.3 != r.3 {
        return orient_rational(a, b, c);
    }
    let small = [p.0, p.1, p.2, q.0, q.1, q.2, r.0, r.1, r.2]
        .iter()
        .all(|v| v.unsigned_abs() < 1 << 40);
    if small {
        // Each product of three below 2^120, six of them below 2^123.
        let det = p.0 * (q.1 * r.2 - r.1 * q.2) - p.1 * (q.0 * r.2 - r.0 * q.2)
            + p.2 * (q.0 * r.1 - r.0 * q.1);
        return Sign::of_cmp(Some(det.cmp(&0)));
    }
    let [x0, y0, w0, x1, y1, w1, x2, y2, w2] =
        [p.0, p.1, p.2, q.0, q.1, q.2, r.0, r.1, r.2].map(BigInt::from);
    let det = &x0 * (&y1 * &w2 - &y2 * &w1) - &y0 * (&x1 * &w2 - &x2 * &w1)
        + &w0 * (&x1 * &y2 - &x2 * &y1);
    Sign::of_cmp(Some(det.sign().cmp(&num_bigint::Sign::NoSign)))
}

fn orient_rational(a: &LoopPoint, b: &LoopPoint, c: &LoopPoint) -> Sign {
    let (p, q, r): (std::borrow::Cow<'_, Point2>, _, _) = (a.exact(), b.exact(), c.exact());
    orient2d_rat(&p, &q, &r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::Rat;
    use proptest::prelude::*;

    fn big(x: i128) -> BigInt {
        BigInt::from(x)
    }

    proptest! {
        #[test]
        fn products_compare_exactly(a in any::<i128>(), b in any::<i128>(), c in any::<i128>(), d in any::<i128>(), same in any::<bool>()) {
            let (c, d) = if same { (b, a) } else { (c, d) };
            prop_assert_eq!(cmp_products(a, b, c, d), (big(a) * big(b)).cmp(&(big(c) * big(d))));
        }

        /// Against the rational predicates, on points of one grid with
        /// wide and narrow integers, collinear by construction half the
        /// time, and on the same point twice.
        #[test]
        fn orientation_and_order_equal_the_rationals(
            pts in proptest::collection::vec((any::<i128>(), any::<i128>(), 1i128..(1i128 << 125), 0u32..127), 3),
            e in -300i32..300, collinear in any::<bool>(), twice in any::<bool>()
        ) {
            let mut held: Vec<LoopPoint> = pts
                .iter()
                .map(|&(x, y, w, k)| {
                    let shift = k % 100;
                    LoopPoint::from_integers(x >> shift, y >> shift, (w >> (k % 126)).max(1), e).unwrap()
                })
                .collect();
            if collinear {
                // The midpoint of the first two.
                let (x0, y0, w0, _) = held[0].as_integers().unwrap();
                let (x1, y1, w1, _) = held[1].as_integers().unwrap();
                let fits = [x0, y0, w0, x1, y1, w1].iter().all(|v| v.unsigned_abs() < 1 << 60);
                if fits {
                    held[2] = LoopPoint::from_integers(x0 * w1 + x1 * w0, y0 * w1 + y1 * w0, 2 * w0 * w1, e).unwrap();
                }
            }
            if twice {
                held[1] = held[0].clone();
            }
            let exact: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
            prop_assert_eq!(orient(&held[0], &held[1], &held[2]), orient2d_rat(&exact[0], &exact[1], &exact[2]));
            prop_assert_eq!(cmp_coordinate(&held[0], &held[1], 0), exact[0].x.cmp(&exact[1].x));
            prop_assert_eq!(cmp_coordinate(&held[0], &held[1], 1), exact[0].y.cmp(&exact[1].y));
            // A rational point beside grid points.
            let r = LoopPoint::from(Point2 { x: Rat::new(1.into(), 3.into()), y: exact[2].y.clone() });
            prop_assert_eq!(cmp_coordinate(&held[2], &r, 1), std::cmp::Ordering::Equal);
            prop_assert_eq!(orient(&held[0], &held[1], &r), orient2d_rat(&exact[0], &exact[1], &r.exact()));
        }
    }
}
