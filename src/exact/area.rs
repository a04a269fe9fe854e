//! Input: a closed polygon of exact rational points. Output: its exact
//! signed area (shoelace), or a certified enclosure of it.
//!
//! Crossings at one level usually have distinct denominators (one per
//! edge), so the exact area of a loop of `n` points has a denominator of
//! about `n` times their size. Adding the `n` shoelace terms one by one
//! (each addition reducing by a big gcd) is quadratic in that size, which
//! made large loops cost seconds; here the terms are summed on a balanced
//! tree of unreduced fractions sharing neighbours' denominators, and the
//! result is reduced by the (small) point denominators one at a time, never
//! by a big gcd.

use super::frame::Frame;
use super::point::{gcd_u128, LoopPoint, Point2};
use super::rational::{rat_to_f64, Rat};
use num_bigint::{BigInt, BigUint};
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

/// A point as integers over one denominator: `(X / D, Y / D)`, `D > 0`.
struct Homogeneous {
    x: BigInt,
    y: BigInt,
    d: BigInt,
}

/// An exact point the shoelace can take: written over one denominator.
pub trait ExactPoint {
    /// `(X, Y, D)` with the point `(X / D, Y / D)`, `D > 0`.
    fn over_one_denominator(&self) -> (BigInt, BigInt, BigInt);

    /// An upper bound on the bits of that `D`, without building it.
    fn denominator_bits(&self) -> u64;
}

impl ExactPoint for Point2 {
    fn over_one_denominator(&self) -> (BigInt, BigInt, BigInt) {
        let (dx, dy) = (self.x.denom(), self.y.denom());
        if dx == dy {
            return (self.x.numer().clone(), self.y.numer().clone(), dx.clone());
        }
        let d = dx.lcm(dy);
        (self.x.numer() * (&d / dx), self.y.numer() * (&d / dy), d)
    }

    fn denominator_bits(&self) -> u64 {
        self.x.denom().bits() + self.y.denom().bits()
    }
}

impl ExactPoint for LoopPoint {
    /// Over the least common denominator: the integers' common factor and
    /// the powers of two shared with `2^e` are cancelled in `i128` first,
    /// so the exact area's products stay as small as the reduced points'.
    fn over_one_denominator(&self) -> (BigInt, BigInt, BigInt) {
        let Some((x, y, w, e)) = self.as_integers() else {
            return self.exact().over_one_denominator();
        };
        if x == 0 && y == 0 {
            return (BigInt::zero(), BigInt::zero(), BigInt::one());
        }
        let g = gcd_u128(
            gcd_u128(x.unsigned_abs(), y.unsigned_abs()),
            w.unsigned_abs(),
        ) as i128;
        let (x, y, w) = (x / g, y / g, w / g);
        let tz = |v: i128| if v == 0 { 128 } else { v.trailing_zeros() };
        if e >= 0 {
            let t = w.trailing_zeros().min(e as u32);
            let e = e as u32 - t;
            (
                BigInt::from(x) << e,
                BigInt::from(y) << e,
                BigInt::from(w >> t),
            )
        } else {
            let t = tz(x).min(tz(y)).min(e.unsigned_abs());
            let k = e.unsigned_abs() - t;
            (
                BigInt::from(x >> t),
                BigInt::from(y >> t),
                BigInt::from(w) << k,
            )
        }
    }

    fn denominator_bits(&self) -> u64 {
        match self.as_integers() {
            Some((_, _, w, e)) => {
                u64::from(128 - w.leading_zeros()) + u64::from(e.min(0).unsigned_abs())
            }
            None => self
                .lazy_denominator_bits()
                .unwrap_or_else(|| self.exact().denominator_bits()),
        }
    }
}

/// The unit roundoff of `f64`, `u = 2^-53`: the bounds below are proven
/// bounds on rounding error, not tolerances; a sign they cannot decide is
/// decided exactly.
const U: f64 = f64::EPSILON / 2.0;

