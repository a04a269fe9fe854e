//! Input: the mesh, the exact vertex signs at a level, a side. Output: the
//! verifier's own L- or L+ (SPEC section 6), derived from the SPEC alone:
//! a vertex on the plane counts as above (L-) or below (L+), every crossed
//! face gives one piece of the face walk between two edge crossings, and
//! the pieces are chained through edges (one in, one out per edge). Each
//! loop is given by its crossed edges and by its limit: each crossing's
//! element (the edge's end on the plane, or the edge), consecutive equal
//! ones merged.
//!
//! Also the exact tests a result's limit loops must pass: the first
//! non-zero term of the signed area in `epsilon`, and containment for
//! small `epsilon > 0` (crossing parity on points that move with
//! `epsilon`, [`crate::exact::perturbed`]).

use super::doc::On;
use super::facts::{face_piece, Side};
use crate::exact::filter::FilteredPoint;
use crate::exact::frame::Frame;
use crate::exact::perturbed::{EpsPoint, Motion, Towards};
use crate::exact::planar::Planar;
use crate::exact::point::LoopPoint;
use crate::exact::rational::{decompose, Rat};
use crate::exact::{Point2, Sign};
use crate::ids::VertexId;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use num_bigint::BigInt;
use num_traits::Zero;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};
use std::cmp::Ordering;
use std::collections::HashMap;

/// One loop of a one-sided limit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct LimitLoop {
    /// The edges crossed at `c -/+ epsilon`, in order.
    pub crossings: Vec<u32>,
    /// Their limits, consecutive equal ones merged (cyclically), starting
    /// with the limit of `crossings[0]`.
    pub on: Vec<On>,
}

/// The loops of L- (`Side::Below`) or L+ (`Side::Above`), or the edge
/// where the pieces do not chain (which the SPEC rules out for a valid
/// mesh).
pub(super) fn limit_loops(
    mesh: &Mesh,
    topo: &Topology,
    signs: &[Sign],
    side: Side,
) -> Result<Vec<LimitLoop>, u32> {
    let nudge = match side {
        Side::Below => Sign::Positive,
        Side::Above => Sign::Negative,
    };
    let perturbed = |v: u32| match signs[v as usize] {
        Sign::Zero => nudge,
        s => s,
    };
    let mut next: HashMap<u32, u32> = HashMap::new();
    for f in 0..mesh.num_faces() {
        let tri = mesh.faces[f].map(|v| v.0);
        let edges = topo.face_edges[f].map(|e| e.0);
        if let Some((On::Edge(from), On::Edge(to))) = face_piece(tri.map(perturbed), tri, edges) {
            let from = from as u32;
            if next.insert(from, to as u32).is_some() {
                return Err(from);
            }
        }
    }
    let limit = |e: u32| {
        let [a, b] = topo.edges[e as usize].v;
        if signs[a.idx()] == Sign::Zero {
            On::Vertex(a.0.into())
        } else if signs[b.idx()] == Sign::Zero {
            On::Vertex(b.0.into())
        } else {
            On::Edge(e.into())
        }
    };
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashMap<u32, ()> = HashMap::new();
    let mut out = Vec::new();
    for s in starts {
        if seen.contains_key(&s) {
            continue;
        }
        let mut crossings = Vec::new();
        let mut e = s;
        loop {
            seen.insert(e, ());
            crossings.push(e);
            e = *next.get(&e).ok_or(e)?;
            if e == s {
                break;
            }
            if seen.contains_key(&e) {
                return Err(e);
            }
        }
        // Start where a run of equal limits starts.
        let n = crossings.len();
        let first = (0..n)
            .find(|&k| limit(crossings[k]) != limit(crossings[(k + n - 1) % n]))
            .unwrap_or(0);
        crossings.rotate_left(first);
        let mut on: Vec<On> = Vec::new();
        for &e in &crossings {
            let l = limit(e);
            if on.last() != Some(&l) {
                on.push(l);
            }
        }
        out.push(LimitLoop { crossings, on });
    }
    Ok(out)
}

/// A cyclic sequence in a canonical rotation (the least of the rotations
/// that start at its least element), so that loops written from any start
/// compare equal.
pub(super) fn canonical(on: &[On]) -> Vec<On> {
    let Some(least) = on.iter().min() else {
        return Vec::new();
    };
    let rotation = |r: usize| on[r..].iter().chain(&on[..r]).copied().collect::<Vec<On>>();
    (0..on.len())
        .filter(|&r| on[r] == *least)
        .map(rotation)
        .min()
        .unwrap_or_default()
}

