//! Input: exact points. Output: exact signs (loop orientation, orient2d,
//! y-order), fast.
//!
//! Each exact coordinate is approximated once by a double within `2^-50`
//! of it relatively (for a point held as integers `x 2^e / w`: the
//! integers converted, times `w`'s reciprocal; otherwise the nearest
//! double). A
//! loop's orientation is the shoelace on those approximations with an
//! a-priori error bound ([`signed_area_filtered`]). For orient2d and the
//! y-order each approximation gives an interval of doubles (`2^-50` of it
//! each way, widened by one ulp), and every operation widens its rounded
//! result outward by one ulp, so the computed interval always contains the
//! exact value. When a bound or an interval excludes zero, its sign is the
//! exact sign; otherwise exact rational arithmetic decides.
//! Property-tested against the plain rational predicates.

use super::area::shoelace_about_first;
use super::frame::Frame;
use super::homogeneous;
use super::point::LoopPoint;
use super::predicates::{orient2d_points, Sign};
use super::rational::rat_to_f64;

/// A closed interval of doubles known to contain an exact value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    lo: f64,
    hi: f64,
}

impl Interval {
    const EVERYTHING: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The enclosure of an exact value from its approximation `v`
    /// (see [`FilteredPoint`]): `[v - r, v + r]` with `r = 2^-50 |v|` (an
    /// exact product in this range), widened by one ulp each way.
    #[inline]
    fn around(v: f64) -> Interval {
        if v == 0.0 {
            return Interval { lo: 0.0, hi: 0.0 };
        }
        let m = v.abs();
        if !(TINY..).contains(&m) {
            return Interval::EVERYTHING;
        }
        let r = m * REL;
        Interval::widen(v - r, v + r)
    }

    /// A value known exactly.
    #[inline]
    pub(crate) fn at(v: f64) -> Interval {
        Interval { lo: v, hi: v }
    }

    #[inline]
    fn widen(lo: f64, hi: f64) -> Interval {
        Interval {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }

    #[inline]
    pub(crate) fn add(self, o: Interval) -> Interval {
        Interval::widen(self.lo + o.lo, self.hi + o.hi)
    }

    #[inline]
    pub(crate) fn sub(self, o: Interval) -> Interval {
        Interval::widen(self.lo - o.hi, self.hi - o.lo)
    }

    #[inline]
    pub(crate) fn mul(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Interval::EVERYTHING;
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::widen(lo, hi)
    }

    /// The negated interval (exact).
    #[inline]
    pub(crate) fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }

    /// The quotient; everything when the divisor may be zero. Over a
    /// divisor of one sign the quotient is monotone in each argument, so
    /// the four quotients of the ends bound it, each within one ulp.
    #[inline]
    pub(crate) fn div(self, o: Interval) -> Interval {
        if !(o.lo > 0.0 || o.hi < 0.0) {
            return Interval::EVERYTHING;
        }
        let q = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if q.iter().any(|x| x.is_nan()) {
            return Interval::EVERYTHING;
        }
        let lo = q.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::widen(lo, hi)
    }

    /// The order of the exact values two intervals enclose, when they are
    /// disjoint or both single values.
    #[inline]
    fn cmp_with(self, o: Interval) -> Option<std::cmp::Ordering> {
        if self.lo == self.hi && o.lo == o.hi {
            self.lo.partial_cmp(&o.lo)
        } else if self.hi < o.lo {
            Some(std::cmp::Ordering::Less)
        } else if self.lo > o.hi {
            Some(std::cmp::Ordering::Greater)
        } else {
            None
        }
    }

    /// The sign, when the interval decides it (finite and away from zero).
    #[inline]
    pub(crate) fn sign(self) -> Option<Sign> {
        if self.lo > 0.0 && self.lo.is_finite() && self.hi.is_finite() {
            Some(Sign::Positive)
        } else if self.hi < 0.0 && self.lo.is_finite() && self.hi.is_finite() {
            Some(Sign::Negative)
        } else {
            None
        }
    }
}

/// The relative error bound of a point's approximation: `2^-50`.
const REL: f64 = 1.0 / (1u64 << 50) as f64;

/// Below this magnitude an approximation carries no relative bound
/// (subnormal results, and `2^-50 |v|` would not be exact).
const TINY: f64 = f64::from_bits((1023 - 960) << 52);

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

