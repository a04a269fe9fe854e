//! Input: the corners of mesh faces (doubles). Output: twice the signed
//! area of each face's `(x, y)` projection, exactly, and exact sums of
//! their magnitudes (the areas of face regions, SPEC 7.3 and 7.6).
//!
//! Doubles are dyadic, so these areas are too: `m 2^e`. Each face is put
//! on its own binary grid (the lowest set bit of its six coordinates), so
//! its integers are as small as the face allows wherever it lies. The
//! determinant is taken in `i128` when they span at most 62 places, in
//! 256-bit integers on the stack up to 126 places, and with big integers
//! beyond. Nothing is rounded.

use super::dyadic::Dyadic;
use super::point::Layout;
use super::Sign;
use ethnum::{I256, U256};
use num_bigint::BigInt;

/// Twice the signed area of a triangle's `(x, y)` projection, exactly:
/// `m 2^e`. Its sign is `orient2d` of the three corners.
#[derive(Clone, Debug)]
pub enum TwiceArea {
    /// `m 2^e`, `m` in 256 bits.
    Wide { m: I256, e: i32 },
    /// `m 2^e` with a big-integer `m` (corners more than 126 binary
    /// places apart).
    Big(Dyadic),
}

impl TwiceArea {
    /// The sign, exactly.
    pub fn sign(&self) -> Sign {
        match self {
            TwiceArea::Wide { m, .. } => Sign::of_ordering(m.cmp(&I256::ZERO)),
            TwiceArea::Big(d) => d.sign(),
        }
    }
}

