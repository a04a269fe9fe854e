//! Input: a point with `f64` coordinates and a chain of 3MF affine
//! transforms (12 `f64` entries each). Output: the transformed point as
//! doubles when every coordinate of its exact image is one, else the exact
//! image as rationals (for snapping to place; nothing here rounds it).
//!
//! Every finite `f64` is a dyadic rational `m * 2^e`; sums and products of
//! dyadics are dyadic, so the image is computed exactly with big integers
//! (no rounding anywhere) and converted back only if that loses nothing.
//! The whole chain is applied exactly; only the final point must be `f64`.

use crate::exact::rational::Rat;
use num_bigint::BigInt;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// A 3MF transform: `m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32`,
/// row-vector convention: `x' = x m00 + y m10 + z m20 + m30`, and so on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Affine(pub(super) [f64; 12]);

impl Affine {
    pub(super) const IDENTITY: Affine =
        Affine([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);

    pub(super) fn is_identity(&self) -> bool {
        self.0 == Self::IDENTITY.0
    }

    /// Whether the linear part is the identity (a pure translation).
    fn is_translation(&self) -> bool {
        self.0[..9] == Self::IDENTITY.0[..9]
    }
}

/// An exact dyadic rational `m * 2^e`.
#[derive(Clone, Debug)]
struct Dyadic {
    m: BigInt,
    e: i64,
}

impl Dyadic {
    /// The exact value of a finite `f64`.
    fn from_f64(x: f64) -> Dyadic {
        let bits = x.to_bits();
        let negative = bits >> 63 == 1;
        let exp = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (m, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), exp - 1075)
        };
        let m = BigInt::from(m);
        Dyadic {
            m: if negative { -m } else { m },
            e,
        }
    }

    fn mul(&self, other: &Dyadic) -> Dyadic {
        Dyadic {
            m: &self.m * &other.m,
            e: self.e + other.e,
        }
    }

    fn add(&self, other: &Dyadic) -> Dyadic {
        if self.m.is_zero() {
            return other.clone();
        }
        if other.m.is_zero() {
            return self.clone();
        }
        let (lo, hi) = if self.e <= other.e {
            (self, other)
        } else {
            (other, self)
        };
        // The exponents of finite f64 products stay within a few thousand.
        let shift = (hi.e - lo.e) as usize;
        Dyadic {
            m: &lo.m + (&hi.m << shift),
            e: lo.e,
        }
    }

    /// The same value as a rational, in lowest terms without a greatest
    /// common divisor: the mantissa's trailing zeros are the only common
    /// factor with a power of two.
    fn to_rat(&self) -> Rat {
        let Some(tz) = self.m.trailing_zeros() else {
            return Rat::zero();
        };
        let m = &self.m >> tz;
        // Products of finite f64 keep `e` within a few thousand.
        let e = self.e + tz as i64;
        match u32::try_from(e) {
            Ok(up) => Rat::from_integer(m << up),
            Err(_) => Rat::new_raw(m, BigInt::one() << e.unsigned_abs()),
        }
    }

    /// The `f64` with exactly this value, if there is one.
    fn to_f64(&self) -> Option<f64> {
        if self.m.is_zero() {
            return Some(0.0);
        }
        let tz = self.m.trailing_zeros().unwrap_or(0);
        let m = &self.m >> tz;
        let e = self.e.checked_add(i64::try_from(tz).ok()?)?;
        let bits = i64::try_from(m.bits()).ok()?;
        if bits > 53 || e < -1074 || e + bits > 1024 {
            return None;
        }
        let mant = m.abs().to_u64()? as f64; // at most 53 bits: exact
        let pow = if e >= -1022 {
            f64::from_bits(((e + 1023) as u64) << 52)
        } else {
            f64::from_bits(1u64 << (e + 1074))
        };
        let v = mant * pow; // representable, hence exact
        Some(if m.is_negative() { -v } else { v })
    }
}

/// Where a vertex lands under a chain of transforms, exactly.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Image {
    /// Every coordinate of the exact image is an `f64`.
    Doubles([f64; 3]),
    /// Some coordinate is not: the whole exact image.
    Exact([Rat; 3]),
}

/// Applies `chain` (innermost transform first) to `p` exactly; `None` if an
/// input is not finite while a transform is not the identity.
pub(super) fn apply_chain(p: [f64; 3], chain: &[Affine]) -> Option<Image> {
    let active: Vec<&Affine> = chain.iter().filter(|t| !t.is_identity()).collect();
    match active.as_slice() {
        [] => return Some(Image::Doubles(p)),
        [t] if t.is_translation() => {
            if let Some(q) = translate(p, [t.0[9], t.0[10], t.0[11]]) {
                return Some(Image::Doubles(q));
            }
        }
        _ => {}
    }
    if !p.iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut q = p.map(Dyadic::from_f64);
    for t in active {
        let m = t.0.map(Dyadic::from_f64);
        let row = |c: usize| {
            q[0].mul(&m[c])
                .add(&q[1].mul(&m[3 + c]))
                .add(&q[2].mul(&m[6 + c]))
                .add(&m[9 + c])
        };
        q = [row(0), row(1), row(2)];
    }
    Some(match (q[0].to_f64(), q[1].to_f64(), q[2].to_f64()) {
        (Some(x), Some(y), Some(z)) => Image::Doubles([x, y, z]),
        _ => Image::Exact(q.map(|c| c.to_rat())),
    })
}

