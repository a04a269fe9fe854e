//! Input: an edge's two positions and an exact level. Output: the nearest
//! doubles of their crossing, rounded from its exact value held in 256-bit
//! integers on the stack (`ethnum`): no heap, no gcd; and the bits of its
//! coordinates' reduced denominators (for the summary's bound), from the
//! same integers with one `u128` gcd.
//!
//! This is the path for the crossings that the certified double-double
//! bound ([`super::crossing::certified_crossing`]) leaves undecided:
//! values at or within the bound of the midpoint between two doubles.
//! `f64` coordinates at simple levels give many exact ties: the edge from
//! `z = 0` to `z = 1.25` cut at `0.375` has `x = (7 ax + 3 bx) / 10`, a
//! midpoint between two doubles for about one edge in twenty of an `f64`
//! CAD part. Before, each took the big-rational crossing with its gcds
//! (about 1.1 us against about 0.2 us here).
//!
//! The crossing is `x = 2^e0 X / W` with the six coordinates `k 2^e0` on
//! their common binary grid and the level `p / q 2^k` (`p`, `q` odd):
//! `X = ax W + (bx - ax)(p' - q' az)`, `W = q' (bz - az)`, where
//! `p' / q'` is the level in units of `2^e0`. The bounds below keep every
//! product inside `I256`; the quotient is rounded once, as
//! [`super::rational::ratio_to_f64`] does in `i128`.

use super::level::Level;
use super::point::Layout;
use super::rational::scaled_quotient;
use ethnum::{I256, U256};

/// Every coordinate is `k 2^e0` with `|k| < 2^100`...
const PLACES: i32 = 100;
/// ...the level's numerator in units of `2^e0` is below `2^150` and its
/// denominator below `2^50`. Then `|bz - az|, |bx - ax| < 2^101`,
/// `|W| < 2^151`, `|p' - q' az| < 2^150 + 2^150 = 2^151` and
/// `|X| < 2^100 2^151 + 2^101 2^151 < 2^253`.
const NUMERATOR_BITS: u32 = 150;
const DENOMINATOR_BITS: u32 = 50;

/// The nearest doubles (ties to even) of the crossing of edge `(a, b)`
/// with `level` (the caller guarantees `az != bz`), or `None` when the
/// values exceed the bounds above, the level does not fit `i128`, or a
/// rounded coordinate would not be zero or a normal double (then the
/// caller takes the big-rational path). Exact value, one rounding: equal
/// to the rounding of the big-rational reference (property-tested).
pub fn nearest_crossing(a: [f64; 3], b: [f64; 3], level: &Level) -> Option<[f64; 2]> {
    let (x, y, w, e0) = crossing_integers(a, b, level)?;
    Some([nearest(x, w, e0)?, nearest(y, w, e0)?])
}

/// The bits of the denominators of the crossing's coordinates in lowest
/// terms (what `Point2::denominator_bits` of the exact point reads), or
/// `None` beyond the bounds above or when the odd part of `W` does not fit
/// `u128` (then the caller builds the exact point). Exact, with no heap:
/// `x = X 2^e0 / W`; the odd part of the reduced denominator is
/// `odd(W) / gcd(X, odd(W))` (one remainder and a `u128` gcd), its power
/// of two what `2^e0 2^tz(X) / 2^tz(W)` leaves below the line.
pub fn crossing_denominator_bits(a: [f64; 3], b: [f64; 3], level: &Level) -> Option<u64> {
    let (x, y, w, e0) = crossing_integers(a, b, level)?;
    let tw = w.trailing_zeros();
    let odd = w >> tw;
    if odd > U256::from(u128::MAX) {
        return None;
    }
    let odd = odd.as_u128();
    let bits = |n: I256| -> u64 {
        if n == 0 {
            // Zero is 0 / 1.
            return 1;
        }
        let m = n.unsigned_abs();
        let g = super::point::gcd_u128(rem_u128(m, odd), odd);
        let odd_bits = u64::from(128 - (odd / g).leading_zeros());
        let twos = i64::from(tw) - i64::from(m.trailing_zeros()) - i64::from(e0);
        odd_bits + twos.max(0) as u64
    };
    Some(bits(x) + bits(y))
}

/// `m mod d` (`d > 0`). A divisor below `2^64` (most crossings' odd
/// denominators) is taken a 64-bit word of `m` at a time, each step a
/// `u128` remainder whose dividend `r 2^64 + word < d 2^64` fits; a wider
/// one by `U256`'s own division.
fn rem_u128(m: U256, d: u128) -> u128 {
    if d > u128::from(u64::MAX) {
        return (m % U256::from(d)).as_u128();
    }
    let (high, low) = m.into_words();
    [low >> 64, low & u128::from(u64::MAX)]
        .into_iter()
        .fold(high % d, |r, word| ((r << 64) | word) % d)
}

