//! Input: the largest coordinate magnitude of a mesh. Output: the power of
//! two `2^s` by which the slicer's floating-point filters multiply every
//! coordinate (and every level), so that a mesh scaled to the ends of the
//! double range (`1e-300`, `1e300`) is filtered where their error bounds
//! are proven, instead of falling to big rationals.
//!
//! Nothing here decides anything by itself. Signs of orientations,
//! comparisons and areas do not change when every point is multiplied by
//! one power of two, and the nearest double commutes with that scaling
//! wherever both values are normal: [`Frame::back`] refuses the rest, and
//! the caller takes the exact path (or, for a crossing among the
//! subnormals, decides on their grid's image in the frame: see
//! `on_subnormal_grid` in [`super::crossing`]). Multiplying by a power of
//! two is exact whenever the result is a normal double ([`times_pow2`]):
//! callers check that range after [`Frame::place`].

use super::rational::{rat_times_pow2, Rat};
use super::scale::{leading_exponent, times_pow2};

/// Magnitudes within `2^-200 ..= 2^200` are left where they are (the
/// identity frame, which every ordinary mesh takes): every filter accepts
/// them. A range of the filters' proofs, not a tolerance.
const UNSCALED: std::ops::RangeInclusive<i32> = -200..=200;

/// The leading exponents `e` (`2^e <= |x| < 2^(e+1)`) of coordinates that
/// every exact predicate and filter takes as they are, with no scaling or
/// range check of its own: the static filters' vouched range
/// ([`super::orient_filter::Filter`], `[2^-247, 2^299]`), inside `robust`'s
/// windows ([`super::predicates`]: `[2^-248, 2^300)` for orient3d, wider
/// for orient2d). A range of their proofs, not a tolerance.
pub const PREDICATE_RANGE: std::ops::RangeInclusive<i32> = -247..=298;

/// Multiplication by `2^shift`, chosen once per mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    shift: i32,
}

impl Frame {
    /// No scaling.
    pub const IDENTITY: Frame = Frame { shift: 0 };

    /// The frame of coordinates whose largest magnitude is `top`: the
    /// identity within `2^±200`, else the shift that brings `top` into
    /// `[1, 2)`. Non-finite or zero: the identity.
    pub fn for_magnitude(top: f64) -> Frame {
        match leading_exponent(top) {
            Some(e) if top.is_finite() && !UNSCALED.contains(&e) => Frame { shift: -e },
            _ => Frame::IDENTITY,
        }
    }

    /// The frame of a set of points (see [`Frame::for_magnitude`]).
    pub fn for_points<const N: usize>(points: impl IntoIterator<Item = [f64; N]>) -> Frame {
        let top = points
            .into_iter()
            .flatten()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Frame::for_magnitude(top)
    }

    /// A frame in which every non-zero coordinate of `points` has a
    /// magnitude within [`PREDICATE_RANGE`], where the exact predicates
    /// and the filters take coordinates as they are: the identity when
    /// they already do, else the shift nearest to bringing the largest
    /// magnitude into `[1, 2)` ([`Frame::for_magnitude`]'s choice). `None`
    /// when no shift does (the coordinates span more binades than the
    /// range, or one is not finite), or every coordinate is zero. Placing a
    /// coordinate in the frame is then exact: its result is a normal
    /// double.
    pub fn for_predicates(points: &[[f64; 3]]) -> Option<Frame> {
        let mut span: Option<(i32, i32)> = None;
        for &x in points.iter().flatten() {
            if !x.is_finite() {
                return None;
            }
            if let Some(e) = leading_exponent(x) {
                span = Some(span.map_or((e, e), |(l, h)| (l.min(e), h.max(e))));
            }
        }
        let (low, high) = span?;
        // Shifts s with low + s >= range.start and high + s <= range.end.
        let (from, to) = (PREDICATE_RANGE.start() - low, PREDICATE_RANGE.end() - high);
        (from <= to).then(|| Frame {
            shift: if (from..=to).contains(&0) {
                0
            } else {
                (-high).clamp(from, to)
            },
        })
    }

    /// Whether this frame leaves every value as it is.
    #[inline(always)]
    pub fn is_identity(self) -> bool {
        self.shift == 0
    }

    /// The exponent `s` of the frame's factor `2^s`.
    pub fn shift(self) -> i32 {
        self.shift
    }

