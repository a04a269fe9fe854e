//! Input: closed loops of exact points that may touch at vertices but never
//! cross. Output: each loop's role (outer or hole) and parent loop.
//!
//! Decided exactly (a floating-point filter first, exact rationals when it
//! cannot decide): each loop's representative point is the midpoint of one
//! of its segments that no other segment runs back along (so it lies on no
//! other loop: loops share only vertices, or whole segments run both ways); containment is exact crossing parity. Candidates come from a
//! uniform grid of rounded bounding boxes widened outward by one ulp, so the
//! filter never drops a true container and the cost stays near-linear for
//! many small loops side by side.

use crate::exact::filter::{cmp_y, orient2d_filtered, FilteredPoint, Key};
use crate::exact::point::LoopPoint;
use crate::exact::rational::Rat;
use crate::exact::{Point2, Sign};
use rustc_hash::FxHashSet as HashSet;
use std::cmp::Ordering;

/// Outer boundary or hole (SPEC section 9 `role`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// At even nesting depth.
    Outer,
    /// At odd nesting depth.
    Hole,
}

/// The nesting of one loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Nesting {
    /// Outer or hole.
    pub role: Role,
    /// The smallest loop containing this one.
    pub parent: Option<usize>,
    /// Number of loops containing this one.
    pub depth: usize,
}

/// Whether exact point `r` is strictly inside the closed polygon `poly`
/// (crossing parity; `r` is never on `poly` where this is used).
pub fn contains(poly: &[FilteredPoint<'_>], r: &FilteredPoint<'_>) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let p = &poly[i];
        let q = &poly[(i + 1) % n];
        let p_above = cmp_y(p, r) == Ordering::Greater;
        let q_above = cmp_y(q, r) == Ordering::Greater;
        if p_above == q_above {
            continue;
        }
        let o = orient2d_filtered(p, q, r);
        let crosses_right = if q_above {
            o == Sign::Positive
        } else {
            o == Sign::Negative
        };
        if crosses_right {
            inside = !inside;
        }
    }
    inside
}

/// The keys of one loop's points, and of every segment of its family.
#[derive(Clone, Copy)]
struct LoopKeys<'k> {
    points: &'k [Key],
    family: &'k HashSet<(Key, Key)>,
}