/// The bits of `v` from its highest set bit to its lowest (zero for zero).
#[inline]
fn significant_bits(v: i128) -> u32 {
    let m = v.unsigned_abs();
    if m == 0 {
        0
    } else {
        128 - m.leading_zeros() - m.trailing_zeros()
    }
}

/// Approximations of `x 2^e / w` and `y 2^e / w` (`w > 0`) within
/// `2^-50` of them, relatively: `x`, `y` and `w` converted to doubles
/// (relative error below `1.001u` each, `u = 2^-53`), `w`'s reciprocal
/// taken once (below `u`) and multiplied (below `u`): below `4.01u` in
/// all. `None` out of the range where scaling is exact.
#[inline]
fn approx_pair(x: i128, y: i128, w: i128, e: i32) -> Option<(f64, f64)> {
    // The origin is itself at every scale.
    if x == 0 && y == 0 {
        return Some((0.0, 0.0));
    }
    if !(-900..=900).contains(&e) {
        return None;
    }
    let scale = f64::from_bits(((e + 1023) as u64) << 52);
    // 1 <= w < 2^126: the reciprocal is a normal double.
    let inv = 1.0 / to_f64_within_ulp(w);
    let one = |n: i128| {
        if n == 0 {
            return Some(0.0);
        }
        let v = to_f64_within_ulp(n) * inv * scale;
        (TINY..=1.0 / TINY).contains(&v.abs()).then_some(v)
    };
    Some((one(x)?, one(y)?))
}

/// An exact point with approximations of its coordinates and enclosures
/// derived from them, computed once: each approximation is exactly zero
/// when the coordinate is, else within `2^-50` of it relatively when its
/// magnitude is at least `2^-960`, else NaN (no information); in a frame
/// that scales up, a coordinate whose nearest double is subnormal (or zero)
/// is that double placed, within an absolute error besides (`abs`). A point held
/// as integers over a power of two `w` whose integers are doubles (below
/// `2^53`) and whose scale is exact is its approximation exactly (`is_double`):
/// its enclosure is that one value, and its predicates are decided on the
/// doubles (exact predicates, [`super::predicates`]). So is each coordinate
/// a crossing shares with both ends of its edge
/// ([`LoopPoint::known_doubles`]), where the frame places it exactly; a
/// point with both is a double.
///
/// The approximations are of the point in a [`Frame`] (times `2^s`, the
/// mesh's power of two; the identity for every ordinary mesh), which no
/// sign depends on: every point compared with another must share its
/// frame.
#[derive(Clone, Debug)]
pub struct FilteredPoint<'a> {
    exact: &'a LoopPoint,
    x: f64,
    y: f64,
    is_double: bool,
    /// Whether each approximation is the coordinate exactly (in the
    /// frame), as for every coordinate when `is_double`.
    exact_axes: [bool; 2],
    frame: Frame,
    /// An error bound on top of the relative one, for both coordinates:
    /// zero but where a nearest double is subnormal (or zero for a value
    /// that is not) and the frame scales up: then half the subnormal
    /// spacing in the frame.
    abs: f64,
    /// The enclosures derived from `x` and `y` (see `enclose`).
    ix: Interval,
    iy: Interval,
}

impl<'a> FilteredPoint<'a> {
    /// Approximates an exact point (in the identity frame: for points of
    /// ordinary magnitude) and encloses it.
    pub fn new(p: &'a LoopPoint) -> Self {
        Self::in_frame(p, Frame::IDENTITY)
    }

    /// Approximates an exact point in `frame` and encloses it.
    pub fn in_frame(p: &'a LoopPoint, frame: Frame) -> Self {
        let mut f = Self::approximate(p, frame);
        f.enclose();
        f
    }

