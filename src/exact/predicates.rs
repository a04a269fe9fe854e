//! Input: exact points (`f64` coordinates or [`Point2`]).
//! Output: exact signs of orientation determinants, for every finite
//! double (subnormals and the largest magnitudes included).
//!
//! `f64` predicates use Shewchuk's adaptive predicates from `robust` where
//! they are proven exact, else an integer determinant; rational ones
//! compute the determinant exactly.
//!
//! # When `robust` is exact, and why the guard guarantees it
//!
//! Shewchuk's and Ozaki's proofs (the adaptive stages, the splitter, the
//! error bounds `THETA`, `CCWERRBOUND_*`, `O3DERRBOUND_*`) assume binary
//! floating point with 53-bit significands and an unbounded exponent
//! range: every operation rounds to nearest with relative error at most
//! `u = 2^-53`, and never overflows or underflows. IEEE `f64` differs from
//! that model only (i) above `2^1024` (overflow) and (ii) below `2^-1022`,
//! where results are rounded to multiples of `2^-1074` (lossy underflow).
//!
//! Write every non-zero input coordinate as `m 2^e` with `m` odd; let `L`
//! be the least `e` and `H` the least integer with every `|x| < 2^H`.
//! Every value `robust` computes is one of:
//! - a *lattice* value: an exact sum, difference or product of inputs and
//!   of earlier lattice values, rounded or not (the differences, their
//!   tails, the two-product heads and tails, expansion components, the
//!   estimates `det`, the permanents). A degree-`d` one (a product of `d`
//!   coordinate differences and their sums; `d <= 2` for orient2d, `<= 3`
//!   for orient3d) is an integer multiple of `2^(d L)` when `L < 0` (of
//!   `2^L` otherwise), because rounding a multiple of `2^g` (`g >= -1074`)
//!   to a double gives a multiple of `2^g` again;
//! - an *error bound*: a constant `k` times lattice values (`THETA`,
//!   `RESULTERRBOUND` about `2^-51.4`, `CCWERRBOUND_C` about `2^-102.8`,
//!   `O3DERRBOUND_C` about `2^-101.3`: every `k >= 2^-103`), and sums of
//!   such non-negative terms.
//!
//! If every lattice value is a multiple of `2^g` with `g >= -900`, then
//! (ii) never happens: an exact lattice result below `2^-1022` is a
//! multiple of `2^-1074`, hence a subnormal computed exactly, as in the
//! model (it has fewer than 53 significant bits); a non-zero error bound is
//! at least `2^-103 2^-900 > 2^-1022`, a normal number rounded as in the
//! model. If every `|x| < 2^450` (orient2d) or `2^300` (orient3d), (i)
//! never happens: differences stay below `2^451` (`2^301`), products of two
//! below `2^903` (of three below `2^904`), a split value (a difference, or
//! in orient3d an expansion component of degree 2) times the splitter
//! `2^27 + 1` below `2^633`, and every sum of at most 192 expansion
//! components or bound terms below `2^912`. So `robust` runs exactly as in
//! the model, and its sign is exact: this is the *window* `L >= -450`,
//! `H <= 450` for orient2d (`2 L >= -900`) and `L >= -300`, `H <= 300` for
//! orient3d (`3 L >= -900`).
//!
//! The guard: a coordinate that is zero or has `2^(low + 52) <= |x| <
//! 2^high` (two comparisons) has `e >= low` (a double's lowest set bit is
//! at most 52 places below its leading one) and `|x| < 2^high`; when all
//! of a call's coordinates pass, `robust` runs on them as they are. Else
//! `L` and `H` are read from the bits. The sign of a determinant does not
//! change when every coordinate is multiplied by one power of two `2^s`,
//! and with `s = high - H` the products are exact (each result is a
//! multiple of `2^(L + s)`, at least `2^low`, and below `2^high`: a double)
//! and lie in the window whenever `H - L <= high - low` (900 bits for
//! orient2d, 600 for orient3d). Wider spreads (a coordinate near `2^1000`
//! beside one near `2^-1000` in one call) take the exact integer
//! determinant on the common grid `2^L` (`num-bigint`). A NaN or infinite
//! result from `robust` cannot happen in the window; were it to, the
//! integer determinant decides, never a silent zero. Property-tested
//! against the plain big-rational determinant with coordinates of every
//! exponent from `-1074` to `1023`.

use super::point::Point2;
use super::rational::{decompose, Rat};
use super::scale::{pow2, spread, times_pow2};
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

/// The exact sign of a quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sign {
    /// Strictly below zero (below the plane, clockwise, ...).
    Negative,
    /// Exactly zero.
    Zero,
    /// Strictly above zero.
    Positive,
}

