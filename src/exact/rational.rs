//! Input: text as a user types a number (`0.6`, `10.35`, `3/5`, `-1e-3`).
//! Output: the exact rational it denotes ([`Rat`]), and the canonical
//! `"p/q"` text of the interchange format.
//!
//! Parsing never goes through `f64`: `0.2` is exactly `1/5`.

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::cmp::Ordering;

/// The exact rational type used on the exact side of the pipeline.
pub type Rat = BigRational;

/// Why a number could not be parsed exactly.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RationalParseError {
    /// The text is empty.
    #[error("empty number")]
    Empty,
    /// The text is not a decimal, a fraction `p/q` or a scientific number.
    #[error("'{0}' is not a number (expected e.g. 0.6, 3/5, -1e-3)")]
    Syntax(String),
    /// The denominator of `p/q` is zero.
    #[error("'{0}' has a zero denominator")]
    ZeroDenominator(String),
    /// The exponent is too large to expand exactly.
    #[error("'{0}' has an exponent outside -4000..=4000")]
    ExponentRange(String),
}

/// Parses a decimal (`10.35`, `-.5`, `1e-3`, `2.5E+2`) or a fraction
/// (`3/5`, `-7/2`) exactly.
///
/// ```
/// use wmslice::exact::{parse_rational, Rat};
/// let r = parse_rational("0.2").unwrap();
/// assert_eq!(r, Rat::new(1.into(), 5.into()));
/// assert_eq!(parse_rational("-1e-3").unwrap(), Rat::new((-1).into(), 1000.into()));
/// ```
pub fn parse_rational(text: &str) -> Result<Rat, RationalParseError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(RationalParseError::Empty);
    }
    if let Some((p, q)) = t.split_once('/') {
        let num = parse_decimal(p.trim()).ok_or_else(|| syntax(t))?;
        let den = parse_decimal(q.trim()).ok_or_else(|| syntax(t))?;
        if den.is_zero() {
            return Err(RationalParseError::ZeroDenominator(t.to_string()));
        }
        return Ok(num / den);
    }
    parse_decimal_checked(t)
}

fn syntax(t: &str) -> RationalParseError {
    RationalParseError::Syntax(t.to_string())
}

fn parse_decimal(t: &str) -> Option<Rat> {
    parse_decimal_checked(t).ok()
}

fn parse_decimal_checked(t: &str) -> Result<Rat, RationalParseError> {
    let (mantissa, exponent) = match t.find(['e', 'E']) {
        Some(i) => {
            let exp: i32 = t[i + 1..].parse().map_err(|_| syntax(t))?;
            (&t[..i], exp)
        }
        None => (t, 0),
    };
    if !(-4000..=4000).contains(&exponent) {
        return Err(RationalParseError::ExponentRange(t.to_string()));
    }
    let (negative, digits) = match mantissa.as_bytes().first() {
        Some(b'-') => (true, &mantissa[1..]),
        Some(b'+') => (false, &mantissa[1..]),
        _ => (false, mantissa),
    };
    let (int_part, frac_part) = digits.split_once('.').unwrap_or((digits, ""));
    if int_part.is_empty() && frac_part.is_empty() {
        return Err(syntax(t));
    }
    if !int_part.bytes().all(|b| b.is_ascii_digit())
        || !frac_part.bytes().all(|b| b.is_ascii_digit())
    {
        return Err(syntax(t));
    }
    let all_digits = format!("{int_part}{frac_part}");
    let scale = exponent - frac_part.len() as i32;
    small_decimal(&all_digits, negative, scale)
        .or_else(|| big_decimal(&all_digits, negative, scale))
        .ok_or_else(|| syntax(t))
}

/// `digits 10^scale` (negated when `negative`; no digits is zero) in big
/// integers, for any length and scale.
fn big_decimal(digits: &str, negative: bool, scale: i32) -> Option<Rat> {
    let mut num: BigInt = if digits.is_empty() {
        BigInt::zero()
    } else {
        digits.parse().ok()?
    };
    if negative {
        num = -num;
    }
    let ten = BigInt::from(10u32);
    Some(if scale >= 0 {
        Rat::from_integer(num * num_traits::pow(ten, scale as usize))
    } else {
        Rat::new(num, num_traits::pow(ten, (-scale) as usize))
    })
}

