//! Input: the crossings of a one-sided limit (SPEC section 6): an edge
//! `(a, b)` crossed at the level `c + s epsilon` (`s = -1` for L-, `+1` for
//! L+). Output: the crossing as a point that moves with the infinitesimal
//! `epsilon > 0`, and exact predicates on such points.
//!
//! The crossing of `(a, b)` at height `c + s epsilon` is
//! `p(epsilon) = p0 + epsilon d` with `p0` its limit (the crossing at `c`,
//! or the end of the edge that lies on the plane) and
//! `d = s (b - a) / (h(b) - h(a))` (x and y only), exactly. Every predicate
//! of such points is a polynomial in `epsilon`; its sign for every small
//! enough `epsilon > 0` is the sign of its first non-zero coefficient
//! (simulation of simplicity, with the true perturbation rather than an
//! invented one). So these predicates describe the contour at every
//! regular level close enough to `c` on that side, where loops are disjoint
//! simple polygons, even where their limits touch or run along each other.
//!
//! The constant term is decided by the filtered predicates of
//! [`FilteredPoint`]; the other terms are needed only where the limits
//! tie. Comparing two velocities is an order of exact products of the
//! edges' differences, or the sign of one `orient3d` of their ends
//! (exact, adaptive; `cmp_velocity_of` derives it). A loop's area terms
//! are summed on certified enclosures first (`area_terms_filtered`). An
//! orientation's other terms are signs of `orient3d` of the mesh's own
//! doubles where the tied points move along edges from one vertex on the
//! plane (a loop collapsing to an isolated extremum, or passing through a
//! saddle), as `EpsPoint::orient_at_one_vertex` derives; else certified
//! enclosures (`EpsPoint::orient_enclosed`); exact rationals last. Every
//! filter works in the limits' frame (see `Frame`): signs do not change
//! under one power of two.

use super::area::signed_area;
use super::crossing::{two_prod, two_sum};
use super::filter::{
    cmp_x, cmp_y, orient2d_filtered, signed_area_filtered, FilteredPoint, Interval,
};
use super::frame::Frame;
use super::planar::Planar;
use super::point::{LoopPoint, Point2};
use super::predicates::orient3d;
use super::rational::{rat_from_f64, Rat};
use super::scale::{leading_exponent, times_pow2};
use super::Sign;
use num_traits::Zero;
use std::cell::OnceCell;
use std::cmp::Ordering;

/// Which side of the level a one-sided limit lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Towards {
    /// `c - epsilon` (L-).
    Below,
    /// `c + epsilon` (L+).
    Above,
}

impl Towards {
    /// `s`: the sign of the side.
    fn sign(self) -> Sign {
        match self {
            Towards::Below => Sign::Negative,
            Towards::Above => Sign::Positive,
        }
    }
}

/// How a point moves with `epsilon`: along an edge, crossed at
/// `c +/- epsilon`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// The edge's ends (exact doubles, in the mesh's stored units).
    pub a: [f64; 3],
    /// The other end; `h(b) != h(a)`.
    pub b: [f64; 3],
    /// The side of the level.
    pub towards: Towards,
}

impl Motion {
    /// The end of this edge other than `v`, if `v` is one of its ends.
    fn other_end(&self, v: [f64; 3]) -> Option<[f64; 3]> {
        if self.a == v {
            Some(self.b)
        } else if self.b == v {
            Some(self.a)
        } else {
            None
        }
    }

    /// An enclosure of `d` (see [`Motion::velocity`]).
    fn velocity_enclosure(&self) -> [Interval; 2] {
        let diff = |k: usize| Interval::at(self.b[k]).sub(Interval::at(self.a[k]));
        let dz = match self.towards {
            Towards::Above => diff(2),
            Towards::Below => diff(2).neg(),
        };
        [diff(0).div(dz), diff(1).div(dz)]
    }

    /// `d = s (b - a) / (h(b) - h(a))` in x and y, exactly.
    fn velocity(&self) -> Point2 {
        let r = |k: usize| rat_from_f64(self.b[k]) - rat_from_f64(self.a[k]);
        let dz = r(2);
        let dz = match self.towards {
            Towards::Above => dz,
            Towards::Below => -dz,
        };
        Point2 {
            x: r(0) / &dz,
            y: r(1) / &dz,
        }
    }
}

/// A point `p0 + epsilon d` of a one-sided limit: its limit `p0` (exact,
/// filtered) and its velocity `d` (exact, computed on first use).
#[derive(Clone, Debug)]
pub struct EpsPoint<'a> {
    base: FilteredPoint<'a>,
    motion: Motion,
    /// Boxed: most points never need it, and the point stays small.
    velocity: OnceCell<Box<Point2>>,
}

impl<'a> EpsPoint<'a> {
    /// The crossing whose limit is `base` (enclosed here) and which moves
    /// as `motion` says.
    pub fn new(base: &'a LoopPoint, motion: Motion) -> Self {
        Self::with_base(FilteredPoint::new(base), motion)
    }

    /// As [`EpsPoint::new`], with the limit already filtered and enclosed
    /// (shared by the crossings of one run).
    pub fn with_base(base: FilteredPoint<'a>, motion: Motion) -> Self {
        EpsPoint {
            base,
            motion,
            velocity: OnceCell::new(),
        }
    }

    /// The limit point, filtered.
    pub fn base(&self) -> &FilteredPoint<'a> {
        &self.base
    }

    /// The exact velocity `d`.
    pub fn velocity(&self) -> &Point2 {
        self.velocity
            .get_or_init(|| Box::new(self.motion.velocity()))
    }
}

fn cross(ax: &Rat, ay: &Rat, bx: &Rat, by: &Rat) -> Rat {
    ax * by - ay * bx
}

