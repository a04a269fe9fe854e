//! Input: doubles and a power of two. Output: their exact products, and
//! the binary exponents that say when such a product is exact.
//!
//! Signs of determinants and of volumes do not change when every
//! coordinate is multiplied by one power of two `2^s`; multiplying a double
//! by `2^s` is exact when the result is a double (no overflow, and no set
//! bit below `2^-1074`). The predicates and the volume filter use this to
//! bring extreme coordinates (subnormal, or near `2^1023`) to where their
//! floating-point arithmetic is proven exact or bounded.

use super::rational::decompose;

/// `2^k` for `-1022 <= k <= 1023` (a normal double).
#[inline]
pub fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `x 2^s`, by multiplications with normal powers of two (at most three
/// for any `s` a finite result can need). Exact whenever the result
/// `x 2^s` is a double: each intermediate product lies between `x` and the
/// result in magnitude, with no set bit lower than both of theirs, so it
/// is a double too.
#[inline]
pub fn times_pow2(x: f64, s: i32) -> f64 {
    let (mut y, mut s) = (x, s);
    while !(-1022..=1023).contains(&s) {
        let step = s.clamp(-1022, 1023);
        y *= pow2(step);
        s -= step;
    }
    y * pow2(s)
}

/// `(L, H)` of the finite non-zero values: `L` the least exponent of a set
/// bit (`x = m 2^e`, `m` odd, `e >= L`), `H` the least integer with every
/// `|x| < 2^H`; `None` when every value is zero. Non-finite values are
/// skipped (callers check finiteness first).
pub fn spread(xs: &[f64]) -> Option<(i32, i32)> {
    xs.iter()
        .filter_map(|&x| decompose(x))
        .map(|(m, e)| (e, e + 64 - m.unsigned_abs().leading_zeros() as i32))
        .reduce(|(l, h), (e, t)| (l.min(e), h.max(t)))
}

/// The exponent of the leading bit of a finite non-zero `x`
/// (`2^k <= |x| < 2^(k+1)`, subnormals included).
pub fn leading_exponent(x: f64) -> Option<i32> {
    decompose(x).map(|(m, e)| e + 63 - m.unsigned_abs().leading_zeros() as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;
    use crate::exact::Rat;

    #[test]
    fn scaling_is_exact_across_the_range() {
        let tiny = f64::from_bits(1);
        assert_eq!(times_pow2(tiny, 2097), 2f64.powi(1023));
        assert_eq!(times_pow2(2f64.powi(1023), -2097), tiny);
        for x in [tiny, 3.0 * tiny, 1.5, f64::MAX, -0.1, f64::MIN_POSITIVE] {
            let (l, h) = spread(&[x]).unwrap();
            // Every s whose result is a double.
            for s in [-1074 - l, 1023 - h, 0, 17, -17]
                .into_iter()
                .filter(|s| (-1074 - l..=1023 - h).contains(s))
            {
                let y = times_pow2(x, s);
                let two = Rat::from_integer(2.into());
                assert_eq!(rat_from_f64(y), rat_from_f64(x) * two.pow(s), "{x} 2^{s}");
            }
        }
        assert_eq!(spread(&[0.0, 6.0, -0.25]), Some((-2, 3)));
        assert_eq!(spread(&[0.0]), None);
        assert_eq!(leading_exponent(tiny), Some(-1074));
        assert_eq!(leading_exponent(-6.0), Some(2));
    }
}