/// `digits 10^scale` (negated when `negative`) in lowest terms with one
/// `u128` gcd, when the digits and the power of ten fit (a levels file's
/// decimals, `0.0074999999999991115`); `None` otherwise (big integers).
fn small_decimal(digits: &str, negative: bool, scale: i32) -> Option<Rat> {
    if digits.len() > 38 || digits.is_empty() {
        return None;
    }
    let n: u128 = digits.parse().ok()?;
    let pow = 10u128.checked_pow(scale.unsigned_abs())?;
    let (n, d) = if scale >= 0 {
        (n.checked_mul(pow)?, 1)
    } else {
        let g = n.gcd(&pow).max(1);
        (n / g, pow / g)
    };
    let n = i128::try_from(n).ok()?;
    Some(Rat::new_raw(
        BigInt::from(if negative { -n } else { n }),
        BigInt::from(d),
    ))
}

/// An exact rational for people: its canonical text and, in brackets,
/// its nearest double (`"3/20 (~0.15)"`); the double is rounded, for
/// reading only.
pub fn rat_to_string_with_nearest(r: &Rat) -> String {
    format!("{} (~{})", rat_to_string(r), rat_to_f64(r))
}

/// The canonical text of an exact rational: `"p"` or `"p/q"` in lowest terms
/// with `q > 1` (the interchange format's `rational`).
pub fn rat_to_string(r: &Rat) -> String {
    // Parts within i128 (every level of a usual plan) print as the same
    // decimal digits, without big-integer division.
    match (r.numer().to_i128(), r.denom().to_i128()) {
        (Some(p), Some(1)) => p.to_string(),
        (Some(p), Some(q)) => format!("{p}/{q}"),
        _ => big_rat_to_string(r),
    }
}

/// [`rat_to_string`] through big-integer formatting, for any size.
fn big_rat_to_string(r: &Rat) -> String {
    if r.denom().is_one() {
        r.numer().to_string()
    } else {
        format!("{}/{}", r.numer(), r.denom())
    }
}

/// `c / s` (`s != 0`), exact: in `i128` with one gcd when the cross
/// products fit (a level put in a snapped mesh's grid units, once per
/// level), else in big rationals.
pub fn rat_div(c: &Rat, s: &Rat) -> Rat {
    let parts = |r: &Rat| r.numer().to_i128().zip(r.denom().to_i128());
    let small = || {
        let ((p, q), (a, b)) = (parts(c)?, parts(s)?);
        // c / s = (p b) / (q a), with q, b > 0.
        let (n, d) = (p.checked_mul(b)?, q.checked_mul(a)?);
        let (n, d) = if d < 0 {
            (n.checked_neg()?, d.checked_neg()?)
        } else {
            (n, d)
        };
        (d > 0).then_some(())?;
        let g = super::point::gcd_u128(n.unsigned_abs(), d.unsigned_abs()) as i128;
        Some(Rat::new_raw((n / g).into(), (d / g).into()))
    };
    small().unwrap_or_else(|| c / s)
}

/// The exact value of a finite `f64` (every finite float is a dyadic rational).
///
/// Non-finite inputs are rejected by validation before any exact arithmetic;
/// here they map to zero so that no caller can panic.
pub fn rat_from_f64(x: f64) -> Rat {
    // Built from the odd mantissa directly: already in lowest terms, so no
    // gcd is taken.
    match decompose(x) {
        None => Rat::zero(),
        Some((m, e)) if e >= 0 => Rat::from_integer(BigInt::from(m) << e as u32),
        Some((m, e)) => Rat::new_raw(BigInt::from(m), BigInt::one() << (-e) as u32),
    }
}