/// The crossings of a loop as points moving with `epsilon`, in stored
/// units: limits first (owned), then the moving points built on them.
pub(super) struct Moving {
    limits: Vec<LoopPoint>,
    motions: Vec<Motion>,
}

impl Moving {
    /// The crossings of `edges` at `c -/+ epsilon`, with `c` in stored units.
    pub fn new(mesh: &Mesh, topo: &Topology, c: &Rat, edges: &[u32], side: Side) -> Moving {
        let towards = match side {
            Side::Below => Towards::Below,
            Side::Above => Towards::Above,
        };
        let mut limits = Vec::with_capacity(edges.len());
        let mut motions = Vec::with_capacity(edges.len());
        for &e in edges {
            let [a, b] = topo.edges[e as usize].v.map(|v: VertexId| mesh.pos(v));
            limits.push(LoopPoint::from(crossing(a, b, c)));
            motions.push(Motion { a, b, towards });
        }
        Moving { limits, motions }
    }

    /// The moving points, their limits filtered in `frame` (see
    /// [`Frame`]: a power of two, which changes no answer, so that a mesh
    /// near `1e-300` still has bounded enclosures).
    pub fn points(&self, frame: Frame) -> Vec<EpsPoint<'_>> {
        self.limits
            .iter()
            .zip(&self.motions)
            .map(|(l, &m)| EpsPoint::with_base(FilteredPoint::in_frame(l, frame), m))
            .collect()
    }
}

/// The crossing of edge `(a, b)` (`a[2] != b[2]`) with the plane `z = c`,
/// in plain big integers: `x = (ax (zb - c) + bx (c - za)) / (zb - za)`
/// with every double an integer in units of `2^e` (the least exponent of
/// the six), so each coordinate is one fraction, brought to lowest terms
/// once (near `1e-300`, with a decimal level, its terms have hundreds of
/// digits, and a reduction after every operation took most of `verify`).
fn crossing(a: [f64; 3], b: [f64; 3], c: &Rat) -> Point2 {
    let parts = [a[0], a[1], a[2], b[0], b[1], b[2]].map(decompose);
    let e = parts.iter().flatten().map(|&(_, k)| k).min().unwrap_or(0);
    // Each double times 2^-e: an integer, as k >= e.
    let [ax, ay, za, bx, by, zb] =
        parts.map(|p| p.map_or_else(BigInt::zero, |(m, k)| BigInt::from(m) << (k - e)));
    // c 2^-e = p / q.
    let (p, q) = if e <= 0 {
        (c.numer() << -e, c.denom().clone())
    } else {
        (c.numer().clone(), c.denom() << e)
    };
    let (wa, wb) = (&zb * &q - &p, &p - &za * &q);
    let den = &q * (&zb - &za);
    let coordinate = |u: &BigInt, v: &BigInt| {
        let num = u * &wa + v * &wb;
        if e >= 0 {
            Rat::new(num << e, den.clone())
        } else {
            Rat::new(num, &den << -e)
        }
    };
    Point2 {
        x: coordinate(&ax, &bx),
        y: coordinate(&ay, &by),
    }
}

