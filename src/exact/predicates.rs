//! Input: exact points (`f64` coordinates or [`Point2`]).
//! Output: exact signs of orientation determinants.
//!
//! `f64` predicates use Shewchuk's adaptive predicates from `robust`, whose
//! sign is exact for finite `f64` inputs; rational ones compute the
//! determinant exactly.

use super::point::Point2;
use super::rational::Rat;
use num_traits::Signed;
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
    /// Sign from an ordering of `x` against zero.
    #[inline]
    pub fn of_cmp(o: Option<Ordering>) -> Sign {
        match o {
            Some(Ordering::Less) => Sign::Negative,
            Some(Ordering::Greater) => Sign::Positive,
            _ => Sign::Zero,
        }
    }

    /// The sign of a float determinant returned by `robust` (exact sign).
    #[inline]
    pub fn of_f64(x: f64) -> Sign {
        Sign::of_cmp(x.partial_cmp(&0.0))
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

    /// The opposite sign.
    #[inline]
    pub fn flip(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }
}

fn coord(p: [f64; 3], i: usize, j: usize) -> robust::Coord<f64> {
    robust::Coord { x: p[i], y: p[j] }
}

/// Exact sign of the orientation of `(a, b, c)` projected on the `(x, y)`
/// plane: positive when counter-clockwise seen from `+z`.
#[inline]
pub fn orient2d_xy(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Sign {
    orient2d_axes(a, b, c, 0, 1)
}

/// Exact orientation of `(a, b, c)` projected on the plane of axes `i`, `j`.
#[inline]
pub fn orient2d_axes(a: [f64; 3], b: [f64; 3], c: [f64; 3], i: usize, j: usize) -> Sign {
    Sign::of_f64(robust::orient2d(
        coord(a, i, j),
        coord(b, i, j),
        coord(c, i, j),
    ))
}

/// Exact sign of the signed volume of the tetrahedron `(a, b, c, d)`:
/// positive when `d` lies on the side of the triangle `(a, b, c)` that its
/// counter-clockwise normal points to.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    let p = |v: [f64; 3]| robust::Coord3D {
        x: v[0],
        y: v[1],
        z: v[2],
    };
    // robust's orient3d is positive when d is below (a, b, c) seen with
    // (a, b, c) counter-clockwise; flip to the right-hand convention.
    Sign::of_f64(robust::orient3d(p(a), p(b), p(c), p(d))).flip()
}

/// Whether a triangle has zero area (its three vertices are collinear),
/// decided exactly.
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

    #[test]
    fn orient3d_is_right_handed() {
        let o = [0.0, 0.0, 0.0];
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        assert_eq!(orient3d(o, x, y, [0.0, 0.0, 1.0]), Sign::Positive);
        assert_eq!(orient3d(o, x, y, [0.0, 0.0, -1.0]), Sign::Negative);
        assert_eq!(orient3d(o, x, y, [5.0, 7.0, 0.0]), Sign::Zero);
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
}