/// `r 2^s`, exact and in lowest terms. `r` is in lowest terms, so only
/// factors of two can cancel: they are counted, no gcd is taken (the
/// generic product takes three, each as long as the numbers' bit length).
pub fn rat_times_pow2(r: &Rat, s: i32) -> Rat {
    if s == 0 || r.is_zero() {
        return r.clone();
    }
    let (n, d) = (r.numer(), r.denom());
    let k = u64::from(s.unsigned_abs());
    if s > 0 {
        let cancel = d.trailing_zeros().unwrap_or(0).min(k);
        Rat::new_raw(n << (k - cancel), d >> cancel)
    } else {
        let cancel = n.trailing_zeros().unwrap_or(0).min(k);
        Rat::new_raw(n >> cancel, d << (k - cancel))
    }
}

/// `c - x` exactly, over `c`'s denominator times a power of two, not
/// reduced (for a rounding or a sign, which depend on the value only).
fn minus_f64(c: &Rat, x: f64) -> Rat {
    let Some((m, e)) = decompose(x) else {
        return c.clone();
    };
    let (p, q) = (c.numer(), c.denom());
    let m = BigInt::from(m);
    let k = u64::from(e.unsigned_abs());
    if e >= 0 {
        Rat::new_raw(p - (m << k) * q, q.clone())
    } else {
        Rat::new_raw((p << k) - m * q, q << k)
    }
}

/// The `f64` nearest to `c - x` (ties to even), exact: the difference is
/// rounded once, unreduced ([`rat_to_f64`] depends on the value only).
pub fn rat_minus_f64_to_f64(c: &Rat, x: f64) -> f64 {
    rat_to_f64(&minus_f64(c, x))
}

/// `x` compared with `c`, exactly, for a finite `x`: the sign of one
/// integer, `x - c` times a positive denominator (the rational comparison
/// expands both into continued fractions, a big division per term).
pub fn cmp_f64_rat(x: f64, c: &Rat) -> Ordering {
    BigInt::zero().cmp(minus_f64(c, x).numer())
}

/// `x = mantissa * 2^exponent` with an odd mantissa (or `None` for zero or
/// non-finite values).
pub fn decompose(x: f64) -> Option<(i64, i32)> {
    if x == 0.0 || !x.is_finite() {
        return None;
    }
    let bits = x.to_bits();
    let sign = if bits >> 63 == 1 { -1 } else { 1 };
    let exp_bits = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    let (mut m, mut e) = if exp_bits == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp_bits - 1075)
    };
    let tz = m.trailing_zeros();
    m >>= tz;
    e += tz as i32;
    Some((sign * m as i64, e))
}

/// The `f64` nearest to `r` (ties to even): the only rounding step, used for
/// output. Exact when `r` is representable.
pub fn rat_to_f64(r: &Rat) -> f64 {
    // Both parts exact as doubles: IEEE division rounds the quotient
    // correctly, in one step.
    if let (Some(n), Some(d)) = (r.numer().to_i64(), r.denom().to_i64()) {
        const EXACT: i64 = 1 << 53;
        if (-EXACT..=EXACT).contains(&n) && d <= EXACT {
            return n as f64 / d as f64;
        }
    }
    // Both parts within 128 bits: integer division to 55 or 56 bits plus
    // a sticky bit (as for points stored as integers), no big numbers.
    if let (Some(n), Some(d)) = (r.numer().to_i128(), r.denom().to_u128()) {
        if let Some(f) = ratio_to_f64_normal(n.unsigned_abs(), d, 0) {
            return if n < 0 { -f } else { f };
        }
    }
    // num-rational rounds the quotient correctly for BigRational.
    r.to_f64().unwrap_or(if r.is_negative() {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    })
}

