//! Input: an edge's two positions (doubles) and an exact level. Output:
//! the nearest doubles of the crossing point, certified, without building
//! its exact value; and [`Crossings`], which picks the number path of each
//! loop point (grid, per-edge integers, certified double-double, big
//! rationals) and counts the paths taken.
//!
//! The crossing of edge `(a, b)` with `z = c` is, per coordinate,
//! `x = (ax U + bx V) / D` with `D = bz - az`, `U = bz - c`, `V = c - az`
//! (a convex combination: `U / D` and `V / D` lie in `[0, 1]` when `c`
//! lies between the heights). [`certified_crossing`] evaluates it in
//! double-double arithmetic (error-free transformations: `TwoSum`, and
//! `TwoProd` by a fused multiply-add) with a proven bound `B` on
//! `|x - (x0 + x1)|`, then returns the double nearest `x` only when the
//! interval `[x0 + x1 - B, x0 + x1 + B]` lies strictly inside the rounding
//! interval of one double; otherwise `None`, and the caller computes the
//! exact value. Its cost does not depend on where the coordinates lie
//! (only their range is bounded, so that nothing underflows or
//! overflows; a mesh beyond it is first multiplied by the power of two of
//! its [`Frame`]). The derivation of `B` is on `coordinates` (below).

use super::frame::Frame;
use super::grid::{GridLevel, MeshGrid};
use super::level::{nearest_gap, shl, Level};
use super::point::{may_fit_edge_grid, LoopPoint};
use super::rational::{decompose, rat_minus_f64_to_f64, rat_to_f64, ratio_to_f64};
use crate::ids::VertexId;
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// The unit roundoff of `f64`, `u = 2^-53`.
const U: f64 = f64::EPSILON / 2.0;

/// Inputs are zero or of magnitude in `[2^-300, 2^300]`; intermediate
/// heights in `[2^-400, 2^400]`, results in `[2^-500, 2^500]`: so every
/// product is exact by `TwoProd` (no underflow of its low part) and no
/// bound underflows or overflows.
const IN_LO: f64 = f64::from_bits((1023 - 300) << 52);
const IN_HI: f64 = f64::from_bits((1023 + 300) << 52);
const MID_LO: f64 = f64::from_bits((1023 - 400) << 52);
const MID_HI: f64 = f64::from_bits((1023 + 400) << 52);
const OUT_LO: f64 = f64::from_bits((1023 - 500) << 52);
const OUT_HI: f64 = f64::from_bits((1023 + 500) << 52);

/// `2^-700`: covers every error that the relative bounds miss because a
/// product underflowed (see [`coordinates`]).
const ABS: f64 = f64::from_bits((1023 - 700) << 52);
/// `2^-1000`: covers the bound's own underflows.
const ABS_BOUND: f64 = f64::from_bits((1023 - 1000) << 52);

/// `a + b = s + e` exactly (Knuth's TwoSum; exact for all finite inputs
/// whose sum does not overflow).
#[inline(always)]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a b = p + e` exactly (TwoProd by FMA; exact when the exponents of `a`
/// and `b` sum to at least `-969`, so that `e` does not underflow).
#[inline(always)]
pub(crate) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// The two lanes (`x` and `y`) of one step of [`coordinates`].
#[inline(always)]
fn lanes<T>(f: impl FnMut(usize) -> T) -> [T; 2] {
    std::array::from_fn(f)
}

/// Whether `v` is zero or of magnitude in `[lo, hi]`: the range in which
/// the error analysis of [`coordinates`] holds (nothing overflows or
/// underflows). Not a tolerance: a value outside it only sends the
/// crossing to the exact path.
#[inline(always)]
fn in_range(v: f64, lo: f64, hi: f64) -> bool {
    (v == 0.0) | ((lo <= v.abs()) & (v.abs() <= hi))
}

/// Whether every value is [`in_range`], without a branch per value.
#[inline(always)]
fn all_in_range<const N: usize>(vs: [f64; N], lo: f64, hi: f64) -> bool {
    vs.iter().fold(true, |all, &v| all & in_range(v, lo, hi))
}

/// A level in a [`Frame`] as a double-double: `|c 2^s - (hi + lo)| <= err`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelApprox {
    hi: f64,
    lo: f64,
    err: f64,
    frame: Frame,
    /// The spacing of the subnormal doubles, `2^-1074`, in the frame
    /// (zero unless the frame scales up: a mesh among the subnormals or
    /// near them), and `2^53` times it, the image of `2^-1021`: below it
    /// the doubles are evenly spaced by `2^-1074`.
    grid: f64,
    grid_top: f64,
}

impl LevelApprox {
    /// `hi` the nearest double of `c 2^s` (the level in the mesh's
    /// `frame`), `lo` the nearest double of `c 2^s - hi` (so
    /// `err = u |lo|`); `None` out of the range of [`certified_crossing`]
    /// (then every crossing takes the exact path).
    pub fn new(level: &Level, frame: Frame) -> Option<LevelApprox> {
        if frame.is_identity() {
            return Self::in_frame(level, frame);
        }
        Self::in_frame(&Level::new(frame.scale(level.value())), frame)
    }

    /// As [`LevelApprox::new`], for `level` already multiplied by `2^s`.
    fn in_frame(level: &Level, frame: Frame) -> Option<LevelApprox> {
        let c = level.value();
        let hi = rat_to_f64(c);
        if !in_range(hi, IN_LO, IN_HI) {
            return None;
        }
        let lo = level
            .wide()
            .and_then(|(p, q)| residual(p, q, hi))
            .unwrap_or_else(|| rat_minus_f64_to_f64(c, hi));
        // |lo| <= u |hi|; below 2^-1000 it could be subnormal (then the
        // relative bound fails): refused.
        if !in_range(lo, f64::from_bits((1023 - 1000) << 52), IN_HI) {
            return None;
        }
        // Non-identity frames shift by more than 200: `grid` is normal.
        let grid = if frame.shift() > 0 {
            frame.place(f64::from_bits(1))
        } else {
            0.0
        };
        Some(LevelApprox {
            hi,
            lo,
            err: U * lo.abs(),
            frame,
            grid,
            grid_top: grid * f64::from_bits((1023 + 53) << 52),
        })
    }
}

