//! Input: a mesh and an exact level. Output: what a strong-Morse slicer
//! returns (the paper's Figure 6c/f): DELIBERATELY WRONG at degenerate
//! levels, kept only to show the difference.
//!
//! It follows the paper's Algorithm 1, line 33, literally: every face with
//! `min <= c <= max` yields a segment between the first two distinct points
//! where its edges meet the plane (an edge lying in the plane gives both
//! ends), and segments are chained by comparing coordinates. A face that
//! touches the plane at one vertex gives a zero-length segment; an in-plane
//! edge is emitted once per neighbour face; in-plane faces emit their
//! edges. The exact arithmetic is kept so the only error is the method's.

use crate::exact::area::signed_area;
use crate::exact::rational::Rat;
use crate::exact::{Level, Point2, Sign};
use crate::mesh::Mesh;
use num_traits::{Signed, Zero};
use std::collections::HashMap;

/// The naive slicer's output at one level.
#[derive(Clone, Debug, PartialEq)]
pub struct NaiveSlice {
    /// Every segment emitted (possibly zero-length or repeated).
    pub segments: Vec<[Point2; 2]>,
    /// Segments of zero length.
    pub zero_length: usize,
    /// Segments emitted more than once (either direction).
    pub duplicates: usize,
    /// Closed polylines found by coordinate matching, with their areas.
    pub loops: Vec<(Vec<Point2>, Rat)>,
    /// Open polylines left over.
    pub open: usize,
}

/// Slices one level the strong-Morse way.
pub fn naive_slice(mesh: &Mesh, c: &Rat) -> NaiveSlice {
    let level = Level::new(c.clone());
    let mut segments = Vec::new();
    for tri in &mesh.faces {
        let p = tri.map(|v| mesh.pos(v));
        let s = p.map(|q| level.sign_of(q[2]));
        let touches_low = s.iter().any(|&x| x != Sign::Positive);
        let touches_high = s.iter().any(|&x| x != Sign::Negative);
        if !(touches_low && touches_high) {
            continue;
        }
        let mut pts: Vec<Point2> = Vec::new();
        for i in 0..3 {
            let (a, b) = (p[i], p[(i + 1) % 3]);
            let (sa, sb) = (s[i], s[(i + 1) % 3]);
            let mut add = |q: Point2| {
                if !pts.contains(&q) {
                    pts.push(q);
                }
            };
            match (sa, sb) {
                (Sign::Zero, _) => add(Point2::of_vertex(a)),
                (_, Sign::Zero) => add(Point2::of_vertex(b)),
                (x, y) if x != y => add(Point2::on_edge(a, b, &level)),
                _ => {}
            }
            if sa == Sign::Zero && sb == Sign::Zero {
                add(Point2::of_vertex(b));
            }
        }
        let first = pts[0].clone();
        let second = pts.get(1).cloned().unwrap_or_else(|| first.clone());
        segments.push([first, second]);
    }
    let zero_length = segments.iter().filter(|s| s[0] == s[1]).count();
    let mut count: HashMap<(&Point2, &Point2), usize> = HashMap::new();
    for s in &segments {
        let key = if (&s[0].x, &s[0].y) <= (&s[1].x, &s[1].y) {
            (&s[0], &s[1])
        } else {
            (&s[1], &s[0])
        };
        *count.entry(key).or_default() += 1;
    }
    let duplicates = count.values().filter(|&&n| n > 1).map(|n| n - 1).sum();
    let (loops, open) = chain_by_coordinates(&segments);
    NaiveSlice {
        segments,
        zero_length,
        duplicates,
        loops,
        open,
    }
}

/// Greedy chaining by point equality, as coordinate-matching slicers do.
fn chain_by_coordinates(segments: &[[Point2; 2]]) -> (Vec<(Vec<Point2>, Rat)>, usize) {
    let mut at: HashMap<&Point2, Vec<usize>> = HashMap::new();
    for (i, s) in segments.iter().enumerate() {
        if s[0] != s[1] {
            at.entry(&s[0]).or_default().push(i);
            at.entry(&s[1]).or_default().push(i);
        }
    }
    let mut used = vec![false; segments.len()];
    let mut loops = Vec::new();
    let mut open = 0;
    for start in 0..segments.len() {
        if used[start] || segments[start][0] == segments[start][1] {
            continue;
        }
        used[start] = true;
        let first = &segments[start][0];
        let mut poly = vec![first.clone()];
        let mut cur = &segments[start][1];
        let closed = loop {
            if cur == first {
                break true;
            }
            poly.push(cur.clone());
            let next = at[cur].iter().copied().find(|&j| !used[j]);
            match next {
                Some(j) => {
                    used[j] = true;
                    cur = if &segments[j][0] == cur {
                        &segments[j][1]
                    } else {
                        &segments[j][0]
                    };
                }
                None => break false,
            }
        };
        if closed {
            let area = signed_area(&poly).abs();
            loops.push((poly, area));
        } else {
            open += 1;
        }
    }
    (loops, open)
}

impl NaiveSlice {
    /// Total area the naive slicer would fill.
    pub fn filled_area(&self) -> Rat {
        self.loops.iter().fold(Rat::zero(), |a, (_, area)| a + area)
    }
}