impl Sign {
    /// Sign from an ordering of `x` against zero (`None`, an unordered
    /// NaN, counts as zero: callers pass finite values only).
    #[inline]
    pub fn of_cmp(o: Option<Ordering>) -> Sign {
        match o {
            Some(Ordering::Less) => Sign::Negative,
            Some(Ordering::Greater) => Sign::Positive,
            _ => Sign::Zero,
        }
    }

    /// The sign of an ordering (`Less` is negative).
    #[inline]
    pub fn of_ordering(o: Ordering) -> Sign {
        Sign::of_cmp(Some(o))
    }

    /// The sign of an exact rational.
    pub fn of_rat(x: &Rat) -> Sign {
        if x.is_positive() {
            Sign::Positive
        } else if x.is_negative() {
            Sign::Negative
        } else {
            Sign::Zero
        }
    }

    /// The sign of an exact integer.
    pub fn of_int(x: &BigInt) -> Sign {
        Sign::of_ordering(x.sign().cmp(&num_bigint::Sign::NoSign))
    }

    /// The opposite sign.
    #[inline]
    pub fn flip(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }

    /// The ordering of a quantity of this sign against zero.
    #[inline]
    pub fn ordering(self) -> Ordering {
        match self {
            Sign::Negative => Ordering::Less,
            Sign::Zero => Ordering::Equal,
            Sign::Positive => Ordering::Greater,
        }
    }
}

/// The sign of a product.
impl std::ops::Mul for Sign {
    type Output = Sign;

    #[inline]
    fn mul(self, other: Sign) -> Sign {
        match other {
            Sign::Positive => self,
            Sign::Zero => Sign::Zero,
            Sign::Negative => self.flip(),
        }
    }
}

/// The exponent window in which `robust` is exact for one predicate (see
/// the module doc): every input a multiple of `2^low` below `2^high`.
#[derive(Clone, Copy)]
struct Window {
    low: i32,
    high: i32,
}

/// orient2d: `2 low >= -900`, products below `2^903`.
const WINDOW_2D: Window = Window {
    low: -450,
    high: 450,
};

/// orient3d: `3 low >= -900`, products below `2^904`.
const WINDOW_3D: Window = Window {
    low: -300,
    high: 300,
};

impl Window {
    /// The cheap test: zero, or `2^(low + 52) <= |x| < 2^high`.
    #[inline]
    fn holds(self, xs: &[f64]) -> bool {
        let lo = pow2(self.low + 52);
        let hi = pow2(self.high);
        xs.iter().all(|&x| x == 0.0 || (lo..hi).contains(&x.abs()))
    }

    /// The coordinates as `robust` may take them: as they are when the
    /// cheap test passes, else multiplied by one power of two (exactly)
    /// into the window, or `None` when they span more bits than it has.
    ///
    /// # Panics
    ///
    /// On a non-finite coordinate (validation rejects such meshes before
    /// any predicate is evaluated).
    #[inline]
    fn fit<const N: usize>(self, xs: [f64; N]) -> Option<[f64; N]> {
        if self.holds(&xs) {
            return Some(xs);
        }
        let (low, high) = finite_spread(&xs)?;
        if high - low > self.high - self.low {
            return None;
        }
        let s = self.high - high;
        // Exact: each product is a multiple of 2^(low + s) >= 2^self.low
        // below 2^self.high, a double.
        Some(xs.map(|x| times_pow2(x, s)))
    }
}

/// `(L, H)` of the values ([`spread`]); `None` when all are zero.
///
/// # Panics
///
/// On a non-finite value.
fn finite_spread(xs: &[f64]) -> Option<(i32, i32)> {
    assert!(
        xs.iter().all(|x| x.is_finite()),
        "exact predicates take finite coordinates only (validation rejects others)"
    );
    spread(xs)
}

/// The values as integers on their common grid `2^L` (`x = k 2^L`).
fn on_common_grid<const N: usize>(xs: [f64; N]) -> [BigInt; N] {
    let low = finite_spread(&xs).map_or(0, |(l, _)| l);
    xs.map(|x| match decompose(x) {
        Some((m, e)) => BigInt::from(m) << (e - low) as u32,
        None => BigInt::zero(),
    })
}

/// The sign `robust` returned, or `None` for a NaN or infinite value
/// (impossible in the window; the caller then takes the exact path).
#[inline]
fn robust_sign(det: f64) -> Option<Sign> {
    det.is_finite().then(|| Sign::of_cmp(det.partial_cmp(&0.0)))
}