/// The nearest double of `p / q - hi` (`q > 0`, `hi` the nearest double
/// of `p / q`), in `i128`: `hi = m 2^e`, so `p / q - hi` is
/// `(p 2^-e - m q) 2^e / q` for `e < 0`, whose numerator
/// [`nearest_gap`] computes without overflow, and `(p - m q 2^e) / q` for
/// `e >= 0` when the products fit; rounded once by [`ratio_to_f64`]
/// (equal to `rat_to_f64` of the same value).
fn residual(p: i128, q: i128, hi: f64) -> Option<f64> {
    let q_u = u128::try_from(q).ok()?;
    let Some((m, e)) = decompose(hi) else {
        return Some(ratio_to_f64(p, q_u, 0));
    };
    Some(if e >= 0 {
        let mq = i128::from(m).checked_mul(q)?;
        ratio_to_f64(p.checked_sub(shl(mq, e as u32)?)?, q_u, 0)
    } else {
        ratio_to_f64(nearest_gap(p, q, m, e.unsigned_abs())?, q_u, e)
    })
}

/// The nearest doubles of both coordinates of the crossing, each
/// `x = (ax U + bx V) / D` (`ax`, `bx`: the ends' `x` and their `y`), when
/// the certified bound decides both; `(u_h, u_l, u_e)` and
/// `(v_h, v_l, v_e)` `U` and `V` as double-doubles with error bounds,
/// `(d_h, d_l)` = `D = bz - az` exactly (`az != bz`), `d_inv = fl(1 / Dh)`.
///
/// The two coordinates take the same operations in the same order (the
/// compiler pairs them into two-lane instructions: `steps64_1m` certified
/// crossings 38 -> 33 ns each); each result is as a one-coordinate
/// evaluation would round it, so the derivation below is per coordinate.
///
/// Derivation (every `fl` rounds to nearest, `u = 2^-53`; ranges as in
/// `IN_LO..MID_HI`, so TwoSum and TwoProd are exact and nothing
/// underflows):
///
/// 1. `(P1, p1) = TwoProd(ax, Uh)`, `q1 = fl(ax Ul)`, likewise `P2, p2`
///    from `bx, Vh` and `q2 = fl(bx Vl)`; `(S, s) = TwoSum(P1, P2)`;
///    `t = fl(((s + p1) + p2) + (q1 + q2))`; `(Nh, Nl) = TwoSum(S, t)`.
///    Then `N = ax U + bx V = Nh + Nl + eN` with
///    `|eN| <= g4 (|s| + |p1| + |p2| + |ax Ul| + |bx Vl|)
///    + u (|ax Ul| + |bx Vl|) + |ax| Ue + |bx| Ve`, `g4 = 4u / (1 - 4u)`
///    (recursive summation of five terms, two rounded products, and the
///    errors of `U` and `V`). With `|ax Ul| <= |q1| (1 + 2u)`:
///    `|eN| <= 5u (|s| + |p1| + |p2| + |q1| + |q2|) + |ax| Ue + |bx| Ve`.
/// 2. `i = fl(1 / Dh)` (one division per point, shared by `x` and `y`),
///    `x0 = fl(Nh i)`, within a factor `(1 + u)^2` of `Nh / Dh`: any
///    double that close serves. `(P, p) = TwoProd(x0, Dh)`. `Nh - P` is
///    exact (Sterbenz: `P` is within a factor `(1 + u)^3` of `Nh`, same
///    sign).
///    `R = N - x0 (Dh + Dl) = (Nh - P) - p + Nl - x0 Dl + eN` exactly;
///    `r = fl(fl((Nh - P) - p) + fl(Nl - fl(x0 Dl)))`, with
///    `|R - r| <= 3u (|Nh - P| + |p| + |Nl| + |x0 Dl|) + u |x0 Dl| + |eN|
///    =: eR` (three additions of four terms, one product; the `3u`
///    absorbs `g3`'s `1 / (1 - 3u)` with the slack below).
/// 3. `x = x0 + R / (Dh + Dl)`; `x1 = fl(r i)`, within `2.01u |r / Dh|`
///    of `r / Dh`. With `|Dl| <= u |Dh|`:
///    `|R / (Dh + Dl) - x1| <= |r / Dh| (1.01u + 2.01u) + eR / (|Dh| (1 - u))`,
///    so `|x - (x0 + x1)| <= 4.02u |x1| + 1.01 eR / |Dh|` (the `u` of
///    `Dl` and the `2.01u` of the product, over `|r / Dh| <= 1.01 |x1|`,
///    rounded up).
///
/// Underflow: a sum that underflows is exact, and TwoProd is exact in the
/// ranges checked (`|ax Uh| >= 2^-700`; `|x0 Dh|` is near `|Nh|`, which
/// is at least `2^-900` whenever `|f| >= 2^-500` is accepted below). A
/// rounded product that underflows (`q1`, `q2`, `x0 Dl`, and the
/// products that evaluate `Ue`, `Ve`, `eN`, `eR`) errs by at most
/// `2^-1074` beyond its relative bound, multiplied by at most `2^300`
/// (`|ax| Ue`): below `2^-770` in all. `ABS = 2^-700`, added to `|eN|`
/// and to `eR`, covers it.
///
/// The bound is evaluated in rounded arithmetic on non-negative terms
/// (fewer than 30 operations, each raising at most `u` relatively; the
/// division by `|Dh|` is a product by `|i|`, one more such rounding), then
/// doubled, plus `2^-1000` for the underflow of its smallest terms: a
/// safe upper bound. `(f, e) = TwoSum(x0, x1)`, `f` the
/// candidate; `x0 + x1 - f = e` exactly. The exact `x` rounds to `f` when
/// `e + B < g+/2` and `e - B > -g-/2` (`g+`, `g-` the gaps to `f`'s
/// neighbours, halved exactly); each test is on a rounded sum compared
/// with a double, which rounding cannot flip (rounding is monotone). Ties
/// are never decided here.
#[inline(always)]
fn coordinates(
    ax: [f64; 2],
    bx: [f64; 2],
    (u_h, u_l, u_e): (f64, f64, f64),
    (v_h, v_l, v_e): (f64, f64, f64),
    (d_h, d_l, d_inv): (f64, f64, f64),
    (grid, grid_top): (f64, f64),
) -> Option<[f64; 2]> {
    // Straight-line code on both lanes; the decision per lane follows.
    let (p1, q1, p2, q2) = (
        lanes(|i| two_prod(ax[i], u_h)),
        lanes(|i| ax[i] * u_l),
        lanes(|i| two_prod(bx[i], v_h)),
        lanes(|i| bx[i] * v_l),
    );
    let s = lanes(|i| two_sum(p1[i].0, p2[i].0));
    let t = lanes(|i| ((s[i].1 + p1[i].1) + p2[i].1) + (q1[i] + q2[i]));
    let n = lanes(|i| two_sum(s[i].0, t[i]));
    let e_n = lanes(|i| {
        5.0 * U * (s[i].1.abs() + p1[i].1.abs() + p2[i].1.abs() + q1[i].abs() + q2[i].abs())
            + ax[i].abs() * u_e
            + bx[i].abs() * v_e
            + ABS
    });
    let x0 = lanes(|i| n[i].0 * d_inv);
    let p = lanes(|i| two_prod(x0[i], d_h));
    let diff = lanes(|i| n[i].0 - p[i].0);
    let x0dl = lanes(|i| x0[i] * d_l);
    let r = lanes(|i| (diff[i] - p[i].1) + (n[i].1 - x0dl[i]));
    let e_r = lanes(|i| {
        3.0 * U * (diff[i].abs() + p[i].1.abs() + n[i].1.abs() + x0dl[i].abs())
            + U * x0dl[i].abs()
            + e_n[i]
            + ABS
    });
    let x1 = lanes(|i| r[i] * d_inv);
    let bound = lanes(|i| 2.0 * (4.02 * U * x1[i].abs() + 1.01 * e_r[i] * d_inv.abs()) + ABS_BOUND);
    let fe = lanes(|i| two_sum(x0[i], x1[i]));
    // On |f|: its error `e` with the sign of `f` taken out, and the gaps
    // to its neighbours halved (exact). `|f|` is a positive normal double
    // wherever it is used below (in `[OUT_LO, OUT_HI]`), so its neighbours
    // are the adjacent bit patterns.
    let m = lanes(|i| fe[i].0.abs());
    let e = lanes(|i| if fe[i].0 > 0.0 { fe[i].1 } else { -fe[i].1 });
    let up = lanes(|i| (f64::from_bits(m[i].to_bits().wrapping_add(1)) - m[i]) / 2.0);
    let down = lanes(|i| (m[i] - f64::from_bits(m[i].to_bits().wrapping_sub(1))) / 2.0);
    let coordinate = |i: usize| {
        if ax[i] == bx[i] {
            // A convex combination of one value (also when both are zero;
            // `+ 0.0` writes a zero as `0`, as the exact path rounds it).
            return Some(ax[i] + 0.0);
        }
        let (f, bound) = (fe[i].0, bound[i]);
        if !(OUT_LO..=OUT_HI).contains(&m[i]) || !bound.is_finite() {
            return None;
        }
        // Which grid the nearest double rounds to (the exact image of
        // `2^-1021`, not a tolerance): below it the doubles are spaced by
        // `2^-1074`. This picks the rounding of the coordinate written
        // out (and handed to the filters with its error bound); no
        // classification, chaining, orientation or nesting decision is
        // taken here.
        if m[i] < grid_top {
            return on_subnormal_grid(f, fe[i].1, bound, grid);
        }
        (e[i] + bound < up[i] && e[i] - bound > -down[i]).then_some(f)
    };
    Some([coordinate(0)?, coordinate(1)?])
}

