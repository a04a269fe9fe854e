//! Input: closed loops of exact points that never cross (they may touch at
//! points), each with its exact orientation. Output: each loop's role
//! (outer or hole) and parent loop.
//!
//! Decided exactly, on any point type with exact predicates ([`Planar`]):
//! plain exact points for S_O and dF, points moving with an infinitesimal
//! `epsilon` for L- and L+ (whose limits may run along each other).
//!
//! Two methods give the same answer. Ray casting: each loop's
//! representative point (one of its vertices that lies on no other loop)
//! is tested by exact crossing parity against the loops whose bounding
//! boxes hold it (found through a uniform grid of boxes); cheap when loops
//! lie side by side. A plane sweep (`sweep.rs`): `O(n log n)` in
//! the number of points however deep the nesting. The sweep is taken when
//! the ray casting's work, counted before it starts, would exceed a few
//! times the sweep's, or when a loop has no representative.

mod order;
mod sweep;

use crate::exact::area::signed_area;
use crate::exact::filter::FilteredPoint;
use crate::exact::frame::Frame;
use crate::exact::planar::Planar;
use crate::exact::point::LoopPoint;
use crate::exact::Sign;
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

/// Whether `r` is strictly inside the closed polygon `poly` (crossing
/// parity, exact; `r` must not lie on `poly`).
pub fn contains<P: Planar>(poly: &[P], r: &P) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let p = &poly[i];
        let q = &poly[(i + 1) % n];
        let p_above = p.cmp_y(r) == Ordering::Greater;
        let q_above = q.cmp_y(r) == Ordering::Greater;
        if p_above == q_above {
            continue;
        }
        let o = P::orient(p, q, r);
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

#[derive(Clone, Copy)]
struct Bbox {
    lo: [f64; 2],
    hi: [f64; 2],
}

fn bbox<P: Planar>(poly: &[P]) -> Bbox {
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

/// A family of loops to nest: each loop's points in order (first not
/// repeated, enclosures computed), the exact sign of its area, and the
/// index of one of its points that lies on no other loop of the family,
/// where the caller knows one.
pub struct Family<'f, L> {
    /// The loops.
    pub loops: &'f [L],
    /// The exact sign of each loop's area.
    pub orientation: &'f [Sign],
    /// A point of each loop on no other loop, if known.
    pub representative: &'f [Option<usize>],
}

/// How many times the sweep's estimated work the ray casting may cost.
const RAY_BUDGET: usize = 4;

/// Nests a family of loops (see the module documentation).
pub fn nest<P: Planar, L: AsRef<[P]>>(family: &Family<'_, L>) -> Vec<Nesting> {
    let loops = family.loops;
    let n = loops.len();
    if n < 2 {
        let alone = Nesting {
            role: Role::Outer,
            parent: None,
            depth: 0,
        };
        return vec![alone; n];
    }
    let parents = match candidates(family) {
        Some(containers) => ray_cast_parents(family, &containers),
        None => sweep::parents(loops, family.orientation),
    };
    with_depths(&parents)
}

/// For each loop, the loops that may contain its representative (their
/// boxes hold it), or `None` when some loop has no representative or
/// testing them all would cost more than the sweep.
fn candidates<P: Planar, L: AsRef<[P]>>(family: &Family<'_, L>) -> Option<Vec<Vec<u32>>> {
    let loops = family.loops;
    let n = loops.len();
    let reps: Vec<&P> = (0..n)
        .map(|i| family.representative[i].map(|k| &loops[i].as_ref()[k]))
        .collect::<Option<_>>()?;
    let points: usize = loops.iter().map(|l| l.as_ref().len()).sum();
    let budget = RAY_BUDGET * points * (usize::BITS - points.leading_zeros()) as usize;
    let boxes: Vec<Bbox> = loops.iter().map(|l| bbox(l.as_ref())).collect();
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
        if span.partial_cmp(&0.0) != Some(Ordering::Greater) {
            return 0;
        }
        (((x - lo[k]) / span * cells as f64) as usize).min(cells - 1)
    };
    // Boxes spanning many cells (loops around many others) make the grid
    // itself quadratic: count its entries first.
    let span = |b: &Bbox, k: usize| cell_of(b.hi[k], k) - cell_of(b.lo[k], k) + 1;
    let entries: usize = boxes.iter().map(|b| span(b, 0) * span(b, 1)).sum();
    if entries > budget {
        return None;
    }
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
    for (i, b) in boxes.iter().enumerate() {
        for cx in cell_of(b.lo[0], 0)..=cell_of(b.hi[0], 0) {
            for cy in cell_of(b.lo[1], 1)..=cell_of(b.hi[1], 1) {
                grid[cy * cells + cx].push(i as u32);
            }
        }
    }
    let mut work = 0usize;
    let mut out = vec![Vec::new(); n];
    for (i, r) in reps.iter().enumerate() {
        let f = r.rounded();
        for &j in &grid[cell_of(f[1], 1) * cells + cell_of(f[0], 0)] {
            let b = &boxes[j as usize];
            // Exact reject: the nearest doubles of the exact point lie
            // outside the box of enclosures only if the point does.
            if j as usize == i
                || f[0] < b.lo[0]
                || f[0] > b.hi[0]
                || f[1] < b.lo[1]
                || f[1] > b.hi[1]
            {
                continue;
            }
            work += loops[j as usize].as_ref().len();
            if work > budget {
                return None;
            }
            out[i].push(j);
        }
    }
    Some(out)
}

