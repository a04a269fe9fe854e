//! Input: an exact level `c` and vertex heights (`f64`, exact).
//! Output: the exact sign `sign(h - c)`.
//!
//! The level keeps the two adjacent doubles that bracket it, so the exact
//! comparison of a double with `c` is two float comparisons: there is no
//! double strictly between `lo` and `hi`.

use super::rational::{cmp_f64_rat, decompose, rat_to_f64, rat_to_string, Rat};
use super::Sign;
use num_traits::ToPrimitive;
use std::fmt;

/// An exact level `c` with its bracketing doubles `lo <= c <= hi`
/// (`lo == hi` exactly when `c` is a double).
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    value: Rat,
    lo: f64,
    hi: f64,
    small: Option<(i128, i128)>,
    /// `c = p / q` when both fit `i128` (`q > 0`).
    wide: Option<(i128, i128)>,
    /// `c = p / q 2^k` with `p`, `q` odd (or `p = 0`, `q = 1`, `k = 0`)
    /// when both fit `i128` (`q > 0`): levels of meshes at the ends of the
    /// double range, whose numerators or denominators are mostly twos.
    odd_parts: Option<(i128, i128, i32)>,
}

/// `(p, q, k)` with `n / d = p / q 2^k`, `p` and `q` odd (`p = 0`, `q = 1`,
/// `k = 0` for zero), when they fit `i128` and `k` fits `i32`.
fn odd_parts(value: &Rat) -> Option<(i128, i128, i32)> {
    let (n, d) = (value.numer(), value.denom());
    let Some(tn) = n.trailing_zeros() else {
        return Some((0, 1, 0));
    };
    let td = d.trailing_zeros()?;
    let k = i32::try_from(tn).ok()? - i32::try_from(td).ok()?;
    Some(((n >> tn).to_i128()?, (d >> td).to_i128()?, k))
}

/// `x 2^k`, when it fits `i128`.
#[inline]
pub(crate) fn shl(x: i128, k: u32) -> Option<i128> {
    if x == 0 {
        return Some(0);
    }
    if k >= 127 {
        return None;
    }
    let y = x << k;
    (y >> k == x).then_some(y)
}

/// `p 2^k - m q` for `m 2^-k` (`k > 0`) the nearest double of `p / q`
/// (`q > 0`), exact.
///
/// Its magnitude is `|p / q - m 2^-k| q 2^k`. The nearest double is within
/// half the spacing `2^u` of the doubles around it (`u <= -k`: `m` need not
/// be the full significand), so the magnitude is at most `q / 2 < 2^126`.
/// The products are therefore taken modulo `2^128` (wrapping): the residue
/// in `(-2^127, 2^127)` is the value itself, however large `p 2^k` and
/// `m q` are. No division, no big integers. A residue beyond `q / 2`
/// cannot be the gap of the nearest double: `None` then (the caller's
/// exact path), a guard should the precondition ever fail.
#[inline]
pub(crate) fn nearest_gap(p: i128, q: i128, m: i64, k: u32) -> Option<i128> {
    // p 2^k modulo 2^128 (zero once k >= 128).
    let shifted = if k >= 128 { 0 } else { p.wrapping_shl(k) };
    let gap = shifted.wrapping_sub(i128::from(m).wrapping_mul(q));
    (gap.unsigned_abs() <= q.unsigned_abs() / 2).then_some(gap)
}

/// `sign(f - p / q)` for `f` the nearest double of `p / q` (finite,
/// `q > 0`), decided in `i128`: by [`nearest_gap`] when `f`'s last bit is
/// a fraction, else when the products fit (else `None`).
fn cmp_nearest(f: f64, p: i128, q: i128) -> Option<std::cmp::Ordering> {
    let Some((m, e)) = decompose(f) else {
        // f is zero: the sign of -p.
        return Some(0.cmp(&p));
    };
    // f = m 2^e; f - p/q has the sign of m q 2^e - p.
    Some(if e >= 0 {
        shl(i128::from(m).checked_mul(q)?, e as u32)?.cmp(&p)
    } else {
        0.cmp(&nearest_gap(p, q, m, e.unsigned_abs())?)
    })
}

impl Level {
    /// Wraps an exact rational level.
    pub fn new(value: Rat) -> Self {
        let f = rat_to_f64(&value);
        let wide = value.numer().to_i128().zip(value.denom().to_i128());
        let (lo, hi) = if f.is_infinite() {
            if f > 0.0 {
                (f64::MAX, f64::INFINITY)
            } else {
                (f64::NEG_INFINITY, f64::MIN)
            }
        } else {
            let order = wide
                .and_then(|(p, q)| cmp_nearest(f, p, q))
                .unwrap_or_else(|| cmp_f64_rat(f, &value));
            match order {
                std::cmp::Ordering::Equal => (f, f),
                std::cmp::Ordering::Less => (f, f.next_up()),
                std::cmp::Ordering::Greater => (f.next_down(), f),
            }
        };
        let small = wide.filter(|(p, q)| p.unsigned_abs() < 1 << 62 && *q < 1 << 62);
        Level {
            odd_parts: odd_parts(&value),
            value,
            lo,
            hi,
            small,
            wide,
        }
    }