/// Where the nearest double lies below `2^-1021` (the subnormals and the
/// least normal binade, all spaced by `2^-1074`): in a frame scaling by
/// `2^s`, `x 2^s` rounds to a multiple `r = k g` of `g = 2^(s - 1074)`.
/// `f / g` is exact (a power of two, `|f| < 2^53 g`) and rounds to `k`;
/// `d = f - r` is exact (a multiple of `f`'s ulp, which is at most `g`,
/// below `g / 2`). The exact value lies within `e + B` of `f`, so within
/// `d + e +- B` of `r`: `r` is the rounding when `|d| + |e| + B < g / 2`,
/// tested as `d +- S` against `+-g / 2` with `S >= |e| + B` (one rounding
/// each, monotone). `r 2^-s = k 2^-1074` is then the nearest double,
/// exactly. Ties are never decided here.
#[inline(never)]
fn on_subnormal_grid(f: f64, e: f64, bound: f64, grid: f64) -> Option<f64> {
    let r = (f / grid).round_ties_even() * grid;
    let d = f - r;
    let slack = (bound + e.abs()).next_up();
    let half = grid / 2.0;
    (d + slack < half && d - slack > -half).then_some(r)
}

/// The nearest doubles of the crossing of edge `(a, b)` with the level,
/// when the certified bound decides both (see `coordinates`); `None`
/// out of range or when undecided. The caller guarantees `az != bz`.
///
/// On x86-64 CPUs with FMA the arithmetic is compiled for it (chosen at
/// run time): `f64::mul_add` is the same correctly rounded operation
/// either way, one instruction instead of a library call, and no other
/// expression is contracted, so the results are bit for bit the same.
#[inline]
pub fn certified_crossing(a: [f64; 3], b: [f64; 3], c: &LevelApprox) -> Option<[f64; 2]> {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU has FMA (checked just above).
            return unsafe { certified_crossing_fma(a, b, c) };
        }
    }
    certified_crossing_with(a, b, c)
}