/// The signed area of a closed polygon from the nearest doubles `q` of its
/// exact points, when a certified bound shows its sign; `None` otherwise
/// (the caller then rounds the exact area). [`shoelace_about_first`] with
/// the nearest doubles' relative error `u = 2^-53`.
///
/// A loop at the ends of the double range (beyond `2^±200`) is computed in
/// the [`Frame`] of its magnitude instead (its subnormal coordinates with
/// their absolute error): the same value, scaled by the frame's exact
/// power of two, when it is normal in both; else, when the
/// bound shows the exact area beyond the largest double, an infinity of
/// its sign, and when it shows it below half the least subnormal (so it
/// rounds to zero), a zero of its sign.
pub fn rounded_area(q: &[[f64; 2]]) -> Option<f64> {
    // Output only: the `area` number written without `--exact`. No decision
    // reads it (orientation, roles and nesting use exact signs).
    let certified = |(twice, bound): (f64, f64)| twice.abs() > bound && twice.is_finite();
    match shoelace_about_first(q.len(), |i| q[i], U, 0.0) {
        Some(t) if certified(t) => return Some(t.0 / 2.0),
        _ => {}
    }
    let frame = Frame::for_points(q.iter().copied());
    if frame.is_identity() {
        return None;
    }
    // Within `u` of the exact values in the frame (see `place_normal`); a
    // frame that scales up places every double exactly, and a subnormal or
    // zero in `q` errs by at most `2^-1075`: `2^(s - 1075)` in the frame.
    let scales_up = frame.shift() > 0;
    let place = |v: f64| {
        if scales_up {
            Some(frame.place(v)).filter(|p| p.is_finite())
        } else {
            frame.place_normal(v)
        }
    };
    let placed: Vec<[f64; 2]> = q
        .iter()
        .map(|&[x, y]| Some([place(x)?, place(y)?]))
        .collect::<Option<_>>()?;
    let hidden = frame.place(f64::from_bits(1)) / 2.0;
    let (twice, bound) = shoelace_about_first(q.len(), |i| placed[i], U, hidden)?;
    if !certified((twice, bound)) {
        return None;
    }
    let half = twice / 2.0;
    if let Some(area) = frame.back_area(half) {
        return Some(area);
    }
    // `|A| 2^2s` lies within `[lo, hi]` (rounded outward).
    let lo = ((twice.abs() - bound) / 2.0).next_down();
    let hi = ((twice.abs() + bound) / 2.0).next_up();
    if lo > frame.place_area(f64::MAX) {
        Some(f64::INFINITY.copysign(twice))
    } else if hi < frame.place_area(f64::from_bits(1)) / 2.0 {
        Some(0.0f64.copysign(twice))
    } else {
        None
    }
}

