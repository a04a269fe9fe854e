//! Input: an exact level `c` and vertex heights (`f64`, exact).
//! Output: the exact sign `sign(h - c)`.
//!
//! The level keeps the two adjacent doubles that bracket it, so the exact
//! comparison of a double with `c` is two float comparisons: there is no
//! double strictly between `lo` and `hi`.

use super::rational::{decompose, rat_from_f64, rat_to_f64, rat_to_string, Rat};
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

/// `sign(f - p / q)` for a finite double `f` and `q > 0`, decided in
/// `i128` when the products fit (else `None`).
fn cmp_double(f: f64, p: i128, q: i128) -> Option<std::cmp::Ordering> {
    let Some((m, e)) = decompose(f) else {
        // f is zero: the sign of -p.
        return Some(0.cmp(&p));
    };
    let mq = i128::from(m).checked_mul(q)?;
    // f = m 2^e; f - p/q has the sign of m q 2^e - p.
    Some(if e >= 0 {
        shl(mq, e as u32)?.cmp(&p)
    } else {
        mq.cmp(&shl(p, e.unsigned_abs())?)
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
                .and_then(|(p, q)| cmp_double(f, p, q))
                .unwrap_or_else(|| rat_from_f64(f).cmp(&value));
            match order {
                std::cmp::Ordering::Equal => (f, f),
                std::cmp::Ordering::Less => (f, f.next_up()),
                std::cmp::Ordering::Greater => (f.next_down(), f),
            }
        };
        let small = wide.filter(|(p, q)| p.unsigned_abs() < 1 << 62 && *q < 1 << 62);
        Level {
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
        /// The integer comparison of a double with `p / q` agrees with
        /// the rational one.
        #[test]
        fn double_comparison_is_exact(bits in proptest::num::u64::ANY, p in proptest::num::i128::ANY, pb in 1u32..128, q in 1i128..i128::MAX, qb in 1u32..127) {
            let f = f64::from_bits(bits);
            proptest::prop_assume!(f.is_finite());
            let (p, q) = (p >> (128 - pb), (q >> (127 - qb)).max(1));
            if let Some(o) = cmp_double(f, p, q) {
                let r = Rat::new(p.into(), q.into());
                proptest::prop_assert_eq!(o, rat_from_f64(f).cmp(&r));
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