    /// Approximates an exact point in `frame`; its enclosures say nothing
    /// (the whole line) until [`FilteredPoint::enclose`]. Enough for the
    /// loop area.
    pub fn approximate(p: &'a LoopPoint, frame: Frame) -> Self {
        let ints = p.as_integers();
        let from_integers =
            ints.and_then(|(x, y, w, e)| approx_pair(x, y, w, e.checked_add(frame.shift())?));
        // Integers of at most 53 significant bits convert exactly (the
        // bits `to_f64_within_ulp` drops are zeros), and approx_pair's
        // scaling by 1 / w (a power of two) and 2^e is exact in its range:
        // then the doubles are the point. So a vertex whose coordinates
        // lie in different binades is a double too.
        let is_double = from_integers.is_some()
            && ints.is_some_and(|(x, y, w, _)| {
                w.count_ones() == 1 && significant_bits(x) <= 53 && significant_bits(y) <= 53
            });
        let (x, y, abs) = from_integers.map_or_else(
            || {
                // The nearest doubles: within 2^-53 relatively when normal, and
                // so placed in the frame (exactly, when normal there too).
                let [x, y] = p.to_f64();
                let [zero_x, zero_y] = p.zero_coordinates();
                let bounded = |v: f64, zero: bool| match frame.place_normal(v) {
                    _ if v == 0.0 && zero => (0.0, 0.0),
                    Some(placed) if v != 0.0 && placed.abs() >= TINY => (placed, 0.0),
                    // Below the normal doubles (the double's own format,
                    // not a tolerance) the rounding errs by at most
                    // `2^-1075`: the error model, not a decision; placed by
                    // scaling up, exactly.
                    _ if frame.shift() > 0 && v.abs() < f64::MIN_POSITIVE => {
                        (frame.place(v), frame.place(f64::from_bits(1)) / 2.0)
                    }
                    _ => (f64::NAN, 0.0),
                };
                let ((x, ex), (y, ey)) = (bounded(x, zero_x), bounded(y, zero_y));
                (x, y, ex.max(ey))
            },
            |(x, y)| (x, y, 0.0),
        );
        // A coordinate known to be a double (an edge parallel to that
        // axis) is its approximation exactly where the frame places it
        // exactly.
        let known = p
            .known_doubles()
            .map(|v| v.and_then(|v| frame.place_normal(v)));
        let [x, y] = [(x, known[0]), (y, known[1])].map(|(a, k)| k.unwrap_or(a));
        let exact_axes = known.map(|k| k.is_some());
        FilteredPoint {
            exact: p,
            x,
            y,
            is_double: is_double || exact_axes == [true, true],
            exact_axes,
            frame,
            abs,
            ix: Interval::EVERYTHING,
            iy: Interval::EVERYTHING,
        }
    }

    /// Computes the enclosures from the approximations.
    pub fn enclose(&mut self) {
        if self.is_double {
            self.ix = Interval::at(self.x);
            self.iy = Interval::at(self.y);
        } else {
            let around = |v: f64| {
                let i = Interval::around(v);
                if self.abs > 0.0 {
                    Interval::widen(i.lo - self.abs, i.hi + self.abs)
                } else {
                    i
                }
            };
            let [ix, iy] = [(self.x, self.exact_axes[0]), (self.y, self.exact_axes[1])]
                .map(|(v, exact)| if exact { Interval::at(v) } else { around(v) });
            self.ix = ix;
            self.iy = iy;
        }
    }

    /// The enclosures of the point's coordinates, in its frame.
    #[inline]
    pub(crate) fn enclosure(&self) -> [Interval; 2] {
        [self.ix, self.iy]
    }

    /// The frame the approximations are in.
    #[inline]
    pub(crate) fn frame(&self) -> Frame {
        self.frame
    }

    /// The exact point as two doubles, when it is exactly them.
    #[inline]
    pub fn as_double(&self) -> Option<[f64; 2]> {
        self.is_double.then_some([self.x, self.y])
    }

    /// Doubles enclosing the exact point: `([x_lo, y_lo], [x_hi, y_hi])`.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let (x, y) = (self.ix, self.iy);
        ([x.lo, y.lo], [x.hi, y.hi])
    }

    /// The exact point.
    pub fn exact(&self) -> &'a LoopPoint {
        self.exact
    }

    /// The nearest doubles of the exact point in the frame (of the point
    /// itself in the identity frame): a monotone rounding, consistent with
    /// [`FilteredPoint::bounds`].
    pub fn rounded(&self) -> [f64; 2] {
        let nearest = self.exact.to_f64();
        if self.frame.is_identity() {
            return nearest;
        }
        let zero = self.exact.zero_coordinates();
        let [x, y] = [0, 1].map(|k| {
            let v = nearest[k];
            (v != 0.0 || zero[k])
                .then(|| self.frame.place_normal(v))
                .flatten()
        });
        // A coordinate subnormal on one side (or rounded to zero): rounded
        // from the exact value in the frame.
        x.zip(y).map_or_else(
            || {
                let p = self.exact.exact();
                [&p.x, &p.y].map(|v| rat_to_f64(&self.frame.scale(v)))
            },
            |(x, y)| [x, y],
        )
    }
}

