//! Input: exact rational points. Output: the exact sign of orient2d, fast.
//!
//! A floating-point filter: every exact value is enclosed in an interval of
//! doubles (the nearest double, widened by one ulp each way), and every
//! operation widens its rounded result outward by one ulp, so the computed
//! interval always contains the exact determinant. When it excludes zero,
//! its sign is the exact sign; otherwise the exact rational determinant
//! decides. Property-tested against the plain rational predicate.

use super::point::Point2;
use super::predicates::{orient2d_rat, Sign};
use super::rational::rat_to_f64;

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

/// The bits of a point's rounded coordinates: equal for equal points (so a
/// cheap hash key), possibly equal for distinct ones.
pub type Key = (u64, u64);

/// An exact point with interval enclosures of its coordinates, computed once.
#[derive(Clone, Debug)]
pub struct FilteredPoint<'a> {
    exact: &'a Point2,
    x: Interval,
    y: Interval,
    key: Key,
}

impl<'a> FilteredPoint<'a> {
    /// Encloses an exact point.
    pub fn new(p: &'a Point2) -> Self {
        let (x, y) = (rat_to_f64(&p.x), rat_to_f64(&p.y));
        FilteredPoint {
            exact: p,
            x: Interval::around(x),
            y: Interval::around(y),
            key: ((x + 0.0).to_bits(), (y + 0.0).to_bits()),
        }
    }

    /// Doubles enclosing the exact point: `([x_lo, y_lo], [x_hi, y_hi])`.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        ([self.x.lo, self.y.lo], [self.x.hi, self.y.hi])
    }

    /// The rounded coordinates as a hash key.
    pub fn key(&self) -> Key {
        self.key
    }

    /// The exact point.
    pub fn exact(&self) -> &'a Point2 {
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
        a.exact.y.cmp(&b.exact.y)
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
        .unwrap_or_else(|| orient2d_rat(a.exact, b.exact, c.exact))
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
            let f: Vec<FilteredPoint<'_>> = poly.iter().map(FilteredPoint::new).collect();
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
            let f = |p| FilteredPoint::new(p);
            prop_assert_eq!(orient2d_filtered(&f(&a), &f(&b), &f(&c)), orient2d_rat(&a, &b, &c));
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
            let f = |p| FilteredPoint::new(p);
            for c in [&on, &near] {
                prop_assert_eq!(orient2d_filtered(&f(&p0), &f(&far), &f(c)), orient2d_rat(&p0, &far, c));
            }
        }
    }
}