/// [`certified_crossing`] compiled with FMA instructions.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn certified_crossing_fma(a: [f64; 3], b: [f64; 3], c: &LevelApprox) -> Option<[f64; 2]> {
    certified_crossing_with(a, b, c)
}

/// In the level's frame: the identity for every ordinary mesh; else the
/// ends placed (exact when they land in the accepted range, which
/// [`crossing_in_frame`] checks, and no value underflows to zero) and the
/// results brought back, when the nearest doubles commute with the
/// scaling ([`Frame::back`]).
#[inline(always)]
fn certified_crossing_with(a: [f64; 3], b: [f64; 3], c: &LevelApprox) -> Option<[f64; 2]> {
    let frame = c.frame;
    if frame.is_identity() {
        return crossing_in_frame(a, b, c);
    }
    let (pa, pb) = (a.map(|v| frame.place(v)), b.map(|v| frame.place(v)));
    // A value that underflowed to zero would pass the range check.
    if a.iter()
        .chain(&b)
        .zip(pa.iter().chain(&pb))
        .any(|(v, p)| (*v == 0.0) != (*p == 0.0))
    {
        return None;
    }
    let [x, y] = crossing_in_frame(pa, pb, c)?;
    // Below the image of `2^-1021` (an exact power of two, not a tolerance)
    // the result is a multiple of the subnormal spacing, decided on that
    // grid: brought back exactly. Only how the rounded output coordinate is
    // brought back depends on it, never a decision of the slicer.
    let back = |v: f64| {
        if v.abs() < c.grid_top {
            Some(frame.place_back(v))
        } else {
            frame.back(v)
        }
    };
    Some([back(x)?, back(y)?])
}

#[inline(always)]
fn crossing_in_frame(a: [f64; 3], b: [f64; 3], c: &LevelApprox) -> Option<[f64; 2]> {
    let (az, bz) = (a[2], b[2]);
    if !all_in_range([a[0], a[1], az, b[0], b[1], bz], IN_LO, IN_HI) {
        return None;
    }
    // D exactly; U = bz - c and V = c - az as double-doubles (the level's
    // error plus one rounding each: TwoSum is exact).
    let (d_h, d_l) = two_sum(bz, -az);
    let (v1, v2) = two_sum(c.hi, -az);
    let v3 = v2 + c.lo;
    let (v_h, v_l) = two_sum(v1, v3);
    let v_e = U * v3.abs() + c.err;
    let (u1, u2) = two_sum(bz, -c.hi);
    let u3 = u2 - c.lo;
    let (u_h, u_l) = two_sum(u1, u3);
    let u_e = U * u3.abs() + c.err;
    if !all_in_range([d_h, v_h, u_h], MID_LO, MID_HI) || d_h == 0.0 {
        return None;
    }
    let uu = (u_h, u_l, u_e);
    let vv = (v_h, v_l, v_e);
    // D in [2^-400, 2^400]: its reciprocal is a normal double.
    let dd = (d_h, d_l, 1.0 / d_h);
    let grid = (c.grid, c.grid_top);
    coordinates([a[0], a[1]], [b[0], b[1]], uu, vv, dd, grid)
}

/// The number path a loop point took.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberPath {
    /// Integers on the mesh's one binary grid ([`MeshGrid`]).
    Grid,
    /// Integers on the edge's own binary grid (`i128`).
    Edge,
    /// Certified double-double; the exact value built only on demand.
    Certified,
    /// Rounded from the exact value in 256-bit integers ([`super::wide`]),
    /// when the certified bound does not decide (ties); the exact value
    /// built only on demand.
    Wide,
    /// Big rationals.
    Big,
}

impl NumberPath {
    /// Every path, in the order they are tried.
    pub const ALL: [NumberPath; 5] = [
        NumberPath::Grid,
        NumberPath::Edge,
        NumberPath::Certified,
        NumberPath::Wide,
        NumberPath::Big,
    ];

    /// The path's name as `--verbose` prints it.
    pub fn name(self) -> &'static str {
        match self {
            NumberPath::Grid => "grid",
            NumberPath::Edge => "per-edge",
            NumberPath::Certified => "certified",
            NumberPath::Wide => "wide",
            NumberPath::Big => "big",
        }
    }
}

static TAKEN: [AtomicU64; 5] = [
    AtomicU64::new(0),
    AtomicU64::new(0),
    AtomicU64::new(0),
    AtomicU64::new(0),
    AtomicU64::new(0),
];

/// How many loop points took each path since the process started (or
/// since [`reset_path_counts`]), in the order of [`NumberPath::ALL`].
pub fn path_counts() -> [u64; 5] {
    TAKEN.each_ref().map(|c| c.load(Ordering::Relaxed))
}

/// Sets the counts of [`path_counts`] to zero.
pub fn reset_path_counts() {
    TAKEN.iter().for_each(|c| c.store(0, Ordering::Relaxed));
}

/// Builds the exact loop points of one level: on the mesh's grid when
/// the mesh and the level fit it, else per edge. Counts the paths taken
/// (added to [`path_counts`] when dropped).
pub struct Crossings<'a> {
    grid: Option<(&'a MeshGrid, GridLevel)>,
    /// See [`EdgeGridEnds`].
    ends: Option<&'a EdgeGridEnds>,
    level: Arc<Level>,
    approx: Option<LevelApprox>,
    frame: Frame,
    taken: [Cell<u64>; 5],
}

impl<'a> Crossings<'a> {
    /// The point builder of one level (`level` in the mesh's stored units,
    /// `frame` the mesh's, see [`Frame`]).
    /// `ends`: the mesh's [`EdgeGridEnds`], if any.
    pub fn new(
        grid: Option<&'a MeshGrid>,
        ends: Option<&'a EdgeGridEnds>,
        level: &Arc<Level>,
        frame: Frame,
    ) -> Self {
        let grid = grid.and_then(|g| Some((g, g.level(level)?)));
        Crossings {
            grid,
            ends,
            approx: if grid.is_none() {
                LevelApprox::new(level, frame)
            } else {
                None
            },
            frame,
            level: Arc::clone(level),
            taken: Default::default(),
        }
    }