/// Twice the signed area of a closed polygon of `n` points and a bound on
/// its error, from approximations `q(i)` of its exact points `p_i`, each
/// coordinate within `rel |q| + abs` of the exact one (`rel` at least `u`;
/// `abs` for approximations that may be zero, or subnormal, where the
/// exact value is not: a rounding below the least normal double, placed in
/// a [`Frame`]).
///
/// The shoelace is taken relative to the first point,
/// `2A = sum_i D_i x D_{i+1}` with `D_i = q_i - q_0` in doubles, so that the
/// error scales with the loop's own size, not with its distance from the
/// origin. With `u = 2^-53`, `m` the largest coordinate magnitude, `d` the
/// largest `|D_i|` coordinate and `T = sum |Dx_i Dy_{i+1}| + |Dy_i Dx_{i+1}|`:
/// each exact `p_i` is within `rel |q_i| + abs` of `q_i` per coordinate,
/// and each `D_i` within `u |D_i|` of `q_i - q_0`, so
/// `D_i = P_i + E_i` (`P_i = p_i - p_0`) with
/// `|E_i| <= e = 2 rel m + 1.01 u d + 2^-1073 + 2 abs` (the third term for
/// subnormal roundings). Then `|D_i x D_{i+1} - P_i x P_{i+1}| <= 4 e (d + e) + 2 e^2`,
/// and evaluating the sum of the `2n` products in doubles adds at most
/// `gamma_{2n+2} T` (`gamma_k = k u / (1 - k u)`) plus `2n 2^-1074` for
/// underflows. So
///
/// `|computed 2A - exact 2A| <= n (4 e (d + e) + 2 e^2) + gamma_{2n+2} T + 4n 2^-1074`,
///
/// about `n d (8 rel m + 4u d)`: relative to the loop's size `d` times its
/// distance `m` from the origin, never `m^2`. The bound itself is evaluated
/// in doubles with a relative margin of `2^-20` (it has fewer than `3n + 20`
/// roundings, each below `u`). Coordinates must lie within `2^500` and
/// `n < 2^20`, so nothing overflows; else `None` (also for a NaN).
pub fn shoelace_about_first(
    n: usize,
    q: impl Fn(usize) -> [f64; 2],
    rel: f64,
    abs: f64,
) -> Option<(f64, f64)> {
    if n < 3 {
        return Some((0.0, 0.0));
    }
    // The range in which the bound is proven (nothing overflows), not a
    // tolerance: outside it the caller takes the exact area.
    let limit = f64::from_bits((1023 + 500) << 52);
    if n >= 1 << 20 || !(0..n).flat_map(&q).all(|v| v.abs() <= limit) {
        return None;
    }
    let [x0, y0] = q(0);
    let (mut m, mut d) = (0.0f64, 0.0f64);
    let (mut twice, mut magnitude) = (0.0f64, 0.0f64);
    let mut prev = [0.0, 0.0];
    for p in (1..n).chain(std::iter::once(0)).map(&q) {
        let cur = [p[0] - x0, p[1] - y0];
        m = m.max(p[0].abs()).max(p[1].abs());
        d = d.max(cur[0].abs()).max(cur[1].abs());
        let (a, b) = (prev[0] * cur[1], prev[1] * cur[0]);
        twice += a - b;
        magnitude += a.abs() + b.abs();
        prev = cur;
    }
    // `2^-1074`; `e` with `rel = u` and `abs = 0` takes the same
    // operations as `u (2m + 1.01d) + 2^-1073` (adding zero is exact).
    let tiny = f64::from_bits(1);
    let e = (U * (2.0 * (rel / U) * m + 1.01 * d) + 2.0 * tiny) + 2.0 * abs;
    let k = (2 * n + 2) as f64 * U;
    let gamma = k / (1.0 - k);
    let nf = n as f64;
    let bound = (nf * (4.0 * e * (d + e) + 2.0 * e * e) + gamma * magnitude + 4.0 * nf * tiny)
        * (1.0 + f64::from_bits((1023 - 20) << 52));
    Some((twice, bound))
}

/// Exact signed area of a closed polygon (shoelace): positive when
/// counter-clockwise. Exact for any rational points; equal to
/// [`signed_area_reference`] (property-tested).
pub fn signed_area<P: ExactPoint>(points: &[P]) -> Rat {
    total_signed_area([points])
}

/// The exact sum of the signed areas of closed polygons (the area a
/// family of nested loops encloses), reduced once at the end.
pub fn total_signed_area<'a, P: ExactPoint + 'a>(
    polygons: impl IntoIterator<Item = &'a [P]>,
) -> Rat {
    AreaSum::of(polygons).reduce()
}

/// An exact signed area held as an unreduced fraction: rounding it is
/// cheap (near-linear), reducing it to lowest terms costs about the
/// number of points times the size of the denominator.
#[derive(Clone, Debug)]
pub struct AreaSum {
    twice: BigInt,
    product: BigInt,
    factors: Vec<BigUint>,
}

