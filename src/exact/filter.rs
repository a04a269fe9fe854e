//! Input: exact points. Output: the exact sign of orient2d, fast.
//!
//! A floating-point filter: every exact value is enclosed in an interval of
//! doubles (for a point held as integers `x 2^e / w`: the quotient of the
//! two rounded integers, widened by 8 ulps of relative error against at
//! most 4; otherwise the nearest double, widened by one ulp), and every
//! operation widens its rounded result outward by one ulp, so the computed
//! interval always contains the exact determinant. When it excludes zero,
//! its sign is the exact sign; otherwise the exact rational determinant
//! decides. Property-tested against the plain rational predicate.

use super::point::LoopPoint;
use super::predicates::{orient2d_rat, Sign};

/// A closed interval of doubles known to contain an exact value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    lo: f64,
    hi: f64,
}

impl Interval {
    /// An interval around a double known to be within half an ulp of the
    /// exact value (a correctly rounded result).
    #[inline]
    fn around(f: f64) -> Interval {
        Interval {
            lo: f.next_down(),
            hi: f.next_up(),
        }
    }

    /// An interval around `n 2^e / w` (`w > 0`) from one rounded
    /// division: `n` and `w` are converted to doubles (relative error below
    /// `1.001u` each, `u = 2^-53`) and divided (relative error below `4u`
    /// in all), then widened by `8u |v|` (an exact product) and one ulp
    /// each way. `None` outside the range where that
    /// product is exact and nothing overflows.
    #[inline]
    fn around_ratio(n: i128, w: i128, e: i32) -> Option<Interval> {
        if n == 0 {
            return Some(Interval { lo: 0.0, hi: 0.0 });
        }
        if !(-900..=900).contains(&e) {
            return None;
        }
        let scale = f64::from_bits(((e + 1023) as u64) << 52);
        let v = to_f64_within_ulp(n) / to_f64_within_ulp(w) * scale;
        let m = v.abs();
        if !(1e-250..=1e250).contains(&m) {
            return None;
        }
        let r = m * f64::from_bits((1023 - 50) << 52);
        Some(Interval::widen(v - r, v + r))
    }

    #[inline]
    fn widen(lo: f64, hi: f64) -> Interval {
        Interval {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }

    #[inline]
    fn add(self, o: Interval) -> Interval {
        Interval::widen(self.lo + o.lo, self.hi + o.hi)
    }

    #[inline]
    fn sub(self, o: Interval) -> Interval {
        Interval::widen(self.lo - o.hi, self.hi - o.lo)
    }

    #[inline]
    fn mul(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Interval {
                lo: f64::NEG_INFINITY,
                hi: f64::INFINITY,
            };
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::widen(lo, hi)
    }

    /// The sign, when the interval decides it (finite and away from zero).
    #[inline]
    fn sign(self) -> Option<Sign> {
        if self.lo > 0.0 && self.lo.is_finite() && self.hi.is_finite() {
            Some(Sign::Positive)
        } else if self.hi < 0.0 && self.lo.is_finite() && self.hi.is_finite() {
            Some(Sign::Negative)
        } else {
            None
        }
    }
}

/// `v` as a double within `(1 + 2^-9) u |v|`: the top 63 bits truncated
/// (relative error below `2^-62`), then rounded by the hardware's `i64`
/// conversion (`i128` conversion is a slow library call).
#[inline]
fn to_f64_within_ulp(v: i128) -> f64 {
    if let Ok(small) = i64::try_from(v) {
        return small as f64;
    }
    let shift = 65 - v.unsigned_abs().leading_zeros();
    ((v >> shift) as i64 as f64) * f64::from_bits(((shift + 1023) as u64) << 52)
}

/// The bits of a point's nearest doubles: equal for equal points (so a
/// cheap hash key), possibly equal for distinct ones.
pub type Key = (u64, u64);

/// An exact point with interval enclosures of its coordinates, computed once.
#[derive(Clone, Debug)]
pub struct FilteredPoint<'a> {
    exact: &'a LoopPoint,
    x: Interval,
    y: Interval,
}

impl<'a> FilteredPoint<'a> {
    /// Encloses an exact point.
    pub fn new(p: &'a LoopPoint) -> Self {
        let from_integers = p.as_integers().and_then(|(x, y, w, e)| {
            Some((
                Interval::around_ratio(x, w, e)?,
                Interval::around_ratio(y, w, e)?,
            ))
        });
        let (x, y) = from_integers.unwrap_or_else(|| {
            let [x, y] = p.to_f64();
            (Interval::around(x), Interval::around(y))
        });
        FilteredPoint { exact: p, x, y }
    }