/// `p + t` coordinate-wise, if every sum is exact (checked with the
/// error-free two-sum: the rounding error of a finite sum is itself an f64).
fn translate(p: [f64; 3], t: [f64; 3]) -> Option<[f64; 3]> {
    let mut out = [0.0; 3];
    for i in 0..3 {
        let (a, b) = (p[i], t[i]);
        let s = a + b;
        if !s.is_finite() {
            return None;
        }
        let bb = s - a;
        let err = (a - (s - bb)) + (b - bb);
        if err != 0.0 {
            return None;
        }
        out[i] = s;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dyadic_round_trips_every_kind_of_f64() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            -3.75,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -2.5e-310,
        ] {
            let back = Dyadic::from_f64(x).to_f64().unwrap();
            assert_eq!(back, x);
        }
    }

    #[test]
    fn integer_scale_and_translation_are_exact() {
        let t = Affine([
            2.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, -1.0, 10.0, 0.25, 3.0,
        ]);
        assert_eq!(
            apply_chain([0.75, 3.0, 1.5], &[t]),
            Some(Image::Doubles([11.5, 1.75, 1.5]))
        );
    }

    /// The exact rational of a double (`Dyadic`'s own conversion is what
    /// is under test, so this one goes through `num-rational`).
    fn r(x: f64) -> Rat {
        Rat::from_float(x).unwrap()
    }

    #[test]
    fn an_image_that_rounds_is_given_exactly() {
        let t = Affine([0.1, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        assert_eq!(
            apply_chain([0.1, 0.5, 2.0], &[t]),
            Some(Image::Exact([r(0.1) * r(0.1), r(0.5), r(2.0)]))
        );
        // A translation whose sums round (the usual 3MF placement on a
        // printer's bed), and one far beyond the doubles' range.
        let shift = Affine([
            1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 125.0, 1e20, 0.0,
        ]);
        assert_eq!(
            apply_chain([0.1, 0.1, -0.0], &[shift]),
            Some(Image::Exact([r(0.1) + r(125.0), r(0.1) + r(1e20), r(0.0)]))
        );
        let far = Affine([
            1.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            1.0,
            f64::MAX,
            0.0,
            0.0,
        ]);
        assert_eq!(
            apply_chain([f64::MAX, 0.0, 0.0], &[far]),
            Some(Image::Exact([r(f64::MAX) + r(f64::MAX), r(0.0), r(0.0)]))
        );
        // Subnormal products: exponents below the doubles' range.
        let tiny = Affine([
            5e-324, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        ]);
        assert_eq!(
            apply_chain([0.5, 0.0, 0.0], &[tiny]),
            Some(Image::Exact([r(5e-324) * r(0.5), r(0.0), r(0.0)]))
        );
    }

    /// `to_rat` skips the greatest common divisor: its rationals must still
    /// be in lowest terms (a zero as `0/1`), as `rat_to_string` and hashing
    /// see their parts.
    #[test]
    fn exact_images_are_in_lowest_terms() {
        let t = Affine([
            0.309017, 0.951057, 0.0, -0.951057, 0.309017, 0.0, 0.0, 0.0, 1.0, 125.3, 0.0, 24.0,
        ]);
        // Sample points (not tolerances): plain decimals, one whose z
        // lands on zero, one with a tiny coordinate.
        for p in [[0.1, 0.2, 0.0], [0.1, 0.0, -24.0], [3.0, -4.5, 1e-300]] {
            let Some(Image::Exact(q)) = apply_chain(p, &[t]) else {
                panic!("{p:?} has an image of doubles");
            };
            for c in q {
                let low = c.reduced();
                assert_eq!((c.numer(), c.denom()), (low.numer(), low.denom()));
            }
        }
    }

    #[test]
    fn a_non_finite_input_under_a_transform_has_no_image() {
        let shift = Affine([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0]);
        assert_eq!(apply_chain([f64::NAN, 0.0, 0.0], &[shift]), None);
        assert_eq!(
            apply_chain([f64::INFINITY, 0.0, 0.0], &[Affine::IDENTITY]),
            Some(Image::Doubles([f64::INFINITY, 0.0, 0.0]))
        );
    }

    #[test]
    fn chains_compose_exactly() {
        let rot = Affine([0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        let shift = Affine([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0]);
        // (x, y, z) -> (-y, x, z) -> (-y + 1, x + 2, z + 3)
        assert_eq!(
            apply_chain([0.5, 0.25, 0.0], &[rot, shift]),
            Some(Image::Doubles([0.75, 2.5, 3.0]))
        );
    }
}
