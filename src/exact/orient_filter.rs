//! Input: points with `f64` coordinates. Output: the exact sign of
//! orient2d or orient3d when a floating-point evaluation with a proven
//! error bound shows it, else `None` (the caller then asks the exact
//! predicates of [`super::predicates`]).
//!
//! A filter lets a caller try several predicates cheaply and pay for an
//! exact evaluation only where it is still needed: an exactly zero
//! orientation (coplanar faces of CAD parts) always takes the slow exact
//! path, so a test that can be decided by another, non-zero sign should
//! look at that one first.
//!
//! The bounds are Shewchuk's ("Adaptive Precision Floating-Point Arithmetic
//! and Fast Robust Geometric Predicates", Discrete Comput. Geom. 18, 1997,
//! section 4.3 and the code `predicates.c`): with `e = 2^-53` and the
//! determinant evaluated in exactly the order below (differences first,
//! then products and sums), the computed value differs from the exact one
//! by at most `(3 + 16 e) e |detleft + detright|` for orient2d (there
//! `ccwerrboundA`; `detleft`, `detright` of one sign, else the sign is
//! clear) and `(7 + 56 e) e P` for orient3d (`o3derrboundA`, `P` the
//! permanent: the same sum with every term's absolute value). Those
//! bounds assume no underflow or overflow, so the filter answers only when
//! every difference is zero or lies in `[2^-300, 2^300]` in magnitude:
//! products of two or three such numbers then stay normal and finite, and
//! the differences themselves, being representable whenever they are
//! that small or smaller, were not rounded into the subnormal range.
//!
//! That holds for every difference of coordinates that are each zero or
//! of magnitude in `[2^-247, 2^299]`: two such nonzero doubles are
//! multiples of `2^-299` (the ulp of `2^-247`), so they are equal or at
//! least that far apart, and no difference exceeds `2^300`. A [`Filter`]
//! made by [`Filter::for_points`] knows whether all of a mesh's
//! coordinates are so, and then skips the per-call check.
//! Property-tested against the exact predicates, across the `f64` range.

use super::predicates::Sign;

/// Half an ulp of 1: the unit roundoff of `f64`.
const EPS: f64 = 1.0 / 9_007_199_254_740_992.0; // 2^-53
const CCW_BOUND: f64 = (3.0 + 16.0 * EPS) * EPS;
const O3D_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
/// Differences must be zero or within `[SMALL, LARGE]` in magnitude.
const SMALL: f64 = pow2(-300);
const LARGE: f64 = pow2(300);

/// Coordinates must be zero or within `[SMALL_COORD, LARGE_COORD]` for
/// [`Filter::for_points`] to vouch for every difference.
const SMALL_COORD: f64 = pow2(-247);
const LARGE_COORD: f64 = pow2(299);

/// `2^e` for a normal exponent `e` (built from its bits: exact).
const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

#[inline]
fn in_range(x: f64) -> bool {
    let m = x.abs();
    (SMALL..=LARGE).contains(&m) | (m == 0.0)
}

/// The filters, knowing whether every coordinate they will see is zero or
/// of magnitude in `[2^-247, 2^299]` (then no per-call range check).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Filter {
    vouched: bool,
}

impl Filter {
    /// Filters that check each call's differences.
    pub const CHECKING: Filter = Filter { vouched: false };

    /// Filters for these points: unchecked calls when every coordinate is
    /// in the range above. Every point later passed must be one of them.
    pub fn for_points(points: &[[f64; 3]]) -> Filter {
        let ok = |x: f64| {
            let m = x.abs();
            (SMALL_COORD..=LARGE_COORD).contains(&m) | (m == 0.0)
        };
        Filter {
            vouched: points.iter().all(|p| ok(p[0]) & ok(p[1]) & ok(p[2])),
        }
    }

    /// These filters, extended to `more` points.
    pub fn with(self, more: &[[f64; 3]]) -> Filter {
        Filter {
            vouched: self.vouched && Filter::for_points(more).vouched,
        }
    }

    /// [`orient2d_axes_filter`] for points of this filter.
    #[inline]
    pub fn orient2d_axes(
        self,
        a: [f64; 3],
        b: [f64; 3],
        c: [f64; 3],
        i: usize,
        j: usize,
    ) -> Option<Sign> {
        orient2d_inner(a, b, c, i, j, self.vouched)
    }