    /// `c = p / q` with `p`, `q` in `i128` (`q > 0`), when it fits.
    #[inline]
    pub fn wide(&self) -> Option<(i128, i128)> {
        self.wide
    }

    /// `c = p / q 2^k` with `p` and `q` odd (`q > 0`; zero is `0 / 1`), when
    /// they fit `i128`.
    #[inline]
    pub fn odd_parts(&self) -> Option<(i128, i128, i32)> {
        self.odd_parts
    }

    /// `c = p / q` with `|p|, q < 2^62`, when it is that small (the integer
    /// fast paths use it).
    #[inline]
    pub fn small(&self) -> Option<(i128, i128)> {
        self.small
    }

    /// The exact value.
    pub fn value(&self) -> &Rat {
        &self.value
    }

    /// The nearest double (rounded: for display only).
    pub fn approx(&self) -> f64 {
        rat_to_f64(&self.value)
    }

    /// `sign(h - c)` for a finite double `h`, decided exactly.
    #[inline]
    pub fn sign_of(&self, h: f64) -> Sign {
        self.bracket().sign_of(h)
    }

    /// The bracketing doubles alone (16 bytes: for scanning many levels).
    #[inline]
    pub fn bracket(&self) -> Bracket {
        Bracket {
            lo: self.lo,
            hi: self.hi,
        }
    }
}

/// The two adjacent doubles bracketing a level, which decide
/// `sign(h - c)` for every double `h` exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    lo: f64,
    hi: f64,
}

impl Bracket {
    /// `sign(h - c)` for a finite double `h`, decided exactly.
    #[inline]
    pub fn sign_of(self, h: f64) -> Sign {
        if self.lo == self.hi {
            Sign::of_cmp(h.partial_cmp(&self.lo))
        } else if h <= self.lo {
            Sign::Negative
        } else {
            Sign::Positive
        }
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&rat_to_string(&self.value))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;
    use crate::exact::rational::rat_from_f64;

    #[test]
    fn sign_is_exact_next_to_a_non_double_level() {
        let c = Level::new(parse_rational("0.6").unwrap());
        let f32_06 = 0.6f32 as f64; // 0.60000002384...
        assert_eq!(c.sign_of(0.6), Sign::Negative); // the double 0.6 is below 3/5
        assert_eq!(c.sign_of(f32_06), Sign::Positive);
        assert_eq!(c.sign_of(0.6f64.next_up()), Sign::Positive);
        let third = Level::new(parse_rational("1/3").unwrap());
        assert_eq!(third.sign_of(1.0 / 3.0), Sign::Negative);
        assert_eq!(third.sign_of((1.0f64 / 3.0).next_up()), Sign::Positive);
    }

    proptest::proptest! {
        /// The comparison of `p / q` with its nearest double, and the
        /// gap between them, agree with the rational ones; the gap needs
        /// no fallback (`p`, `q` need not be in lowest terms).
        #[test]
        fn nearest_comparison_is_exact(p in proptest::num::i128::ANY, pb in 1u32..128, q in 1i128..i128::MAX, qb in 1u32..127) {
            let (p, q) = (p >> (128 - pb), (q >> (127 - qb)).max(1));
            let r = Rat::new(p.into(), q.into());
            let f = rat_to_f64(&r);
            proptest::prop_assume!(f.is_finite());
            let want = rat_from_f64(f).cmp(&r);
            match decompose(f) {
                Some((m, e)) if e < 0 => {
                    let k = e.unsigned_abs();
                    let gap = num_bigint::BigInt::from(p) * num_bigint::BigInt::from(2).pow(k)
                        - num_bigint::BigInt::from(m) * num_bigint::BigInt::from(q);
                    proptest::prop_assert_eq!(nearest_gap(p, q, m, k).map(num_bigint::BigInt::from), Some(gap));
                    proptest::prop_assert_eq!(cmp_nearest(f, p, q), Some(want));
                    // A neighbour of the nearest double, not the nearest:
                    // its gap when within q / 2, else refused. Below 3q/2,
                    // it cannot wrap for q < 2^125.
                    if let Some((m, e)) = decompose(f.next_up()).filter(|&(_, e)| e < 0 && q < 1 << 125) {
                        let k = e.unsigned_abs();
                        let gap = num_bigint::BigInt::from(p) * num_bigint::BigInt::from(2).pow(k)
                            - num_bigint::BigInt::from(m) * num_bigint::BigInt::from(q);
                        let within = gap.magnitude() <= &num_bigint::BigUint::from(q.unsigned_abs() / 2);
                        proptest::prop_assert_eq!(nearest_gap(p, q, m, k).map(num_bigint::BigInt::from), within.then_some(gap));
                    }
                }
                _ => {
                    if let Some(o) = cmp_nearest(f, p, q) {
                        proptest::prop_assert_eq!(o, want);
                    }
                }
            }
        }
    }

    #[test]
    fn sign_is_zero_only_on_the_level() {
        let c = Level::new(parse_rational("5/4").unwrap());
        assert_eq!(c.sign_of(1.25), Sign::Zero);
        assert_eq!(c.sign_of(1.25f64.next_down()), Sign::Negative);
        assert_eq!(c.sign_of(1.25f64.next_up()), Sign::Positive);
    }
}