/// The sign of the signed area at small `epsilon > 0`: the first non-zero
/// of `a0` (given) and `a1`, `a2`, computed from the moving points with
/// plain rationals.
pub(super) fn area_sign(a0: &Rat, pts: &[EpsPoint<'_>]) -> Sign {
    if !a0.is_zero() {
        return Sign::of_rat(a0);
    }
    let n = pts.len();
    let cross = |u: &Point2, v: &Point2| &u.x * &v.y - &u.y * &v.x;
    let (mut a1, mut a2) = (Rat::zero(), Rat::zero());
    for i in 0..n {
        let (p, q) = (&pts[i], &pts[(i + 1) % n]);
        let (p0, q0) = (p.base().exact().exact(), q.base().exact().exact());
        a1 += cross(&p0, q.velocity()) + cross(p.velocity(), &q0);
        a2 += cross(p.velocity(), q.velocity());
    }
    if a1.is_zero() {
        Sign::of_rat(&a2)
    } else {
        Sign::of_rat(&a1)
    }
}

/// For each loop, the loops that contain its first point for small
/// `epsilon > 0` (symbolic, never a number; [`inside`], exact), in index
/// order. A loop is tested only where the closed box of its points'
/// enclosures meets the point's enclosure (an R-tree query): a point
/// whose limit lies strictly outside the box of a loop's limits stays
/// outside the loop for small `epsilon`, so skipping the others changes
/// no answer. Loops with an unbounded enclosure (coordinates outside the
/// filters' range) are always tested.
pub(super) fn containers(loops: &[Vec<EpsPoint<'_>>]) -> Vec<Vec<usize>> {
    let bounded = |[lo, hi]: [[f64; 2]; 2]| lo.iter().chain(&hi).all(|v| v.is_finite());
    let boxes: Vec<[[f64; 2]; 2]> = loops
        .iter()
        .map(|l| {
            l.iter().fold(
                [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]],
                |[lo, hi], p| {
                    // An enclosure that says nothing (NaN) is unbounded.
                    let (a, b) = p.bounds();
                    let a = a.map(|v| if v.is_nan() { f64::NEG_INFINITY } else { v });
                    let b = b.map(|v| if v.is_nan() { f64::INFINITY } else { v });
                    [
                        [lo[0].min(a[0]), lo[1].min(a[1])],
                        [hi[0].max(b[0]), hi[1].max(b[1])],
                    ]
                },
            )
        })
        .collect();
    let (finite, unbounded): (Vec<usize>, Vec<usize>) =
        (0..loops.len()).partition(|&j| bounded(boxes[j]));
    let tree = RTree::bulk_load(
        finite
            .iter()
            .map(|&j| GeomWithData::new(Rectangle::from_corners(boxes[j][0], boxes[j][1]), j))
            .collect(),
    );
    (0..loops.len())
        .map(|i| {
            let Some(r) = loops[i].first() else {
                return Vec::new();
            };
            let (lo, hi) = r.bounds();
            let mut near: Vec<usize> = if bounded([lo, hi]) {
                let query = AABB::from_corners(lo, hi);
                tree.locate_in_envelope_intersecting(&query)
                    .map(|g| g.data)
                    .chain(unbounded.iter().copied())
                    .collect()
            } else {
                (0..loops.len()).collect()
            };
            near.sort_unstable();
            near.retain(|&j| j != i && inside(&loops[j], r));
            near
        })
        .collect()
}

/// Whether `r` lies inside the polygon `poly` for small `epsilon > 0`
/// (crossing parity of a ray to +x; `r` is on no segment of `poly`).
pub(super) fn inside(poly: &[EpsPoint<'_>], r: &EpsPoint<'_>) -> bool {
    let n = poly.len();
    let mut odd = false;
    for i in 0..n {
        let (p, q) = (&poly[i], &poly[(i + 1) % n]);
        let pa = p.cmp_y(r) == Ordering::Greater;
        let qa = q.cmp_y(r) == Ordering::Greater;
        if pa != qa {
            let o = EpsPoint::orient(p, q, r);
            if (qa && o == Sign::Positive) || (!qa && o == Sign::Negative) {
                odd = !odd;
            }
        }
    }
    odd
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;
    use proptest::prelude::*;

    /// A double of any exponent (finite; zero now and then).
    fn any_double() -> impl Strategy<Value = f64> {
        prop_oneof![
            1 => Just(0.0),
            8 => any::<u64>().prop_map(f64::from_bits).prop_filter("finite", |x| x.is_finite()),
            4 => (-1000i32..1000, -1000.0f64..1000.0).prop_map(|(k, m)| m * 2f64.powi(k / 10)),
        ]
    }

    /// A loop of a mesh near `2^-1000` (below the filters' range in
    /// stored units) has a bounded box in the mesh's frame, so the R-tree
    /// can prune it; in stored units it has none, and every loop would be
    /// tested against every other (an egg crate at `1e-300`: 508 s).
    #[test]
    fn loops_near_the_least_doubles_are_bounded_in_their_frame() {
        let t = 2f64.powi(-1000);
        let ends = [
            ([t, 0.0, -t], [t, t, t]),
            ([3.0 * t, t, -t], [2.0 * t, 0.0, t]),
            ([0.0, 2.0 * t, -t], [t, 2.0 * t, t]),
        ];
        let moving = Moving {
            limits: ends
                .iter()
                .map(|&(a, b)| LoopPoint::from(crossing(a, b, &Rat::zero())))
                .collect(),
            motions: ends
                .iter()
                .map(|&(a, b)| Motion {
                    a,
                    b,
                    towards: Towards::Above,
                })
                .collect(),
        };
        let frame = Frame::for_points(ends.iter().flat_map(|&(a, b)| [a, b]));
        let bounded = |frame: Frame| {
            moving.points(frame).iter().all(|p| {
                let (lo, hi) = p.bounds();
                lo.iter().chain(&hi).all(|v| v.is_finite())
            })
        };
        assert!(bounded(frame));
        assert!(!bounded(Frame::IDENTITY));
    }

    proptest! {
        /// The R-tree's pruning changes no answer: every loop's containers
        /// are those every other loop's parity test finds. Squares and
        /// points collapsing at vertices on a small grid (nested, shared
        /// sides, shared corners, one point's box touching another loop's),
        /// some with a corner below the filters' range (unbounded enclosures).
        #[test]
        fn containers_are_those_of_every_pair(
            squares in prop::collection::vec((0i32..12, 0i32..12, 0i32..6, any::<bool>()), 1..24),
            tiny in prop::collection::vec(prop::bool::weighted(0.2), 24),
        ) {
            // A first corner moved to (t, t), below the filters' range:
            // the loop's enclosure is unbounded.
            let t = 2f64.powi(-1000);
            let limits: Vec<Vec<LoopPoint>> = squares
                .iter()
                .enumerate()
                .map(|(i, &(x, y, size, _))| {
                    let corners = if size == 0 {
                        vec![(x, y); 3]
                    } else {
                        vec![(x, y), (x + size, y), (x + size, y + size), (x, y + size)]
                    };
                    corners
                        .into_iter()
                        .enumerate()
                        .map(|(k, (a, b))| {
                            let p = if k == 0 && tiny[i] { [t, t] } else { [f64::from(a), f64::from(b)] };
                            LoopPoint::of_vertex([p[0], p[1], 0.0])
                        })
                        .collect()
                })
                .collect();
            let loops: Vec<Vec<EpsPoint<'_>>> = limits
                .iter()
                .zip(&squares)
                .map(|(ps, &(x, y, size, out))| {
                    let centre = [f64::from(2 * x + size), f64::from(2 * y + size)];
                    ps.iter()
                        .enumerate()
                        .map(|(k, p)| {
                            let [px, py] = p.to_f64();
                            // Away from the centre (or turning, for a
                            // collapsed loop), outwards or inwards.
                            let (dx, dy) = if size == 0 {
                                [(1.0, 0.0), (-1.0, 1.0), (-1.0, -1.0)][k % 3]
                            } else {
                                (2.0 * px - centre[0], 2.0 * py - centre[1])
                            };
                            let s = if out { 1.0 } else { -1.0 };
                            let a = [px, py, 0.0];
                            let b = [px + s * dx, py + s * dy, 1.0];
                            EpsPoint::new(p, Motion { a, b, towards: Towards::Above })
                        })
                        .collect()
                })
                .collect();
            let every: Vec<Vec<usize>> = (0..loops.len())
                .map(|i| {
                    (0..loops.len())
                        .filter(|&j| j != i && inside(&loops[j], &loops[i][0]))
                        .collect()
                })
                .collect();
            prop_assert_eq!(containers(&loops), every);
        }

        /// The one-fraction crossing equals `a + (b - a) t`, `t = (c -
        /// za) / (zb - za)`, in rationals step by step, at a level between
        /// the ends (its decimal neighbours too).
        #[test]
        fn crossing_agrees_with_the_stepwise_rationals(
            a in prop::array::uniform3(any_double()),
            b in prop::array::uniform3(any_double()),
            t in 1u32..1000,
            tenth in any::<bool>(),
        ) {
            prop_assume!(a[2] != b[2]);
            let (za, zb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let mut c = &za + (&zb - &za) * Rat::new(t.into(), 1000.into());
            if tenth {
                c += Rat::new(1.into(), 10.into());
            }
            let s = (&c - &za) / (&zb - &za);
            let lerp = |k: usize| rat_from_f64(a[k]) + (rat_from_f64(b[k]) - rat_from_f64(a[k])) * &s;
            let p = crossing(a, b, &c);
            prop_assert_eq!(p.x, lerp(0));
            prop_assert_eq!(p.y, lerp(1));
        }
    }
}