/// Exact comparison of the y coordinates of two points (filtered).
pub fn cmp_y(a: &FilteredPoint<'_>, b: &FilteredPoint<'_>) -> std::cmp::Ordering {
    a.iy.cmp_with(b.iy)
        .unwrap_or_else(|| homogeneous::cmp_coordinate(a.exact, b.exact, 1))
}

/// Exact comparison of the x coordinates of two points (filtered).
pub fn cmp_x(a: &FilteredPoint<'_>, b: &FilteredPoint<'_>) -> std::cmp::Ordering {
    a.ix.cmp_with(b.ix)
        .unwrap_or_else(|| homogeneous::cmp_coordinate(a.exact, b.exact, 0))
}

/// Exact orientation of three points: the filter when it decides, else the
/// exact determinant ([`homogeneous::orient`]).
pub fn orient2d_filtered(
    a: &FilteredPoint<'_>,
    b: &FilteredPoint<'_>,
    c: &FilteredPoint<'_>,
) -> Sign {
    // Points that are their doubles: Shewchuk's adaptive predicate, whose
    // first stage is a static filter (exact for every finite double).
    if a.is_double && b.is_double && c.is_double {
        return orient2d_points([a.x, a.y], [b.x, b.y], [c.x, c.y]);
    }
    // Two of them one exact point (the points of one run around a vertex
    // on the plane share their limit): the determinant is zero, without
    // the exact values.
    if std::ptr::eq(a.exact, b.exact)
        || std::ptr::eq(b.exact, c.exact)
        || std::ptr::eq(c.exact, a.exact)
    {
        return Sign::Zero;
    }
    let det =
        b.ix.sub(a.ix)
            .mul(c.iy.sub(a.iy))
            .sub(b.iy.sub(a.iy).mul(c.ix.sub(a.ix)));
    det.sign()
        .unwrap_or_else(|| homogeneous::orient(a.exact, b.exact, c.exact))
}

/// A certified estimate of a polygon's signed area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaEstimate {
    /// The exact sign, when the certified error bound excludes zero.
    pub sign: Option<Sign>,
    /// A double within the certified bound of the exact signed area (so
    /// of the exact sign whenever `sign` is known).
    pub approx: f64,
}

