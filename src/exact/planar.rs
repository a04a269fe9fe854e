//! Input: points of the plane `z = c`, exact, with cheap enclosures.
//! Output: the exact predicates that nesting and sweeping need, behind one
//! trait, so that the same algorithms run on plain exact points
//! ([`FilteredPoint`]) and on one-sided limit points moving with an
//! infinitesimal `epsilon` ([`super::perturbed::EpsPoint`]).

use super::filter::{cmp_x, cmp_y, orient2d_filtered, FilteredPoint};
use super::Sign;
use std::cmp::Ordering;

/// A point with exact comparisons and orientation.
///
/// Every method is exact: its answer is the sign of the exact quantity
/// (for points moving with `epsilon`, the sign for every small enough
/// `epsilon > 0`). Only [`Planar::bounds`] and [`Planar::rounded`] are
/// doubles, and they bound or round the exact point (at `epsilon = 0`).
pub trait Planar {
    /// Exact order of the y coordinates.
    fn cmp_y(&self, other: &Self) -> Ordering;

    /// Exact order of the x coordinates.
    fn cmp_x(&self, other: &Self) -> Ordering;

    /// Exact orientation of `(a, b, c)`: positive when counter-clockwise.
    fn orient(a: &Self, b: &Self, c: &Self) -> Sign;

    /// Doubles enclosing the point: `([x_lo, y_lo], [x_hi, y_hi])`.
    fn bounds(&self) -> ([f64; 2], [f64; 2]);

    /// The nearest doubles of the point (at `epsilon = 0`), in the frame
    /// of [`Planar::bounds`] (see [`super::frame::Frame`]).
    fn rounded(&self) -> [f64; 2];

    /// The point's coordinates when it is exactly these two doubles (then
    /// the double predicates of [`super::predicates`] decide exactly).
    fn as_double(&self) -> Option<[f64; 2]> {
        None
    }

    /// The sweep order: by y, then by x (exact).
    fn cmp_yx(&self, other: &Self) -> Ordering {
        self.cmp_y(other).then_with(|| self.cmp_x(other))
    }
}

impl Planar for FilteredPoint<'_> {
    #[inline]
    fn cmp_y(&self, other: &Self) -> Ordering {
        cmp_y(self, other)
    }

    #[inline]
    fn cmp_x(&self, other: &Self) -> Ordering {
        cmp_x(self, other)
    }

    #[inline]
    fn orient(a: &Self, b: &Self, c: &Self) -> Sign {
        orient2d_filtered(a, b, c)
    }

    #[inline]
    fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        FilteredPoint::bounds(self)
    }

    fn rounded(&self) -> [f64; 2] {
        FilteredPoint::rounded(self)
    }

    #[inline]
    fn as_double(&self) -> Option<[f64; 2]> {
        FilteredPoint::as_double(self)
    }
}