    /// The frame in which the level's points are filtered.
    pub fn frame(&self) -> Frame {
        self.frame
    }

    fn count(&self, path: NumberPath) {
        let c = &self.taken[path as usize];
        c.set(c.get() + 1);
    }

    /// The exact point of vertex `v` at position `p`.
    #[inline]
    pub fn vertex(&self, v: VertexId, p: [f64; 3]) -> LoopPoint {
        match &self.grid {
            Some((g, _)) => {
                self.count(NumberPath::Grid);
                g.point(v)
            }
            None => {
                let lp = LoopPoint::of_vertex(p);
                self.count(if lp.as_integers().is_some() {
                    NumberPath::Edge
                } else {
                    NumberPath::Big
                });
                lp
            }
        }
    }

    /// The exact crossing of edge `(a, b)` (positions `pa`, `pb`,
    /// `h(a) != h(b)`) with the level.
    #[inline]
    pub fn crossing(&self, a: VertexId, b: VertexId, pa: [f64; 3], pb: [f64; 3]) -> LoopPoint {
        if let Some((g, level)) = &self.grid {
            self.count(NumberPath::Grid);
            return g.crossing(a, b, level);
        }
        let (level, approx) = (&self.level, self.approx.as_ref());
        let (lp, path) = match self.ends {
            Some(ends) if !ends.may_fit(a, b) => {
                LoopPoint::on_edge_off_edge_grid(pa, pb, level, approx)
            }
            _ => LoopPoint::on_edge_with(pa, pb, level, approx),
        };
        self.count(path);
        lp
    }
}

/// Per vertex, whether an edge ending there may take the per-edge integer
/// crossing (see [`LoopPoint::on_edge_with`]): in an `f64` mesh most
/// coordinates need 50 places or more on their own, and every crossing
/// would first read its edge's binary layout only to find it does not fit
/// (`steps64_1m` x 1000: slicing 2-9% faster without that read, old and
/// new run side by side four times). Built once per mesh, when some vertex
/// does not fit; a `false` decides nothing but which path is tried first,
/// never a value.
///
/// One bit per vertex (a bit set: an eighth of a byte table, so that it
/// stays in cache beside the positions).
#[derive(Clone, Debug)]
pub struct EdgeGridEnds(Vec<u64>);

impl EdgeGridEnds {
    /// The table of `positions`, or `None` when every vertex may fit
    /// (then nothing is skipped and no table is read).
    pub fn new(positions: &[[f64; 3]]) -> Option<Self> {
        let bits: Vec<u64> = positions
            .chunks(64)
            .map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0, |w, (i, &p)| w | u64::from(may_fit_edge_grid(p)) << i)
            })
            .collect();
        let fitting: usize = bits.iter().map(|w| w.count_ones() as usize).sum();
        (fitting < positions.len()).then_some(EdgeGridEnds(bits))
    }

    /// Whether edge `(a, b)` may take the per-edge integer crossing.
    #[inline]
    fn may_fit(&self, a: VertexId, b: VertexId) -> bool {
        let bit = |v: VertexId| self.0[v.idx() / 64] >> (v.idx() % 64) & 1 == 1;
        bit(a) & bit(b)
    }
}