/// Estimates the exact signed area of a closed polygon: the shoelace on
/// the approximations in plain doubles with an a-priori error bound, or,
/// when coordinates are out of that bound's range, in interval arithmetic
/// (every operation widened outward by one ulp).
pub fn signed_area_filtered(points: &[FilteredPoint<'_>]) -> AreaEstimate {
    if points.len() < 3 {
        return AreaEstimate {
            sign: Some(Sign::Zero),
            approx: 0.0,
        };
    }
    match signed_area_static(points) {
        Some(decided) if decided.sign.is_some() => decided,
        // A small loop far from the origin: about its first point.
        about_origin => signed_area_about_first(points)
            .or(about_origin)
            .unwrap_or_else(|| signed_area_intervals(points)),
    }
}

/// The shoelace about the first point ([`shoelace_about_first`]) on the
/// approximations, each within `2^-50` of its exact coordinate relatively
/// (so within `REL (1 + 2^-49)` of the approximation); `Some` only when
/// its certified bound decides the sign. Its error grows with the loop's
/// size times its distance from the origin, where [`signed_area_static`]'s
/// grows with the distance squared: a part at `1e9` from the origin.
fn signed_area_about_first(points: &[FilteredPoint<'_>]) -> Option<AreaEstimate> {
    // The approximations' proven relative error, not a tolerance.
    let rel = REL * (1.0 + 2.0 * REL);
    let abs = points.iter().fold(0.0f64, |m, p| m.max(p.abs));
    let (twice, bound) =
        shoelace_about_first(points.len(), |i| [points[i].x, points[i].y], rel, abs)?;
    let sign = sign_beyond(twice, bound)?;
    Some(AreaEstimate {
        sign: Some(sign),
        approx: twice / 2.0,
    })
}

/// The sign of `twice` when the proven error `bound` cannot flip it.
fn sign_beyond(twice: f64, bound: f64) -> Option<Sign> {
    if twice > bound {
        Some(Sign::Positive)
    } else if twice < -bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// The shoelace `S = sum(x_i y_j - x_j y_i)` on the approximations, with
/// `M = sum(|x_i y_j| + |x_j y_i|)`. Each coordinate is within
/// `eps = 2^-50` of its exact value relatively, so each exact product is
/// within `(2 eps + eps^2)` of the product of approximations; rounding the
/// `2n` products and summing them adds at most `u + gamma_2n (1 + u)` of
/// `M` (`u = 2^-53`, `gamma_k = k u / (1 - k u)`), and `M` itself is
/// computed within `gamma_2n`. Hence `|S - 2A| <= (2.03 eps + 1.04 g) M`
/// with `g = (2n + 4) u < 0.01`, and `B = (2.1 eps + 2 g) M` bounds it with
/// room for its own rounding. Coordinates must be zero or in
/// `[2^-480, 2^480]` so that no product underflows or overflows.
fn signed_area_static(points: &[FilteredPoint<'_>]) -> Option<AreaEstimate> {
    const LO: f64 = f64::from_bits((1023 - 480) << 52);
    const HI: f64 = f64::from_bits((1023 + 480) << 52);
    let n = points.len();
    let in_range = |v: f64| v == 0.0 || (LO..=HI).contains(&v.abs());
    // u = EPSILON / 2 is the unit roundoff: `bound` is a proven bound on
    // the rounding error, not a tolerance; when it cannot decide the sign,
    // the caller decides it exactly.
    let g = (2 * n + 4) as f64 * (f64::EPSILON / 2.0);
    // Its bound is relative only: points with an absolute error go on.
    let fits = |p: &FilteredPoint<'_>| in_range(p.x) && in_range(p.y) && p.abs == 0.0;
    if g >= 0.01 || !points.iter().all(fits) {
        return None;
    }
    let (mut twice, mut magnitude) = (0.0f64, 0.0f64);
    let mut prev = &points[n - 1];
    for p in points {
        let (a, b) = (prev.x * p.y, p.x * prev.y);
        twice += a - b;
        magnitude += a.abs() + b.abs();
        prev = p;
    }
    let bound = (2.1 * REL + 2.0 * g) * magnitude;
    Some(AreaEstimate {
        sign: sign_beyond(twice, bound),
        approx: twice / 2.0,
    })
}

/// An enclosure of twice the signed area of a closed polygon: the
/// shoelace on the points' enclosures, every operation widened outward.
pub(crate) fn twice_area_enclosure(points: &[FilteredPoint<'_>]) -> Interval {
    let n = points.len();
    let mut twice = Interval { lo: 0.0, hi: 0.0 };
    for i in 0..n {
        let (p, q) = (&points[i], &points[(i + 1) % n]);
        twice = twice.add(p.ix.mul(q.iy).sub(q.ix.mul(p.iy)));
    }
    twice
}

/// The shoelace in interval arithmetic.
fn signed_area_intervals(points: &[FilteredPoint<'_>]) -> AreaEstimate {
    let twice = twice_area_enclosure(points);
    // Halving is exact (barring underflow, which the widening covers).
    let (lo, hi) = ((twice.lo / 2.0).next_down(), (twice.hi / 2.0).next_up());
    let area = Interval { lo, hi };
    AreaEstimate {
        sign: area.sign(),
        approx: lo / 2.0 + hi / 2.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::area::signed_area_reference;
    use crate::exact::point::Point2;
    use crate::exact::predicates::orient2d_rat;
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

    /// Integers of at most 53 significant bits are doubles wherever
    /// they lie (a vertex whose coordinates are in different binades, as
    /// `(37.3, 0.01)`); 54 bits are not. Hand-made: the exact values are
    /// read back from the integers.
    #[test]
    fn doubles_by_their_significant_bits() {
        let vertex = LoopPoint::of_vertex([37.3, 0.01, 0.0]);
        let f = FilteredPoint::new(&vertex);
        assert_eq!(f.as_double(), Some([37.3, 0.01]));
        let wide = ((1i128 << 53) - 1) << 70;
        let far = LoopPoint::from_integers(wide, -3, 4, -2).unwrap();
        let [x, y] = FilteredPoint::new(&far).as_double().unwrap();
        let exact = far.exact();
        assert_eq!(
            (Rat::from_float(x).unwrap(), Rat::from_float(y).unwrap()),
            (exact.x.clone(), exact.y.clone())
        );
        let odd = LoopPoint::from_integers((1i128 << 53) + 1, 1, 1, 0).unwrap();
        assert_eq!(FilteredPoint::new(&odd).as_double(), None);
        assert_eq!(
            (
                significant_bits(0),
                significant_bits(-12),
                significant_bits(wide)
            ),
            (0, 2, 53)
        );
    }

    /// A triangle of thirds and sevenths at `1e9` from the origin: the
    /// shoelace about the origin cannot tell its sign (its error grows
    /// with `1e18`), the one about its first point can.
    #[test]
    fn small_loop_far_from_the_origin_is_decided_by_the_filter() {
        let o = 1_000_000_000i64;
        let held: Vec<LoopPoint> = [(1, 3, 1, 7), (7, 3, 2, 7), (4, 3, 12, 7)]
            .map(|(a, b, c, d)| LoopPoint::from(pt((3 * o + a, b), (7 * o + c, d))))
            .into();
        let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
        assert_eq!(signed_area_static(&f).and_then(|a| a.sign), None);
        assert_eq!(signed_area_filtered(&f).sign, Some(Sign::Positive));
    }

    /// A triangle of rational points among the subnormals (their nearest
    /// doubles subnormal): in its frame the filter decides its orientation
    /// and each orient2d, with the doubles' absolute error.
    #[test]
    fn subnormal_points_are_decided_in_their_frame() {
        let tiny = Rat::new(1.into(), 3.into()) * Rat::from_integer(2.into()).pow(-1040);
        let held: Vec<LoopPoint> = [(0, 0), (7, 1), (2, 5)]
            .map(|(x, y)| {
                let p = pt((x, 1), (y, 1)).scaled(&tiny);
                LoopPoint::from(p)
            })
            .into();
        assert!(held[1].to_f64()[0].abs() < f64::MIN_POSITIVE);
        let frame = Frame::for_points(held.iter().map(LoopPoint::to_f64));
        let f: Vec<FilteredPoint<'_>> = held
            .iter()
            .map(|p| FilteredPoint::in_frame(p, frame))
            .collect();
        assert_eq!(signed_area_filtered(&f).sign, Some(Sign::Positive));
        assert!(f[1].abs > 0.0);
        let det = b_minus_a_cross(&f);
        assert_eq!(det.sign(), Some(Sign::Positive));
    }

    /// The interval determinant of `orient2d_filtered` for three points.
    fn b_minus_a_cross(f: &[FilteredPoint<'_>]) -> Interval {
        let (a, b, c) = (&f[0], &f[1], &f[2]);
        b.ix.sub(a.ix)
            .mul(c.iy.sub(a.iy))
            .sub(b.iy.sub(a.iy).mul(c.ix.sub(a.ix)))
    }

    /// A double drawn across the range (mantissa and exponent).
    fn any_double() -> impl Strategy<Value = f64> {
        (-(1i64 << 53)..(1i64 << 53), -1000i32..960)
            .prop_map(|(m, e)| crate::exact::scale::times_pow2(m as f64, e))
    }

    proptest! {
        /// The quotient of two intervals holds every quotient of their
        /// members (here their ends, where the extremes lie) and is a few
        /// units in the last place wide when they are single doubles.
        #[test]
        fn quotients_are_enclosed(
            [a, b, c, d] in proptest::array::uniform4(any_double()),
        ) {
            let rat = crate::exact::rational::rat_from_f64;
            let (n, m) = (Interval::widen(a.min(b), a.max(b)), Interval::widen(c.min(d), c.max(d)));
            let q = n.div(m);
            if m.lo > 0.0 || m.hi < 0.0 {
                for x in [n.lo, n.hi] {
                    for y in [m.lo, m.hi] {
                        let exact = rat(x) / rat(y);
                        prop_assert!(q.lo == f64::NEG_INFINITY || rat(q.lo) <= exact);
                        prop_assert!(q.hi == f64::INFINITY || exact <= rat(q.hi));
                    }
                }
            } else {
                prop_assert_eq!(q, Interval::EVERYTHING);
            }
            if c != 0.0 {
                let q = Interval::at(a).div(Interval::at(c));
                let exact = rat(a) / rat(c);
                prop_assert!(q.lo == f64::NEG_INFINITY || rat(q.lo) <= exact);
                prop_assert!(q.hi == f64::INFINITY || exact <= rat(q.hi));
                let r = a / c;
                // The width claim is made where the rounded quotient is a
                // normal double away from overflow (a test's precondition,
                // not a tolerance: nothing here decides a sign).
                if r.is_normal() && r.abs() < f64::MAX / 4.0 {
                    prop_assert!(q.lo >= r.next_down() && q.hi <= r.next_up());
                }
            }
        }

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

        /// The static bound on points held as integers (long, thin and
        /// degenerate polygons: a line with one point a tiny step off).
        #[test]
        fn static_area_bound_is_certified(
            pts in proptest::collection::vec((-(1i128 << 100)..(1i128 << 100), -(1i128 << 100)..(1i128 << 100), 1i128..(1 << 60)), 3..200),
            e in -200i32..200, thin in 0u8..3, off in -3i128..=3
        ) {
            let mut held: Vec<LoopPoint> = pts.iter().map(|&(x, y, w)| LoopPoint::from_integers(x, y, w, e).unwrap()).collect();
            if thin > 0 {
                // Every point on the line y = 3x (over w), one moved by `off`.
                for (i, p) in held.iter_mut().enumerate() {
                    let (x, _, w, _) = p.as_integers().unwrap();
                    let x = x >> 2;
                    let y = 3 * x + if i == 1 { off } else { 0 };
                    *p = LoopPoint::from_integers(x, y, w, e).unwrap();
                }
            }
            let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
            let exact_points: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
            let exact = crate::exact::area::signed_area_reference(&exact_points);
            let est = signed_area_filtered(&f);
            if let Some(s) = est.sign {
                prop_assert_eq!(s, Sign::of_rat(&exact));
                if s != Sign::Zero {
                    prop_assert_eq!(Sign::of_rat(&crate::exact::rational::rat_from_f64(est.approx)), s);
                }
            }
            if let Some(st) = signed_area_static(&f) {
                if let Some(s) = st.sign {
                    prop_assert_eq!(s, Sign::of_rat(&exact));
                }
            }
        }

        /// Loops of small rational steps far from the origin (at `k 2^s`,
        /// `s` up to 80, or a decimal), some nearly degenerate: the
        /// shoelace about the first point, when it decides, gives the exact
        /// sign, and so does the whole filter.
        #[test]
        fn area_about_the_first_point_is_certified_far_from_the_origin(
            steps in proptest::collection::vec(((-40i64..40, 1i64..64), (-40i64..40, 1i64..64)), 3..40),
            (k, s) in (1i64..1 << 20, 0i32..60),
            decimal in proptest::bool::ANY,
            thin in proptest::bool::ANY,
        ) {
            let o = if decimal {
                Rat::new((k * 1_000_003).into(), 1000.into())
            } else {
                Rat::from_integer(num_bigint::BigInt::from(k) << s)
            };
            let mut poly: Vec<Point2> = steps
                .iter()
                .map(|&((a, b), (c, d))| Point2 {
                    x: &o + Rat::new(a.into(), b.into()),
                    y: &o * Rat::from_integer(2.into()) + Rat::new(c.into(), d.into()),
                })
                .collect();
            if thin {
                // On the line through the first point with slope 3, one point
                // a 2^-60 step off.
                let (x0, y0) = (poly[0].x.clone(), poly[0].y.clone());
                for (i, p) in poly.iter_mut().enumerate().skip(1) {
                    let off = Rat::new((i64::from(i == 1)).into(), (1i64 << 60).into());
                    p.y = &y0 + (&p.x - &x0) * Rat::from_integer(3.into()) + off;
                }
            }
            let held: Vec<LoopPoint> = poly.iter().cloned().map(LoopPoint::from).collect();
            let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
            let exact = Sign::of_rat(&crate::exact::area::signed_area_reference(&poly));
            if let Some(a) = signed_area_about_first(&f) {
                prop_assert_eq!(a.sign, Some(exact));
            }
            if let Some(s) = signed_area_filtered(&f).sign {
                prop_assert_eq!(s, exact);
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

        /// A loop of fractions multiplied by any power of two `2^k`, held as
        /// rationals (nearest doubles, as crossings keep them) or as
        /// integers: in the frame of its magnitude, every filtered sign
        /// (area, orient2d, y- and x-order) is the exact sign, the frame's
        /// nearest doubles lie within the enclosures, and the area is
        /// decided wherever it is at `k = 0` and the nearest doubles at
        /// `2^k` are normal.
        #[test]
        fn framed_filters_are_exact_at_every_scale(
            pts in proptest::collection::vec((frac(), frac()), 3..12),
            k in -1100i32..1030, as_integers in proptest::bool::ANY
        ) {
            let two = Rat::from_integer(2.into()).pow(k);
            let exact: Vec<Point2> = pts.iter().map(|&(x, y)| pt(x, y).scaled(&two)).collect();
            let held: Vec<LoopPoint> = if as_integers {
                // Over the product-free denominator 1: integer numerators.
                pts.iter()
                    .map(|&((xn, _), (yn, _))| LoopPoint::from_integers(xn.into(), yn.into(), 1, k).unwrap())
                    .collect()
            } else {
                exact.iter().cloned().map(LoopPoint::from).collect()
            };
            let exact: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
            let frame = Frame::for_points(held.iter().map(LoopPoint::to_f64));
            let f: Vec<FilteredPoint<'_>> = held.iter().map(|p| FilteredPoint::in_frame(p, frame)).collect();
            let area = Sign::of_rat(&signed_area_reference(&exact));
            let estimate = signed_area_filtered(&f).sign;
            if let Some(s) = estimate {
                prop_assert_eq!(s, area);
            }
            prop_assert_eq!(orient2d_filtered(&f[0], &f[1], &f[2]), orient2d_rat(&exact[0], &exact[1], &exact[2]));
            prop_assert_eq!(cmp_y(&f[0], &f[1]), exact[0].y.cmp(&exact[1].y));
            prop_assert_eq!(cmp_x(&f[1], &f[2]), exact[1].x.cmp(&exact[2].x));
            for p in &f {
                let (lo, hi) = p.bounds();
                let r = p.rounded();
                for c in 0..2 {
                    prop_assert!(lo[c] <= r[c] && r[c] <= hi[c]);
                }
            }
            // At k = 0, in the identity frame.
            let held0: Vec<LoopPoint> = pts.iter().map(|&(x, y)| LoopPoint::from(pt(x, y))).collect();
            let f0: Vec<FilteredPoint<'_>> = held0.iter().map(FilteredPoint::new).collect();
            let normal = held.iter().all(|p| {
                p.to_f64().iter().zip(p.zero_coordinates()).all(|(&v, zero)| zero || (v.abs() > f64::MIN_POSITIVE && v.is_finite()))
            });
            if !as_integers && normal && signed_area_filtered(&f0).sign.is_some() {
                prop_assert!(estimate.is_some(), "undecided at 2^{}", k);
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

        /// Points that are their doubles (integers over 1, below 2^53, any
        /// grid exponent): single-value enclosures and the double
        /// predicates agree with the rationals, on lines and off them.
        #[test]
        fn double_points_decide_like_the_rationals(
            xs in proptest::collection::vec(-(1i128 << 53)..=(1i128 << 53), 6),
            e in -900i32..900, line in 0u8..3, ws in proptest::collection::vec(0u32..126, 3)
        ) {
            let mut v = xs.clone();
            if line == 1 {
                // c on the line through a and b (a + 2 (b - a)), if it fits.
                let (cx, cy) = (2 * v[2] - v[0], 2 * v[3] - v[1]);
                if cx.unsigned_abs() <= 1 << 53 && cy.unsigned_abs() <= 1 << 53 {
                    v[4] = cx;
                    v[5] = cy;
                }
            } else if line == 2 {
                v[3] = v[1]; // a and b share y
            }
            // Over 1, or over powers of two (the line through a and b is
            // then built over 1, so only `line == 2` mixes them).
            let w = |i: usize| if line == 1 { 1 } else { 1i128 << ws[i] };
            let held: Vec<LoopPoint> = (0..3).map(|i| LoopPoint::from_integers(v[2 * i], v[2 * i + 1], w(i), e).unwrap()).collect();
            let f: Vec<FilteredPoint<'_>> = held.iter().map(FilteredPoint::new).collect();
            let exact: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
            prop_assert_eq!(orient2d_filtered(&f[0], &f[1], &f[2]), orient2d_rat(&exact[0], &exact[1], &exact[2]));
            prop_assert_eq!(cmp_y(&f[0], &f[1]), exact[0].y.cmp(&exact[1].y));
            prop_assert_eq!(cmp_x(&f[0], &f[2]), exact[0].x.cmp(&exact[2].x));
        }
    }
}