/// The `f64` nearest to `n 2^e / d` (ties to even), for `d > 0`: the
/// rounding of a point stored as integers. Integer division to 55 or 56
/// bits plus a sticky bit, rounded once (to odd, then by the hardware's
/// conversion); when the result would be subnormal or
/// overflow (or `d >= 2^126`), through [`rat_to_f64`].
/// Equal to `rat_to_f64` of the same value (property-tested).
pub fn ratio_to_f64(n: i128, d: u128, e: i32) -> f64 {
    if n == 0 {
        return 0.0;
    }
    // Both exact as doubles: one IEEE division rounds correctly, and the
    // power-of-two scaling is exact while the result stays normal.
    const EXACT: u128 = 1 << 53;
    if n.unsigned_abs() <= EXACT && d <= EXACT && (-1000..=1000).contains(&e) {
        let v = (n as f64) / (d as f64) * f64::from_bits(((e + 1023) as u64) << 52);
        if v.abs() >= f64::MIN_POSITIVE && v.is_finite() {
            return v;
        }
    }
    ratio_to_f64_normal(n.unsigned_abs(), d, e)
        .map(|f| if n < 0 { -f } else { f })
        .unwrap_or_else(|| rat_to_f64(&ratio_to_rat(n, d, e)))
}

/// `n 2^e / d` as a rational.
fn ratio_to_rat(n: i128, d: u128, e: i32) -> Rat {
    Rat::new(n.into(), d.into()) * Rat::from_integer(2.into()).pow(e)
}

fn ratio_to_f64_normal(num: u128, d: u128, e: i32) -> Option<f64> {
    if d == 0 || d >= 1 << 126 {
        return None;
    }
    let bits = |v: u128| 128 - v.leading_zeros() as i32;
    // q = floor(num 2^s / d) lies in [2^54, 2^56).
    let s = 55 - (bits(num) - bits(d));
    let (q, sticky) = if s <= 0 {
        let k = (-s) as u32;
        let high = num >> k;
        let dropped = k > 0 && num & ((1u128 << k) - 1) != 0;
        (high / d, dropped || high % d != 0)
    } else if s as u32 <= num.leading_zeros() {
        // The shifted numerator fits: one division, the remainder by a
        // multiplication.
        let shifted = num << s;
        let q = shifted / d;
        (q, shifted != q * d)
    } else {
        shifted_quotient_wide(num, s as u32, d)
    };
    // q has 55 or 56 bits, two or more beyond a double's 53: with the
    // sticky bit folded into its last bit (rounding to odd), the
    // hardware's conversion rounds once, to nearest even, exactly as the
    // exact quotient would round. No branch on the (random) low bits.
    let q = (q as u64) | u64::from(sticky);
    scaled_quotient(q, i64::from(e) - i64::from(s))
}

/// `q 2^exp` rounded, for `q` in `[2^54, 2^56)` with its sticky bit
/// folded into its last bit: `q` rounds once, at the conversion to a
/// double. When the result is normal and finite (its leading bit at
/// `2^-1022` to `2^1023`; else `None`) that conversion rounded at the
/// result's own 53 bits, and every product by a power of two is exact:
/// one by `2^exp` when it is a normal double, else two ([`times_pow2`](crate::exact::scale::times_pow2)).
#[inline]
pub(crate) fn scaled_quotient(q: u64, exp: i64) -> Option<f64> {
    let v = q as i64 as f64;
    let lead = ((v.to_bits() >> 52) as i64 - 1023) + exp;
    if !(-1022..=1023).contains(&lead) {
        return None;
    }
    Some(if exp >= -1022 {
        v * f64::from_bits(((exp + 1023) as u64) << 52)
    } else {
        super::scale::times_pow2(v, exp as i32)
    })
}