    /// [`orient3d_filter`] for points of this filter.
    #[inline]
    pub fn orient3d(self, a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Option<Sign> {
        orient3d_inner(a, b, c, d, self.vouched)
    }
}

/// The sign of [`super::predicates::orient2d_axes`]`(a, b, c, i, j)`, when
/// the filter shows it.
#[inline]
pub fn orient2d_axes_filter(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    i: usize,
    j: usize,
) -> Option<Sign> {
    orient2d_inner(a, b, c, i, j, false)
}

#[inline(always)]
fn orient2d_inner(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    i: usize,
    j: usize,
    vouched: bool,
) -> Option<Sign> {
    let (acx, bcx, acy, bcy) = (a[i] - c[i], b[i] - c[i], a[j] - c[j], b[j] - c[j]);
    if !vouched && !(in_range(acx) & in_range(bcx) & in_range(acy) & in_range(bcy)) {
        return None;
    }
    let detleft = acx * bcy;
    let detright = acy * bcx;
    let det = detleft - detright;
    let bound = CCW_BOUND * (detleft.abs() + detright.abs());
    if det > bound {
        Some(Sign::Positive)
    } else if -det > bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// The sign of [`super::predicates::orient3d`]`(a, b, c, d)` (positive
/// when `d` is on the side that the counter-clockwise normal of `(a, b,
/// c)` points to), when the filter shows it.
#[inline]
pub fn orient3d_filter(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Option<Sign> {
    orient3d_inner(a, b, c, d, false)
}

#[inline(always)]
fn orient3d_inner(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    vouched: bool,
) -> Option<Sign> {
    let (adx, bdx, cdx) = (a[0] - d[0], b[0] - d[0], c[0] - d[0]);
    let (ady, bdy, cdy) = (a[1] - d[1], b[1] - d[1], c[1] - d[1]);
    let (adz, bdz, cdz) = (a[2] - d[2], b[2] - d[2], c[2] - d[2]);
    let ok = vouched
        || in_range(adx)
            & in_range(bdx)
            & in_range(cdx)
            & in_range(ady)
            & in_range(bdy)
            & in_range(cdy)
            & in_range(adz)
            & in_range(bdz)
            & in_range(cdz);
    if !ok {
        return None;
    }
    let bdxcdy = bdx * cdy;
    let cdxbdy = cdx * bdy;
    let cdxady = cdx * ady;
    let adxcdy = adx * cdy;
    let adxbdy = adx * bdy;
    let bdxady = bdx * ady;
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let bound = O3D_BOUND * permanent;
    // This determinant is positive when d is below (a, b, c) seen with
    // (a, b, c) counter-clockwise: the opposite of the project's sign.
    if det > bound {
        Some(Sign::Negative)
    } else if -det > bound {
        Some(Sign::Positive)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::predicates::{orient2d_axes, orient3d};
    use super::*;
    use proptest::prelude::*;

    /// Small integer grids scaled by a power of two (many exact zeros and
    /// near-zeros), or any finite double.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            (-4i32..4, -300i32..300).prop_map(|(k, e)| f64::from(k) * 2f64.powi(e)),
            (-4i32..4).prop_map(f64::from),
            any::<f64>().prop_filter("finite", |x| x.is_finite()),
            any::<f32>()
                .prop_filter("finite", |x| x.is_finite())
                .prop_map(f64::from),
        ]
    }

    fn point() -> impl Strategy<Value = [f64; 3]> {
        [coordinate(), coordinate(), coordinate()]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        #[test]
        fn filtered_signs_are_exact_signs(a in point(), b in point(), c in point(), d in point()) {
            if let Some(s) = orient3d_filter(a, b, c, d) {
                prop_assert_eq!(s, orient3d(a, b, c, d));
            }
            // Unchecked calls, where the points' filter allows them.
            let f = Filter::for_points(&[a, b, c, d]);
            if let Some(s) = f.orient3d(a, b, c, d) {
                prop_assert_eq!(s, orient3d(a, b, c, d));
            }
            if let Some(s) = f.orient2d_axes(a, b, c, 0, 1) {
                prop_assert_eq!(s, orient2d_axes(a, b, c, 0, 1));
            }
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                if let Some(s) = orient2d_axes_filter(a, b, c, i, j) {
                    prop_assert_eq!(s, orient2d_axes(a, b, c, i, j));
                }
            }
        }

        /// A nearly flat tetrahedron: d one step off the plane of three
        /// integer points.
        #[test]
        fn near_zero_signs_are_left_to_the_exact_predicates_or_right(
            a in proptest::array::uniform3(-8i32..8),
            b in proptest::array::uniform3(-8i32..8),
            c in proptest::array::uniform3(-8i32..8),
            s in 0.0f64..1.0,
            t in 0.0f64..1.0,
        ) {
            let (a, b, c) = (a.map(f64::from), b.map(f64::from), c.map(f64::from));
            let on: [f64; 3] = std::array::from_fn(|k| a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]));
            for d in [on, on.map(|x| x.next_up()), on.map(|x| x.next_down())] {
                if let Some(sign) = orient3d_filter(a, b, c, d) {
                    prop_assert_eq!(sign, orient3d(a, b, c, d));
                }
            }
        }
    }

    #[test]
    fn ordinary_signs_are_shown_and_zeros_are_not() {
        let o = [0.0, 0.0, 0.0];
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(orient3d_filter(o, x, y, z), Some(Sign::Positive));
        assert_eq!(orient3d_filter(o, y, x, z), Some(Sign::Negative));
        assert_eq!(orient3d_filter(o, x, y, [3.0, 5.0, 0.0]), None);
        assert_eq!(orient2d_axes_filter(o, x, y, 0, 1), Some(Sign::Positive));
        assert_eq!(orient2d_axes_filter(o, x, [2.0, 0.0, 0.0], 0, 1), None);
        // Out of the guarded range: left to the exact predicates.
        let tiny = [1e-200, 0.0, 0.0];
        assert_eq!(orient3d_filter(o, tiny, y, z), None);
        assert_eq!(Filter::for_points(&[o, tiny, y, z]), Filter::CHECKING);
        assert_ne!(Filter::for_points(&[o, x, y, z]), Filter::CHECKING);
        // The range's ends, as stated.
        assert_eq!(SMALL_COORD, 2f64.powi(-247));
        assert_eq!(LARGE_COORD, 2f64.powi(299));
        assert_eq!(SMALL, 2f64.powi(-300));
        assert_eq!(LARGE, 2f64.powi(300));
    }
}
