//! Input: mesh positions and an exact level. Output: exact points in the
//! plane `z = c` ([`Point2`]: reduced rationals; [`LoopPoint`]: the same
//! values kept as integers, built without a gcd or an allocation), and
//! their rounding for output.

use super::crossing::{certified_crossing, LevelApprox, NumberPath};
use super::level::Level;
use super::rational::{decompose, ratio_to_f64};
use super::rational::{rat_from_f64, rat_to_f64, Rat};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{Signed, ToPrimitive, Zero};
use std::borrow::Cow;
use std::sync::Arc;

/// A point of the plane `z = c` with exact rational coordinates.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Point2 {
    /// Exact x.
    pub x: Rat,
    /// Exact y.
    pub y: Rat,
}

impl Point2 {
    /// The exact `(x, y)` of a mesh position.
    pub fn of_vertex(p: [f64; 3]) -> Self {
        Point2 {
            x: rat_from_f64(p[0]),
            y: rat_from_f64(p[1]),
        }
    }

    /// The exact crossing of edge `(a, b)` with the plane `z = c`:
    /// `p = (a (h(b) - c) + b (c - h(a))) / (h(b) - h(a))`.
    /// The caller guarantees `h(a) != h(b)`.
    ///
    /// Fast path: when the six coordinates share a binary exponent with
    /// small integer mantissas and the level is a small fraction, the
    /// point is computed in `i128` (overflow-checked) and reduced with an
    /// integer gcd; otherwise, or on overflow, with big rationals. Both give
    /// the same reduced rational (property-tested).
    pub fn on_edge(a: [f64; 3], b: [f64; 3], level: &Level) -> Self {
        match crossing_i128(a, b, level) {
            Some(h) => h.reduce(),
            None => crossing_big(a, b, level),
        }
    }

    /// The crossing with big rationals only: the reference for the fast path.
    pub fn on_edge_reference(a: [f64; 3], b: [f64; 3], level: &Level) -> Self {
        let za = rat_from_f64(a[2]);
        let zb = rat_from_f64(b[2]);
        let t = (level.value() - &za) / (&zb - &za);
        let lerp = |p: f64, q: f64| {
            let p = rat_from_f64(p);
            let q = rat_from_f64(q);
            &p + (q - &p) * &t
        };
        Point2 {
            x: lerp(a[0], b[0]),
            y: lerp(a[1], b[1]),
        }
    }

    /// The nearest doubles (rounding for output only).
    pub fn to_f64(&self) -> [f64; 2] {
        [rat_to_f64(&self.x), rat_to_f64(&self.y)]
    }

    /// The point with both coordinates multiplied by `s` (exact).
    pub fn scaled(&self, s: &Rat) -> Point2 {
        Point2 {
            x: &self.x * s,
            y: &self.y * s,
        }
    }
}

/// How a set of doubles lies on the binary grid: each as
/// `±mantissa 2^exponent` (the mantissa not reduced), and the lowest and
/// the highest set bit among them. Read from the bits (no `i128` shift):
/// this runs once per crossing.
pub(super) struct Layout<const N: usize> {
    mantissas: [u64; N],
    exponents: [i32; N],
    negative: [bool; N],
    /// The exponent of the lowest set bit (`0` when all are zero): every
    /// value is `k 2^lowest` with `k` an integer.
    pub lowest: i32,
    /// The exponent of the highest set bit (`lowest - 1` when all are
    /// zero).
    highest: i32,
}

impl<const N: usize> Layout<N> {
    /// The layout of `xs`, or `None` if one is infinite or NaN.
    #[inline(always)]
    pub fn of(xs: [f64; N]) -> Option<Self> {
        const EXPONENT: u64 = 0x7ff;
        const FRACTION: u64 = (1 << 52) - 1;
        let mut out = Layout {
            mantissas: [0; N],
            exponents: [0; N],
            negative: [false; N],
            lowest: i32::MAX,
            highest: i32::MIN,
        };
        for (i, x) in xs.into_iter().enumerate() {
            let bits = x.to_bits();
            let biased = ((bits >> 52) & EXPONENT) as i32;
            if biased == EXPONENT as i32 {
                return None;
            }
            let fraction = bits & FRACTION;
            let (m, e) = if biased == 0 {
                (fraction, -1074)
            } else {
                (fraction | (1 << 52), biased - 1075)
            };
            if m != 0 {
                out.lowest = out.lowest.min(e + m.trailing_zeros() as i32);
                out.highest = out.highest.max(e + 63 - m.leading_zeros() as i32);
            }
            out.mantissas[i] = m;
            out.exponents[i] = e;
            out.negative[i] = bits >> 63 == 1;
        }
        if out.lowest == i32::MAX {
            (out.lowest, out.highest) = (0, -1);
        }
        Some(out)
    }

    /// The number of binary places the integers `k` need: every
    /// `|k| < 2^places`.
    #[inline(always)]
    pub fn places(&self) -> i32 {
        self.highest - self.lowest + 1
    }

    /// Each value as `k` (`x = k 2^lowest`) in `u64` or `u128`, its sign
    /// dropped. The caller checks that `k` fits (`places()` at most the
    /// width): then every shift is below 53 places to the right (the bits
    /// shifted out are zero, as `lowest` is at or below each non-zero
    /// value's lowest set bit) or below the width to the left.
    #[inline(always)]
    fn magnitudes<T>(&self) -> [T; N]
    where
        T: From<u64> + std::ops::Shl<i32, Output = T> + std::ops::Shr<i32, Output = T>,
    {
        std::array::from_fn(|i| {
            let (m, e) = (self.mantissas[i], self.exponents[i]);
            if m == 0 {
                T::from(0)
            } else if e >= self.lowest {
                T::from(m) << (e - self.lowest)
            } else {
                T::from(m) >> (self.lowest - e)
            }
        })
    }

    /// Each value as `k` in `i64`, when `places() <= 63`.
    #[inline(always)]
    pub fn ints_i64(&self) -> Option<[i64; N]> {
        (self.places() <= 63).then(|| {
            let ks = self.magnitudes::<u64>();
            std::array::from_fn(|i| {
                if self.negative[i] {
                    -(ks[i] as i64)
                } else {
                    ks[i] as i64
                }
            })
        })
    }