/// Twice the signed area of the `(x, y)` projection of the triangle
/// `a, b, c`, exactly (positive when counter-clockwise seen from `+z`).
/// `None` if a coordinate is infinite or NaN.
pub fn twice_area_xy(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<TwiceArea> {
    let layout = Layout::of([a[0], a[1], b[0], b[1], c[0], c[1]])?;
    let e = 2 * layout.lowest;
    if layout.places() <= 62 {
        // |k| < 2^62: differences below 2^63, products below 2^126, their
        // difference below 2^127.
        let [ax, ay, bx, by, cx, cy] = layout.ints_i64()?.map(i128::from);
        let m = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        return Some(TwiceArea::Wide {
            m: I256::from(m),
            e,
        });
    }
    if let Some([ax, ay, bx, by, cx, cy]) = layout.ints_i128().filter(|_| layout.places() <= 126) {
        // |k| < 2^126: differences below 2^127 (in `i128`), products below
        // 2^254, their difference below 2^255.
        let wide = |x: i128| I256::from(x);
        let m = wide(bx - ax) * wide(cy - ay) - wide(by - ay) * wide(cx - ax);
        return Some(TwiceArea::Wide { m, e });
    }
    let [ax, ay, bx, by, cx, cy] = layout.ints_big();
    let m = (&bx - &ax) * (&cy - &ay) - (&by - &ay) * (&cx - &ax);
    Some(TwiceArea::Big(Dyadic::new(m, e)))
}

/// An exact sum of magnitudes `|m| 2^e`: a `U256` on the grid of the
/// lowest exponent added, while the sum fits, and a big-integer
/// [`Dyadic`] for what does not.
#[derive(Clone, Debug, Default)]
pub struct MagnitudeSum {
    low: U256,
    e: i32,
    rest: Dyadic,
}

impl MagnitudeSum {
    /// Adds `|x|`, exactly.
    pub fn add_abs(&mut self, x: &TwiceArea) {
        match x {
            TwiceArea::Wide { m, e } => self.add(m.unsigned_abs(), *e),
            TwiceArea::Big(d) => self.rest.add_abs(d),
        }
    }

    /// Adds `m 2^e`, exactly.
    fn add(&mut self, m: U256, e: i32) {
        if m == U256::ZERO {
            return;
        }
        if self.low == U256::ZERO {
            (self.low, self.e) = (m, e);
            return;
        }
        // The one on the higher grid is rewritten on the lower one (its
        // integer shifted `s` places up) when no bit leaves the top; then
        // the two are added, when the sum does not carry out.
        let (kept, lifted, s, lower) = if e >= self.e {
            (self.low, m, e - self.e, self.e)
        } else {
            (m, self.low, self.e - e, e)
        };
        let s = s.unsigned_abs();
        if s < lifted.leading_zeros() {
            if let Some(sum) = kept.checked_add(lifted << s) {
                (self.low, self.e) = (sum, lower);
                return;
            }
        }
        self.rest.add(&big(m), e);
    }

    /// The sum times `2^shift`, as a rational in lowest terms.
    pub fn to_rat_times_pow2(&self, shift: i32) -> super::Rat {
        let mut total = self.rest.clone();
        total.add(&big(self.low), self.e);
        total.to_rat_times_pow2(shift)
    }
}

/// `m` as a big integer.
fn big(m: U256) -> BigInt {
    BigInt::from_bytes_le(num_bigint::Sign::Plus, &m.to_le_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::area::signed_area_reference;
    use crate::exact::point::Point2;
    use crate::exact::Rat;
    use num_traits::{Signed, Zero};

    /// Twice the area by rationals: the reference.
    fn reference(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Rat {
        let pts: Vec<Point2> = [a, b, c].iter().map(|p| Point2::of_vertex(*p)).collect();
        signed_area_reference(&pts) * Rat::from_integer(2.into())
    }

    fn value(t: &TwiceArea) -> Rat {
        let mut s = MagnitudeSum::default();
        s.add_abs(t);
        let v = s.to_rat_times_pow2(0);
        if t.sign() == Sign::Negative {
            -v
        } else {
            v
        }
    }

    /// A double from raw bits, finite.
    fn finite(bits: u64) -> f64 {
        let x = f64::from_bits(bits);
        if x.is_finite() {
            x
        } else {
            f64::from_bits(bits & !(0x7ff << 52))
        }
    }

    #[test]
    fn hand_derived_areas() {
        // The unit right triangle: twice its area is 1, counter-clockwise.
        let t = twice_area_xy([0.0; 3], [1.0, 0.0, 5.0], [0.0, 1.0, -2.0]).unwrap();
        assert_eq!(t.sign(), Sign::Positive);
        assert_eq!(value(&t), Rat::from_integer(1.into()));
        // Clockwise, at 2^-1074 and 2^1000 apart: (2^1000)(2^-1074)
        // = 2^-74, negative; this spans 2075 places (big integers).
        let tiny = f64::from_bits(1);
        let t = twice_area_xy([0.0; 3], [0.0, 2f64.powi(1000), 0.0], [tiny, 0.0, 0.0]).unwrap();
        assert!(matches!(t, TwiceArea::Big(_)));
        assert_eq!(t.sign(), Sign::Negative);
        assert_eq!(value(&t), -Rat::new(1.into(), BigInt::from(1) << 74u32));
        // Collinear: zero.
        let t = twice_area_xy([0.1, 0.2, 0.0], [0.2, 0.4, 0.0], [0.4, 0.8, 0.0]).unwrap();
        assert_eq!(
            t.sign(),
            match value(&t).cmp(&Rat::zero()) {
                std::cmp::Ordering::Equal => Sign::Zero,
                std::cmp::Ordering::Greater => Sign::Positive,
                std::cmp::Ordering::Less => Sign::Negative,
            }
        );
        assert!(twice_area_xy([f64::NAN, 0.0, 0.0], [0.0; 3], [1.0; 3]).is_none());
    }

    /// At the edges of the `i128` and 256-bit paths: `a = (1, -X)`,
    /// `b = (X, X)`, `c = (-X, X)` span `places(X) + 1` places, and twice
    /// their area is `(X - 1) 2X + 2X (X + 1) = 4 X^2`, with differences
    /// up to `2X` on the way.
    #[test]
    fn widest_faces_of_each_path() {
        for top in [61, 62, 125, 126, 127] {
            // The largest double below 2^(top + 1): 53 ones ending at 2^top.
            let x = 2f64.powi(top + 1) - 2f64.powi(top - 52);
            let (a, b, c) = ([1.0, -x, 0.0], [x, x, 0.0], [-x, x, 0.0]);
            let t = twice_area_xy(a, b, c).unwrap();
            let big_x = BigInt::from((1u64 << 53) - 1) << (top - 52) as u32;
            let expect = Rat::from_integer(BigInt::from(4) * &big_x * &big_x);
            assert_eq!(value(&t), expect, "X just below 2^{}", top + 1);
            assert_eq!(matches!(t, TwiceArea::Big(_)), top >= 126);
        }
    }

    #[test]
    fn sums_carry_across_exponents_and_spill() {
        // Magnitudes on grids far apart: 2^200 + 2^-300 (exactly), and a
        // sum past 256 bits (2^255 twice).
        let mut s = MagnitudeSum::default();
        s.add(U256::ONE, 200);
        s.add(U256::ONE, -300);
        let two = Rat::from_integer(2.into());
        let pow = |k: i32| {
            if k >= 0 {
                Rat::from_integer(BigInt::from(1) << k as u32)
            } else {
                Rat::new(1.into(), BigInt::from(1) << (-k) as u32)
            }
        };
        assert_eq!(s.to_rat_times_pow2(0), pow(200) + pow(-300));
        let mut s = MagnitudeSum::default();
        s.add(U256::ONE << 255u32, 0);
        s.add(U256::ONE << 255u32, 0);
        s.add(U256::from(3u32), -1);
        assert_eq!(
            s.to_rat_times_pow2(-1),
            (pow(256) + Rat::new(3.into(), 2.into())) / two
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

        /// Every face's twice area equals the rational shoelace, with its
        /// sign, for coordinates from any bits (the whole `f64` range),
        /// from `f32`, on one exponent, and decimals.
        #[test]
        fn equals_the_rational_reference(
            bits in proptest::array::uniform6(proptest::num::u64::ANY),
            kind in 0u8..4,
            exp in -1074i32..960,
        ) {
            let x = |i: usize| match kind {
                0 => finite(bits[i]),
                1 => f64::from(f32::from_bits(bits[i] as u32 & 0xbfff_ffff)),
                // Integers of up to 53 bits on one exponent, and zeros.
                2 => (bits[i] as i64 >> 11) as f64 * 2f64.powi(exp.max(-1000)),
                // Decimals with up to five digits, as a text file holds them.
                _ => (bits[i] as i64 >> 47) as f64 * 0.1,
            };
            let (a, b, c) = ([x(0), x(1), 0.0], [x(2), x(3), 0.0], [x(4), x(5), 0.0]);
            let t = twice_area_xy(a, b, c).unwrap();
            let expect = reference(a, b, c);
            proptest::prop_assert_eq!(value(&t), expect.clone());
            let sign = if expect.is_zero() { Sign::Zero } else if expect.is_positive() { Sign::Positive } else { Sign::Negative };
            proptest::prop_assert_eq!(t.sign(), sign);
            proptest::prop_assert_eq!(crate::exact::predicates::orient2d_xy(a, b, c), sign);
        }

        /// A sum of magnitudes equals the rational sum, in any order.
        #[test]
        fn sums_equal_the_rational_sum(
            faces in proptest::collection::vec(proptest::array::uniform6(proptest::num::u64::ANY), 1..12),
            scale in proptest::collection::vec(-300i32..300, 12),
        ) {
            let mut sum = MagnitudeSum::default();
            let mut expect = Rat::zero();
            for (i, bits) in faces.iter().enumerate() {
                // Integers of up to 40 bits on scattered grids, as faces
                // of one region are.
                let x = |k: usize| (bits[k] as i64 >> 24) as f64 * 2f64.powi(scale[i]);
                let (a, b, c) = ([x(0), x(1), 0.0], [x(2), x(3), 0.0], [x(4), x(5), 0.0]);
                sum.add_abs(&twice_area_xy(a, b, c).unwrap());
                expect += reference(a, b, c).abs();
            }
            proptest::prop_assert_eq!(sum.to_rat_times_pow2(-1), expect / Rat::from_integer(2.into()));
        }
    }
}