    /// Doubles enclosing the exact point: `([x_lo, y_lo], [x_hi, y_hi])`.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        ([self.x.lo, self.y.lo], [self.x.hi, self.y.hi])
    }

    /// The nearest doubles as a hash key (a correctly rounded division
    /// per coordinate: computed on each call).
    pub fn key(&self) -> Key {
        let [x, y] = self.exact.to_f64();
        ((x + 0.0).to_bits(), (y + 0.0).to_bits())
    }

    /// Whether the enclosures prove the two points distinct.
    pub fn disjoint(&self, other: &FilteredPoint<'_>) -> bool {
        let apart = |a: Interval, b: Interval| a.hi < b.lo || b.hi < a.lo;
        apart(self.x, other.x) || apart(self.y, other.y)
    }

    /// The exact point.
    pub fn exact(&self) -> &'a LoopPoint {
        self.exact
    }
}

/// Exact comparison of the y coordinates of two points (filtered).
pub fn cmp_y(a: &FilteredPoint<'_>, b: &FilteredPoint<'_>) -> std::cmp::Ordering {
    if a.y.hi < b.y.lo {
        std::cmp::Ordering::Less
    } else if a.y.lo > b.y.hi {
        std::cmp::Ordering::Greater
    } else {
        a.exact.exact().y.cmp(&b.exact.exact().y)
    }
}

/// Exact orientation of three points: the filter when it decides, else the
/// exact rational determinant.
pub fn orient2d_filtered(
    a: &FilteredPoint<'_>,
    b: &FilteredPoint<'_>,
    c: &FilteredPoint<'_>,
) -> Sign {
    let det =
        b.x.sub(a.x)
            .mul(c.y.sub(a.y))
            .sub(b.y.sub(a.y).mul(c.x.sub(a.x)));
    det.sign()
        .unwrap_or_else(|| orient2d_rat(&a.exact.exact(), &b.exact.exact(), &c.exact.exact()))
}

/// A certified estimate of a polygon's signed area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaEstimate {
    /// The exact sign, when the enclosure excludes zero.
    pub sign: Option<Sign>,
    /// The midpoint of an interval of doubles that contains the exact
    /// signed area (so of the exact sign whenever `sign` is known).
    pub approx: f64,
}

