//! Input: mesh positions and an exact level. Output: exact rational points
//! in the plane `z = c`, their exact areas, and their rounding for output.

use super::level::Level;
use super::rational::{rat_from_f64, rat_to_f64, Rat};
use num_traits::Zero;

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
    pub fn on_edge(a: [f64; 3], b: [f64; 3], level: &Level) -> Self {
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

/// Exact signed area of a closed polygon (shoelace): positive when
/// counter-clockwise.
pub fn signed_area(points: &[Point2]) -> Rat {
    let n = points.len();
    let mut twice = Rat::zero();
    for i in 0..n {
        let p = &points[i];
        let q = &points[(i + 1) % n];
        twice += &p.x * &q.y - &q.x * &p.y;
    }
    twice / Rat::from_integer(2.into())
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

    #[test]
    fn square_area() {
        let sq: Vec<Point2> = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
            .iter()
            .map(|p| Point2::of_vertex([p[0], p[1], 0.0]))
            .collect();
        assert_eq!(signed_area(&sq), Rat::from_integer(4.into()));
        let rev: Vec<Point2> = sq.into_iter().rev().collect();
        assert_eq!(signed_area(&rev), Rat::from_integer((-4).into()));
    }
}