/// [`orient2d_xy`] on points given as `[x, y]`: Shewchuk's static filter
/// first ([`super::orient_filter`], where its bound and range are proven),
/// the exact predicate where the filter cannot decide. For hot loops over
/// points that are doubles.
#[inline]
pub fn orient2d_points(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let [a, b, c] = [a, b, c].map(|p| [p[0], p[1], 0.0]);
    super::orient_filter::orient2d_axes_filter(a, b, c, 0, 1)
        .unwrap_or_else(|| orient2d_xy(a, b, c))
}

/// Exact sign of the orientation of `(a, b, c)` projected on the `(x, y)`
/// plane: positive when counter-clockwise seen from `+z`. Exact for every
/// finite double.
///
/// # Panics
///
/// On a non-finite coordinate.
#[inline]
pub fn orient2d_xy(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Sign {
    orient2d_axes(a, b, c, 0, 1)
}

/// Exact orientation of `(a, b, c)` projected on the plane of axes `i`, `j`
/// (positive when counter-clockwise with axis `i` to the right and `j`
/// up). Exact for every finite double.
///
/// # Panics
///
/// On a non-finite coordinate.
#[inline]
pub fn orient2d_axes(a: [f64; 3], b: [f64; 3], c: [f64; 3], i: usize, j: usize) -> Sign {
    let xs = [a[i], a[j], b[i], b[j], c[i], c[j]];
    WINDOW_2D
        .fit(xs)
        .and_then(|[ax, ay, bx, by, cx, cy]| {
            let p = |x, y| robust::Coord { x, y };
            robust_sign(robust::orient2d(p(ax, ay), p(bx, by), p(cx, cy)))
        })
        .unwrap_or_else(|| orient2d_integers(xs))
}

/// orient2d on the common binary grid of the six coordinates
/// `[ax, ay, bx, by, cx, cy]`, in big integers.
fn orient2d_integers(xs: [f64; 6]) -> Sign {
    let [ax, ay, bx, by, cx, cy] = on_common_grid(xs);
    let det = (&bx - &ax) * (&cy - &ay) - (&by - &ay) * (&cx - &ax);
    Sign::of_int(&det)
}

/// Exact sign of the signed volume of the tetrahedron `(a, b, c, d)`:
/// positive when `d` lies on the side of the triangle `(a, b, c)` that its
/// counter-clockwise normal points to. Exact for every finite double.
///
/// # Panics
///
/// On a non-finite coordinate.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    let xs = [
        a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
    ];
    WINDOW_3D
        .fit(xs)
        .and_then(|s| {
            let p = |k: usize| robust::Coord3D {
                x: s[3 * k],
                y: s[3 * k + 1],
                z: s[3 * k + 2],
            };
            // robust's orient3d is positive when d is below (a, b, c) seen
            // with (a, b, c) counter-clockwise; flip to the right-hand
            // convention.
            robust_sign(robust::orient3d(p(0), p(1), p(2), p(3))).map(Sign::flip)
        })
        .unwrap_or_else(|| orient3d_integers(xs))
}

/// orient3d on the common binary grid of the twelve coordinates, in big
/// integers: the sign of `(b - a) . ((c - a) x (d - a))`.
fn orient3d_integers(xs: [f64; 12]) -> Sign {
    let k = on_common_grid(xs);
    let diff = |p: usize| [0, 1, 2].map(|i| &k[3 * p + i] - &k[i]);
    let (u, v, w) = (diff(1), diff(2), diff(3));
    let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1]) - &u[1] * (&v[0] * &w[2] - &v[2] * &w[0])
        + &u[2] * (&v[0] * &w[1] - &v[1] * &w[0]);
    Sign::of_int(&det)
}

/// Whether a triangle has zero area (its three vertices are collinear),
/// decided exactly for every finite double.
///
/// # Panics
///
/// On a non-finite coordinate.
pub fn is_degenerate_triangle(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    (0..3).all(|k| orient2d_axes(a, b, c, k, (k + 1) % 3) == Sign::Zero)
}