    /// `x 2^s`, exact and in lowest terms ([`rat_times_pow2`]).
    pub fn scale(self, x: &Rat) -> Rat {
        rat_times_pow2(x, self.shift)
    }

    /// `v 2^s`: exact when the result is a normal double or zero (the
    /// caller checks its range).
    #[inline(always)]
    pub fn place(self, v: f64) -> f64 {
        times_pow2(v, self.shift)
    }

    /// `v 2^s` when it is exactly that and within `u` relatively of it
    /// wherever `v` is of something exact: `v` zero, or `v` and the result
    /// both normal. A value that would underflow to zero is refused.
    #[inline(always)]
    pub fn place_normal(self, v: f64) -> Option<f64> {
        let p = self.place(v);
        (v == 0.0 || (normal(v) && normal(p))).then_some(p)
    }

    /// The value `r 2^-s` back in the mesh's units. When `r` is the nearest
    /// double of some exact `X 2^s` (and zero only when `X` is), the answer
    /// is the nearest double of `X`: it is given for `r` zero, or for `r`
    /// normal with `r 2^-s` finite and strictly above the least normal
    /// double in magnitude (there the doubles on both sides of the value
    /// are spaced as in the frame; at or below it they are not). Else
    /// `None`.
    #[inline(always)]
    pub fn back(self, r: f64) -> Option<f64> {
        back_by(r, self.shift)
    }

    /// `v 2^-s` for a value known to be exactly that (a multiple of the
    /// frame's image of `2^-1074`, or a placed double).
    #[inline(always)]
    pub fn place_back(self, v: f64) -> f64 {
        times_pow2(v, -self.shift)
    }

    /// [`Frame::back`] for an area (a value in units of `2^2s`).
    pub fn back_area(self, a: f64) -> Option<f64> {
        back_by(a, 2 * self.shift)
    }

    /// `v 2^(2s)` for a bound on areas in the mesh's units (exact when the
    /// result is normal).
    pub fn place_area(self, v: f64) -> f64 {
        times_pow2(v, 2 * self.shift)
    }
}

/// Finite and at least the least normal double in magnitude.
#[inline(always)]
fn normal(v: f64) -> bool {
    v.is_finite() && v.abs() >= f64::MIN_POSITIVE
}