    /// Each value as `k`, a big integer (any number of places).
    pub fn ints_big(&self) -> [BigInt; N] {
        std::array::from_fn(|i| {
            let (m, e) = (self.mantissas[i], self.exponents[i]);
            // `lowest` is at most 52 places above a non-zero value's
            // exponent (its lowest set bit): the bits shifted out are zero.
            let k = if m == 0 {
                BigInt::zero()
            } else if e >= self.lowest {
                BigInt::from(m) << (e - self.lowest) as u32
            } else {
                BigInt::from(m >> (self.lowest - e))
            };
            if self.negative[i] {
                -k
            } else {
                k
            }
        })
    }

    /// Each value as `k` in `i128`, when `places() <= 127`.
    pub fn ints_i128(&self) -> Option<[i128; N]> {
        (self.places() <= 127).then(|| {
            let ks = self.magnitudes::<u128>();
            std::array::from_fn(|i| {
                if self.negative[i] {
                    -(ks[i] as i128)
                } else {
                    ks[i] as i128
                }
            })
        })
    }
}

/// `a = k * 2^e0` for the common exponent `e0` of a set of doubles (the
/// lowest set bit among them; `0` when all are zero), when every
/// `|k| < 2^40`: that is, when the highest set bit and the lowest one lie
/// fewer than 40 binary places apart.
#[inline(always)]
fn common_ints<const N: usize>(xs: [f64; N]) -> Option<([i64; N], i32)> {
    let layout = Layout::of(xs)?;
    if layout.places() > 40 {
        return None;
    }
    Some((layout.ints_i64()?, layout.lowest))
}

/// Whether an edge with an end at `p` may take the per-edge integer
/// crossing: `p`'s own coordinates span at most 40 binary places (the
/// six coordinates of an edge span at least as many as three of them, and
/// [`common_ints`] takes at most 40). `false` says the edge does not fit;
/// `true` says nothing.
pub(crate) fn may_fit_edge_grid(p: [f64; 3]) -> bool {
    Layout::of(p).is_some_and(|l| l.places() <= 40)
}

/// The crossing with big integers: the six coordinates on their common
/// binary grid `2^e0`, the level `p / q` in its units, then
/// `x = 2^e0 X / (q dz)` with `X = ax q dz + (bx - ax)(p - q az)`
/// (likewise `y`), reduced by [`reduce_over`]: a few products and two
/// small gcds per coordinate, where the rational operations would reduce
/// after each of them. Equal to [`Point2::on_edge_reference`]
/// (property-tested over the whole `f64` range).
fn crossing_big(a: [f64; 3], b: [f64; 3], level: &Level) -> Point2 {
    let parts = [a[0], a[1], a[2], b[0], b[1], b[2]].map(decompose);
    let e0 = parts.iter().flatten().map(|&(_, e)| e).min().unwrap_or(0);
    let int = |p: Option<(i64, i32)>| {
        p.map_or_else(BigInt::zero, |(m, e)| BigInt::from(m) << (e - e0) as usize)
    };
    let [ax, ay, az, bx, by, bz] = parts.map(int);
    let (p, q) = (level.value().numer().clone(), level.value().denom().clone());
    let (p, q) = if e0 <= 0 {
        (p << e0.unsigned_abs() as usize, q)
    } else {
        (p, q << e0 as usize)
    };
    let mut dz = bz - &az;
    let s = &p - &q * &az;
    let qdz = &q * &dz;
    let mut x = &ax * &qdz + (&bx - &ax) * &s;
    let mut y = &ay * &qdz + (&by - &ay) * &s;
    if dz.is_negative() {
        dz = -dz;
        x = -x;
        y = -y;
    }
    Point2 {
        x: reduce_over(x, &q, &dz, e0),
        y: reduce_over(y, &q, &dz, e0),
    }
}

/// `n 2^e / (q d)` in lowest terms (`q, d > 0`). `gcd(n, q d)` is
/// `g1 g2` with `g1 = gcd(n, q)` and `g2 = gcd(n / g1, d)` (once `n / g1`
/// and `q / g1` are coprime, a common factor of `n / g1` and `(q / g1) d`
/// divides `d`); each is one remainder by a number that fits `u128` and a
/// `u128` gcd. Larger `q` or `d` take one big gcd.
fn reduce_over(n: BigInt, q: &BigInt, d: &BigInt, e: i32) -> Rat {
    if n.is_zero() {
        return Rat::zero();
    }
    let small = |v: &BigInt| v.to_u128().filter(|&v| v > 0);
    let (n, w) = match (small(q), small(d)) {
        (Some(qs), Some(ds)) => {
            let rem = |n: &BigInt, m: u128| {
                (n % BigInt::from(m))
                    .magnitude()
                    .to_u128()
                    .expect("a remainder below m")
            };
            let g1 = gcd_u128(rem(&n, qs), qs);
            let n = n / BigInt::from(g1);
            let g2 = gcd_u128(rem(&n, ds), ds);
            let n = n / BigInt::from(g2);
            (n, BigInt::from(qs / g1) * BigInt::from(ds / g2))
        }
        _ => {
            let w = q * d;
            let g = n.gcd(&w);
            (n / &g, w / g)
        }
    };
    // Cancel powers of two between 2^e and the other side.
    let (n, w) = if e >= 0 {
        let tz = w
            .trailing_zeros()
            .unwrap_or(0)
            .min(u64::from(e.unsigned_abs()));
        (n << (u64::from(e.unsigned_abs()) - tz), w >> tz)
    } else {
        let tz = n
            .trailing_zeros()
            .unwrap_or(0)
            .min(u64::from(e.unsigned_abs()));
        (n >> tz, w << (u64::from(e.unsigned_abs()) - tz))
    };
    Rat::new_raw(n, w)
}