/// Exact orientation of three rational points: positive when
/// counter-clockwise.
pub fn orient2d_rat(a: &Point2, b: &Point2, c: &Point2) -> Sign {
    let det = (&b.x - &a.x) * (&c.y - &a.y) - (&b.y - &a.y) * (&c.x - &a.x);
    Sign::of_rat(&det)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;
    use proptest::prelude::*;

    /// `k 2^e`, exactly (`|k| < 2^53`, `-1074 <= e`, result finite).
    fn ldexp(k: i64, e: i32) -> f64 {
        times_pow2(k as f64, e)
    }

    fn rat3(p: [f64; 3]) -> [Rat; 3] {
        p.map(rat_from_f64)
    }

    /// The plain big-rational orient2d on axes `i`, `j`.
    fn reference2(a: [f64; 3], b: [f64; 3], c: [f64; 3], i: usize, j: usize) -> Sign {
        let p = |q: [f64; 3]| Point2 {
            x: rat_from_f64(q[i]),
            y: rat_from_f64(q[j]),
        };
        orient2d_rat(&p(a), &p(b), &p(c))
    }

    /// The plain big-rational orient3d: `(b - a) . ((c - a) x (d - a))`.
    fn reference3(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
        let [a, b, c, d] = [a, b, c, d].map(rat3);
        let diff = |p: &[Rat; 3]| [0, 1, 2].map(|i| &p[i] - &a[i]);
        let (u, v, w) = (diff(&b), diff(&c), diff(&d));
        let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1]) - &u[1] * (&v[0] * &w[2] - &v[2] * &w[0])
            + &u[2] * (&v[0] * &w[1] - &v[1] * &w[0]);
        Sign::of_rat(&det)
    }

    /// Any finite double: every biased exponent (subnormals and the
    /// largest binade included), a random significand and sign, and zero.
    fn any_double() -> impl Strategy<Value = f64> {
        prop_oneof![
            1 => Just(0.0),
            8 => (0u64..2047, proptest::num::u64::ANY, proptest::bool::ANY).prop_map(|(e, f, neg)| {
                let bits = (e << 52) | (f & ((1 << 52) - 1)) | (u64::from(neg) << 63);
                f64::from_bits(bits)
            }),
            // Short significands, so that sums and differences are often exact.
            4 => (-1074i32..=1000, -64i64..64).prop_map(|(e, k)| ldexp(k, e)),
        ]
    }

    fn any_point() -> impl Strategy<Value = [f64; 3]> {
        proptest::array::uniform3(any_double())
    }

    #[test]
    fn orient3d_is_right_handed() {
        let o = [0.0, 0.0, 0.0];
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        assert_eq!(orient3d(o, x, y, [0.0, 0.0, 1.0]), Sign::Positive);
        assert_eq!(orient3d(o, x, y, [0.0, 0.0, -1.0]), Sign::Negative);
        assert_eq!(orient3d(o, x, y, [5.0, 7.0, 0.0]), Sign::Zero);
        assert_eq!(
            orient3d_integers([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
            Sign::Positive
        );
    }

    #[test]
    fn orient2d_counter_clockwise_is_positive() {
        let o = [0.0, 0.0, 3.0];
        assert_eq!(
            orient2d_xy(o, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            Sign::Positive
        );
        assert_eq!(
            orient2d_xy(o, [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
            Sign::Negative
        );
        // Nearly collinear points that naive float arithmetic gets wrong.
        let a = [0.5, 0.5, 0.0];
        let b = [12.0, 12.0, 0.0];
        let c = [24.0, 24.0, 0.0];
        assert_eq!(orient2d_xy(a, b, c), Sign::Zero);
        let c2 = [24.0f64.next_up(), 24.0, 0.0];
        assert_eq!(orient2d_xy(a, b, c2), Sign::Negative);
    }

    #[test]
    fn degenerate_triangles() {
        let a = [0.0, 0.0, 0.0];
        assert!(is_degenerate_triangle(a, [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]));
        assert!(!is_degenerate_triangle(a, [1.0, 1.0, 1.0], [2.0, 2.0, 2.5]));
    }

    /// The unit triangle and tetrahedron scaled by every power of two a
    /// double holds: `robust` alone underflows to zero below about
    /// `2^-537` (orient2d) and overflows above about `2^340` (orient3d).
    #[test]
    fn every_power_of_two_scale_keeps_the_sign() {
        for k in -1074..=1021 {
            let s = ldexp(1, k);
            let (o, x, y, z) = ([0.0; 3], [s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]);
            assert_eq!(orient2d_xy(o, x, y), Sign::Positive, "2^{k}");
            assert_eq!(orient2d_xy(o, y, x), Sign::Negative, "2^{k}");
            assert!(!is_degenerate_triangle(o, x, y), "2^{k}");
            assert_eq!(orient3d(o, x, y, z), Sign::Positive, "2^{k}");
            assert_eq!(orient3d(o, y, x, z), Sign::Negative, "2^{k}");
        }
        // The largest double and the smallest subnormal in one call.
        let (big, tiny) = (f64::MAX, f64::from_bits(1));
        assert_eq!(
            orient2d_xy([0.0; 3], [big, big, 0.0], [tiny, tiny, 0.0]),
            Sign::Zero
        );
        assert_eq!(
            orient2d_xy([0.0; 3], [big, big, 0.0], [tiny, 2.0 * tiny, 0.0]),
            Sign::Positive
        );
        assert_eq!(
            orient3d([0.0; 3], [big, 0.0, 0.0], [0.0, tiny, 0.0], [0.0, 0.0, big]),
            Sign::Positive
        );
        assert_eq!(
            orient3d(
                [0.0; 3],
                [big, 0.0, 0.0],
                [0.0, tiny, 0.0],
                [big, -tiny, 0.0]
            ),
            Sign::Zero
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Coordinates of every exponent, mixed in one call: every
        /// projection of orient2d, orient3d and the degeneracy test equal
        /// the plain big-rational determinants.
        #[test]
        fn predicates_equal_the_rational_reference_on_every_double(
            a in any_point(), b in any_point(), c in any_point(), d in any_point()
        ) {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                prop_assert_eq!(orient2d_axes(a, b, c, i, j), reference2(a, b, c, i, j));
            }
            prop_assert_eq!(orient3d(a, b, c, d), reference3(a, b, c, d));
            prop_assert_eq!(
                orient2d_points([a[0], a[1]], [b[0], b[1]], [c[0], c[1]]),
                reference2(a, b, c, 0, 1)
            );
            let flat = (0..3).all(|k| reference2(a, b, c, k, (k + 1) % 3) == Sign::Zero);
            prop_assert_eq!(is_degenerate_triangle(a, b, c), flat);
        }

        /// Points on one lattice `k 2^e` (any `e`), collinear or coplanar
        /// by construction, and moved one lattice step off: the window's
        /// scaling and `robust`'s exact stages decide them.
        #[test]
        fn exactly_collinear_and_coplanar_points_on_any_scale(
            e in -1074i32..=960, a in proptest::array::uniform3(-(1i64 << 20)..(1 << 20)),
            u in proptest::array::uniform3(-(1i64 << 10)..(1 << 10)),
            v in proptest::array::uniform3(-(1i64 << 10)..(1 << 10)),
            s in -64i64..64, t in -64i64..64, off in -1i64..=1, axis in 0usize..3
        ) {
            let at = |k: [i64; 3]| k.map(|x| ldexp(x, e));
            let plus = |p: [i64; 3], q: [i64; 3], m: i64| [0, 1, 2].map(|i| p[i] + m * q[i]);
            let (pa, pb) = (at(a), at(plus(a, u, 1)));
            let mut on = plus(a, u, s);
            on[axis] += off;
            let pc = at(on);
            prop_assert_eq!(orient2d_xy(pa, pb, pc), reference2(pa, pb, pc, 0, 1));
            let xy = |p: [f64; 3]| [p[0], p[1]];
            prop_assert_eq!(orient2d_points(xy(pa), xy(pb), xy(pc)), reference2(pa, pb, pc, 0, 1));
            prop_assert_eq!(is_degenerate_triangle(pa, pb, pc), off == 0 || u == [0; 3]);
            let mut w = plus(plus(a, u, s), v, t);
            w[axis] += off;
            let (pc, pd) = (at(plus(a, v, 1)), at(w));
            let want = reference3(pa, pb, pc, pd);
            prop_assert_eq!(orient3d(pa, pb, pc, pd), want);
            if off == 0 {
                prop_assert_eq!(want, Sign::Zero);
            }
        }

        /// Points on one line through the origin at scales far apart in one
        /// call (beyond the window: the integer path), and one point a
        /// lattice step off it.
        #[test]
        fn collinear_points_spanning_the_whole_range(
            d in proptest::array::uniform2(-(1i64 << 20)..(1 << 20)),
            k in proptest::array::uniform3((-(1i64 << 30)..(1 << 30), -1074i32..=970)),
            off in -1i64..=1
        ) {
            let p = |(m, e): (i64, i32)| [ldexp(m * d[0], e), ldexp(m * d[1], e), 0.0];
            let (a, b, mut c) = (p(k[0]), p(k[1]), p(k[2]));
            c[1] += ldexp(off, -1074);
            let want = reference2(a, b, c, 0, 1);
            prop_assert_eq!(orient2d_xy(a, b, c), want);
            if c[1] == p(k[2])[1] {
                prop_assert_eq!(want, Sign::Zero);
            }
            prop_assert_eq!(orient2d_integers([a[0], a[1], b[0], b[1], c[0], c[1]]), want);
        }
    }
}