impl AreaSum {
    /// The summed signed area of closed polygons.
    pub fn of<'a, P: ExactPoint + 'a>(polygons: impl IntoIterator<Item = &'a [P]>) -> AreaSum {
        let mut parts: Vec<(BigInt, BigInt)> = Vec::new();
        let mut factors: Vec<BigUint> = vec![BigUint::from(2u8)];
        for points in polygons {
            let n = points.len();
            if n < 3 {
                // Two points bound nothing: the two terms cancel.
                continue;
            }
            let h: Vec<Homogeneous> = points
                .iter()
                .map(|p| {
                    let (x, y, d) = p.over_one_denominator();
                    Homogeneous { x, y, d }
                })
                .collect();
            // Twice the area of the open chain 0..n-1, over the product of all D.
            let (chain, product) = chain_sum(&h, 0, n - 1);
            let (first, last) = (&h[0], &h[n - 1]);
            let closing = &last.x * &first.y - &first.x * &last.y;
            parts.push((chain + closing * (&product / (&first.d * &last.d)), product));
            factors.extend(h.iter().map(|p| p.d.magnitude().clone()));
        }
        let (twice, product) =
            sum_fractions(parts).unwrap_or_else(|| (BigInt::zero(), BigInt::one()));
        AreaSum {
            twice,
            product,
            factors,
        }
    }

    /// The nearest double of the exact area.
    pub fn to_f64(&self) -> f64 {
        rat_to_f64(&Rat::new_raw(self.twice.clone(), &self.product * 2))
    }

    /// An upper bound on [`AreaSum::denominator_bits`] of the same
    /// polygons, from the points' denominators alone (linear time, no big
    /// numbers): to decide whether the exact sum is worth building.
    pub fn denominator_bits_bound<'a, P: ExactPoint + 'a>(
        polygons: impl IntoIterator<Item = &'a [P]>,
    ) -> u64 {
        let points: u64 = polygons
            .into_iter()
            .filter(|p| p.len() >= 3)
            .flatten()
            .map(ExactPoint::denominator_bits)
            .sum();
        points + 2
    }

    /// Bits of the unreduced denominator: an upper bound on the reduced
    /// one's, and what [`AreaSum::reduce`] costs grows with.
    pub fn denominator_bits(&self) -> u64 {
        self.product.bits() + 1
    }

    /// Whether the exact area is `r`: one cross-multiplication, no
    /// reduction (a claimed area in lowest terms is checked, and then
    /// taken, at the cost of a product).
    pub fn is(&self, r: &Rat) -> bool {
        &self.twice * r.denom() == r.numer() * (&self.product * 2)
    }

    /// The exact area in lowest terms.
    pub fn reduce(self) -> Rat {
        if self.twice.is_zero() {
            return Rat::zero();
        }
        lowest_terms(self.twice, self.product * 2, self.factors)
    }
}

/// The sum of fractions `a / p` (`p > 0`) as one unreduced fraction over
/// the product of the `p`, added on a balanced tree.
fn sum_fractions(mut parts: Vec<(BigInt, BigInt)>) -> Option<(BigInt, BigInt)> {
    while parts.len() > 1 {
        let mut next = Vec::with_capacity(parts.len().div_ceil(2));
        let mut it = parts.into_iter();
        while let Some((a1, p1)) = it.next() {
            next.push(match it.next() {
                Some((a2, p2)) => (a1 * &p2 + a2 * &p1, p1 * p2),
                None => (a1, p1),
            });
        }
        parts = next;
    }
    parts.pop()
}