/// The gcd: Euclid's `u128` steps until both numbers fit in `u64` (`u128`
/// division is a slow library call), then the binary gcd on `u64`.
pub(crate) fn gcd_u128(mut a: u128, mut b: u128) -> u128 {
    let wide = u128::from(u64::MAX);
    while b != 0 && (a > wide || b > wide) {
        (a, b) = (b, a % b);
    }
    if a == 0 || b == 0 {
        return a | b;
    }
    let (mut a, mut b) = (a as u64, b as u64);
    let shift = (a | b).trailing_zeros();
    a >>= a.trailing_zeros();
    loop {
        b >>= b.trailing_zeros();
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        b -= a;
        if b == 0 {
            return u128::from(a << shift);
        }
    }
}

/// `v * 2^s`, or `None` if any bit would be lost.
fn shl_exact(v: i128, s: i32) -> Option<i128> {
    let s = u32::try_from(s).ok().filter(|&s| s < 126)?;
    (v.unsigned_abs() >> (126 - s) == 0).then(|| v << s)
}

/// `num * 2^e / den` as a reduced rational (`den > 0`).
fn reduced(num: i128, den: i128, e: i32) -> Rat {
    if num == 0 {
        return Rat::zero();
    }
    let g = gcd_u128(num.unsigned_abs(), den.unsigned_abs()).max(1) as i128;
    let (n, d) = (num / g, den / g);
    // Cancel powers of two between 2^e and the other side; the shift that
    // remains is done in i128 when no bit is lost.
    let (n, d) = if e >= 0 {
        let tz = d.trailing_zeros().min(e as u32);
        (shifted(n, e - tz as i32), BigInt::from(d >> tz))
    } else {
        let tz = n.trailing_zeros().min((-e) as u32);
        (BigInt::from(n >> tz), shifted(d, -e - tz as i32))
    };
    Rat::new_raw(n, d)
}

/// `v * 2^s` (`s >= 0`) as a big integer.
fn shifted(v: i128, s: i32) -> BigInt {
    match shl_exact(v, s) {
        Some(k) => BigInt::from(k),
        None => BigInt::from(v) << s as u32,
    }
}

/// The point `(x 2^e / w, y 2^e / w)`, `0 < w < 2^126`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Scaled {
    x: i128,
    y: i128,
    w: i128,
    e: i32,
}

impl Scaled {
    fn reduce(&self) -> Point2 {
        Point2 {
            x: reduced(self.x, self.w, self.e),
            y: reduced(self.y, self.w, self.e),
        }
    }

    /// The point times `s = a 2^t / b` (exact), still as integers when the
    /// products fit: `x` and `y` times `a`, `w` times `b`, `t` added to
    /// `e`. `None` when they do not fit.
    fn times(self, s: SplitScale) -> Option<Scaled> {
        let w = self.w.checked_mul(s.b)?;
        (w < 1 << 126).then_some(Scaled {
            x: self.x.checked_mul(s.a)?,
            y: self.y.checked_mul(s.a)?,
            w,
            e: self.e.checked_add(s.t)?,
        })
    }

    fn to_f64(self) -> [f64; 2] {
        let w = self.w as u128;
        [
            ratio_to_f64(self.x, w, self.e),
            ratio_to_f64(self.y, w, self.e),
        ]
    }
}

/// The crossing of edge `(a, b)` with the level in `i128`, unreduced, or
/// `None` when the inputs do not fit (overflow-checked). Inlined: returned
/// through the stack, the 64-byte result was copied twice with stalled
/// loads (6% of slicing an origin-centred `f32` torus).
#[inline(always)]
fn crossing_i128(a: [f64; 3], b: [f64; 3], level: &Level) -> Option<Scaled> {
    let (p, q) = level.small()?;
    let ([ax, ay, az, bx, by, bz], e0) = common_ints([a[0], a[1], a[2], b[0], b[1], b[2]])?;
    // In units of 2^e0 the level is p / (q 2^e0).
    let (p, q) = if e0 >= 0 {
        (p, shl_exact(q, e0)?)
    } else {
        (shl_exact(p, -e0)?, q)
    };
    if p.unsigned_abs() >= 1 << 80 || q >= 1 << 80 {
        return None;
    }
    // x = (ax q dz + (bx - ax)(p - q az)) / (q dz), dz = bz - az, with
    // |k| < 2^40 (so |dz|, |bx - ax| < 2^41) and |p|, q < 2^80.
    let dz = i128::from(bz - az);
    let w = q * dz;
    let s = p - q * i128::from(az);
    let (x, y) = if q < 1 << 43 {
        // |w| < 2^84 and |s| < 2^80 + 2^83 < 2^84: each product below
        // 2^125, their sum below 2^126. Nothing to check.
        let coord = |u: i64, v: i64| i128::from(u) * w + i128::from(v - u) * s;
        (coord(ax, bx), coord(ay, by))
    } else {
        // |w| < 2^121 and |s| < 2^122: the two products of `coord` can
        // overflow; their sizes are checked by bit length first
        // (`checked_mul` on i128 is a slow library call).
        let bits = |v: i128| 128 - v.unsigned_abs().leading_zeros();
        let coord = |u: i64, v: i64| -> Option<i128> {
            let (u, d) = (i128::from(u), i128::from(v - u));
            if bits(u) + bits(w) <= 126 && bits(d) + bits(s) <= 126 {
                Some(u * w + d * s)
            } else {
                u.checked_mul(w)?.checked_add(d.checked_mul(s)?)
            }
        };
        (coord(ax, bx)?, coord(ay, by)?)
    };
    // The checked sums can be exactly -2^127, which has no negation in
    // `i128` (`-x` would wrap to itself: the point's sign flipped); |x|,
    // |y| < 2^127 keeps every holder's negation and `unsigned_abs` exact.
    if x == i128::MIN || y == i128::MIN {
        return None;
    }
    let (x, y, w) = if w < 0 { (-x, -y, -w) } else { (x, y, w) };
    if w == 0 || w >= 1 << 126 {
        return None;
    }
    Some(Scaled { x, y, w, e: e0 })
}