/// Points whose edges all have an end at one point `v` (the vertex on the
/// plane that a collapsed loop shrinks to, or that a run of a loop passes
/// through): `v`, and each edge's other end `w`.
///
/// With `E = w - v` and `delta = h(w) - h(v)` (never zero), the velocity
/// of a point is `s E_xy / delta` whichever end the motion names first, so
/// products of velocities are those of the rows `(E_x, E_y, delta)` over
/// the product of the `delta`s: signs of determinants of `f64` points,
/// which [`orient3d`] and [`orient2d_axes`](crate::exact::predicates::orient2d_axes) decide exactly (no rational).
fn at_one_vertex<const N: usize>(ms: [&Motion; N]) -> Option<([f64; 3], [[f64; 3]; N])> {
    let first = ms[0];
    [first.a, first.b].into_iter().find_map(|v| {
        let mut ends = [[0.0; 3]; N];
        for (end, m) in ends.iter_mut().zip(ms) {
            *end = m.other_end(v)?;
        }
        Some((v, ends))
    })
}

/// `p` multiplied by the frame's `2^s`, when every coordinate is exactly
/// that (see [`Frame::place_normal`]); `p` itself in the identity frame.
fn placed(frame: Frame, p: [f64; 3]) -> Option<[f64; 3]> {
    if frame.is_identity() {
        return Some(p);
    }
    let [x, y, z] = p.map(|v| frame.place_normal(v));
    Some([x?, y?, z?])
}

/// The sign of `h(w) - h(v)`, never zero for an edge a point moves along.
fn rise(v: [f64; 3], w: [f64; 3]) -> Sign {
    Sign::of_cmp(w[2].partial_cmp(&v[2]))
}

/// `d_p - d_q` in coordinate `k` (0: x, 1: y) for points moving along
/// edges `E = b - a` and `F = d - c` (any four doubles), on sides of signs
/// `s` and `t`: `d_p = s E_k / E_z`, `d_q = t F_k / F_z`. With `u = s t`
/// and `G = (F_k, u F_z)` (the second edge's heights negated when the
/// sides differ), `d_p - d_q = s (E_k G_z - G_k E_z) / (E_z G_z)`. The
/// numerator is `-det(Q - P, R - P, S - P)` for the points
/// `P = (a_k, a_z, 0)`, `Q = (b_k, b_z, 0)`, `R = (c_k, u c_z, 1)`,
/// `S = (d_k, u d_z, 1)` (expand along the last column): one
/// [`orient3d`] of the mesh's own doubles, exact, no rational.
///
/// First, where the four differences are doubles (as on a grid): see
/// [`cmp_velocity_in_doubles`].
fn cmp_velocity_of(p: &Motion, q: &Motion, k: usize) -> Ordering {
    if let Some(o) = cmp_velocity_in_doubles(p, q, k) {
        return o;
    }
    // Negating a double is exact.
    let u = if p.towards == q.towards { 1.0 } else { -1.0 };
    // Any `lambda > 0` in place of the last column's 1 multiplies the
    // determinant by `lambda`: a power of two of the ends' magnitude keeps
    // the twelve coordinates within `robust`'s window at the ends of the
    // range (else they span over 600 bits and the integers decide).
    let top = [p.a, p.b, q.a, q.b]
        .iter()
        .flat_map(|v| [v[k], v[2]])
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let lambda = leading_exponent(top).map_or(1.0, |e| times_pow2(1.0, e));
    let first = |v: [f64; 3]| [v[k], v[2], 0.0];
    let second = |v: [f64; 3]| [v[k], u * v[2], lambda];
    let det = orient3d(first(p.a), first(p.b), second(q.a), second(q.b));
    let rise_q = Sign::of_cmp((u * q.b[2]).partial_cmp(&(u * q.a[2])));
    (det.flip() * rise(p.a, p.b) * rise_q * p.towards.sign()).ordering()
}

/// `b - a` when it is a double: the error of the rounded difference is
/// exactly zero (Knuth's TwoSum).
fn exact_difference(a: f64, b: f64) -> Option<f64> {
    let (d, e) = two_sum(b, -a);
    (e == 0.0).then_some(d)
}

/// Factors within [`cmp_double_products`]' range: as they are, else all
/// multiplied by the power of two that brings the largest into `[1, 2)`,
/// when every result is zero or at least `2^-480` (so each is exactly its
/// product: only normal values are scaled down, and scaling up cannot
/// round). Both products of two factors are then multiplied by one
/// positive square, and keep their order.
fn in_product_range_scaled(xs: [f64; 4]) -> Option<[f64; 4]> {
    if xs.iter().all(|&x| in_product_range(x)) {
        return Some(xs);
    }
    let top = xs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let e = leading_exponent(top)?;
    let ys = xs.map(|x| times_pow2(x, -e));
    ys.iter().all(|&y| in_product_range(y)).then_some(ys)
}

/// `2^-480`, `2^480`: factors of magnitude between these (or zero) have
/// products that neither overflow nor lose their rounding error to
/// underflow (exponents summing to at least `-960 > -969`).
const FACTOR_LO: f64 = f64::from_bits((1023 - 480) << 52);
const FACTOR_HI: f64 = f64::from_bits((1023 + 480) << 52);

fn in_product_range(x: f64) -> bool {
    x == 0.0 || (FACTOR_LO..=FACTOR_HI).contains(&x.abs())
}

/// The exact order of `a b` and `c d` for factors in range: rounding is
/// monotone, so unequal rounded products are ordered as the exact ones;
/// equal ones are ordered by their exact errors ([`two_prod`]).
fn cmp_double_products(a: f64, b: f64, c: f64, d: f64) -> Ordering {
    let (p, q) = (a * b, c * d);
    if p != q {
        return if p < q {
            Ordering::Less
        } else {
            Ordering::Greater
        };
    }
    // Ties only: the errors cost an `fma` each (a library call without it).
    let ((_, e), (_, f)) = (two_prod(a, b), two_prod(c, d));
    e.partial_cmp(&f).unwrap_or(Ordering::Equal)
}