/// `(A, P)` with `A / P` the sum of the shoelace terms of consecutive
/// points `l..=r` (`r > l`) and `P` the product of their denominators:
/// neighbouring halves share the middle point's denominator, so nothing
/// is ever multiplied in twice.
fn chain_sum(h: &[Homogeneous], l: usize, r: usize) -> (BigInt, BigInt) {
    if r == l + 1 {
        let (a, b) = (&h[l], &h[r]);
        return (&a.x * &b.y - &b.x * &a.y, &a.d * &b.d);
    }
    let m = (l + r) / 2;
    let (a1, p1) = chain_sum(h, l, m);
    let (a2, p2) = chain_sum(h, m, r);
    let dm = &h[m].d;
    let (q1, q2) = (&p1 / dm, &p2 / dm);
    (a1 * &q2 + a2 * q1, p1 * q2)
}

/// `num / den` (`num != 0`) in lowest terms, where `den` is the product
/// of `factors` (small numbers, or small ones times large powers of two,
/// as the denominators of a mesh near `1e-300` are).
///
/// The common power of two goes first, by shifts: then `num` or `den` is
/// odd, and `den = 2^r F` with `F` the product of the factors' odd parts
/// and `r = 0` or `num` odd. The common odd part is removed factor by
/// factor, each step a division by a small odd number, so no gcd of two
/// big numbers is ever taken; `den = 2^r F` holds throughout, with `F`
/// the product of what is left of the factors. Afterwards every odd part
/// is coprime to the numerator, hence so is `den`.
fn lowest_terms(num: BigInt, den: BigInt, factors: Vec<BigUint>) -> Rat {
    let negative = num.is_negative();
    let (mut num, mut den) = (num.into_parts().1, den.into_parts().1);
    let twos = |v: &BigUint| v.trailing_zeros().unwrap_or(0);
    let shift = twos(&num).min(twos(&den));
    num >>= shift;
    den >>= shift;
    for f in factors {
        let mut f = &f >> twos(&f);
        while !f.is_one() {
            let g = (&num % &f).gcd(&f);
            if g.is_one() {
                break;
            }
            num /= &g;
            den /= &g;
            f /= &g;
        }
    }
    let num = BigInt::from(num);
    Rat::new_raw(if negative { -num } else { num }, BigInt::from(den))
}