/// `r 2^-s` when both are normal (the result strictly above the least
/// normal double), or `r` zero.
#[inline(always)]
fn back_by(r: f64, s: i32) -> Option<f64> {
    let v = times_pow2(r, -s);
    let both = normal(r) && v.abs() > f64::MIN_POSITIVE && v.is_finite();
    (r == 0.0 || both).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::{rat_from_f64, rat_to_f64};
    use crate::exact::Rat;
    use num_bigint::BigInt;
    use proptest::prelude::*;

    #[test]
    fn ordinary_magnitudes_take_the_identity() {
        for top in [0.0, 1.0, 40.0, 3.6e-16, 1e9, 1e60, f64::INFINITY, f64::NAN] {
            assert!(Frame::for_magnitude(top).is_identity(), "{top}");
        }
        assert_eq!(Frame::for_magnitude(1e-300).shift(), 997);
        assert_eq!(Frame::for_magnitude(1e300).shift(), -996);
        assert_eq!(Frame::for_magnitude(-f64::MAX).shift(), -1023);
        assert_eq!(Frame::for_magnitude(5e-324).shift(), 1074);
    }

    /// Shifts derived by hand from the inputs' leading exponents (the
    /// coordinates are test inputs, the range is [`PREDICATE_RANGE`]).
    #[test]
    fn predicate_frames_by_hand() {
        let frame = |ps: &[[f64; 3]]| Frame::for_predicates(ps).map(Frame::shift);
        // In the range already (3.6e-16 is near 2^-51): the identity.
        assert_eq!(frame(&[[40.0, -3.6e-16, 0.0], [1e80, 1e-70, 2.0]]), Some(0));
        // The largest brought into [1, 2) when the rest follows.
        assert_eq!(frame(&[[1e-300, 0.0, 3e-310]]), Some(997));
        assert_eq!(frame(&[[1e300, -1e250, 0.0]]), Some(-996));
        // 2^-700 and 2^-300: the least no lower than 2^-247 takes the
        // shift 453, which leaves the largest at 2^153 (not in [1, 2)).
        let (tiny, small) = (times_pow2(1.0, -700), times_pow2(1.0, -300));
        assert_eq!(frame(&[[tiny, small, 0.0]]), Some(453));
        // No shift brings 2^-600 and 2^0 into 546 binades; nothing to
        // place; not finite.
        assert_eq!(frame(&[[times_pow2(1.0, -600), 1.0, 0.0]]), None);
        assert_eq!(frame(&[[0.0; 3]]), None);
        assert_eq!(frame(&[]), None);
        assert_eq!(frame(&[[1.0, f64::NAN, 0.0]]), None);
        assert_eq!(frame(&[[1e-300, f64::INFINITY, 0.0]]), None);
    }

    proptest! {
        /// A predicate frame places every coordinate exactly in
        /// [`PREDICATE_RANGE`], is the identity when they are there, and
        /// is refused only when their binades span more than the range.
        #[test]
        fn predicate_frames_place_exactly_in_range(
            exps in proptest::collection::vec((-1074i32..=1023, any::<u64>(), any::<bool>()), 1..12),
        ) {
            let xs: Vec<f64> = exps
                .iter()
                .map(|&(e, bits, zero)| {
                    let x = f64::from_bits(bits & ((1 << 63) | ((1 << 52) - 1)) | (1023 << 52));
                    if zero { 0.0 } else { times_pow2(x, e.min(1023)) }
                })
                .collect();
            let points: Vec<[f64; 3]> = xs.chunks(3).map(|c| std::array::from_fn(|i| c.get(i).copied().unwrap_or(0.0))).collect();
            let leads: Vec<i32> = xs.iter().filter_map(|&x| leading_exponent(x)).collect();
            match Frame::for_predicates(&points) {
                Some(frame) => {
                    let in_range = |e: &i32| PREDICATE_RANGE.contains(e);
                    prop_assert_eq!(frame.is_identity(), leads.iter().all(in_range));
                    for &x in &xs {
                        let p = frame.place(x);
                        prop_assert_eq!(rat_from_f64(p), frame.scale(&rat_from_f64(x)));
                        prop_assert!(x == 0.0 || leading_exponent(p).is_some_and(|e| in_range(&e)));
                    }
                }
                None => {
                    let (lo, hi) = (leads.iter().min(), leads.iter().max());
                    prop_assert!(lo.is_none() || hi.unwrap() - lo.unwrap() > PREDICATE_RANGE.end() - PREDICATE_RANGE.start());
                }
            }
        }
    }

    proptest! {
        // Values that vanish in the frame are skipped: many, at the ends.
        #![proptest_config(ProptestConfig { max_global_rejects: 1 << 20, ..ProptestConfig::default() })]

        /// `back` of the nearest double of `X 2^s` is the nearest double of
        /// `X`, whenever it answers; it answers for every normal result
        /// strictly above the least normal double.
        #[test]
        fn back_is_the_nearest_double(bits in any::<u64>(), num in any::<i64>(), den in 1i64..i64::MAX, top in any::<u64>()) {
            let top = f64::from_bits(top);
            let frame = Frame::for_magnitude(top);
            let anchor = f64::from_bits(bits);
            prop_assume!(anchor.is_finite());
            // An exact value near a double: the double plus a fraction of
            // its gap.
            let gap = rat_from_f64(anchor.next_up()) - rat_from_f64(anchor);
            let x = rat_from_f64(anchor) + gap * Rat::new(BigInt::from(num % 1000), BigInt::from(den % 997 + 1));
            let s = frame.shift();
            let scaled = frame.scale(&x);
            prop_assert_eq!(&scaled, &(&x * Rat::from_integer(BigInt::from(2)).pow(s)));
            let in_frame = rat_to_f64(&scaled);
            let nearest = rat_to_f64(&x);
            // The precondition: zero in the frame only when the value is.
            prop_assume!(in_frame != 0.0 || x == Rat::from_integer(BigInt::from(0)));
            match frame.back(in_frame) {
                Some(v) => prop_assert_eq!(v.to_bits(), nearest.to_bits()),
                None => {
                    let normal = |v: f64| v.is_finite() && v.abs() > f64::MIN_POSITIVE;
                    prop_assert!(!normal(in_frame) || !normal(nearest));
                }
            }
        }
    }
}