/// [`cmp_velocity_of`] where `E_k`, `E_z`, `F_k`, `F_z` are doubles
/// (checked exactly; `None` otherwise, or where they span too many bits
/// to share one scaling): the sign of `E_k G_z - G_k E_z` is the order of
/// two exact products.
fn cmp_velocity_in_doubles(p: &Motion, q: &Motion, k: usize) -> Option<Ordering> {
    let [ek, ez, fk, fz] = in_product_range_scaled([
        exact_difference(p.a[k], p.b[k])?,
        exact_difference(p.a[2], p.b[2])?,
        exact_difference(q.a[k], q.b[k])?,
        exact_difference(q.a[2], q.b[2])?,
    ])?;
    let gz = if p.towards == q.towards { fz } else { -fz };
    let numerator = Sign::of_ordering(cmp_double_products(ek, gz, fk, ez));
    let signs = Sign::of_cmp(ez.partial_cmp(&0.0)) * Sign::of_cmp(gz.partial_cmp(&0.0));
    Some((numerator * signs * p.towards.sign()).ordering())
}

impl EpsPoint<'_> {
    /// `d_self - d_other` in coordinate `k` (0: x, 1: y), exactly.
    fn cmp_velocity(&self, other: &Self, k: usize) -> Ordering {
        cmp_velocity_of(&self.motion, &other.motion, k)
    }

    /// [`EpsPoint::cmp_velocity`] in exact rationals (the tests' reference).
    #[cfg(test)]
    fn cmp_velocity_in_rationals(&self, other: &Self, k: usize) -> Ordering {
        let (a, b) = (self.velocity(), other.velocity());
        if k == 0 {
            a.x.cmp(&b.x)
        } else {
            a.y.cmp(&b.y)
        }
    }

    /// [`Planar::orient`] where `k0 = 0` because two or three of the
    /// limits are one point, without rationals where the points with one
    /// limit move along edges from one point `v` (as around a vertex on
    /// the plane) and the answer is a determinant of doubles; else `None`.
    ///
    /// Three with one limit: `B = C = 0`, so `k1 = 0`, and `k2 = det(E_a,
    /// E_b, E_c) / (delta_a delta_b delta_c)` (the determinant of the rows
    /// `(E_x, E_y, delta)` expanded along its last column is `sum delta_a
    /// (E_b x E_c)`; `s^2 = 1`). Two (turned to come first: the
    /// orientation and each of its coefficients are unchanged by a cyclic
    /// turn) whose limit is `v` itself, the third's limit `r` a double:
    /// `B = 0`, so `k1 = dB x C = s det(E_p, E_q, (C, 0)) / (delta_p
    /// delta_q)` with `C = r - v`, which is `orient3d(v, w_p, w_q, (r,
    /// h(v)))`; when it is zero, `k2` is left to the rationals. In a
    /// scaled frame, `v`, `w_p` and `w_q` are placed in it (exactly, else
    /// `None`) to meet the limits' doubles there.
    fn orient_at_one_vertex(a: &Self, b: &Self, c: &Self) -> Option<Sign> {
        let (ab, bc) = (a.same_limit(b), b.same_limit(c));
        if ab && bc {
            let (v, [wa, wb, wc]) = at_one_vertex([&a.motion, &b.motion, &c.motion])?;
            return Some(orient3d(v, wa, wb, wc) * rise(v, wa) * rise(v, wb) * rise(v, wc));
        }
        let (p, q, r) = if ab {
            (a, b, c)
        } else if bc {
            (b, c, a)
        } else if c.same_limit(a) {
            (c, a, b)
        } else {
            return None;
        };
        if p.motion.towards != q.motion.towards {
            return None;
        }
        // In the limits' frame: every determinant's sign and every rise
        // is unchanged by the exact scaling.
        let frame = p.base.frame();
        if r.base.frame() != frame {
            return None;
        }
        let (v, [wp, wq]) = at_one_vertex([&p.motion, &q.motion])?;
        let (v, wp, wq) = (placed(frame, v)?, placed(frame, wp)?, placed(frame, wq)?);
        if p.base.as_double()? != [v[0], v[1]] {
            return None;
        }
        let [x, y] = r.base.as_double()?;
        let k1 =
            orient3d(v, wp, wq, [x, y, v[2]]) * rise(v, wp) * rise(v, wq) * p.motion.towards.sign();
        (k1 != Sign::Zero).then_some(k1)
    }

    /// The sign of `k1`, else of `k2`, of [`Planar::orient`] (for
    /// `k0 = 0`) on certified enclosures, when they decide it: `B` and `C`
    /// from the limits' enclosures (exactly zero where the limits are one
    /// point), `dB` and `dC` from the velocities' (exactly zero where two
    /// points move along one edge to one side), every operation widened
    /// outward (see [`Interval`]). `k1` exactly zero (each of its products
    /// has a factor exactly zero) goes on to `k2`; a point compared with
    /// itself is `Zero`. `None` when an enclosure holds zero but is not
    /// exactly zero, or the limits are in different frames.
    ///
    /// In a frame scaled by `2^s`, `B` and `C` are `2^s` times their
    /// values in stored units and the velocities are the same (ratios of
    /// differences): `k1` is multiplied by `2^s`, `k2` not at all, and
    /// neither sign changes.
    fn orient_enclosed(a: &Self, b: &Self, c: &Self) -> Option<Sign> {
        let frame = a.base.frame();
        if b.base.frame() != frame || c.base.frame() != frame {
            return None;
        }
        let limit_from_a = |p: &Self| {
            (!p.same_limit(a)).then(|| {
                let ([px, py], [ax, ay]) = (p.base.enclosure(), a.base.enclosure());
                [px.sub(ax), py.sub(ay)]
            })
        };
        let velocity_from_a = |p: &Self| {
            (p.motion != a.motion).then(|| {
                let ([px, py], [ax, ay]) =
                    (p.motion.velocity_enclosure(), a.motion.velocity_enclosure());
                [px.sub(ax), py.sub(ay)]
            })
        };
        let (bb, cc) = (limit_from_a(b), limit_from_a(c));
        let (db, dc) = (velocity_from_a(b), velocity_from_a(c));
        match add_unless_zero(cross_unless_zero(bb, dc), cross_unless_zero(db, cc)) {
            Some(k1) => k1.sign(),
            None => cross_unless_zero(db, dc).map_or(Some(Sign::Zero), Interval::sign),
        }
    }

    /// The sign of `k1`, else of `k2`, of [`Planar::orient`], in exact
    /// rationals (the limits' and the velocities'), for `k0 = 0`.
    fn orient_in_rationals(a: &Self, b: &Self, c: &Self) -> Sign {
        let (pa, pb, pc) = (
            a.base.exact().exact(),
            b.base.exact().exact(),
            c.base.exact().exact(),
        );
        let (va, vb, vc) = (a.velocity(), b.velocity(), c.velocity());
        let (bx, by) = (&pb.x - &pa.x, &pb.y - &pa.y);
        let (cx, cy) = (&pc.x - &pa.x, &pc.y - &pa.y);
        let (dbx, dby) = (&vb.x - &va.x, &vb.y - &va.y);
        let (dcx, dcy) = (&vc.x - &va.x, &vc.y - &va.y);
        let k1 = cross(&bx, &by, &dcx, &dcy) + cross(&dbx, &dby, &cx, &cy);
        if !k1.is_zero() {
            return Sign::of_rat(&k1);
        }
        Sign::of_rat(&cross(&dbx, &dby, &dcx, &dcy))
    }

    /// Whether the limits of `self` and `other` are one point.
    fn same_limit(&self, other: &Self) -> bool {
        std::ptr::eq(self.base.exact(), other.base.exact())
            || (cmp_x(&self.base, &other.base).is_eq() && cmp_y(&self.base, &other.base).is_eq())
    }
}