/// An exact point of a loop (S_O, dF, L-, L+), stored compactly: as
/// integers `(x 2^e / w, y 2^e / w)` when they fit in `i128` (vertices and
/// crossings of a mesh on one 62-bit grid, see [`crate::exact::grid`], or
/// of an edge whose ends span at most 40 bits of one grid, at a level that
/// is a small fraction); else, for a crossing, as its edge and level with
/// the certified nearest doubles (lazy: the exact value is built only when
/// asked for, see [`crate::exact::crossing`]); else as reduced rationals.
/// Every form is exact; equality is by value.
/// [`LoopPoint::exact`] gives the reduced rationals, [`LoopPoint::to_f64`]
/// the nearest doubles.
#[derive(Clone, Debug)]
pub struct LoopPoint(Repr);

#[derive(Clone, Debug)]
enum Repr {
    Scaled(Scaled),
    Lazy(Lazy),
    Rational(Box<Point2>),
}

/// The crossing of edge `(a, b)` with `level`, and its nearest doubles.
#[derive(Clone, Debug)]
struct Lazy {
    nearest: [f64; 2],
    a: [f64; 3],
    b: [f64; 3],
    level: Arc<Level>,
}

impl Lazy {
    fn exact(&self) -> Point2 {
        Point2::on_edge(self.a, self.b, &self.level)
    }

    /// Whether the two are the same edge (either way) at the same level.
    fn same_recipe(&self, o: &Lazy) -> bool {
        let level = Arc::ptr_eq(&self.level, &o.level) || self.level.value() == o.level.value();
        let bits = |p: [f64; 3]| p.map(f64::to_bits);
        let (a, b, oa, ob) = (bits(self.a), bits(self.b), bits(o.a), bits(o.b));
        level && ((a, b) == (oa, ob) || (a, b) == (ob, oa))
    }

    /// Whether coordinate `axis` (0 for x, 1 for y) is the same for both
    /// by construction: edges whose ends hold the same values of that
    /// coordinate and of z (either way round), at the same level. The
    /// crossing's coordinate, `a_k + (b_k - a_k) (c - a_z) / (b_z - a_z)`,
    /// depends on nothing else (as on the walls of one row of holes cut
    /// into the same bands).
    fn same_coordinate_recipe(&self, o: &Lazy, axis: usize) -> bool {
        let ends = |p: [f64; 3]| (p[axis].to_bits(), p[2].to_bits());
        let (a, b, oa, ob) = (ends(self.a), ends(self.b), ends(o.a), ends(o.b));
        ((a, b) == (oa, ob) || (a, b) == (ob, oa))
            && (Arc::ptr_eq(&self.level, &o.level) || self.level.value() == o.level.value())
    }
}

impl LoopPoint {
    /// The exact `(x, y)` of a mesh position.
    pub fn of_vertex(p: [f64; 3]) -> Self {
        let on_grid = || {
            let parts = [p[0], p[1]].map(decompose);
            if !(p[0].is_finite() && p[1].is_finite()) {
                return None;
            }
            let e = parts.iter().flatten().map(|&(_, e)| e).min().unwrap_or(0);
            let [x, y] = parts.map(|q| q.map_or(Some(0), |(m, k)| shl_exact(m.into(), k - e)));
            Some(Scaled {
                x: x?,
                y: y?,
                w: 1,
                e,
            })
        };
        match on_grid() {
            Some(h) => LoopPoint(Repr::Scaled(h)),
            None => Point2::of_vertex(p).into(),
        }
    }

    /// The exact crossing of edge `(a, b)` with the plane `z = c` (see
    /// [`Point2::on_edge`]); the caller guarantees `h(a) != h(b)`.
    pub fn on_edge(a: [f64; 3], b: [f64; 3], level: &Level) -> Self {
        match crossing_i128(a, b, level) {
            Some(h) => LoopPoint(Repr::Scaled(h)),
            None => Point2::on_edge_reference(a, b, level).into(),
        }
    }

    /// The exact crossing of edge `(a, b)` with `level` (`h(a) != h(b)`),
    /// and the path that built it: integers on the edge's grid when they
    /// fit `i128`; else, when `approx` (the level's double-double) is given
    /// and the certified bound decides both nearest doubles, the edge and
    /// the level kept with those doubles (the exact value built on
    /// demand); else big rationals. Every path gives the same value.
    pub fn on_edge_with(
        a: [f64; 3],
        b: [f64; 3],
        level: &Arc<Level>,
        approx: Option<&LevelApprox>,
    ) -> (Self, NumberPath) {
        if let Some(h) = crossing_i128(a, b, level) {
            return (LoopPoint(Repr::Scaled(h)), NumberPath::Edge);
        }
        Self::on_edge_off_edge_grid(a, b, level, approx)
    }

    /// [`LoopPoint::on_edge_with`] past its first path, for an edge known
    /// not to fit it (an end fails [`may_fit_edge_grid`]): the same point
    /// and path, without reading the edge's binary layout first.
    pub(crate) fn on_edge_off_edge_grid(
        a: [f64; 3],
        b: [f64; 3],
        level: &Arc<Level>,
        approx: Option<&LevelApprox>,
    ) -> (Self, NumberPath) {
        let lazy = |nearest| {
            LoopPoint(Repr::Lazy(Lazy {
                nearest,
                a,
                b,
                level: Arc::clone(level),
            }))
        };
        // A lazy point's doubles tell its zero coordinates
        // (`zero_coordinates`): a nearest double of zero must mean a zero
        // value. Below half the least subnormal a nonzero value rounds to
        // zero too; such a crossing (or an exact zero not known from its
        // ends) goes to the big rationals, which keep the exact value.
        let tells_zeros =
            |n: &[f64; 2]| (0..2).all(|k| n[k] != 0.0 || (a[k] == 0.0 && b[k] == 0.0));
        if let Some(nearest) = approx
            .and_then(|c| certified_crossing(a, b, c))
            .filter(tells_zeros)
        {
            return (lazy(nearest), NumberPath::Certified);
        }
        // Undecided (a crossing exactly halfway between two doubles, or
        // out of the certified range): the exact value decides the
        // rounding, in 256-bit integers when it fits them.
        if let Some(nearest) = super::wide::nearest_crossing(a, b, level).filter(tells_zeros) {
            return (lazy(nearest), NumberPath::Wide);
        }
        // Else in big rationals. The exact value is kept only when its
        // doubles would not tell a zero coordinate (`zero_coordinates`):
        // otherwise it is rebuilt on demand.
        let exact = crossing_big(a, b, level);
        let nearest = exact.to_f64();
        let zeros_told = [(&exact.x, nearest[0]), (&exact.y, nearest[1])]
            .iter()
            .all(|(v, f)| v.is_zero() == (*f == 0.0));
        if zeros_told {
            (lazy(nearest), NumberPath::Big)
        } else {
            (exact.into(), NumberPath::Big)
        }
    }