/// `(X, Y, W, e0)` with the crossing `(X 2^e0 / W, Y 2^e0 / W)`, `W > 0`,
/// within the bounds above (see the module documentation).
fn crossing_integers(a: [f64; 3], b: [f64; 3], level: &Level) -> Option<(I256, I256, U256, i32)> {
    let (p, q, k) = level.odd_parts()?;
    let layout = Layout::of([a[0], a[1], a[2], b[0], b[1], b[2]])?;
    if layout.places() > PLACES {
        return None;
    }
    let [ax, ay, az, bx, by, bz] = layout.ints_i128()?;
    let e0 = layout.lowest;
    // p / q 2^k in units of 2^e0: p / q 2^(k - e0), the power of two on
    // whichever side it belongs (p and q odd: nothing else cancels).
    let (p, q) = (I256::from(p), I256::from(q));
    let t = i64::from(k) - i64::from(e0);
    let (p, q) = if p == 0 {
        (p, I256::ONE)
    } else if t >= 0 {
        (shifted(p, u32::try_from(t).ok()?)?, q)
    } else {
        (p, shifted(q, u32::try_from(-t).ok()?)?)
    };
    if bits(p) > NUMERATOR_BITS || bits(q) > DENOMINATOR_BITS {
        return None;
    }
    let w = q * I256::from(bz - az);
    let s = p - q * I256::from(az);
    let coord = |u: i128, v: i128| I256::from(u) * w + I256::from(v - u) * s;
    let (x, y) = (coord(ax, bx), coord(ay, by));
    let (x, y, w) = if w < 0 { (-x, -y, -w) } else { (x, y, w) };
    if w == 0 {
        return None;
    }
    Some((x, y, w.unsigned_abs(), e0))
}

/// Bits of `|v|`.
fn bits(v: I256) -> u32 {
    256 - v.unsigned_abs().leading_zeros()
}

/// `v 2^k` when it stays within the numerator's bound (else `None`).
fn shifted(v: I256, k: u32) -> Option<I256> {
    (k <= NUMERATOR_BITS && bits(v) + k <= NUMERATOR_BITS).then(|| v << k)
}

