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
//! [`FilteredPoint`]; the other terms, needed only where the limits tie,
//! in exact rationals.

use super::area::signed_area;
use super::filter::{cmp_x, cmp_y, orient2d_filtered, signed_area_filtered, FilteredPoint};
use super::planar::Planar;
use super::point::{LoopPoint, Point2};
use super::rational::{rat_from_f64, Rat};
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

/// How a point moves with `epsilon`: along an edge, crossed at
/// `c +/- epsilon`.
#[derive(Clone, Copy, Debug)]
pub struct Motion {
    /// The edge's ends (exact doubles, in the mesh's stored units).
    pub a: [f64; 3],
    /// The other end; `h(b) != h(a)`.
    pub b: [f64; 3],
    /// The side of the level.
    pub towards: Towards,
}

impl Motion {
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

impl Planar for EpsPoint<'_> {
    fn cmp_y(&self, other: &Self) -> Ordering {
        cmp_y(&self.base, &other.base).then_with(|| self.velocity().y.cmp(&other.velocity().y))
    }

    fn cmp_x(&self, other: &Self) -> Ordering {
        cmp_x(&self.base, &other.base).then_with(|| self.velocity().x.cmp(&other.velocity().x))
    }

    /// `(b - a) x (c - a)` is `k0 + k1 epsilon + k2 epsilon^2` with
    /// `k0 = B x C`, `k1 = B x dC + dB x C`, `k2 = dB x dC` (`B = b0 - a0`,
    /// `dB = db - da`, likewise for `c`): the sign of the first non-zero.
    fn orient(a: &Self, b: &Self, c: &Self) -> Sign {
        let k0 = orient2d_filtered(&a.base, &b.base, &c.base);
        if k0 != Sign::Zero {
            return k0;
        }
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
    let (mut a1, mut a2) = (Rat::zero(), Rat::zero());
    for i in 0..n {
        let (p, q) = (&points[i], &points[(i + 1) % n]);
        let (p0, q0) = (p.base.exact().exact(), q.base.exact().exact());
        let (dp, dq) = (p.velocity(), q.velocity());
        a1 += cross(&p0.x, &p0.y, &dq.x, &dq.y) + cross(&dp.x, &dp.y, &q0.x, &q0.y);
        a2 += cross(&dp.x, &dp.y, &dq.x, &dq.y);
    }
    if a1.is_zero() {
        Sign::of_rat(&a2)
    } else {
        Sign::of_rat(&a1)
    }
}