/// The midpoint of the first segment of `poly` that has non-zero length and
/// whose reverse is not in the family (one-sided limits may run both ways
/// along an edge: a crack or spike of zero width); that midpoint lies on no
/// other loop. Reverses are looked up by the points' nearest doubles
/// (`keys`, given when reversals are possible), which can only skip more
/// segments than needed, never fewer; if every segment is skipped, the
/// first one of non-zero length is used.
fn representative(poly: &[FilteredPoint<'_>], keys: Option<LoopKeys<'_>>) -> Option<LoopPoint> {
    let n = poly.len();
    let ends = |i: usize| (&poly[i], &poly[(i + 1) % n]);
    let reversed =
        |i: usize| keys.is_some_and(|k| k.family.contains(&(k.points[(i + 1) % n], k.points[i])));
    let long = |i: usize| {
        let (p, q) = ends(i);
        p.disjoint(q) || p.exact() != q.exact()
    };
    let pick = (0..n)
        .find(|&i| !reversed(i) && long(i))
        .or_else(|| (0..n).find(|&i| long(i)))?;
    let (p, q) = ends(pick);
    let (p, q) = (p.exact().exact(), q.exact().exact());
    let half = Rat::new(1.into(), 2.into());
    Some(LoopPoint::from(Point2 {
        x: (&p.x + &q.x) * &half,
        y: (&p.y + &q.y) * &half,
    }))
}

#[derive(Clone, Copy)]
struct Bbox {
    lo: [f64; 2],
    hi: [f64; 2],
}

fn bbox(poly: &[FilteredPoint<'_>]) -> Bbox {
    let mut b = Bbox {
        lo: [f64::INFINITY; 2],
        hi: [f64::NEG_INFINITY; 2],
    };
    for p in poly {
        let (lo, hi) = p.bounds();
        for k in 0..2 {
            b.lo[k] = b.lo[k].min(lo[k]);
            b.hi[k] = b.hi[k].max(hi[k]);
        }
    }
    b
}

/// Whether two segments of a family may run both ways between the same
/// two points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reversals {
    /// Never (S_O, dF): every segment's midpoint lies on its loop alone.
    Impossible,
    /// Possibly (one-sided limits: zero-width cracks and spikes), or not
    /// known.
    Possible,
}

/// Nests a family of loops. `loops[i]` is the exact polygon of loop `i`.
pub fn nest<P: AsRef<[LoopPoint]>>(loops: &[P]) -> Vec<Nesting> {
    let mut filtered: Vec<Vec<FilteredPoint<'_>>> = loops
        .iter()
        .map(|l| l.as_ref().iter().map(FilteredPoint::approximate).collect())
        .collect();
    nest_filtered(&mut filtered, Reversals::Possible)
}

/// [`nest`] for loops whose points are already approximated (they are
/// enclosed here when there is more than one loop).
pub fn nest_filtered(
    filtered: &mut [Vec<FilteredPoint<'_>>],
    reversals: Reversals,
) -> Vec<Nesting> {
    let n = filtered.len();
    if n < 2 {
        let alone = Nesting {
            role: Role::Outer,
            parent: None,
            depth: 0,
        };
        return vec![alone; n];
    }
    filtered
        .iter_mut()
        .flatten()
        .for_each(FilteredPoint::enclose);
    let filtered: &[Vec<FilteredPoint<'_>>] = filtered;
    let keys: Vec<Vec<Key>> = match reversals {
        Reversals::Possible => filtered
            .iter()
            .map(|l| l.iter().map(FilteredPoint::key).collect())
            .collect(),
        Reversals::Impossible => Vec::new(),
    };
    let mut segments: HashSet<(Key, Key)> =
        HashSet::with_capacity_and_hasher(keys.iter().map(Vec::len).sum(), Default::default());
    segments.extend(
        keys.iter()
            .flat_map(|k| (0..k.len()).map(|i| (k[i], k[(i + 1) % k.len()]))),
    );
    let reps: Vec<Option<LoopPoint>> = filtered
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let keys = keys.get(i).map(|k| LoopKeys {
                points: k,
                family: &segments,
            });
            representative(l, keys)
        })
        .collect();
    let boxes: Vec<Bbox> = filtered.iter().map(|l| bbox(l)).collect();
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for b in &boxes {
        for k in 0..2 {
            lo[k] = lo[k].min(b.lo[k]);
            hi[k] = hi[k].max(b.hi[k]);
        }
    }
    let cells = ((n as f64).sqrt().ceil() as usize).clamp(1, 1024);
    let cell_of = |x: f64, k: usize| -> usize {
        let span = hi[k] - lo[k];
        if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 0;
        }
        (((x - lo[k]) / span * cells as f64) as usize).min(cells - 1)
    };
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
    for (i, b) in boxes.iter().enumerate() {
        for cx in cell_of(b.lo[0], 0)..=cell_of(b.hi[0], 0) {
            for cy in cell_of(b.lo[1], 1)..=cell_of(b.hi[1], 1) {
                grid[cy * cells + cx].push(i as u32);
            }
        }
    }
    let mut containers: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        let Some(r) = &reps[i] else { continue };
        let rf = FilteredPoint::new(r);
        let f = r.to_f64();
        let cell = &grid[cell_of(f[1], 1) * cells + cell_of(f[0], 0)];
        for &j in cell {
            let j = j as usize;
            if j == i {
                continue;
            }
            let b = &boxes[j];
            // Exact reject: the rounded point lies outside the widened box
            // only if the exact point does.
            if f[0] < b.lo[0] || f[0] > b.hi[0] || f[1] < b.lo[1] || f[1] > b.hi[1] {
                continue;
            }
            if contains(&filtered[j], &rf) {
                containers[i].push(j);
            }
        }
    }
    (0..n)
        .map(|i| {
            let depth = containers[i].len();
            // Containers form a chain; the parent is the deepest of them.
            let parent = containers[i]
                .iter()
                .copied()
                .max_by_key(|&j| (containers[j].len(), std::cmp::Reverse(j)));
            Nesting {
                role: if depth % 2 == 0 {
                    Role::Outer
                } else {
                    Role::Hole
                },
                parent,
                depth,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: i64, y0: i64, s: i64, ccw: bool) -> Vec<LoopPoint> {
        let p = |x: i64, y: i64| {
            LoopPoint::from(Point2 {
                x: Rat::from_integer(x.into()),
                y: Rat::from_integer(y.into()),
            })
        };
        let mut v = vec![p(x0, y0), p(x0 + s, y0), p(x0 + s, y0 + s), p(x0, y0 + s)];
        if !ccw {
            v.reverse();
        }
        v
    }

    #[test]
    fn nested_squares_alternate_roles() {
        let loops = vec![
            square(2, 2, 6, true),
            square(0, 0, 10, true),
            square(4, 4, 2, true),
            square(20, 0, 1, true),
        ];
        let n = nest(&loops);
        assert_eq!(
            n[1],
            Nesting {
                role: Role::Outer,
                parent: None,
                depth: 0
            }
        );
        assert_eq!(
            n[0],
            Nesting {
                role: Role::Hole,
                parent: Some(1),
                depth: 1
            }
        );
        assert_eq!(
            n[2],
            Nesting {
                role: Role::Outer,
                parent: Some(0),
                depth: 2
            }
        );
        assert_eq!(
            n[3],
            Nesting {
                role: Role::Outer,
                parent: None,
                depth: 0
            }
        );
    }

    #[test]
    fn loops_touching_at_a_corner_are_siblings() {
        // Two squares sharing the corner (1, 1), inside a big one.
        let loops = vec![
            square(0, 0, 1, true),
            square(1, 1, 1, true),
            square(-5, -5, 20, true),
        ];
        let n = nest(&loops);
        assert_eq!(n[0].parent, Some(2));
        assert_eq!(n[1].parent, Some(2));
        assert_eq!(n[0].role, Role::Hole);
    }
}