    /// The exact point as reduced rationals.
    pub fn exact(&self) -> Cow<'_, Point2> {
        match &self.0 {
            Repr::Scaled(h) => Cow::Owned(h.reduce()),
            Repr::Lazy(l) => Cow::Owned(l.exact()),
            Repr::Rational(p) => Cow::Borrowed(p),
        }
    }

    /// For a crossing held by its edge and level: the bits of its exact
    /// coordinates' denominators in lowest terms (as
    /// [`crate::exact::area::ExactPoint::denominator_bits`] of
    /// [`LoopPoint::exact`]), computed in 256-bit integers without building
    /// the exact point, when they fit (see
    /// [`super::wide::crossing_denominator_bits`]).
    pub(crate) fn lazy_denominator_bits(&self) -> Option<u64> {
        match &self.0 {
            Repr::Lazy(l) => super::wide::crossing_denominator_bits(l.a, l.b, &l.level),
            _ => None,
        }
    }

    /// The nearest doubles (rounding for output only).
    pub fn to_f64(&self) -> [f64; 2] {
        match &self.0 {
            Repr::Scaled(h) => h.to_f64(),
            Repr::Lazy(l) => l.nearest,
            Repr::Rational(p) => p.to_f64(),
        }
    }

    /// Each coordinate that is known to be a double without exact
    /// arithmetic: a crossing held by its edge `(a, b)` whose ends share
    /// that coordinate lies exactly there (`a + t (b - a)` with `b - a =
    /// 0`, whatever `t`), as on every face parallel to an axis, which CAD
    /// parts are full of. `None` where it is not known this way.
    pub fn known_doubles(&self) -> [Option<f64>; 2] {
        match &self.0 {
            Repr::Lazy(l) => [0, 1].map(|k| (l.a[k] == l.b[k]).then_some(l.a[k])),
            Repr::Scaled(_) | Repr::Rational(_) => [None, None],
        }
    }

    /// Whether coordinate `axis` (0 for x, 1 for y) of the two is known to
    /// be equal without exact arithmetic: crossings of edges that agree in
    /// that coordinate and in z at both ends, at the same level. `false`
    /// says nothing.
    pub fn same_coordinate_by_recipe(&self, o: &LoopPoint, axis: usize) -> bool {
        match (&self.0, &o.0) {
            (Repr::Lazy(a), Repr::Lazy(b)) => a.same_coordinate_recipe(b, axis),
            _ => false,
        }
    }

    /// Whether each coordinate is exactly zero (without building the
    /// exact value).
    pub fn zero_coordinates(&self) -> [bool; 2] {
        match &self.0 {
            Repr::Scaled(h) => [h.x == 0, h.y == 0],
            // A lazy point's doubles are zero only when its value is
            // (`on_edge_with` keeps no other lazily).
            Repr::Lazy(l) => l.nearest.map(|v| v == 0.0),
            Repr::Rational(p) => [p.x.is_zero(), p.y.is_zero()],
        }
    }

    /// The point `(x 2^e / w, y 2^e / w)`, held as integers; `None` unless
    /// `0 < w < 2^126`.
    pub fn from_integers(x: i128, y: i128, w: i128, e: i32) -> Option<LoopPoint> {
        (w > 0 && w < 1 << 126).then_some(LoopPoint(Repr::Scaled(Scaled { x, y, w, e })))
    }

    /// `(x, y, w, e)` with the point `(x 2^e / w, y 2^e / w)`, `w > 0`,
    /// when it is held as integers.
    pub fn as_integers(&self) -> Option<(i128, i128, i128, i32)> {
        match &self.0 {
            Repr::Scaled(h) => Some((h.x, h.y, h.w, h.e)),
            Repr::Lazy(_) | Repr::Rational(_) => None,
        }
    }

    /// The point with both coordinates multiplied by `s` (exact): a point
    /// held as integers stays so when the products fit `i128` (a snapped
    /// mesh's points, scaled back by the grid unit: no big rationals).
    pub fn scaled(&self, s: &Rat) -> LoopPoint {
        self.scaled_by(&Scale::new(s))
    }

    /// [`LoopPoint::scaled`] by a factor split once for many points.
    pub fn scaled_by(&self, s: &Scale) -> LoopPoint {
        if let (Repr::Scaled(h), Some(split)) = (&self.0, s.split) {
            if let Some(h) = h.times(split) {
                return LoopPoint(Repr::Scaled(h));
            }
        }
        self.exact().scaled(&s.rat).into()
    }
}

/// A nonzero rational factor, with its parts `s = a 2^t / b` (`a`, `b`
/// odd, `b > 0`) split once when they fit `i128`, for scaling many points
/// ([`LoopPoint::scaled_by`]).
#[derive(Clone, Debug)]
pub struct Scale {
    rat: Rat,
    split: Option<SplitScale>,
}

#[derive(Clone, Copy, Debug)]
struct SplitScale {
    a: i128,
    b: i128,
    t: i32,
}

impl Scale {
    /// The factor `s` and its split parts.
    pub fn new(s: &Rat) -> Scale {
        let split = || {
            let (a, b) = (s.numer().to_i128()?, s.denom().to_i128()?);
            if a == 0 {
                return None;
            }
            let (ta, tb) = (a.trailing_zeros(), b.trailing_zeros());
            let t = i32::try_from(ta).ok()? - i32::try_from(tb).ok()?;
            Some(SplitScale {
                a: a >> ta,
                b: b >> tb,
                t,
            })
        };
        Scale {
            rat: s.clone(),
            split: split(),
        }
    }
}

impl From<Point2> for LoopPoint {
    fn from(p: Point2) -> Self {
        LoopPoint(Repr::Rational(Box::new(p)))
    }
}