/// The `f64` nearest to `n 2^e / d` (ties to even, `d > 0`) when it is a
/// normal double or zero; `None` otherwise. Integer division to 55 or 56
/// bits and a sticky bit folded into the last one (rounding to odd), then
/// the hardware's conversion rounds once, to nearest even: exactly as
/// the exact quotient rounds.
fn nearest(n: I256, d: U256, e: i32) -> Option<f64> {
    if n == 0 {
        return Some(0.0);
    }
    let num = n.unsigned_abs();
    let bits = |v: U256| 256 - v.leading_zeros() as i32;
    // q = floor(num 2^s / d) lies in [2^54, 2^56).
    let s = 55 - (bits(num) - bits(d));
    let (q, rest) = if s <= 0 {
        // -s < 256: num has at most 253 bits and d at least one.
        let k = s.unsigned_abs();
        let high = num >> k;
        let q = high / d;
        (q, high - q * d != 0 || num & ((U256::ONE << k) - 1) != 0)
    } else if s.unsigned_abs() <= num.leading_zeros() {
        let shifted = num << s.unsigned_abs();
        let q = shifted / d;
        (q, shifted - q * d != 0)
    } else {
        return None;
    };
    let q = q.as_u64() | u64::from(rest);
    let v = scaled_quotient(q, i64::from(e) - i64::from(s))?;
    Some(if n < 0 { -v } else { v })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;
    use crate::exact::point::Point2;
    use crate::exact::rational::{rat_from_f64, Rat};
    use proptest::prelude::*;

    fn reference(a: [f64; 3], b: [f64; 3], level: &Level) -> [f64; 2] {
        Point2::on_edge_reference(a, b, level).to_f64()
    }

    #[test]
    fn ties_round_to_even() {
        // The one rounding of the crossing, to its nearest double for
        // output (SPEC 2: ties to even); every decision uses the exact
        // value. Hand-derived, on exact input doubles: `d(k)` is the k-th
        // double above 1, `1 + k 2^-52`. The edge from x = 1 to
        // d(1) cut at its middle has x = 1 + 2^-53, halfway between 1 and
        // d(1): ties to even give 1. From 1 to d(3), the middle
        // 1 + 3 2^-53 lies halfway between d(1) (odd) and d(2) (even).
        let d = |k: u64| f64::from_bits(1f64.to_bits() + k);
        let half = Level::new(parse_rational("1/2").unwrap());
        assert_eq!(
            nearest_crossing([1.0, 1.0, 0.0], [d(1), 1.0, 1.0], &half),
            Some([1.0, 1.0])
        );
        assert_eq!(
            nearest_crossing([1.0, -1.0, 0.0], [d(3), -1.0, 1.0], &half),
            Some([d(2), -1.0])
        );
        // A decimal cut of an f64 edge that is an exact tie (the case this
        // path is for): checked against the big rationals.
        let (a, b) = (
            [29.818173289042377, 3.2979602339384755, 0.0],
            [29.809704809895177, 3.3736477508643863, 1.25],
        );
        let c = Level::new(parse_rational("0.375").unwrap());
        assert_eq!(nearest_crossing(a, b, &c), Some(reference(a, b, &c)));
    }

    #[test]
    fn ties_far_below_one() {
        // A decimal mesh scaled by 1e-300, cut halfway up an edge: y is
        // (5.33e-299 + 5.23e-299) / 2 of the doubles, exactly halfway
        // between two doubles (their sum needs one bit more), with the
        // level far beyond `i128` (a 53-bit odd part times 2^-1050) and
        // the quotient's scale below the normal doubles. Checked against
        // the big rationals.
        let (a, b) = ([1.1e-300, 5.33e-299, 0.0], [1e-301, 5.23e-299, 1e-300]);
        let half = Level::new(rat_from_f64(b[2]) / Rat::from_integer(2.into()));
        assert!(half.wide().is_none());
        let got = nearest_crossing(a, b, &half);
        assert_eq!(got, Some(reference(a, b, &half)));
        let exact_y = (rat_from_f64(a[1]) + rat_from_f64(b[1])) / Rat::from_integer(2.into());
        let y = got.unwrap()[1];
        let gap = rat_from_f64(y.next_up()) - rat_from_f64(y);
        let off = num_traits::Signed::abs(&(exact_y - rat_from_f64(y))) / gap;
        assert_eq!(off, Rat::new(1.into(), 2.into()), "a tie");
    }

    #[test]
    fn the_zero_level_far_from_one() {
        // Coordinates near 2^300 cut at 0 (found by the fuzzer: a zero
        // numerator was shifted by 300 places).
        let zero = Level::new(Rat::from_integer(0.into()));
        let big = 2f64.powi(300);
        assert_eq!(
            nearest_crossing([big, 0.0, -big], [2.0 * big, big, big], &zero),
            Some([1.5 * big, 0.5 * big])
        );
    }

    #[test]
    fn out_of_bounds_is_refused() {
        let c = Level::new(parse_rational("1/3").unwrap());
        // 2^-60 beside 2^50: 111 binary places.
        assert_eq!(
            nearest_crossing([2f64.powi(-60), 0.0, 0.0], [2f64.powi(50), 0.0, 1.0], &c),
            None
        );
        // A level with a 60-bit denominator.
        let c = Level::new(Rat::new(1.into(), ((1i64 << 60) + 1).into()));
        assert_eq!(nearest_crossing([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], &c), None);
    }

    /// Doubles `k 2^e` with `|k| < 2^60` and one `e` per edge, or any
    /// finite double.
    fn edge() -> impl Strategy<Value = ([f64; 3], [f64; 3])> {
        let close = (
            proptest::array::uniform6(-(1i64 << 60)..1 << 60),
            -1100i32..1000,
        )
            .prop_map(|(ks, e)| {
                let v = ks.map(|k| crate::exact::scale::times_pow2(k as f64, e));
                ([v[0], v[1], v[2]], [v[3], v[4], v[5]])
            });
        let f64s = proptest::array::uniform6(
            proptest::num::f64::POSITIVE
                | proptest::num::f64::NEGATIVE
                | proptest::num::f64::NORMAL
                | proptest::num::f64::ZERO,
        )
        .prop_map(|v| ([v[0], v[1], v[2]], [v[3], v[4], v[5]]));
        prop_oneof![close, f64s]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]
        /// Equal to the big-rational reference whenever it answers, for
        /// levels that are exact fractions of the edge (ties included) and
        /// decimals.
        #[test]
        fn wide_crossing_equals_the_reference(
            (a, b) in edge(), t in 1i64..64, den in 1i64..64, decimals in 0u32..8, kind in 0u8..2,
        ) {
            prop_assume!(a.iter().chain(&b).all(|v| v.is_finite()) && a[2] != b[2]);
            let (za, zb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let frac = Rat::new(t.into(), (den + t).into());
            let exact = &za + (zb - &za) * frac;
            let level = Level::new(if kind == 0 {
                exact
            } else {
                let unit = Rat::from_integer(10.into()).pow(decimals as i32);
                (exact * &unit).round() / unit
            });
            if let Some(x) = nearest_crossing(a, b, &level) {
                prop_assert_eq!(x, reference(a, b, &level));
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1024))]
        /// Where the bounds promise it, the path answers (so the property
        /// above is not vacuous): integers below 2^60 on one grid, cut at
        /// an exact fraction of the edge, near 1 or towards either end of
        /// the range (where the level is far beyond `i128` but its odd
        /// parts are not; the exponents are limited so that every result
        /// is a normal double).
        #[test]
        fn answers_on_a_grid(
            ks in proptest::array::uniform6(-(1i64 << 60)..1 << 60),
            e in prop_oneof![-60i32..40, -900i32..-860, 900i32..960],
            t in 1i64..64, den in 1i64..64,
        ) {
            let v = ks.map(|k| crate::exact::scale::times_pow2(k as f64, e));
            let (a, b) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
            prop_assume!(a[2] != b[2]);
            let (za, zb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let level = Level::new(&za + (zb - &za) * Rat::new(t.into(), (den + t).into()));
            let x = nearest_crossing(a, b, &level);
            prop_assert!(x.is_some());
            prop_assert_eq!(x.unwrap(), reference(a, b, &level));
            prop_assert_eq!(
                crossing_denominator_bits(a, b, &level),
                Some(crate::exact::area::ExactPoint::denominator_bits(
                    &Point2::on_edge_reference(a, b, &level)
                ))
            );
        }
    }

    #[test]
    fn denominator_bits_by_hand() {
        use crate::exact::area::ExactPoint;
        let bits = |b: [f64; 3], c: &str| {
            let level = Level::new(parse_rational(c).unwrap());
            let fast = crossing_denominator_bits([0.0; 3], b, &level);
            assert_eq!(
                fast,
                Some(Point2::on_edge_reference([0.0; 3], b, &level).denominator_bits())
            );
            fast.unwrap()
        };
        // (1/3, 1/3): denominators 3 and 3, two bits each.
        assert_eq!(bits([1.0, 1.0, 3.0], "1"), 4);
        // (1/2, 1/8): denominators 2 and 8.
        assert_eq!(bits([1.0, 0.25, 3.0], "3/2"), 2 + 4);
        // (0, 0): zero is 0 / 1, one bit each.
        assert_eq!(bits([1.0, 0.25, 3.0], "0"), 2);
        // (5/7 2^-3, 5/7 2^60): 7 2^3 below x's line, 7 below y's.
        assert_eq!(bits([0.125, 2f64.powi(60), 7.0], "5"), 6 + 3);
    }

    #[test]
    fn remainders_by_hand() {
        let m = U256::from_words(u128::MAX, u128::MAX);
        // 2^256 - 1 is a multiple of 2^64 - 1 and of 3; 2^256 = 2 (mod 7).
        assert_eq!(rem_u128(m, u128::from(u64::MAX)), 0);
        assert_eq!(rem_u128(m, 3), 0);
        assert_eq!(rem_u128(m - U256::from(6u8), 7), 2);
        assert_eq!(rem_u128(U256::from(10u8), 1), 0);
        assert_eq!(rem_u128(U256::from(10u8), 11), 10);
        // 2^200 mod (2^64 + 1): 2^64 = -1, so 2^200 = 2^8 (2^64)^3 = -2^8.
        let d = (1u128 << 64) + 1;
        assert_eq!(rem_u128(U256::ONE << 200, d), d - 256);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]
        /// The word-by-word remainder equals `U256`'s, for dividends over
        /// all 256 bits and divisors of every width up to 128 bits.
        #[test]
        fn remainders_equal_u256s(
            high in any::<u128>(), low in any::<u128>(), d in 1u128.., width in 1u32..=128,
        ) {
            let d = (d >> (128 - width)).max(1);
            let m = U256::from_words(high, low);
            prop_assert_eq!(rem_u128(m, d), (m % U256::from(d)).as_u128());
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]
        /// The bits of the reduced denominators, computed without building
        /// the point, equal the big-rational reference's whenever they are
        /// given: at fractions of the edge, decimals and levels of any
        /// denominator below `2^62`, over the whole `f64` range.
        #[test]
        fn denominator_bits_equal_the_reference(
            (a, b) in edge(), t in 1i64..64, den in 1i64..64, decimals in 0u32..8, kind in 0u8..3,
            p in any::<i64>(), q in 1i64..i64::MAX,
        ) {
            use crate::exact::area::ExactPoint;
            prop_assume!(a.iter().chain(&b).all(|v| v.is_finite()) && a[2] != b[2]);
            let (za, zb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let frac = Rat::new(t.into(), (den + t).into());
            let exact = &za + (zb - &za) * frac;
            let level = Level::new(match kind {
                0 => exact,
                1 => {
                    let unit = Rat::from_integer(10.into()).pow(decimals as i32);
                    (exact * &unit).round() / unit
                }
                _ => Rat::new(p.into(), q.into()),
            });
            if let Some(bits) = crossing_denominator_bits(a, b, &level) {
                prop_assert_eq!(bits, Point2::on_edge_reference(a, b, &level).denominator_bits());
            }
        }
    }
}