/// Parents by crossing parity: the containers of a loop form a chain; its
/// parent is the deepest of them.
fn ray_cast_parents<P: Planar, L: AsRef<[P]>>(
    family: &Family<'_, L>,
    candidates: &[Vec<u32>],
) -> Vec<Option<usize>> {
    let loops = family.loops;
    let containers: Vec<Vec<usize>> = candidates
        .iter()
        .enumerate()
        .map(|(i, cand)| {
            let k = family.representative[i].unwrap_or(0);
            let r = &loops[i].as_ref()[k];
            cand.iter()
                .map(|&j| j as usize)
                .filter(|&j| contains(loops[j].as_ref(), r))
                .collect()
        })
        .collect();
    containers
        .iter()
        .map(|c| {
            c.iter()
                .copied()
                .max_by_key(|&j| (containers[j].len(), std::cmp::Reverse(j)))
        })
        .collect()
}

/// Nests loops of exact points known only by their coordinates: each
/// loop's orientation computed exactly, nesting by the sweep (no
/// representative is known). For tests and tools; the slicer calls
/// [`nest`] with what its topology knows.
pub fn nest_points(loops: &[Vec<LoopPoint>]) -> Vec<Nesting> {
    let frame = Frame::for_points(loops.iter().flatten().map(LoopPoint::to_f64));
    let filtered: Vec<Vec<FilteredPoint<'_>>> = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|p| FilteredPoint::in_frame(p, frame))
                .collect()
        })
        .collect();
    let orientation: Vec<Sign> = loops
        .iter()
        .map(|l| Sign::of_rat(&signed_area(l)))
        .collect();
    nest(&Family {
        loops: &filtered,
        orientation: &orientation,
        representative: &vec![None; loops.len()],
    })
}

/// Depths and roles from parents.
fn with_depths(parents: &[Option<usize>]) -> Vec<Nesting> {
    let mut depth: Vec<Option<usize>> = vec![None; parents.len()];
    let mut path = Vec::new();
    for start in 0..parents.len() {
        let mut at = start;
        let base = loop {
            if let Some(d) = depth[at] {
                break d + 1;
            }
            path.push(at);
            match parents[at] {
                Some(p) => at = p,
                None => break 0,
            }
        };
        for (k, &p) in path.iter().rev().enumerate() {
            depth[p] = Some(base + k);
        }
        path.clear();
    }
    parents
        .iter()
        .zip(depth)
        .map(|(&parent, d)| {
            let depth = d.unwrap_or(0);
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
    use crate::exact::{Point2, Rat};

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
        let n = nest_points(&loops);
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
        let n = nest_points(&loops);
        assert_eq!(n[0].parent, Some(2));
        assert_eq!(n[1].parent, Some(2));
        assert_eq!(n[0].role, Role::Hole);
    }

    /// Both methods on the contours of random closed meshes at every
    /// vertex height and between (loops touching at saddles, holes in
    /// holes): the sweep's parents equal crossing parity's, which equal
    /// the slicer's.
    #[test]
    fn sweep_equals_ray_casting_on_random_contours() {
        use crate::datasets::slab::{heights_and_midpoints, Slab};
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut tried = 0;
        for _ in 0..60 {
            let bytes: Vec<u8> = (0..48)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    seed as u8
                })
                .collect();
            let mesh = Slab::from_bytes(&bytes).mesh();
            let slicer = crate::Slicer::new(&mesh).unwrap();
            for c in heights_and_midpoints(&mesh) {
                let ls = slicer.slice_at(&c).unwrap();
                let loops: Vec<Vec<FilteredPoint<'_>>> = ls
                    .contours
                    .iter()
                    .map(|l| l.points.iter().map(FilteredPoint::new).collect())
                    .collect();
                let orientation: Vec<Sign> = ls.contours.iter().map(|l| l.orientation).collect();
                let reps: Vec<Option<usize>> = ls
                    .contours
                    .iter()
                    .map(|l| {
                        l.cuts
                            .iter()
                            .position(|c| matches!(c, crate::segment::CutPoint::OnEdge(_)))
                    })
                    .collect();
                let family = Family {
                    loops: &loops,
                    orientation: &orientation,
                    representative: &reps,
                };
                let swept = sweep::parents(&loops, &orientation);
                let stored: Vec<Option<usize>> = ls.contours.iter().map(|l| l.parent).collect();
                assert_eq!(swept, stored, "sweep at {c}");
                if reps.iter().all(Option::is_some) {
                    let all: Vec<Vec<u32>> = (0..loops.len())
                        .map(|i| {
                            (0..loops.len() as u32)
                                .filter(|&j| j as usize != i)
                                .collect()
                        })
                        .collect();
                    assert_eq!(ray_cast_parents(&family, &all), stored, "rays at {c}");
                }
                tried += usize::from(loops.len() > 1);
            }
        }
        assert!(tried > 50, "{tried} levels with several loops");
    }

    #[test]
    fn deep_nesting_goes_to_the_sweep() {
        // 200 nested squares: ray casting would test 200 * 199 / 2 pairs.
        let loops: Vec<Vec<LoopPoint>> = (0..200)
            .map(|i| square(-i, -i, 2 * i + 1, i % 2 == 0))
            .collect();
        let filtered: Vec<Vec<FilteredPoint<'_>>> = loops
            .iter()
            .map(|l| l.iter().map(FilteredPoint::new).collect())
            .collect();
        let orientation: Vec<Sign> = (0..200)
            .map(|i| {
                if i % 2 == 0 {
                    Sign::Positive
                } else {
                    Sign::Negative
                }
            })
            .collect();
        let reps = vec![Some(0); 200];
        let family = Family {
            loops: &filtered,
            orientation: &orientation,
            representative: &reps,
        };
        assert!(candidates(&family).is_none(), "over the ray budget");
        let n = nest(&family);
        for (i, x) in n.iter().enumerate() {
            assert_eq!(x.parent, i.checked_add(1).filter(|&p| p < 200));
            assert_eq!(x.depth, 199 - i);
        }
    }
}