impl PartialEq for LoopPoint {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (Repr::Scaled(a), Repr::Scaled(b)) if a == b => true,
            // Correct rounding is a function of the value: different
            // nearest doubles, different points.
            (Repr::Lazy(a), Repr::Lazy(b)) if a.nearest != b.nearest => false,
            (Repr::Lazy(a), Repr::Lazy(b)) if a.same_recipe(b) => true,
            _ => self.exact() == other.exact(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;

    #[test]
    fn edge_crossing_is_exact() {
        let c = Level::new(parse_rational("0.6").unwrap());
        let p = Point2::on_edge([0.0, 0.0, 0.0], [1.0, 3.0, 1.0], &c);
        assert_eq!(p.x, parse_rational("3/5").unwrap());
        assert_eq!(p.y, parse_rational("9/5").unwrap());
    }

    /// Found by the `adversarial` fuzz target: a product of exactly
    /// `-2^127` (x = 2^39 q dz with q = 2^48, dz = -2^40) negated in
    /// `i128` wrapped to itself, and the crossing's x came out `-2^39`.
    #[test]
    fn a_crossing_product_of_exactly_minus_two_to_the_127_keeps_its_sign() {
        let (a, b) = (
            [2f64.powi(39), 1.0, 2f64.powi(39)],
            [2f64.powi(39), 1.0, -2f64.powi(39)],
        );
        let level = Arc::new(Level::new(Rat::new(1.into(), BigInt::from(1) << 48u32)));
        let p = LoopPoint::on_edge_with(a, b, &level, None)
            .0
            .exact()
            .into_owned();
        assert_eq!(p.x, rat_from_f64(2f64.powi(39)));
        assert_eq!(p.y, Rat::from_integer(1.into()));
        assert_eq!(p, Point2::on_edge_reference(a, b, &level));
    }

    proptest::proptest! {
        /// The per-edge integer path at the limits of `i128`: coordinates
        /// of at most 40 binary places, powers of two and their
        /// neighbours (so that products meet `2^127` exactly or nearly:
        /// the case above), `b` sharing `a`'s x or y at times, levels
        /// `p / 2^m` with `m` up to 81, equal to the big-rational
        /// reference.
        #[test]
        fn edge_crossing_at_the_limits_of_i128_equals_the_reference(
            ka in proptest::array::uniform3((proptest::sample::select(vec![0u32, 1, 38, 39]), -1i64..=1, proptest::bool::ANY)),
            kb in proptest::array::uniform3((proptest::sample::select(vec![0u32, 1, 38, 39]), -1i64..=1, proptest::bool::ANY)),
            same in proptest::array::uniform2(proptest::bool::ANY),
            p in (0u32..80, -1i64..=1, proptest::bool::ANY), m in 40u32..82
        ) {
            let v = |(k, off, neg): (u32, i64, bool)| {
                let x = ((1i64 << k) + off) as f64;
                if neg { -x } else { x }
            };
            let (a, mut b) = (ka.map(v), kb.map(v));
            for i in 0..2 {
                if same[i] {
                    b[i] = a[i];
                }
            }
            proptest::prop_assume!(a[2] != b[2]);
            let (k, off, neg) = p;
            let p = (1i128 << k) + i128::from(off);
            let p = if neg { -p } else { p };
            let level = Arc::new(Level::new(Rat::new(BigInt::from(p), BigInt::from(1) << m)));
            let (fast, _) = LoopPoint::on_edge_with(a, b, &level, None);
            proptest::prop_assert_eq!(fast.exact().into_owned(), Point2::on_edge_reference(a, b, &level));
        }

        /// Crossings whose products land on `2^127` or beside it: x of
        /// `2^k`, a z span of `2^j` across zero, the level `p / 2^m` with
        /// `k + j + m` within one of 127, an odd y so that the common
        /// grid is the integers.
        #[test]
        fn crossing_products_at_two_to_the_127_equal_the_reference(
            k in 30u32..40, j in 30u32..=40, delta in -1i32..=1, p in proptest::sample::select(vec![-3i64, -1, 1, 3]),
            signs in proptest::array::uniform3(proptest::bool::ANY), dx in -1i64..=1, y in proptest::sample::select(vec![1.0, 3.0, -1.0])
        ) {
            let m = 127 - k as i32 - j as i32 + delta;
            proptest::prop_assume!((0..=81).contains(&m));
            let sign = |neg: bool, v: f64| if neg { -v } else { v };
            let x = sign(signs[0], 2f64.powi(k as i32));
            let z = sign(signs[1], 2f64.powi(j as i32 - 1));
            let a = [x, y, z];
            let b = [x + dx as f64, sign(signs[2], y), -z];
            let level = Arc::new(Level::new(Rat::new(BigInt::from(p), BigInt::from(1) << m as u32)));
            let (fast, _) = LoopPoint::on_edge_with(a, b, &level, None);
            proptest::prop_assert_eq!(fast.exact().into_owned(), Point2::on_edge_reference(a, b, &level));
        }

        /// The i128 fast path equals the big-rational reference: integer,
        /// dyadic and arbitrary double coordinates, levels strictly between
        /// the ends (exact fractions of the span, and decimals).
        #[test]
        fn fast_crossing_equals_the_reference(
            a in proptest::array::uniform3(-1000i32..1000), b in proptest::array::uniform3(-1000i32..1000),
            scale in -30i32..10, odd in proptest::bool::ANY, t in 1i64..1000, den in 1i64..1001
        ) {
            let f = |v: [i32; 3]| {
                let s = if odd { 0.1 } else { 2f64.powi(scale) };
                v.map(|x| f64::from(x) * s)
            };
            let (a, b) = (f(a), f(b));
            proptest::prop_assume!(a[2] != b[2]);
            let za = rat_from_f64(a[2]);
            let zb = rat_from_f64(b[2]);
            let frac = Rat::new(t.into(), (den + t).into());
            let level = Level::new(&za + (zb - &za) * frac);
            proptest::prop_assert_eq!(Point2::on_edge(a, b, &level), Point2::on_edge_reference(a, b, &level));
            let reference = Point2::on_edge_reference(a, b, &level);
            if let Some(h) = crossing_i128(a, b, &level) {
                proptest::prop_assert_eq!(h.reduce(), reference.clone());
                proptest::prop_assert_eq!(h.to_f64(), reference.to_f64());
            }
            let lp = LoopPoint::on_edge(a, b, &level);
            proptest::prop_assert_eq!(lp.exact().into_owned(), reference.clone());
            proptest::prop_assert_eq!(lp.to_f64(), reference.to_f64());
        }
    }

    proptest::proptest! {
        /// A point held as integers, scaled by a rational (a grid unit
        /// such as `1/10^9`, a power of two, or parts too wide for
        /// `i128`), is the exact product, and stays integers when the
        /// products are small.
        #[test]
        fn scaled_integers_are_the_exact_product(
            x in proptest::num::i128::ANY, xb in 0u32..100, y in proptest::num::i128::ANY, yb in 0u32..100,
            w in 1u128..(1 << 100), e in -200i32..200,
            a in 1u64..u64::MAX, ab in 0u32..64, b in 1u64..u64::MAX, bb in 0u32..64,
            wide in 0u32..80, negative in proptest::bool::ANY, unit_power in 0u32..13
        ) {
            let (x, y) = (x >> (127 - xb), y >> (127 - yb));
            let p = LoopPoint::from_integers(x, y, w as i128, e).unwrap();
            let (a, b) = ((a >> ab).max(1), (b >> bb).max(1));
            let s = if unit_power > 0 {
                Rat::new(1.into(), num_bigint::BigInt::from(10u64).pow(unit_power))
            } else {
                let n = num_bigint::BigInt::from(a) << wide;
                Rat::new(if negative { -n } else { n }, b.into())
            };
            let got = p.scaled(&s);
            proptest::prop_assert_eq!(got.exact().into_owned(), p.exact().scaled(&s));
            let small = |v: i128| v.unsigned_abs() < 1 << 60;
            if small(x) && small(y) && w < 1 << 60 && a < 1 << 60 && b < 1 << 60 && wide == 0 {
                proptest::prop_assert!(got.as_integers().is_some());
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn binary_gcd_is_the_gcd(a in proptest::num::u128::ANY, b in proptest::num::u128::ANY, k in 0u32..64) {
            let (a, b) = (a >> k, b >> (63 - k));
            let (mut x, mut y) = (a, b);
            while y != 0 {
                (x, y) = (y, x % y);
            }
            proptest::prop_assert_eq!(gcd_u128(a, b), x);
            proptest::prop_assert_eq!(gcd_u128(a, 0), a);
            proptest::prop_assert_eq!(gcd_u128(0, b), b);
        }
    }

    proptest::proptest! {
        /// A vertex point is its two doubles, exactly, for every pair of
        /// finite doubles (integers when the exponents are close, reduced
        /// rationals otherwise).
        #[test]
        fn vertex_points_are_the_doubles(x in proptest::num::f64::ANY, y in proptest::num::f64::ANY, z in proptest::num::f64::ANY) {
            proptest::prop_assume!(x.is_finite() && y.is_finite());
            let p = LoopPoint::of_vertex([x, y, z]);
            proptest::prop_assert_eq!(p.exact().into_owned(), Point2::of_vertex([x, y, z]));
            proptest::prop_assert_eq!(p.to_f64().map(|v| v + 0.0), [x + 0.0, y + 0.0]);
            proptest::prop_assert!(p == LoopPoint::from(Point2::of_vertex([x, y, z])));
        }
    }

    /// Every finite double: either sign, normal, subnormal or zero.
    fn finite() -> proptest::num::f64::Any {
        use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
        POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2048))]
        /// The big-integer crossing equals the big-rational reference for
        /// every pair of finite positions (any bit pattern: subnormals,
        /// huge and tiny values in one edge) and levels that are decimals,
        /// arbitrary fractions of the span, or arbitrary rationals.
        #[test]
        fn big_crossing_equals_the_reference(
            a in proptest::array::uniform3(finite()),
            b in proptest::array::uniform3(finite()),
            small in proptest::array::uniform3(-1000i32..1000), kind in 0u8..3,
            p in proptest::num::i64::ANY, q in 1i64..i64::MAX,
        ) {
            let mut a = a;
            if kind == 2 {
                // Near-zero noise beside ordinary values.
                a = [f64::from(small[0]) * 0.1, 1e-300 * f64::from(small[1]), f64::from(small[2])];
            }
            proptest::prop_assume!(a.iter().chain(&b).all(|v| v.is_finite()) && a[2] != b[2]);
            let (za, zb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let level = Level::new(match kind {
                0 => &za + (&zb - &za) * Rat::new((p.unsigned_abs() % q.unsigned_abs()).into(), q.into()),
                _ => Rat::new(p.into(), q.into()),
            });
            let reference = Point2::on_edge_reference(a, b, &level);
            let fast = crossing_big(a, b, &level);
            proptest::prop_assert_eq!(fast.x.numer(), reference.x.numer());
            proptest::prop_assert_eq!(fast.x.denom(), reference.x.denom());
            proptest::prop_assert_eq!(fast.y.numer(), reference.y.numer());
            proptest::prop_assert_eq!(fast.y.denom(), reference.y.denom());
        }
    }

    /// [`common_ints`] as first written, through [`decompose`] and
    /// overflow-checked `i128` shifts: the reference for its bit reading.
    fn common_ints_reference<const N: usize>(xs: [f64; N]) -> Option<([i128; N], i32)> {
        let parts = xs.map(decompose);
        let e0 = parts.iter().flatten().map(|&(_, e)| e).min().unwrap_or(0);
        let mut out = [0i128; N];
        for (o, p) in out.iter_mut().zip(parts) {
            if let Some((m, e)) = p {
                let k = shl_exact(i128::from(m), e - e0)?;
                if k.unsigned_abs() >= 1 << 40 {
                    return None;
                }
                *o = k;
            } else if xs.iter().any(|x| !x.is_finite()) {
                return None;
            }
        }
        Some((out, e0))
    }

    /// Doubles `k * 2^e` with `|k| < 2^42` and one `e` per array (so that
    /// the fast path is taken about half the time), any exponent (zeros,
    /// subnormals and infinities included), or any bit pattern at all.
    fn six_doubles() -> impl proptest::strategy::Strategy<Value = [f64; 6]> {
        use proptest::prelude::*;
        let close = (
            proptest::array::uniform6(-(1i64 << 42)..1 << 42),
            -1130i32..1030,
            proptest::array::uniform6(0u8..4),
        )
            .prop_map(|(ks, e, zero)| {
                let mut i = 0;
                ks.map(|k| {
                    i += 1;
                    if zero[i - 1] == 0 {
                        0.0
                    } else {
                        crate::exact::scale::times_pow2(k as f64, e)
                    }
                })
            });
        let any = proptest::array::uniform6(proptest::num::f64::ANY);
        prop_oneof![close, any]
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4096))]
        /// The bit reading of the common grid equals the reference, on
        /// coordinates across the whole `f64` range.
        #[test]
        fn common_ints_equal_the_reference(xs in six_doubles()) {
            proptest::prop_assert_eq!(common_ints(xs).map(|(k, e)| (k.map(i128::from), e)), common_ints_reference(xs));
        }

        /// An edge with an end that fails `may_fit_edge_grid` has no
        /// common 40-place grid (its first path would fail), on
        /// coordinates across the whole `f64` range.
        #[test]
        fn an_end_off_the_edge_grid_means_no_common_grid(xs in six_doubles()) {
            let (a, b) = ([xs[0], xs[1], xs[2]], [xs[3], xs[4], xs[5]]);
            if !(may_fit_edge_grid(a) && may_fit_edge_grid(b)) {
                proptest::prop_assert!(common_ints(xs).is_none());
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2048))]
        /// The layout's `i128` integers are the doubles over `2^lowest`,
        /// exactly (checked in big rationals), whenever they need at most
        /// 127 places; and they are offered exactly then.
        #[test]
        fn layout_integers_are_the_values(
            ms in proptest::array::uniform6(-(1i64 << 53)..1 << 53),
            shifts in proptest::array::uniform6(0i32..80), e in -1100i32..900,
        ) {
            let mut i = 0;
            let xs = ms.map(|m| {
                i += 1;
                crate::exact::scale::times_pow2(m as f64, e + shifts[i - 1])
            });
            proptest::prop_assume!(xs.iter().all(|x| x.is_finite()));
            let layout = Layout::of(xs).unwrap();
            let ints = layout.ints_i128();
            proptest::prop_assert_eq!(ints.is_some(), layout.places() <= 127);
            if let Some(ks) = ints {
                let unit = Rat::from_integer(2.into()).pow(layout.lowest);
                for (k, x) in ks.iter().zip(xs) {
                    proptest::prop_assert_eq!(Rat::from_integer((*k).into()) * &unit, rat_from_f64(x));
                }
            }
        }
    }

    #[test]
    fn common_ints_at_the_limits() {
        let tiny = f64::from_bits(1);
        for xs in [
            [0.0; 6],
            [-0.0, 0.0, 1.0, -1.0, 0.5, 3.0],
            [tiny, 0.0, 0.0, 0.0, 0.0, 0.0],
            [tiny, -tiny * 3.0, 0.0, 0.0, 0.0, tiny * (1u64 << 39) as f64],
            [tiny, 0.0, 0.0, 0.0, 0.0, tiny * (1u64 << 40) as f64],
            [f64::MAX, 0.0, 0.0, 0.0, 0.0, 0.0],
            [2f64.powi(1023), 2f64.powi(984), 0.0, 0.0, 0.0, 0.0],
            [2f64.powi(1023), 2f64.powi(983), 0.0, 0.0, 0.0, 0.0],
            [1.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0],
            [1.0, f64::NAN, 0.0, 0.0, 0.0, 0.0],
            [40.0, 3.6e-16, 0.0, 0.0, 0.0, 0.0],
        ] {
            assert_eq!(
                common_ints(xs).map(|(k, e)| (k.map(i128::from), e)),
                common_ints_reference(xs),
                "{xs:?}"
            );
        }
        // Hand-derived: 6 = 3 * 2^1 and -0.375 = -3 * 2^-3 share 2^-3.
        assert_eq!(common_ints([6.0, -0.375, 0.0]), Some(([48, -3, 0], -3)));
        // 2^39 beside 1: 40 binary places, still fits; 2^40 does not.
        assert!(common_ints([2f64.powi(39), 1.0]).is_some());
        assert_eq!(common_ints([2f64.powi(40), 1.0]), None);
    }

    #[test]
    fn loop_points_stay_small() {
        // The lazy crossing (nearest doubles, edge, level) is no larger
        // than the integer form: memory per point unchanged (80 bytes).
        assert!(std::mem::size_of::<LoopPoint>() <= 80);
    }

    #[test]
    fn shifts_never_lose_bits() {
        assert_eq!(shl_exact(3, 4), Some(48));
        assert_eq!(shl_exact(-1, 125), Some(-1 << 125));
        assert_eq!(shl_exact(2, 125), None);
        assert_eq!(shl_exact(1, -1), None);
        // A zero coordinate is canonical 0/1 even with a negative exponent.
        assert_eq!(reduced(0, 8, -3), Rat::zero());
        assert_eq!(reduced(6, 4, -1), Rat::new(3.into(), 4.into()));
        assert_eq!(reduced(3, 4, 3), Rat::from_integer(6.into()));
    }

    #[test]
    fn fast_path_is_taken_on_integer_meshes() {
        let c = Level::new(parse_rational("1/3").unwrap());
        let p = crossing_i128([0.0, 0.0, 0.0], [3.0, 6.0, 1.0], &c)
            .unwrap()
            .reduce();
        assert_eq!(p.x, parse_rational("1").unwrap());
        assert_eq!(p.y, parse_rational("2").unwrap());
        // Dyadic coordinates and a decimal level.
        let c = Level::new(parse_rational("0.3").unwrap());
        let p = crossing_i128([0.5, 0.25, 0.25], [1.5, -0.75, 0.75], &c)
            .unwrap()
            .reduce();
        assert_eq!(
            p,
            Point2::on_edge_reference([0.5, 0.25, 0.25], [1.5, -0.75, 0.75], &c)
        );
    }
}