/// Encloses the exact signed area of a closed polygon (shoelace in
/// interval arithmetic, every operation widened outward by one ulp).
pub fn signed_area_filtered(points: &[FilteredPoint<'_>]) -> AreaEstimate {
    let n = points.len();
    let mut twice = Interval { lo: 0.0, hi: 0.0 };
    for i in 0..n {
        let (p, q) = (&points[i], &points[(i + 1) % n]);
        twice = twice.add(p.x.mul(q.y).sub(q.x.mul(p.y)));
    }
    // Halving is exact (barring underflow, which the widening covers).
    let (lo, hi) = ((twice.lo / 2.0).next_down(), (twice.hi / 2.0).next_up());
    let area = Interval { lo, hi };
    AreaEstimate {
        sign: if n < 3 { Some(Sign::Zero) } else { area.sign() },
        approx: lo / 2.0 + hi / 2.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::point::Point2;
    use crate::exact::rational::Rat;
    use proptest::prelude::*;

    fn pt(x: (i64, i64), y: (i64, i64)) -> Point2 {
        Point2 {
            x: Rat::new(x.0.into(), x.1.into()),
            y: Rat::new(y.0.into(), y.1.into()),
        }
    }

    fn frac() -> impl Strategy<Value = (i64, i64)> {
        (-1_000_000i64..1_000_000, 1i64..1_000_000)
    }

    proptest! {
        /// The enclosure's sign, when given, is the exact sign, and its
        /// midpoint has that sign.
        #[test]
        fn area_enclosure_contains_the_exact_area(
            pts in proptest::collection::vec((frac(), frac()), 0..30),
            thin in proptest::bool::ANY,
        ) {
            let mut poly: Vec<Point2> = pts.iter().map(|&(x, y)| pt(x, y)).collect();
            if thin {
                // Nearly degenerate: every point on one line, but one.
                for (i, p) in poly.iter_mut().enumerate().skip(1) {
                    p.y = &p.x * Rat::from_integer(3.into()) + Rat::new((i as i64 % 2).into(), (1i64 << 50).into());
                }
            }
            let held: Vec<LoopPoint> = poly.iter().cloned().map(LoopPoint::from).collect();
            let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
            let est = signed_area_filtered(&f);
            let exact = crate::exact::area::signed_area_reference(&poly);
            if let Some(s) = est.sign {
                prop_assert_eq!(s, Sign::of_rat(&exact));
                if s != Sign::Zero {
                    prop_assert_eq!(Sign::of_rat(&crate::exact::rational::rat_from_f64(est.approx)), s);
                }
            }
        }

        #[test]
        fn filtered_equals_exact_on_random_points(a in (frac(), frac()), b in (frac(), frac()), c in (frac(), frac())) {
            let (a, b, c) = (pt(a.0, a.1), pt(b.0, b.1), pt(c.0, c.1));
            let held = [&a, &b, &c].map(|p| LoopPoint::from(p.clone()));
            let [fa, fb, fc] = [&held[0], &held[1], &held[2]].map(FilteredPoint::new);
            prop_assert_eq!(orient2d_filtered(&fa, &fb, &fc), orient2d_rat(&a, &b, &c));
        }

        /// Points on one line (and one tiny step off it), where the filter
        /// must give up and the exact path must decide.
        #[test]
        fn filtered_equals_exact_near_collinear(
            p in frac(), q in frac(), s in frac(), t in frac(), u in frac(), off in -2i64..=2
        ) {
            let p0 = pt(p, q);
            let d = pt(s, t);
            let k = Rat::new(u.0.into(), u.1.into());
            let on = Point2 { x: &p0.x + &d.x * &k, y: &p0.y + &d.y * &k };
            let tiny = Rat::new(off.into(), (1i64 << 60).into());
            let near = Point2 { x: &on.x + &tiny, y: on.y.clone() };
            let far = Point2 { x: &p0.x + &d.x, y: &p0.y + &d.y };
            let [l0, lfar] = [&p0, &far].map(|p| LoopPoint::from(p.clone()));
            for c in [&on, &near] {
                let lc = LoopPoint::from(c.clone());
                let [f0, ffar, fc] = [&l0, &lfar, &lc].map(FilteredPoint::new);
                prop_assert_eq!(orient2d_filtered(&f0, &ffar, &fc), orient2d_rat(&p0, &far, c));
            }
        }

        /// Points held as integers `(x 2^e / w, y 2^e / w)`: the enclosure
        /// contains the exact coordinates, and orient2d (also three points
        /// on a line, where the filter must give up) is the exact sign.
        #[test]
        fn integer_points_are_enclosed(
            pts in proptest::collection::vec((proptest::num::i128::ANY, proptest::num::i128::ANY, 1i128..(1 << 100), 0u32..127), 3),
            bits in proptest::collection::vec(1u32..127, 3), e in -1000i32..1000, collinear in proptest::bool::ANY
        ) {
            let mut held: Vec<LoopPoint> = pts.iter().zip(&bits).map(|(&(x, y, w, wb), &b)| {
                let w = (w >> (wb % 100)).max(1);
                LoopPoint::from_integers(x >> (128 - b), y >> (128 - b), w, e).unwrap()
            }).collect();
            if collinear {
                // The midpoint of the first two, over the product of their w.
                let (x0, y0, w0, _) = held[0].as_integers().unwrap();
                let (x1, y1, w1, _) = held[1].as_integers().unwrap();
                let small = |v: i128| v.unsigned_abs() < 1 << 60;
                if [x0, y0, w0, x1, y1, w1].iter().all(|&v| small(v)) {
                    held[2] = LoopPoint::from_integers(x0 * w1 + x1 * w0, y0 * w1 + y1 * w0, 2 * w0 * w1, e).unwrap();
                }
            }
            for p in &held {
                let f = FilteredPoint::new(p);
                let exact = p.exact();
                let (lo, hi) = f.bounds();
                for (k, v) in [&exact.x, &exact.y].into_iter().enumerate() {
                    if lo[k].is_finite() {
                        prop_assert!(crate::exact::rational::rat_from_f64(lo[k]) <= *v);
                    }
                    if hi[k].is_finite() {
                        prop_assert!(crate::exact::rational::rat_from_f64(hi[k]) >= *v);
                    }
                }
            }
            let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
            let exact: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
            prop_assert_eq!(orient2d_filtered(&f[0], &f[1], &f[2]), orient2d_rat(&exact[0], &exact[1], &exact[2]));
            prop_assert_eq!(cmp_y(&f[0], &f[1]), exact[0].y.cmp(&exact[1].y));
        }
    }
}