impl Drop for Crossings<'_> {
    fn drop(&mut self) {
        for (total, c) in TAKEN.iter().zip(&self.taken) {
            if c.get() > 0 {
                total.fetch_add(c.get(), Ordering::Relaxed);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::point::Point2;
    use crate::exact::rational::{rat_from_f64, Rat};
    use num_traits::Signed;
    use proptest::prelude::*;

    /// The bit set: `None` when every vertex fits (130 vertices: two full
    /// words and a partial one); else exactly the edges at the vertex that
    /// does not (its coordinates span 1 to 2^-60, 61 places) are told
    /// apart, wherever it lies in its word.
    #[test]
    fn edge_grid_ends_mark_exactly_the_vertices_off_it() {
        let fits = |k: u32| [f64::from(k), 0.5, -3.0];
        let mut positions: Vec<[f64; 3]> = (0..130).map(fits).collect();
        assert!(EdgeGridEnds::new(&positions).is_none());
        for off in [0usize, 63, 64, 129] {
            positions[off] = [1.0, 2f64.powi(-60), 0.0];
            let ends = EdgeGridEnds::new(&positions).expect("a vertex is off");
            for a in 0..130 {
                for b in [0usize, 1, 63, 64, 65, 128, 129] {
                    let expected = a != off && b != off;
                    let got = ends.may_fit(VertexId::from_idx(a), VertexId::from_idx(b));
                    assert_eq!(got, expected, "off {off}, edge {a}-{b}");
                }
            }
            positions[off] = fits(off as u32);
        }
    }

    proptest! {
        /// The integer residual of a level equals the rational one, and
        /// is found without big numbers unless its nearest double is an
        /// integer.
        #[test]
        fn residual_equals_rational(p in any::<i128>(), pb in 1u32..128, q in 1i128..i128::MAX, qb in 1u32..127) {
            let (p, q) = (p >> (128 - pb), (q >> (127 - qb)).max(1));
            let c = Rat::new(p.into(), q.into());
            let hi = rat_to_f64(&c);
            prop_assume!(hi.is_finite());
            let (p, q) = (c.numer().try_into().unwrap(), c.denom().try_into().unwrap());
            let want = rat_to_f64(&(&c - rat_from_f64(hi)));
            match residual(p, q, hi) {
                Some(r) => prop_assert_eq!(r.to_bits(), want.to_bits()),
                // Only a level whose nearest double is an integer may need
                // the big path.
                None => prop_assert!(decompose(hi).is_some_and(|(_, e)| e >= 0)),
            }
        }
    }

    /// Doubles across the whole range: any finite bit pattern, subnormals,
    /// `f32` values, small integers and decimals, near-zero noise, and
    /// mantissas with random exponents.
    fn coordinate_value() -> impl Strategy<Value = f64> {
        prop_oneof![
            any::<u64>()
                .prop_map(f64::from_bits)
                .prop_filter("finite", |v| v.is_finite()),
            (any::<i64>(), -1074i32..-1000).prop_map(|(m, e)| (m >> 11) as f64 * 2f64.powi(e)),
            any::<u32>()
                .prop_map(f32::from_bits)
                .prop_filter("finite", |v| v.is_finite())
                .prop_map(f64::from),
            (-1000i32..1000).prop_map(f64::from),
            (-100000i32..100000).prop_map(|k| f64::from(k) * 0.001),
            (any::<i32>(), -60i32..-40).prop_map(|(m, e)| f64::from(m) * 2f64.powi(e - 31)),
            (any::<i64>(), -400i32..400).prop_map(|(m, e)| (m >> 11) as f64 * 2f64.powi(e)),
        ]
    }

    /// A level: a fraction of the way between the heights (decimal or
    /// arbitrary), a decimal near them, or an arbitrary rational.
    fn level_for(za: f64, zb: f64, kind: u8, p: i64, q: i64) -> Rat {
        let (ra, rb) = (rat_from_f64(za), rat_from_f64(zb));
        let q = q.unsigned_abs().max(1);
        match kind {
            0 => &ra + (&rb - &ra) * Rat::new((p.unsigned_abs() % q).into(), q.into()),
            1 => &ra + (&rb - &ra) * Rat::new((p.unsigned_abs() % 1000).into(), 1000.into()),
            2 => {
                // The decimal with four digits after the point nearest the middle.
                let mid = (ra + rb) / Rat::from_integer(2.into());
                let scaled = (mid * Rat::from_integer(10000.into())).round();
                scaled / Rat::from_integer(10000.into())
            }
            _ => Rat::new(p.into(), q.into()),
        }
    }

    /// An edge of one part as CAD files hold it: from `a`, by `d` (rising),
    /// rounded to `f32` or to six decimals, with near-zero noise `2^noise`
    /// in one coordinate beside values up to 60.
    fn ordinary_edge(a: [f64; 3], d: [f64; 3], noise: i32, single: bool) -> ([f64; 3], [f64; 3]) {
        let round = |v: f64| {
            if single {
                f64::from(v as f32)
            } else {
                (v * 1e6).round() / 1e6
            }
        };
        let mut a = a.map(round);
        let b = [a[0] + d[0], a[1] + d[1], a[2] + d[2] + 0.01].map(round);
        a[1] = 2f64.powi(noise) * 1.2345;
        (a, b)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]

        /// A certified result is the nearest double of the exact crossing
        /// (the big-rational reference), coordinate by coordinate; the
        /// lazy point's exact value and equality agree with the reference.
        #[test]
        fn certified_doubles_are_the_nearest(
            a in proptest::array::uniform3(coordinate_value()),
            b in proptest::array::uniform3(coordinate_value()),
            kind in 0u8..4, p in any::<i64>(), q in any::<i64>(),
        ) {
            prop_assume!(a[2] != b[2]);
            let level = Level::new(level_for(a[2], b[2], kind, p, q));
            let reference = Point2::on_edge_reference(a, b, &level);
            let nearest = reference.to_f64();
            let approx = LevelApprox::new(&level, Frame::for_points([a, b]));
            if let Some(c) = &approx {
                if let Some(r) = certified_crossing(a, b, c) {
                    prop_assert_eq!(r.map(f64::to_bits), nearest.map(f64::to_bits));
                }
            }
            let shared = Arc::new(level);
            let (lp, _) = LoopPoint::on_edge_with(a, b, &shared, approx.as_ref());
            let (back, _) = LoopPoint::on_edge_with(b, a, &shared, approx.as_ref());
            prop_assert_eq!(lp.to_f64().map(f64::to_bits), nearest.map(f64::to_bits));
            prop_assert_eq!(lp.zero_coordinates(), [reference.x == Rat::from_integer(0.into()), reference.y == Rat::from_integer(0.into())]);
            prop_assert_eq!(lp.exact().into_owned(), reference.clone());
            prop_assert!(lp == back);
            prop_assert!(lp == LoopPoint::from(reference));
        }

        /// Crossings at or within `2^-k` of the middle between two
        /// neighbouring doubles (ends one ulp apart in `x`, any `y`, the
        /// level at the middle height or just off it): a tie is never
        /// decided, and a near-tie is rounded as the exact value rounds.
        /// (Decisions near the rounding boundaries, which random edges
        /// almost never reach.)
        #[test]
        fn ties_and_near_ties_round_as_the_exact_value(
            x in coordinate_value(), y in proptest::array::uniform2(coordinate_value()),
            z in proptest::array::uniform2(coordinate_value()),
            k in 40u32..140, side in -1i32..=1, down in any::<bool>(),
        ) {
            prop_assume!(x.is_finite() && x != 0.0 && z[0] != z[1]);
            let other = if down { x.next_down() } else { x.next_up() };
            prop_assume!(other.is_finite() && other != 0.0);
            let (a, b) = ([x, y[0], z[0]], [other, y[1], z[1]]);
            let (ra, rb) = (rat_from_f64(z[0]), rat_from_f64(z[1]));
            let off = Rat::new(side.into(), Rat::from_integer(2.into()).pow(k as i32).to_integer());
            let t = Rat::new(1.into(), 2.into()) + off;
            let level = Level::new(&ra + (&rb - &ra) * t);
            let nearest = Point2::on_edge_reference(a, b, &level).to_f64();
            if let Some(c) = LevelApprox::new(&level, Frame::for_points([a, b])) {
                if let Some(r) = certified_crossing(a, b, &c) {
                    prop_assert_ne!(side, 0, "a tie was decided");
                    prop_assert_eq!(r.map(f64::to_bits), nearest.map(f64::to_bits));
                }
            }
        }

        /// Crossings of edges that share a coordinate with both ends (faces
        /// parallel to an axis), and of edges moved along one axis (walls
        /// of one row cut into the same bands, whose crossings share the
        /// other coordinate), coordinates across the whole range: the
        /// coordinate they are known to have is the exact one, and the
        /// filtered order of x and y and orient2d (in the points' frame)
        /// are the exact ones.
        #[test]
        fn crossings_on_axis_parallel_edges_decide_exactly(
            a in proptest::array::uniform3(coordinate_value()),
            b in proptest::array::uniform3(coordinate_value()),
            c in proptest::array::uniform3(coordinate_value()),
            shared in proptest::array::uniform3(0u8..3), kind in 0u8..4, p in any::<i64>(), q in any::<i64>(),
        ) {
            use crate::exact::filter::{cmp_x, cmp_y, orient2d_filtered, FilteredPoint};
            use crate::exact::predicates::orient2d_rat;
            // Three edges between `a`'s height and `b`'s (the third
            // going down); `shared[i]` says
            // which of x and y (bit 0 and 1) the i-th edge's ends share,
            // the second and third at the first edge's shared values.
            // Then the first edge moved to `c`'s x, and to `c`'s y.
            prop_assume!(a[2] != b[2]);
            let ends = [(a, b), (c, b), (b, a)];
            let mut edges: Vec<([f64; 3], [f64; 3])> = ends.iter().enumerate().map(|(i, &(p0, p1))| {
                let mut e = (p0, [p1[0], p1[1], if i == 2 { a[2] } else { b[2] }]);
                e.0[2] = if i == 2 { b[2] } else { a[2] };
                for (k, &v) in a.iter().enumerate().take(2) {
                    if shared[i] >> k & 1 == 1 {
                        e.0[k] = v;
                        e.1[k] = v;
                    }
                }
                e
            }).collect();
            let first = edges[0];
            for (k, &to) in c.iter().enumerate().take(2) {
                let mut moved = first;
                moved.0[k] = to;
                moved.1[k] = to + (first.1[k] - first.0[k]);
                prop_assume!(moved.1[k].is_finite());
                edges.push(moved);
            }
            let level = Level::new(level_for(a[2], b[2], kind, p, q));
            let frame = Frame::for_points(edges.iter().flat_map(|&(u, v)| [u, v]));
            let approx = LevelApprox::new(&level, frame);
            let level = Arc::new(level);
            let held: Vec<LoopPoint> = edges.iter().map(|&(u, v)| LoopPoint::on_edge_with(u, v, &level, approx.as_ref()).0).collect();
            let exact: Vec<Point2> = edges.iter().map(|&(u, v)| Point2::on_edge_reference(u, v, &level)).collect();
            for (h, e) in held.iter().zip(&exact) {
                for (k, v) in h.known_doubles().into_iter().enumerate() {
                    if let Some(v) = v {
                        prop_assert_eq!(&rat_from_f64(v), if k == 0 { &e.x } else { &e.y });
                    }
                }
            }
            let f: Vec<_> = held.iter().map(|h| FilteredPoint::in_frame(h, frame)).collect();
            for i in 0..f.len() {
                for j in 0..f.len() {
                    prop_assert_eq!(cmp_x(&f[i], &f[j]), exact[i].x.cmp(&exact[j].x));
                    prop_assert_eq!(cmp_y(&f[i], &f[j]), exact[i].y.cmp(&exact[j].y));
                }
            }
            prop_assert_eq!(orient2d_filtered(&f[0], &f[1], &f[2]), orient2d_rat(&exact[0], &exact[1], &exact[2]));
            prop_assert_eq!(orient2d_filtered(&f[0], &f[3], &f[4]), orient2d_rat(&exact[0], &exact[3], &exact[4]));
        }

        /// Two different crossings are never equal, whatever their paths.
        #[test]
        fn distinct_crossings_differ(
            a in proptest::array::uniform3(coordinate_value()),
            b in proptest::array::uniform3(coordinate_value()),
            k1 in 1i64..999, k2 in 1i64..999,
        ) {
            prop_assume!(a[2] != b[2] && k1 != k2);
            let make = |k: i64| {
                let level = Level::new(level_for(a[2], b[2], 1, k, 1000));
                let approx = LevelApprox::new(&level, Frame::for_points([a, b]));
                let shared = Arc::new(level);
                LoopPoint::on_edge_with(a, b, &shared, approx.as_ref()).0
            };
            let (p1, p2) = (make(k1), make(k2));
            prop_assert_eq!(p1 == p2, p1.exact() == p2.exact());
        }

        /// Edges with ordinary coordinates (f32 and decimal f64 of one part,
        /// near-zero noise beside values of 40) at decimal levels: the
        /// certified path decides almost every crossing.
        #[test]
        fn certified_path_decides_ordinary_edges(
            a in proptest::array::uniform3(-60.0f64..60.0), d in proptest::array::uniform3(-1.0f64..1.0),
            noise in -60i32..-40, single in any::<bool>(), t in 1i64..9999,
        ) {
            let (a, b) = ordinary_edge(a, d, noise, single);
            prop_assume!(a[2] != b[2]);
            let level = Level::new(level_for(a[2], b[2], 1, t, 10000));
            let approx = LevelApprox::new(&level, Frame::IDENTITY).unwrap();
            // A tie (a crossing exactly halfway between two doubles) is
            // the only reason left to refuse.
            if certified_crossing(a, b, &approx).is_none() {
                let exact = Point2::on_edge_reference(a, b, &level);
                let tie = |v: &Rat, f: f64| {
                    let e = rat_from_f64(f);
                    let other = if rat_from_f64(f) < *v { f.next_up() } else { f.next_down() };
                    (v - &e).abs() == (v - rat_from_f64(other)).abs()
                };
                let [x, y] = exact.to_f64();
                prop_assert!(tie(&exact.x, x) || tie(&exact.y, y) || (v_near(&exact.x, x) || v_near(&exact.y, y)));
            }
        }
    }

    proptest! {
        // Scalings that lose a bit are skipped: many, at the ends.
        #![proptest_config(ProptestConfig { cases: 2048, max_global_rejects: 1 << 20, ..ProptestConfig::default() })]

        /// An ordinary edge (decimal, `f32`, near-zero noise) multiplied by
        /// any power of two, at a decimal level multiplied likewise: in the
        /// frame of its magnitude the certified path gives the nearest
        /// doubles of the exact crossing whenever it answers, and it
        /// answers wherever the unscaled edge is decided and the results
        /// stay normal.
        #[test]
        fn framed_crossings_are_the_nearest_at_every_scale(
            a in proptest::array::uniform3(-60.0f64..60.0), d in proptest::array::uniform3(-1.0f64..1.0),
            noise in -60i32..-40, single in any::<bool>(), t in 1i64..9999, k in -1130i32..1030,
        ) {
            let (a, b) = ordinary_edge(a, d, noise, single);
            prop_assume!(a[2] != b[2]);
            let unscaled = Level::new(level_for(a[2], b[2], 1, t, 10000));
            let decided = certified_crossing(a, b, &LevelApprox::new(&unscaled, Frame::IDENTITY).unwrap());
            let times = |v: f64| crate::exact::scale::times_pow2(v, k);
            let (sa, sb) = (a.map(times), b.map(times));
            // Only exact scalings: every coordinate kept.
            prop_assume!(sa.iter().chain(&sb).zip(a.iter().chain(&b)).all(|(s, v)| crate::exact::scale::times_pow2(*s, -k) == *v));
            prop_assume!(sa[2] != sb[2]);
            let level = Level::new(unscaled.value() * Rat::from_integer(2.into()).pow(k));
            let nearest = Point2::on_edge_reference(sa, sb, &level).to_f64();
            let frame = Frame::for_points([sa, sb]);
            let got = LevelApprox::new(&level, frame).and_then(|c| certified_crossing(sa, sb, &c));
            if let Some(r) = got {
                prop_assert_eq!(r.map(f64::to_bits), nearest.map(f64::to_bits));
            }
            let normal = nearest.iter().all(|v| *v == 0.0 || v.abs() > f64::MIN_POSITIVE);
            if decided.is_some() && normal {
                prop_assert!(got.is_some(), "undecided at 2^{}: {:?} {:?}", k, sa, sb);
            }
        }
    }

    /// Whether `v` lies within `2^-60` of `f`'s rounding boundaries
    /// relatively (where the double-double bound may not decide).
    fn v_near(v: &Rat, f: f64) -> bool {
        let e = rat_from_f64(f);
        let half_up = (rat_from_f64(f.next_up()) - &e) / Rat::from_integer(2.into());
        let half_down = (&e - rat_from_f64(f.next_down())) / Rat::from_integer(2.into());
        let off = v - &e;
        let tol = rat_from_f64(f.abs() * 2f64.powi(-60));
        (&off - &half_up).abs() <= tol || (&off + &half_down).abs() <= tol
    }

    /// An edge among the subnormals (decimal, as an OBJ file holds them) at
    /// a decimal level: the crossing's nearest doubles lie on the
    /// subnormal grid, decided there in the frame of the edge.
    #[test]
    fn subnormal_crossings_are_decided_on_the_subnormal_grid() {
        let a = [7.2e-311, -3.1e-312, -2.5e-311];
        let b = [-1.9e-311, 4.4e-311, 6.1e-311];
        for level in ["1e-312", "-2.4e-311", "3.33e-311"] {
            let level = Level::new(crate::exact::parse_rational(level).unwrap());
            let frame = Frame::for_points([a, b]);
            assert!(frame.shift() > 1000);
            let c = LevelApprox::new(&level, frame).unwrap();
            let got = certified_crossing(a, b, &c).expect("decided");
            let nearest = Point2::on_edge_reference(a, b, &level).to_f64();
            assert_eq!(got.map(f64::to_bits), nearest.map(f64::to_bits));
            assert!(got.iter().all(|v| v.abs() < f64::MIN_POSITIVE));
        }
    }

    #[test]
    fn level_approximation_brackets_the_level() {
        let level = Level::new(crate::exact::parse_rational("0.1").unwrap());
        let c = LevelApprox::new(&level, Frame::IDENTITY).unwrap();
        assert_eq!(c.hi, 0.1);
        let rest = level.value() - rat_from_f64(c.hi) - rat_from_f64(c.lo);
        assert!(rest.abs() <= rat_from_f64(c.err));
        // Out of range: refused, so the exact path decides; in the frame
        // of a mesh of that size, accepted.
        let far = Level::new(rat_from_f64(1e300));
        assert!(LevelApprox::new(&far, Frame::IDENTITY).is_none());
        assert!(LevelApprox::new(&far, Frame::for_magnitude(1e300)).is_some());
    }

    #[test]
    fn paths_are_counted() {
        reset_path_counts();
        let level = Arc::new(Level::new(crate::exact::parse_rational("0.3").unwrap()));
        {
            let points = Crossings::new(None, None, &level, Frame::IDENTITY);
            // Spans 80 bits: not on the edge's i128 grid.
            let a = [40.0, 1e-15, 0.0];
            let b = [39.0, 0.5, 1.0];
            let p = points.crossing(VertexId(0), VertexId(1), a, b);
            assert_eq!(
                p.exact().into_owned(),
                Point2::on_edge_reference(a, b, &level)
            );
            let q = points.crossing(VertexId(0), VertexId(1), [0.0, 0.0, 0.0], [3.0, 6.0, 1.0]);
            assert_eq!(q.to_f64(), [0.9, 1.8]);
        }
        let counts = path_counts();
        assert!(counts[NumberPath::Certified as usize] >= 1);
        assert!(counts[NumberPath::Edge as usize] >= 1);
    }
}