impl Planar for EpsPoint<'_> {
    fn cmp_y(&self, other: &Self) -> Ordering {
        cmp_y(&self.base, &other.base).then_with(|| self.cmp_velocity(other, 1))
    }

    fn cmp_x(&self, other: &Self) -> Ordering {
        cmp_x(&self.base, &other.base).then_with(|| self.cmp_velocity(other, 0))
    }

    /// `(b - a) x (c - a)` is `k0 + k1 epsilon + k2 epsilon^2` with
    /// `k0 = B x C`, `k1 = B x dC + dB x C`, `k2 = dB x dC` (`B = b0 - a0`,
    /// `dB = db - da`, likewise for `c`): the sign of the first non-zero.
    /// `epsilon` is symbolic (an infinitesimal), never a number: no
    /// tolerance, only the exact signs of `k0`, `k1`, `k2`.
    fn orient(a: &Self, b: &Self, c: &Self) -> Sign {
        let k0 = orient2d_filtered(&a.base, &b.base, &c.base);
        if k0 != Sign::Zero {
            return k0;
        }
        EpsPoint::orient_at_one_vertex(a, b, c)
            .or_else(|| EpsPoint::orient_enclosed(a, b, c))
            .unwrap_or_else(|| EpsPoint::orient_in_rationals(a, b, c))
    }

    fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        self.base.bounds()
    }

    fn rounded(&self) -> [f64; 2] {
        self.base.rounded()
    }
}