/// The shoelace with rational arithmetic throughout: the reference.
pub fn signed_area_reference(points: &[Point2]) -> Rat {
    let n = points.len();
    let mut twice = Rat::zero();
    for i in 0..n {
        let p = &points[i];
        let q = &points[(i + 1) % n];
        twice += &p.x * &q.y - &q.x * &p.y;
    }
    twice / Rat::from_integer(2.into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;
    use crate::exact::Sign;

    /// `((p, q), (r, s))` is the point `(p/q, r/s)`.
    type Frac2 = ((i64, i64), (i64, i64));

    fn poly(pts: &[Frac2]) -> Vec<Point2> {
        pts.iter()
            .map(|&((a, b), (c, d))| Point2 {
                x: Rat::new(a.into(), b.into()),
                y: Rat::new(c.into(), d.into()),
            })
            .collect()
    }

    proptest::proptest! {
        /// The tree sum with small-factor reduction equals the rational
        /// shoelace, in lowest terms (shared, repeated and coprime
        /// denominators; zero areas).
        #[test]
        fn tree_area_equals_the_reference(
            pts in proptest::collection::vec(((-1000i64..1000, 1i64..60), (-1000i64..1000, 1i64..60)), 0..40)
        ) {
            let poly = poly(&pts);
            let fast = signed_area(&poly);
            let reference = signed_area_reference(&poly);
            proptest::prop_assert_eq!(fast.numer(), reference.numer());
            proptest::prop_assert_eq!(fast.denom(), reference.denom());
            // The cheap bound bounds the unreduced denominator, for both
            // kinds of points (rationals, and integers over w 2^-e).
            let sum = AreaSum::of([poly.as_slice()]);
            proptest::prop_assert!(AreaSum::denominator_bits_bound([poly.as_slice()]) >= sum.denominator_bits());
            // Points held as integers (x 2^e / w): the same exact area, for
            // exponents of both signs and common factors to cancel.
            for e in [-3, 0, 4] {
                let held: Vec<LoopPoint> = pts
                    .iter()
                    .map(|&((a, b), (c, d))| {
                        LoopPoint::from_integers((2 * a * d).into(), (2 * c * b).into(), (6 * b * d).into(), e).unwrap()
                    })
                    .collect();
                let sum = AreaSum::of([held.as_slice()]);
                proptest::prop_assert!(AreaSum::denominator_bits_bound([held.as_slice()]) >= sum.denominator_bits());
                let exact: Vec<Point2> = held.iter().map(|p| p.exact().into_owned()).collect();
                proptest::prop_assert_eq!(signed_area(&held), signed_area_reference(&exact));
            }
        }
    }

    proptest::proptest! {
        /// The total of several polygons equals the sum of their areas.
        #[test]
        fn total_area_is_the_sum(
            a in proptest::collection::vec(((-99i64..99, 1i64..30), (-99i64..99, 1i64..30)), 0..12),
            b in proptest::collection::vec(((-99i64..99, 1i64..30), (-99i64..99, 1i64..30)), 0..12),
        ) {
            let (a, b) = (poly(&a), poly(&b));
            let total = total_signed_area([a.as_slice(), b.as_slice()]);
            let expect = signed_area_reference(&a) + signed_area_reference(&b);
            // Rounding the unreduced fraction gives the nearest double.
            proptest::prop_assert_eq!(AreaSum::of([a.as_slice(), b.as_slice()]).to_f64(), rat_to_f64(&expect));
            proptest::prop_assert_eq!(total, expect);
        }
    }

    #[test]
    fn square_area_and_orientation() {
        let sq = poly(&[
            ((0, 1), (0, 1)),
            ((2, 1), (0, 1)),
            ((2, 1), (2, 1)),
            ((0, 1), (2, 1)),
        ]);
        assert_eq!(signed_area(&sq), Rat::from_integer(4.into()));
        let rev: Vec<Point2> = sq.into_iter().rev().collect();
        assert_eq!(signed_area(&rev), Rat::from_integer((-4).into()));
    }

    #[test]
    fn repeated_factors_cancel_completely() {
        // Triangle (0,0), (1/3,0), (0,1/3): area 1/18; the denominators 3
        // appear in several points and must all cancel against the numerator.
        let t = poly(&[((0, 1), (0, 1)), ((1, 3), (0, 1)), ((0, 1), (1, 3))]);
        assert_eq!(signed_area(&t), Rat::new(1.into(), 18.into()));
        // A degenerate (collinear) polygon with big denominators is zero.
        let line = poly(&[((1, 7), (1, 7)), ((2, 9), (2, 9)), ((5, 11), (5, 11))]);
        assert!(signed_area(&line).is_zero());
    }

    proptest::proptest! {
        /// The rounded area, when given, has the exact sign and lies within
        /// the stated bound of the exact area of the (double) points: on
        /// random polygons anywhere in a wide range, small loops far from
        /// the origin, and nearly degenerate ones.
        #[test]
        fn rounded_area_is_within_its_bound(
            pts in proptest::collection::vec((-1000i64..1000, -1000i64..1000), 3..40),
            exp in -60i32..60, offset in -80i32..80, thin in 0u8..3
        ) {
            let scale = 2f64.powi(exp);
            let shift = 2f64.powi(offset) * 3.0;
            let mut q: Vec<[f64; 2]> = pts.iter().map(|&(x, y)| [x as f64 * scale + shift, y as f64 * scale - shift]).collect();
            if thin == 1 {
                // All on one line but one point one unit off.
                for (i, p) in q.iter_mut().enumerate() {
                    p[1] = p[0] * 0.5 + if i == 1 { scale } else { 0.0 };
                }
            }
            let exact: Vec<Point2> = q.iter().map(|&[x, y]| Point2 { x: rat_from_f64(x), y: rat_from_f64(y) }).collect();
            let a = signed_area_reference(&exact);
            if let Some(v) = rounded_area(&q) {
                proptest::prop_assert_eq!(Sign::of_rat(&rat_from_f64(v)), Sign::of_rat(&a));
                // The bound, recomputed in rationals with the same inputs.
                let u = 2f64.powi(-53);
                let m = q.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                let d = q.iter().fold(0.0f64, |d, p| d.max((p[0] - q[0][0]).abs()).max((p[1] - q[0][1]).abs()));
                let n = q.len() as f64;
                let e = u * (2.0 * m + 1.01 * d) + 2f64.powi(-1073);
                let t = 2.0 * n * (d + e) * (d + e);
                let bound = (n * (4.0 * e * (d + e) + 2.0 * e * e) + (2.0 * n + 2.0) * u * 1.01 * t) / 2.0 + n * 2f64.powi(-1074);
                let err = (rat_from_f64(v) - &a).abs();
                proptest::prop_assert!(err <= rat_from_f64(bound * 1.01), "error {} above bound {}", err, bound);
            }
        }
    }

    proptest::proptest! {
        /// The same loop multiplied by any power of two `2^k`: where the
        /// loop at `k = 0` is decided and the area at `2^k` is a normal
        /// double, the rounded area is the one at `k = 0` times `2^2k`,
        /// exactly (the frame changes no rounding); beyond the doubles it
        /// is the exact area's rounding (an infinity or a zero of its sign);
        /// never a different value.
        #[test]
        fn rounded_area_is_the_same_at_every_scale(
            pts in proptest::collection::vec((-1000i64..1000, -1000i64..1000), 3..20),
            k in -1100i32..1030, offset in -40i32..40
        ) {
            use crate::exact::scale::times_pow2;
            let shift = 2f64.powi(offset) * 3.0;
            let q0: Vec<[f64; 2]> = pts.iter().map(|&(x, y)| [x as f64 + shift, y as f64 - shift]).collect();
            let q: Vec<[f64; 2]> = q0.iter().map(|p| p.map(|v| times_pow2(v, k))).collect();
            // Only exact scalings: every coordinate kept.
            proptest::prop_assume!(q.iter().zip(&q0).all(|(a, b)| a.map(|v| times_pow2(v, -k)) == *b));
            let exact: Vec<Point2> = q.iter().map(|&[x, y]| Point2 { x: rat_from_f64(x), y: rat_from_f64(y) }).collect();
            let a = signed_area_reference(&exact);
            let nearest = rat_to_f64(&a);
            let unscaled = rounded_area(&q0);
            match rounded_area(&q) {
                Some(v) if v.is_infinite() || v == 0.0 => {
                    proptest::prop_assert_eq!(v.to_bits(), nearest.to_bits());
                }
                Some(v) if v.abs() > f64::MIN_POSITIVE => {
                    proptest::prop_assert_eq!(Some(v), unscaled.map(|u| times_pow2(u, 2 * k)));
                }
                // Subnormal: only from the unscaled shoelace, whose bound
                // covers it (`rounded_area_is_within_its_bound`).
                Some(v) => proptest::prop_assert_eq!(Sign::of_rat(&rat_from_f64(v)), Sign::of_rat(&a)),
                None => {
                    let normal = nearest.is_finite() && nearest.abs() > f64::MIN_POSITIVE;
                    proptest::prop_assert!(unscaled.is_none() || !normal, "undecided at 2^{}", k);
                }
            }
        }
    }

    #[test]
    fn rounded_area_of_a_small_loop_far_away_is_decided() {
        // A unit square at 2^40 from the origin: the shoelace about the
        // origin would lose every bit; about the first point it is exact.
        let o = 2f64.powi(40);
        let q = [[o, o], [o + 1.0, o], [o + 1.0, o + 1.0], [o, o + 1.0]];
        assert_eq!(rounded_area(&q), Some(1.0));
        assert_eq!(rounded_area(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), None);
    }
}