/// `floor(num 2^s / d)` and whether the division leaves a remainder, when
/// `num 2^s` overflows 128 bits but the quotient lies in `[2^54, 2^56)`
/// (so `2^73 <= d < 2^126`). One division of the top bits by the top 64
/// bits of `d` gives the quotient to within one: with `d = dt 2^t + low`,
/// `dt = floor(d / 2^t)` in `[2^63, 2^64)` and `nt = floor(num 2^s / 2^t)`
/// below `2^119`, the exact quotient lies between `nt / (dt + 1)` and
/// `(nt + 1) / dt`, both less than `nt / dt^2 + 1 / dt < 1` from `nt /
/// dt`, so the floors differ by at most one. The remainder of that
/// estimate lies in `(-d, 2d)`, below `2^127` in magnitude, so it is exact
/// when computed modulo `2^128` (wrapping), and one step corrects the
/// quotient, exactly. In place of a long division (two divisions per
/// `leading_zeros(d)` bits).
fn shifted_quotient_wide(num: u128, s: u32, d: u128) -> (u128, bool) {
    let t = 64 - d.leading_zeros();
    let dt = d >> t;
    let nt = if s >= t {
        num << (s - t)
    } else {
        num >> (t - s)
    };
    let mut q = nt / dt;
    // num 2^s - q d, modulo 2^128 (a shift by 128 or more leaves 0).
    let low = num.checked_shl(s).unwrap_or(0);
    let mut r = low.wrapping_sub(q.wrapping_mul(d)) as i128;
    let d = d as i128;
    while r < 0 {
        q -= 1;
        r += d;
    }
    while r >= d {
        q += 1;
        r -= d;
    }
    (q, r != 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(p: i64, q: i64) -> Rat {
        Rat::new(p.into(), q.into())
    }

    #[test]
    fn decimals_are_exact() {
        assert_eq!(parse_rational("0.6").unwrap(), r(3, 5));
        assert_eq!(parse_rational("10.35").unwrap(), r(207, 20));
        assert_eq!(parse_rational("-1e-3").unwrap(), r(-1, 1000));
        assert_eq!(parse_rational("2.5E+2").unwrap(), r(250, 1));
        assert_eq!(parse_rational(".5").unwrap(), r(1, 2));
        assert_eq!(parse_rational("3/5").unwrap(), r(3, 5));
        assert_eq!(parse_rational("-6/10").unwrap(), r(-3, 5));
        assert_eq!(parse_rational("0.1/0.3").unwrap(), r(1, 3));
    }

    #[test]
    fn bad_numbers_are_typed_errors() {
        assert_eq!(parse_rational(""), Err(RationalParseError::Empty));
        assert!(matches!(
            parse_rational("abc"),
            Err(RationalParseError::Syntax(_))
        ));
        assert!(matches!(
            parse_rational("1/0"),
            Err(RationalParseError::ZeroDenominator(_))
        ));
        assert!(matches!(
            parse_rational("1e99999"),
            Err(RationalParseError::ExponentRange(_))
        ));
        assert!(matches!(
            parse_rational("1.2.3"),
            Err(RationalParseError::Syntax(_))
        ));
        assert!(matches!(
            parse_rational("-"),
            Err(RationalParseError::Syntax(_))
        ));
    }

    #[test]
    fn canonical_text() {
        assert_eq!(rat_to_string(&r(6, 10)), "3/5");
        assert_eq!(rat_to_string(&r(-4, 2)), "-2");
        assert_eq!(rat_to_string(&r(0, 7)), "0");
    }

    #[test]
    fn float_round_trip_is_exact() {
        for x in [0.1, -0.0, 1e-300, 3.0e20, f64::MIN_POSITIVE, 0.6f32 as f64] {
            assert_eq!(rat_to_f64(&rat_from_f64(x)), x);
        }
        // 1/3 rounds to the nearest double.
        assert_eq!(rat_to_f64(&r(1, 3)), 1.0 / 3.0);
    }

    #[test]
    fn text_at_the_ends_of_i128() {
        for (n, d) in [
            (i128::MIN, 1),
            (i128::MAX, 1),
            (-1, i128::MAX),
            (i128::MIN + 1, 7),
        ] {
            let r = Rat::new(n.into(), d.into());
            assert_eq!(rat_to_string(&r), big_rat_to_string(&r));
        }
        assert_eq!(rat_to_string(&r(-3, 6)), "-1/2");
        assert_eq!(rat_to_string(&r(-4, 2)), "-2");
    }

    proptest::proptest! {
        /// The `u128` path gives the big-integer path's rational, in
        /// lowest terms (a rational not in lowest terms would compare
        /// unequal to an equal one), wherever it answers.
        #[test]
        fn small_decimals_equal_big_ones(digits in "[0-9]{1,40}", negative in proptest::bool::ANY, scale in -45i32..45) {
            let big = big_decimal(&digits, negative, scale).unwrap();
            if let Some(small) = small_decimal(&digits, negative, scale) {
                proptest::prop_assert_eq!((small.numer(), small.denom()), (big.numer(), big.denom()));
            } else {
                proptest::prop_assert!(digits.len() > 38 || scale.abs() > 38 || big.numer().bits() > 126);
            }
        }

        /// A decimal as a user types it (signs, no integer or no fraction
        /// digits, leading zeros, long mantissas, exponents of either case
        /// and sign, surrounding blanks) denotes the value the standard
        /// library's correctly rounded parser reads: the nearest double of
        /// the exact value is its result, and what it reads as an infinity
        /// or as zero (below half the least subnormal) is still the exact
        /// rational (refused only outside `e-4000..=e4000`). An
        /// independent check of the parser and of `rat_to_f64` together.
        #[test]
        fn decimals_denote_what_the_standard_parser_rounds(
            text in "[ \t]{0,1}[+-]?([0-9]{0,25}\\.[0-9]{1,25}|[0-9]{1,25}\\.?)([eE][+-]?0{0,2}[0-9]{1,4})?[ \t]{0,1}"
        ) {
            let reference: f64 = text.trim().parse().unwrap();
            match parse_rational(&text) {
                Ok(r) => {
                    let got = rat_to_f64(&r);
                    if reference.is_finite() {
                        proptest::prop_assert_eq!(got, reference, "{}", text);
                    } else {
                        // Beyond the doubles: the exact value is kept.
                        proptest::prop_assert!(got.is_infinite() && got.signum() == reference.signum());
                    }
                    // Zero exactly when no digit of the mantissa is
                    // (`-0.00e7`), not when it rounds to zero (`1e-400`).
                    let mantissa = text.trim().split(['e', 'E']).next().unwrap();
                    let nonzero = mantissa.bytes().any(|b| (b'1'..=b'9').contains(&b));
                    proptest::prop_assert_eq!(r.is_zero(), !nonzero, "{}", text);
                }
                Err(RationalParseError::ExponentRange(_)) => {
                    let e = text.trim().rsplit(['e', 'E']).next().unwrap();
                    proptest::prop_assert!(e.parse::<i32>().unwrap().abs() > 4000, "{}", text);
                }
                Err(e) => proptest::prop_assert!(false, "{}: {}", text, e),
            }
        }

        /// The one-division fast path rounds like num-rational's general
        /// conversion (numerators and denominators around 2^53).
        #[test]
        fn small_quotients_round_correctly(n in -(1i64 << 54)..(1i64 << 54), d in 1i64..(1i64 << 54), shift in 0u32..40) {
            let r = Rat::new((n >> shift).into(), d.into());
            proptest::prop_assert_eq!(rat_to_f64(&r), r.to_f64().unwrap());
        }

        /// Integer long division rounds like num-rational's conversion of
        /// the same rational: numerators and denominators of every width,
        /// exponents into the subnormal and overflow ranges (fallback).
        #[test]
        fn integer_ratios_round_correctly(
            n in proptest::num::i128::ANY, nb in 1u32..128,
            d in proptest::num::u128::ANY, db in 1u32..129, e in -1200i32..1200
        ) {
            let n = n >> (128 - nb);
            let d = (d >> (128 - db)).max(1);
            let reference = ratio_to_rat(n, d, e).to_f64().unwrap();
            proptest::prop_assert_eq!(ratio_to_f64(n, d, e).to_bits(), reference.to_bits());
        }

        /// Quotients that round into the least normal binades, where the
        /// scale of the rounded quotient is below the normal doubles:
        /// as num-rational rounds them, exact ties (54 significant bits
        /// over one) included.
        #[test]
        fn quotients_in_the_least_normal_binades_round_correctly(
            n in 1i128..(1i128 << 100), d in 1u128..(1u128 << 80),
            m in (1i128 << 52)..(1i128 << 53), top in -1022i32..-960, tie in proptest::bool::ANY,
        ) {
            let (n, d) = if tie { (2 * m + 1, 1) } else { (n, d) };
            let bits = |v: u128| 128 - v.leading_zeros() as i32;
            let e = top + 1 - (bits(n.unsigned_abs()) - bits(d));
            let reference = ratio_to_rat(n, d, e).to_f64().unwrap();
            proptest::prop_assert!(reference >= f64::MIN_POSITIVE);
            proptest::prop_assert_eq!(ratio_to_f64(n, d, e).to_bits(), reference.to_bits());
            proptest::prop_assert_eq!(ratio_to_f64_normal(n.unsigned_abs(), d, e), Some(reference));
        }

        /// The estimate-and-correct quotient of a numerator shifted past
        /// 128 bits, and whether a remainder is left, are big-integer
        /// division's: divisors of 74 to 126 bits (all ones, powers of two
        /// and their neighbours among them), numerators of every width.
        #[test]
        fn wide_shifted_quotients_are_exact(
            num in proptest::num::u128::ANY, nb in 1u32..129,
            d in proptest::num::u128::ANY, db in 74u32..127, edge in 0usize..4
        ) {
            let num = (num >> (128 - nb)).max(1);
            let d = match edge {
                0 => (d >> (128 - db)) | (1 << (db - 1)),
                1 => (1 << db) - 1,
                2 => 1 << (db - 1),
                _ => (1 << (db - 1)) + 1,
            };
            let bits = |v: u128| 128 - v.leading_zeros() as i32;
            let s = 55 - (bits(num) - bits(d));
            proptest::prop_assume!(s > num.leading_zeros() as i32);
            let (q, inexact) = shifted_quotient_wide(num, s as u32, d);
            let (n, d) = (BigInt::from(num) << s as usize, BigInt::from(d));
            proptest::prop_assert_eq!(BigInt::from(q), &n / &d);
            proptest::prop_assert_eq!(inexact, !(&n % &d).is_zero());
        }

        /// The text of a rational is the big-integer text, whether its
        /// parts fit `i128` or not (widths up to 140 bits, both signs).
        #[test]
        fn text_is_the_big_integer_text(
            n in proptest::num::i128::ANY, nb in 1u32..129, nshift in 0u32..13,
            d in proptest::num::u128::ANY, db in 1u32..129, dshift in 0u32..13
        ) {
            let n = BigInt::from(n >> (128 - nb)) << nshift;
            let d = (BigInt::from(d >> (128 - db)) << dshift).max(BigInt::one());
            let r = Rat::new(n, d);
            proptest::prop_assert_eq!(rat_to_string(&r), big_rat_to_string(&r));
        }

        /// The quotient of two rationals equals num-rational's, whether
        /// the parts fit `i128` or not (widths up to 140 bits, both signs).
        #[test]
        fn quotients_are_exact(
            p in proptest::num::i128::ANY, pb in 1u32..129, q in proptest::num::u128::ANY, qb in 1u32..129,
            a in proptest::num::i128::ANY, ab in 1u32..129, b in proptest::num::u128::ANY, bb in 1u32..129,
            shift in 0u32..13
        ) {
            let c = Rat::new(BigInt::from(p >> (128 - pb)), BigInt::from(q >> (128 - qb)).max(BigInt::one()));
            let a = BigInt::from(a >> (128 - ab)) << shift;
            proptest::prop_assume!(!a.is_zero());
            let s = Rat::new(a, BigInt::from(b >> (128 - bb)).max(BigInt::one()));
            // In lowest terms, the sign on the numerator: the same parts.
            let (got, want) = (rat_div(&c, &s), &c / &s);
            proptest::prop_assert_eq!((got.numer(), got.denom()), (want.numer(), want.denom()));
        }

        /// Rationals whose parts fit 128 bits (the integer path of
        /// `rat_to_f64`) round like num-rational's conversion.
        #[test]
        fn wide_rationals_round_correctly(
            n in proptest::num::i128::ANY, nb in 1u32..128,
            d in proptest::num::u128::ANY, db in 1u32..128
        ) {
            let n = n >> (128 - nb);
            let d = (d >> (128 - db)).max(1);
            let r = Rat::new(n.into(), d.into());
            proptest::prop_assert_eq!(rat_to_f64(&r).to_bits(), r.to_f64().unwrap().to_bits());
        }

        /// Exact ties and their neighbours round to even: `(2m + 1) / 2`
        /// at 54 significant bits, times odd and power-of-two divisors.
        #[test]
        fn integer_ratio_ties_go_to_even(m in (1i128 << 52)..(1i128 << 53), k in 0u32..60, odd in 1u128..1000, delta in -1i128..=1) {
            let n = ((2 * m + 1) << k) + delta;
            for d in [1u128 << (k + 1), (1u128 << (k + 1)) * (2 * odd + 1)] {
                let n = n * if d.count_ones() == 1 { 1 } else { (2 * odd + 1) as i128 };
                let reference = ratio_to_rat(n, d, 0).to_f64().unwrap();
                proptest::prop_assert_eq!(ratio_to_f64(n, d, 0), reference);
            }
        }

        /// Multiplying by `2^s` through the trailing zeros gives the
        /// rational product's parts (lowest terms), for parts of up to
        /// 430 bits and shifts far past the double range.
        #[test]
        fn pow2_products_equal_rational_ones(
            p in proptest::num::i128::ANY, pb in 1u32..129, pshift in 0u32..300,
            q in proptest::num::u128::ANY, qb in 1u32..129, qshift in 0u32..300, s in -1300i32..1300
        ) {
            let c = Rat::new(
                BigInt::from(p >> (128 - pb)) << pshift,
                (BigInt::from(q >> (128 - qb)) << qshift).max(BigInt::one()),
            );
            let want = &c * Rat::from_integer(BigInt::from(2)).pow(s);
            let got = rat_times_pow2(&c, s);
            proptest::prop_assert_eq!((got.numer(), got.denom()), (want.numer(), want.denom()));
        }

        /// The difference with a double, rounded once and compared, as the
        /// rational subtraction and comparison give them: for doubles of
        /// any bit pattern and for the nearest double of the value and
        /// its neighbours (the residual of a level's approximation).
        #[test]
        fn differences_with_a_double_are_exact(
            p in proptest::num::i128::ANY, pb in 1u32..129, pshift in 0u32..1100,
            q in proptest::num::u128::ANY, qb in 1u32..129, qshift in 0u32..1100,
            bits in proptest::num::u64::ANY, pick in 0u8..4
        ) {
            let c = Rat::new(
                BigInt::from(p >> (128 - pb)) << pshift,
                (BigInt::from(q >> (128 - qb)) << qshift).max(BigInt::one()),
            );
            let near = rat_to_f64(&c);
            let x = match pick {
                0 => f64::from_bits(bits),
                1 => near,
                2 => near.next_up(),
                _ => near.next_down(),
            };
            proptest::prop_assume!(x.is_finite());
            let diff = &c - rat_from_f64(x);
            proptest::prop_assert_eq!(rat_minus_f64_to_f64(&c, x).to_bits(), rat_to_f64(&diff).to_bits());
            proptest::prop_assert_eq!(cmp_f64_rat(x, &c), rat_from_f64(x).cmp(&c));
        }

        /// The direct construction equals num-rational's (reduced) one for
        /// every finite double, subnormals included.
        #[test]
        fn from_f64_equals_from_float(bits in proptest::num::u64::ANY) {
            let x = f64::from_bits(bits);
            proptest::prop_assume!(x.is_finite());
            let direct = rat_from_f64(x);
            let reference = Rat::from_float(x).unwrap();
            proptest::prop_assert_eq!(direct.numer(), reference.numer());
            proptest::prop_assert_eq!(direct.denom(), reference.denom());
        }
    }
}