/// The exact orientation of a closed polygon of moving points: the sign of
/// the first non-zero coefficient of its signed area
/// `a0 + a1 epsilon + a2 epsilon^2`. `a0` is the limit polygon's area
/// (`limit`: filtered, exact when the filter cannot tell); `a1` and `a2`
/// are computed only when `a0 = 0`:
/// `2 a1 = sum p_i x d_{i+1} + d_i x p_{i+1}`, `2 a2 = sum d_i x d_{i+1}`.
/// Where every `p_i` is one point `p` (a loop collapsing to a point),
/// `2 a1 = p x D + D x p = 0` with `D = sum d_i`, and only `a2` is summed.
/// Each sum on certified enclosures first (`area_terms_filtered`), in
/// exact rationals where they cannot tell.
pub fn orientation(points: &[EpsPoint<'_>], limit: &[LoopPoint]) -> Sign {
    let bases: Vec<FilteredPoint<'_>> = points.iter().map(|p| p.base.clone()).collect();
    if let Some(s) = signed_area_filtered(&bases)
        .sign
        .filter(|&s| s != Sign::Zero)
    {
        return s;
    }
    let a0 = signed_area(limit);
    if !a0.is_zero() {
        return Sign::of_rat(&a0);
    }
    let n = points.len();
    let one_limit = points.iter().all(|p| p.same_limit(&points[0]));
    if let Some(s) = area_terms_filtered(points, one_limit) {
        return s;
    }
    let (mut a1, mut a2) = (Rat::zero(), Rat::zero());
    for i in 0..n {
        let (p, q) = (&points[i], &points[(i + 1) % n]);
        let (dp, dq) = (p.velocity(), q.velocity());
        if !one_limit {
            let (p0, q0) = (p.base.exact().exact(), q.base.exact().exact());
            a1 += cross(&p0.x, &p0.y, &dq.x, &dq.y) + cross(&dp.x, &dp.y, &q0.x, &q0.y);
        }
        a2 += cross(&dp.x, &dp.y, &dq.x, &dq.y);
    }
    if a1.is_zero() {
        Sign::of_rat(&a2)
    } else {
        Sign::of_rat(&a1)
    }
}

/// `x` cross `y` of enclosures, `None` standing for exactly zero.
fn cross_unless_zero(x: Option<[Interval; 2]>, y: Option<[Interval; 2]>) -> Option<Interval> {
    Some(cross_enclosed(x?, y?))
}

/// The sum of enclosures, `None` standing for exactly zero.
fn add_unless_zero(x: Option<Interval>, y: Option<Interval>) -> Option<Interval> {
    match (x, y) {
        (Some(x), Some(y)) => Some(x.add(y)),
        (x, y) => x.or(y),
    }
}

/// `x` cross `y` of enclosures.
fn cross_enclosed([ax, ay]: [Interval; 2], [bx, by]: [Interval; 2]) -> Interval {
    ax.mul(by).sub(ay.mul(bx))
}

/// The sign of `a1` of [`orientation`] (of `a2` when `one_limit`, where
/// `a1 = 0`), when an enclosure of the sum decides it: the limits'
/// enclosures (see [`FilteredPoint`]) and the velocities' (interval
/// quotients of the edges' differences), every operation widened outward
/// (see [`Interval`]). `None` when the enclosure holds zero (then the
/// rationals decide, and go on to `a2` where `a1` is zero) or the limits
/// are in different frames.
///
/// The limits' enclosures are in their frame (`2^s` times stored units),
/// the velocities in stored units: a velocity is a ratio of differences,
/// the same in every frame, so each term of `a1` is `2^s` times its value
/// in stored units and the sum keeps its sign. `a2` has no limit in it.
/// Every interval operation is widened outward by one ulp, which encloses
/// the correctly rounded result anywhere in the double range (subnormal,
/// overflowing: then infinite, and [`Interval::sign`] says nothing).
fn area_terms_filtered(points: &[EpsPoint<'_>], one_limit: bool) -> Option<Sign> {
    let frame = points.first()?.base.frame();
    if points.iter().any(|p| p.base.frame() != frame) {
        return None;
    }
    let d: Vec<[Interval; 2]> = points
        .iter()
        .map(|p| p.motion.velocity_enclosure())
        .collect();
    let n = points.len();
    let mut sum = Interval::at(0.0);
    for i in 0..n {
        let j = (i + 1) % n;
        sum = if one_limit {
            sum.add(cross_enclosed(d[i], d[j]))
        } else {
            let (p, q) = (points[i].base.enclosure(), points[j].base.enclosure());
            sum.add(cross_enclosed(p, d[j]))
                .add(cross_enclosed(d[i], q))
        };
    }
    sum.sign()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::level::Level;
    use proptest::prelude::*;

    /// A double of either sign with a mantissa of `m` and exponent `e`
    /// (nonzero: a rise).
    fn double(m: i64, e: i32) -> f64 {
        crate::exact::scale::times_pow2(m as f64, e)
    }

    /// A point: three doubles drawn across the range (whose limits are
    /// rarely doubles in one frame), or on a small grid (where they are).
    fn point() -> impl Strategy<Value = [f64; 3]> {
        prop_oneof![
            prop::array::uniform3((-(1i64 << 52)..(1i64 << 52), -60i32..60)),
            prop::array::uniform3((-(1i64 << 20)..(1i64 << 20), -3i32..3)),
        ]
        .prop_map(|c| c.map(|(m, e)| double(m, e)))
    }

    /// A height other than `z`.
    fn away(z: f64) -> f64 {
        if z == 0.0 {
            1.0
        } else {
            2.0 * z
        }
    }

    /// Points with limit `v` moving along edges from `vp` to `ws`.
    fn around<'a>(
        v: &'a LoopPoint,
        vp: [f64; 3],
        ws: &[[f64; 3]],
        towards: Towards,
    ) -> Vec<EpsPoint<'a>> {
        ws.iter()
            .enumerate()
            .map(|(i, &w)| {
                // Either end may come first.
                let (a, b) = if i % 2 == 0 { (vp, w) } else { (w, vp) };
                EpsPoint::new(v, Motion { a, b, towards })
            })
            .collect()
    }

    /// `2 a1` and `2 a2` of [`orientation`], every term summed.
    fn area_terms(points: &[EpsPoint<'_>]) -> (Rat, Rat) {
        let n = points.len();
        let (mut a1, mut a2) = (Rat::zero(), Rat::zero());
        for i in 0..n {
            let (p, q) = (&points[i], &points[(i + 1) % n]);
            let (p0, q0) = (p.base.exact().exact(), q.base.exact().exact());
            let (dp, dq) = (p.velocity(), q.velocity());
            a1 += cross(&p0.x, &p0.y, &dq.x, &dq.y) + cross(&dp.x, &dp.y, &q0.x, &q0.y);
            a2 += cross(&dp.x, &dp.y, &dq.x, &dq.y);
        }
        (a1, a2)
    }

    /// L- of a ridge on the plane (`z = 1` along `y = 0`, the roof falling
    /// to `y = -1` and `y = 1` at `z = 0`): a loop with zero limit area,
    /// its bottom run moving to `-y`, its top run back at `+y`, so
    /// counter-clockwise. The enclosures decide it, without rationals: as
    /// it is, and scaled to the ends of the double range (by `2^-1060`,
    /// where the rises are subnormal, and by `2^1000`) with its limits in
    /// the frame a mesh there takes.
    #[test]
    fn a_loop_collapsing_onto_a_ridge_is_decided_by_enclosures() {
        for e in [0, -1060, 1000] {
            let at = |p: [f64; 3]| p.map(|v| double(1, e) * v);
            let xs = [0.0, 5.0, 10.0];
            let on_ridge: Vec<LoopPoint> = xs
                .iter()
                .map(|&x| LoopPoint::of_vertex(at([x, 0.0, 1.0])))
                .collect();
            let frame = Frame::for_points(xs.iter().map(|&x| at([x, 1.0, 1.0])));
            assert_eq!(frame.is_identity(), e == 0);
            let order = [
                (0, -1.0),
                (1, -1.0),
                (2, -1.0),
                (2, 1.0),
                (1, 1.0),
                (0, 1.0),
            ];
            let ps: Vec<EpsPoint<'_>> = order
                .iter()
                .map(|&(i, side)| {
                    let motion = Motion {
                        a: at([xs[i], 0.0, 1.0]),
                        b: at([xs[i], side, 0.0]),
                        towards: Towards::Below,
                    };
                    in_frame(&on_ridge[i], frame, motion)
                })
                .collect();
            let limit: Vec<LoopPoint> = order.iter().map(|&(i, _)| on_ridge[i].clone()).collect();
            assert_eq!(
                area_terms_filtered(&ps, false),
                Some(Sign::Positive),
                "2^{e}"
            );
            assert_eq!(orientation(&ps, &limit), Sign::Positive, "2^{e}");
            let (a1, _) = area_terms(&ps);
            assert_eq!(Sign::of_rat(&a1), Sign::Positive, "2^{e}");
            let reversed: Vec<EpsPoint<'_>> = ps.iter().rev().cloned().collect();
            assert_eq!(
                area_terms_filtered(&reversed, false),
                Some(Sign::Negative),
                "2^{e}"
            );
        }
    }

    /// A point with limit `l` filtered in `frame`.
    fn in_frame(l: &LoopPoint, frame: Frame, motion: Motion) -> EpsPoint<'_> {
        EpsPoint::with_base(FilteredPoint::in_frame(l, frame), motion)
    }

    /// Points around a vertex `v` on the plane and a crossing elsewhere,
    /// all multiplied by `2^shift`, their limits in the frame such a mesh
    /// takes: the two edges from `v` to `ws`, the crossing of `(a, b)`
    /// (turned to cross the plane), which is not a double.
    fn vertex_and_crossing(
        v: [f64; 3],
        ws: [[f64; 3]; 2],
        (a, b): ([f64; 3], [f64; 3]),
        shift: i32,
    ) -> Option<(Frame, [[f64; 3]; 5])> {
        let z = v[2];
        let mut ws = ws;
        for w in &mut ws {
            if w[2] == z {
                w[2] = away(z);
            }
        }
        let (mut a, mut b) = (a, b);
        a[2] = z - a[2].abs().max(1.0);
        b[2] = z + b[2].abs().max(1.0);
        let all =
            [v, ws[0], ws[1], a, b].map(|p| p.map(|x| crate::exact::scale::times_pow2(x, shift)));
        let [v, w0, w1, a, b] = all;
        let fine = all.iter().flatten().all(|x| x.is_finite())
            && [w0, w1].iter().all(|w| w[2] != v[2])
            && a[2] < v[2]
            && v[2] < b[2];
        fine.then(|| (Frame::for_points(all), all))
    }

    /// The hand case of `orient_enclosed`: two points leaving the vertex
    /// `(1, 2, 0)` along `(1, 0, 1)` and `(0, 1, 1)` (velocities `(1, 0)`
    /// and `(0, 1)`) and the crossing `(6.5, 2.2)` of the edge from
    /// `(6, 2.3, -1)` to `(7, 2.1, 1)`, not a double: `k0 = 0`, `k1 = dB x
    /// C = (-1, 1) x (5.5, 0.2) = -5.7`. Decided by the enclosures, at
    /// scale 1 and at both ends of the range.
    #[test]
    fn two_points_at_a_vertex_and_a_crossing_are_decided_by_enclosures() {
        for shift in [0, -1000, 1000] {
            let (frame, [v, w0, w1, a, b]) = vertex_and_crossing(
                [1.0, 2.0, 0.0],
                [[2.0, 2.0, 1.0], [1.0, 3.0, 1.0]],
                ([6.0, 2.3, -1.0], [7.0, 2.1, 1.0]),
                shift,
            )
            .unwrap();
            let level = Level::new(rat_from_f64(v[2]));
            let (at_v, cross) = (LoopPoint::of_vertex(v), LoopPoint::on_edge(a, b, &level));
            let point = |l, a, b| {
                in_frame(
                    l,
                    frame,
                    Motion {
                        a,
                        b,
                        towards: Towards::Above,
                    },
                )
            };
            let (p, q, r) = (
                point(&at_v, v, w0),
                point(&at_v, v, w1),
                point(&cross, a, b),
            );
            assert_eq!(r.base.as_double(), None, "2^{shift}");
            assert_eq!(EpsPoint::orient_at_one_vertex(&p, &q, &r), None);
            assert_eq!(
                EpsPoint::orient_enclosed(&p, &q, &r),
                Some(Sign::Negative),
                "2^{shift}"
            );
            assert_eq!(EpsPoint::orient_in_rationals(&p, &q, &r), Sign::Negative);
            // A point with itself: zero, known without the rationals.
            let r2 = r.clone();
            assert_eq!(EpsPoint::orient_enclosed(&r, &r2, &p), Some(Sign::Zero));
            // The third a vertex on the plane at (6, 2.25), a double in
            // every frame: one orient3d, `k1 = (-1, 1) x (5, 0.25)`.
            let s = |x: f64| crate::exact::scale::times_pow2(x, shift);
            let u = [s(6.0), s(2.25), v[2]];
            let at_u = LoopPoint::of_vertex(u);
            let t = point(&at_u, u, [u[0], u[1], s(1.0)]);
            assert_eq!(
                EpsPoint::orient_at_one_vertex(&p, &q, &t),
                Some(Sign::Negative),
                "2^{shift}"
            );
            assert_eq!(EpsPoint::orient_in_rationals(&p, &q, &t), Sign::Negative);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Where `k0` is zero (two limits one point: two edges from a
        /// vertex on the plane, or one crossing met twice), the enclosures'
        /// answer, and the orientation, equal the rationals', on
        /// coordinates across the range, in frames at either end of it.
        #[test]
        fn enclosed_orientations_equal_the_rationals(
            v in point(), ws in prop::array::uniform2(point()), e in (point(), point()),
            shift in prop_oneof![Just(0i32), -1000i32..-900, 880i32..900],
            ties in 0usize..3, above in any::<bool>(),
        ) {
            let mut ws = ws;
            match ties {
                // The second edge along the first, or sharing a coordinate.
                0 => ws[1] = std::array::from_fn(|i| 2.0 * ws[0][i] - v[i]),
                1 => ws[1][0] = ws[0][0],
                _ => {}
            }
            let Some((frame, [v, w0, w1, a, b])) = vertex_and_crossing(v, ws, e, shift) else {
                return Err(TestCaseError::reject("out of range"));
            };
            let towards = if above { Towards::Above } else { Towards::Below };
            let level = Level::new(rat_from_f64(v[2]));
            let (at_v, cross) = (LoopPoint::of_vertex(v), LoopPoint::on_edge(a, b, &level));
            let point = |l, a, b| in_frame(l, frame, Motion { a, b, towards });
            let (p, q) = (point(&at_v, v, w0), point(&at_v, w1, v));
            let (r, r2) = (point(&cross, a, b), point(&cross, a, b));
            let exact = |a: &EpsPoint<'_>, b: &EpsPoint<'_>, c: &EpsPoint<'_>| {
                let k0 = orient2d_filtered(&a.base, &b.base, &c.base);
                if k0 != Sign::Zero { k0 } else { EpsPoint::orient_in_rationals(a, b, c) }
            };
            for (x, y, z) in [
                (&p, &q, &r), (&q, &r, &p), (&r, &p, &q),
                (&r, &r2, &p), (&p, &r, &r2), (&r2, &q, &r), (&p, &p, &r),
            ] {
                let want = exact(x, y, z);
                prop_assert_eq!(EpsPoint::orient(x, y, z), want);
                if orient2d_filtered(&x.base, &y.base, &z.base) == Sign::Zero {
                    if let Some(s) = EpsPoint::orient_enclosed(x, y, z) {
                        prop_assert_eq!(s, want);
                    }
                }
            }
        }

        /// At one vertex on the plane, orientations and comparisons of
        /// points moving away from it (three, two and a third with another
        /// limit, in every cyclic turn) equal those computed in rationals,
        /// on coordinates across the range, with ties (`w` sharing a
        /// coordinate with `v`, two points on one edge) made often.
        #[test]
        fn shortcuts_at_a_vertex_equal_the_rationals(
            v in point(),
            ws in prop::collection::vec(point(), 3),
            r in point(),
            ties in prop::collection::vec(0usize..6, 3),
            above in any::<bool>(),
        ) {
            let towards = if above { Towards::Above } else { Towards::Below };
            let mut ws = ws;
            for (w, &t) in ws.iter_mut().zip(&ties) {
                // Share a coordinate with v (x or y: ties in the
                // comparisons), or a direction with another edge.
                match t {
                    0 => w[0] = v[0],
                    1 => w[1] = v[1],
                    _ => {}
                }
                if w[2] == v[2] {
                    w[2] = away(v[2]);
                }
            }
            if ties[0] == 5 {
                ws[1] = ws[0];
            }
            let at_v = LoopPoint::of_vertex(v);
            let elsewhere = LoopPoint::of_vertex([r[0], r[1], v[2]]);
            let ps = around(&at_v, v, &ws, towards);
            let q = EpsPoint::new(&elsewhere, Motion { a: r, b: [r[0], r[1], away(r[2])], towards });
            let (a, b, c) = (&ps[0], &ps[1], &ps[2]);
            let exact = |a: &EpsPoint<'_>, b: &EpsPoint<'_>, c: &EpsPoint<'_>| {
                let k0 = orient2d_filtered(&a.base, &b.base, &c.base);
                if k0 != Sign::Zero { k0 } else { EpsPoint::orient_in_rationals(a, b, c) }
            };
            for (x, y, z) in [(a, b, c), (b, c, a), (c, a, b), (a, b, &q), (b, &q, a), (&q, a, b)] {
                prop_assert_eq!(EpsPoint::orient(x, y, z), exact(x, y, z));
            }
            // Two with one limit that is not their edges' shared end (not
            // in a valid mesh): no shortcut may take `v` for the limit.
            let off = LoopPoint::of_vertex([r[1], r[0], v[2]]);
            let offs = around(&off, v, &ws[..2], towards);
            for (x, y, z) in [(&offs[0], &offs[1], &q), (&q, &offs[0], &offs[1])] {
                prop_assert_eq!(EpsPoint::orient(x, y, z), exact(x, y, z));
            }
            // The loop of the three collapsing to `v`: `a1` is zero, and
            // the orientation is the sign of `a2`.
            let (a1, a2) = area_terms(&ps);
            prop_assert!(a1.is_zero());
            prop_assert_eq!(orientation(&ps, std::slice::from_ref(&at_v)), Sign::of_rat(&a2));
            for k in 0..2 {
                prop_assert_eq!(a.cmp_velocity(b, k), a.cmp_velocity_in_rationals(b, k));
                prop_assert_eq!(b.cmp_velocity(c, k), b.cmp_velocity_in_rationals(c, k));
            }
        }

        /// Where the enclosures of `a1` (or of `a2`, for a loop
        /// collapsing to one vertex) decide a sign, it is the sign of the
        /// exact sum; on loops of crossings (limits on their edges) and of
        /// points around one vertex, either side, across the range.
        #[test]
        fn filtered_area_terms_are_the_exact_signs(
            edges in prop::collection::vec((point(), point()), 3..9),
            v in point(),
            c in point(),
            above in any::<bool>(),
        ) {
            let towards = if above { Towards::Above } else { Towards::Below };
            let level = Level::new(rat_from_f64(c[2]));
            // Each edge turned to cross the level: one end below, one above.
            let crossing: Vec<([f64; 3], [f64; 3])> = edges
                .iter()
                .map(|&(mut a, mut b)| {
                    a[2] = c[2] - a[2].abs().max(1.0);
                    b[2] = c[2] + b[2].abs().max(1.0);
                    (a, b)
                })
                .collect();
            prop_assume!(crossing.iter().all(|(a, b)| a[2] < c[2] && c[2] < b[2]));
            let limits: Vec<LoopPoint> =
                crossing.iter().map(|&(a, b)| LoopPoint::on_edge(a, b, &level)).collect();
            let ps: Vec<EpsPoint<'_>> = limits
                .iter()
                .zip(&crossing)
                .map(|(l, &(a, b))| EpsPoint::new(l, Motion { a, b, towards }))
                .collect();
            let (a1, _) = area_terms(&ps);
            if let Some(s) = area_terms_filtered(&ps, false) {
                prop_assert_eq!(s, Sign::of_rat(&a1));
            }
            let at_v = LoopPoint::of_vertex(v);
            let ws: Vec<[f64; 3]> = crossing.iter().map(|&(_, b)| [b[0], b[1], away(v[2])]).collect();
            let around_v = around(&at_v, v, &ws, towards);
            let (_, a2) = area_terms(&around_v);
            if let Some(s) = area_terms_filtered(&around_v, true) {
                prop_assert_eq!(s, Sign::of_rat(&a2));
            }
        }

        /// As above, with every coordinate and the level scaled by `2^t`
        /// towards either end of the double range (into the subnormals, up
        /// to overflowing products) and the limits in the frame such a
        /// mesh takes: the enclosures' signs are still the exact ones.
        #[test]
        fn filtered_area_terms_are_exact_in_scaled_frames(
            edges in prop::collection::vec((point(), point()), 3..9),
            c in point(),
            t in prop_oneof![-1040i32..-900, 880i32..900],
            above in any::<bool>(),
        ) {
            let towards = if above { Towards::Above } else { Towards::Below };
            let at = |p: [f64; 3]| p.map(|v| crate::exact::scale::times_pow2(v, t));
            let crossing: Vec<([f64; 3], [f64; 3])> = edges
                .iter()
                .map(|&(mut a, mut b)| {
                    a[2] = c[2] - a[2].abs().max(1.0);
                    b[2] = c[2] + b[2].abs().max(1.0);
                    (at(a), at(b))
                })
                .collect();
            let z = at(c)[2];
            // Scaling may round (subnormals) or overflow: the edges must
            // still be finite and cross the level.
            prop_assume!(crossing.iter().flat_map(|(a, b)| a.iter().chain(b)).all(|v| v.is_finite()));
            prop_assume!(crossing.iter().all(|(a, b)| a[2] < z && z < b[2]));
            let level = Level::new(rat_from_f64(z));
            let limits: Vec<LoopPoint> =
                crossing.iter().map(|&(a, b)| LoopPoint::on_edge(a, b, &level)).collect();
            let frame = Frame::for_points(crossing.iter().flat_map(|&(a, b)| [a, b]));
            let ps: Vec<EpsPoint<'_>> = limits
                .iter()
                .zip(&crossing)
                .map(|(l, &(a, b))| in_frame(l, frame, Motion { a, b, towards }))
                .collect();
            let (a1, a2) = area_terms(&ps);
            if let Some(s) = area_terms_filtered(&ps, false) {
                prop_assert_eq!(s, Sign::of_rat(&a1));
            }
            if let Some(s) = area_terms_filtered(&ps, true) {
                prop_assert_eq!(s, Sign::of_rat(&a2));
            }
        }

        /// Products of doubles in range are ordered as the rationals
        /// order them, where they round to one double too (a factor
        /// moved by one unit in the last place, or factors traded by a
        /// power of two).
        #[test]
        fn double_products_compare_exactly(
            [a, b, c, d] in prop::array::uniform4((-(1i64 << 52)..(1i64 << 52), -560i32..520)),
            tie in 0usize..4,
        ) {
            let [a, b, mut c, mut d] = [a, b, c, d].map(|(m, e)| double(m, e));
            match tie {
                0 => (c, d) = (a, b.next_up()),
                1 => (c, d) = (double(1, 3) * a, b / double(1, 3)),
                2 => (c, d) = (b, a),
                _ => {}
            }
            // Out of range (a third of the draws) nothing is claimed.
            if [a, b, c, d].iter().all(|&x| in_product_range(x)) {
                let exact =
                    (rat_from_f64(a) * rat_from_f64(b)).cmp(&(rat_from_f64(c) * rat_from_f64(d)));
                prop_assert_eq!(cmp_double_products(a, b, c, d), exact);
            }
        }

        /// The order of two points' velocities along x and y, for any two
        /// edges (on either side of the level, on coordinates across the
        /// range and on a small grid) equals the rationals', with ties
        /// made often: edges sharing an end, parallel or equal, one edge
        /// reversed, ends sharing a coordinate.
        #[test]
        fn velocity_order_equals_the_rationals(
            ends in prop::array::uniform4(point()),
            tie in 0usize..8,
            scale in -3i32..3,
            sides in (any::<bool>(), any::<bool>()),
            shift in prop_oneof![Just(0i32), -1010i32..-900, 880i32..900],
        ) {
            // Towards either end of the range too (the products scaled
            // into range, `orient3d`'s last column scaled with them).
            let ends = ends.map(|p| p.map(|v| crate::exact::scale::times_pow2(v, shift)));
            let [a, mut b, mut c, mut d] = ends;
            match tie {
                // One end shared, then the same edge either way round.
                0 => c = a,
                1 => (c, d) = (a, b),
                2 => (c, d) = (b, a),
                // Parallel: the second edge a scaled copy of the first.
                3 => d = std::array::from_fn(|i| c[i] + double(1, scale) * (b[i] - a[i])),
                // Coordinates shared between the edges' ends.
                4 => (c[0], d[0]) = (a[0], b[0]),
                5 => (c[1], d[1]) = (a[1], b[1]),
                _ => {}
            }
            if b[2] == a[2] {
                b[2] = away(a[2]);
            }
            if d[2] == c[2] {
                d[2] = away(c[2]);
            }
            prop_assume!(d.iter().all(|x| x.is_finite()) && a[2] != b[2] && c[2] != d[2]);
            let side = |above: bool| if above { Towards::Above } else { Towards::Below };
            let limit = LoopPoint::of_vertex([0.0, 0.0, 0.0]);
            let p = EpsPoint::new(&limit, Motion { a, b, towards: side(sides.0) });
            let q = EpsPoint::new(&limit, Motion { a: c, b: d, towards: side(sides.1) });
            for k in 0..2 {
                prop_assert_eq!(p.cmp_velocity(&q, k), p.cmp_velocity_in_rationals(&q, k));
                prop_assert_eq!(q.cmp_velocity(&p, k), q.cmp_velocity_in_rationals(&p, k));
            }
        }
    }
}
