//! Input: a level with vertices on the plane. Output: the one-sided limits
//! L- and L+ (SPEC section 6).
//!
//! A vertex on the plane counts as above (L-) or below (L+); then every
//! crossing is a strict edge crossing, so the segments of the crossed faces
//! are chained through edges alone (one segment in and one out per edge,
//! no vertex tie-break), and each loop is a loop of the contour at every
//! regular level close enough on that side: same edges, same order. Its
//! points are affine in `epsilon` ([`EpsPoint`]); orientation and nesting
//! are decided for small `epsilon > 0`, so they are those of the regular
//! contours even where the limits touch or run along each other.
//!
//! Output points are the limits: a crossing on an edge with an end on the
//! plane sits at that end, and consecutive crossings at one vertex become
//! one point. A loop is collapsed when a region it bounds (the loop minus
//! its children, or its parent minus the parent's children) has zero limit
//! area, exactly (around an extremum, along a ridge and back, on both sides
//! of a closed ridge ring with material on one side only). Such a loop runs
//! along ridge or valley edges (S_NO) throughout, which is checked first;
//! the areas decide, since a ridge ring with material on both sides has
//! loops along it that bound whole discs.

use super::{LevelBuilder, Loop, SliceError};
use crate::chain::chain_loops;
use crate::classify::Side;
use crate::exact::area::signed_area;
use crate::exact::filter::{twice_area_enclosure, FilteredPoint, Interval};
use crate::exact::frame::Frame;
use crate::exact::perturbed::{orientation, EpsPoint, Motion, Towards};
use crate::exact::point::LoopPoint;
use crate::exact::Rat;
use crate::exact::Sign;
use crate::ids::{EdgeId, VertexId};
use crate::nest::{nest, Family};
use crate::segment::{face_segment, Carrier, CutPoint, Segment, Via};
use num_traits::Zero;

/// One loop of a limit before nesting: the crossed edges with their
/// carriers, rotated to start a run of equal limit cuts, and the limit.
struct Chained {
    crossings: Vec<(EdgeId, Carrier)>,
    /// The segment leaving each crossing.
    segments: Vec<usize>,
    /// The limit cut of each run of crossings, and where each run starts.
    cuts: Vec<CutPoint>,
    run_of: Vec<u32>,
    points: Vec<LoopPoint>,
}

impl LevelBuilder<'_> {
    /// L- or L+ (see the module documentation).
    pub(super) fn one_sided(&self, side: Side) -> Result<Vec<Loop>, SliceError> {
        let perturbed = self.signs.perturbed(side);
        let mut segments: Vec<Segment> = Vec::new();
        let mut carriers: Vec<Carrier> = Vec::new();
        for &f in self.active {
            let tri = self.mesh.faces[f.idx()];
            let s = tri.map(|v| perturbed.of(v));
            if let Some((seg, [start, _])) = face_segment(self.topo, f, tri, s) {
                segments.push(seg);
                carriers.push(start);
            }
        }
        let chains = chain_loops(self.topo, &segments)?;
        let chained: Vec<Chained> = chains
            .iter()
            .map(|ch| self.limit_of(ch, &segments, &carriers))
            .collect::<Result<_, _>>()?;
        let towards = match side {
            Side::Below => Towards::Below,
            Side::Above => Towards::Above,
        };
        let frame = self.points.frame();
        let moving: Vec<Vec<EpsPoint<'_>>> = chained
            .iter()
            .map(|c| {
                // One filtered limit per run, shared by its crossings.
                let bases: Vec<FilteredPoint<'_>> = c
                    .points
                    .iter()
                    .map(|p| FilteredPoint::in_frame(p, frame))
                    .collect();
                c.crossings
                    .iter()
                    .zip(&c.run_of)
                    .map(|(&(_, [a, b]), &r)| {
                        let motion = Motion {
                            a: self.mesh.pos(a),
                            b: self.mesh.pos(b),
                            towards,
                        };
                        EpsPoint::with_base(bases[r as usize].clone(), motion)
                    })
                    .collect()
            })
            .collect();
        let signs: Vec<Sign> = moving
            .iter()
            .zip(&chained)
            .map(|(m, c)| orientation(m, &c.points))
            .collect();
        // Every crossing of a limit lies on its loop alone for small
        // epsilon: any point represents its loop.
        let nesting = nest(&Family {
            loops: &moving,
            orientation: &signs,
            representative: &vec![Some(0); moving.len()],
        });
        drop(moving);
        // Only a loop that runs along S_NO edges throughout can bound a
        // region of zero limit area; where there is one, the exact areas
        // decide (see `collapse_by_regions`).
        let may_collapse = chained.iter().any(|c| self.runs_along_s_no(c, &segments));
        let mut loops = Vec::with_capacity(chained.len());
        for ((c, sign), n) in chained.into_iter().zip(signs).zip(nesting) {
            loops.push(Loop {
                cuts: c.cuts,
                points: c.points,
                orientation: sign,
                role: n.role,
                parent: n.parent,
                collapsed: false,
                crossings: c.crossings.into_iter().map(|(e, _)| e).collect(),
            });
        }
        if may_collapse {
            collapse_by_regions(&mut loops, frame);
        }
        Ok(loops)
    }

    /// The limit of a chain of edge crossings: each crossing's cut (the
    /// edge's end on the plane, if any), consecutive equal cuts merged.
    fn limit_of(
        &self,
        chain: &[usize],
        segments: &[Segment],
        carriers: &[Carrier],
    ) -> Result<Chained, SliceError> {
        let limit = |i: usize| -> (CutPoint, Carrier) {
            let [a, b] = carriers[i];
            match segments[i].from {
                CutPoint::OnEdge(_) if self.signs.is_zero(a) => (CutPoint::AtVertex(a), [a; 2]),
                CutPoint::OnEdge(_) if self.signs.is_zero(b) => (CutPoint::AtVertex(b), [b; 2]),
                c => (c, [a, b]),
            }
        };
        let n = chain.len();
        let cut = |k: usize| limit(chain[k % n]).0;
        // Start where a run starts (anywhere if the loop is one run).
        let first = (0..n).find(|&k| cut(k) != cut(k + n - 1)).unwrap_or(0);
        let mut c = Chained {
            crossings: Vec::with_capacity(n),
            segments: Vec::with_capacity(n),
            cuts: Vec::new(),
            run_of: Vec::with_capacity(n),
            points: Vec::new(),
        };
        for k in first..first + n {
            let i = chain[k % n];
            let (cp, carrier) = limit(i);
            if c.cuts.last() != Some(&cp) {
                c.cuts.push(cp);
                c.points.push(self.cut_point(cp, carrier));
            }
            // Perturbed signs are never zero: every end is an edge crossing.
            let CutPoint::OnEdge(edge) = segments[i].from else {
                return Err(self.invariant(format!(
                    "a one-sided segment starts at {:?}",
                    segments[i].from
                )));
            };
            c.crossings.push((edge, carriers[i]));
            c.segments.push(i);
            c.run_of.push((c.cuts.len() - 1) as u32);
        }
        Ok(c)
    }

    /// Whether every piece of the limit between two runs lies on an S_NO
    /// edge: the piece's face has two vertices on the plane, and the face
    /// across their edge has its third vertex on the same side. Necessary
    /// for bounding a region of zero limit area (a piece inside a face, or
    /// on an edge with the faces on both sides, has material of non-zero
    /// width beside it), not sufficient: the loop inside a closed ridge
    /// ring with material below on both sides runs along the ring, yet
    /// bounds the whole disc inside it.
    fn runs_along_s_no(&self, c: &Chained, segments: &[Segment]) -> bool {
        let n = c.crossings.len();
        (0..n)
            .filter(|&k| c.run_of[k] != c.run_of[(k + 1) % n])
            .all(|k| {
                let (CutPoint::AtVertex(u), CutPoint::AtVertex(v)) = (
                    c.cuts[c.run_of[k] as usize],
                    c.cuts[c.run_of[(k + 1) % n] as usize],
                ) else {
                    return false;
                };
                let Via::Face(f) = segments[c.segments[k]].via else {
                    return false;
                };
                self.on_extremal_edge(f, u, v)
            })
    }

    /// Whether edge `(u, v)` of face `f` (whose third vertex is off the
    /// plane) is a ridge or valley: the other face's third vertex is on
    /// the same side.
    fn on_extremal_edge(&self, f: crate::ids::FaceId, u: VertexId, v: VertexId) -> bool {
        let tri = self.mesh.faces[f.idx()];
        let Some(i) = (0..3).find(|&i| {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            (a, b) == (u, v) || (a, b) == (v, u)
        }) else {
            return false;
        };
        let w = tri[(i + 2) % 3];
        let e = self.topo.edge(self.topo.face_edges[f.idx()][i]);
        let other = if e.faces[0] == f {
            e.opposite[1]
        } else {
            e.opposite[0]
        };
        let side = self.signs.of(w);
        side != Sign::Zero && self.signs.of(other) == side
    }
}

/// Sets the collapsed flags by SPEC 6's rule: a loop is collapsed exactly
/// when a region it bounds (the loop minus its children, or its parent
/// minus the parent's children) has zero limit area, exactly.
fn collapse_by_regions(loops: &mut [Loop], frame: Frame) {
    let shapes: Vec<(&[LoopPoint], Option<usize>)> = loops
        .iter()
        .map(|l| (l.points.as_slice(), l.parent))
        .collect();
    let zero = zero_regions(&shapes, frame);
    for (i, l) in loops.iter_mut().enumerate() {
        l.collapsed = zero[i] || l.parent.is_some_and(|p| zero[p]);
    }
}

/// For each loop (its points and parent), whether the region it bounds
/// (the loop minus its children) has zero area, exactly.
///
/// Each region's area is first enclosed (the loops' shoelaces on their
/// points' enclosures in the mesh's `frame`, summed; every operation
/// widened outward): a region whose enclosure excludes zero is not zero.
/// Only the others are summed in exact rationals.
fn zero_regions(loops: &[(&[LoopPoint], Option<usize>)], frame: Frame) -> Vec<bool> {
    let enclosed: Vec<Interval> = loops
        .iter()
        .map(|(points, _)| {
            let filtered: Vec<FilteredPoint<'_>> = points
                .iter()
                .map(|p| FilteredPoint::in_frame(p, frame))
                .collect();
            twice_area_enclosure(&filtered)
        })
        .collect();
    let mut region = enclosed.clone();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); loops.len()];
    for (i, &(_, parent)) in loops.iter().enumerate() {
        if let Some(p) = parent {
            region[p] = region[p].add(enclosed[i]);
            children[p].push(i);
        }
    }
    // Each loop's exact area at most once (a child's serves its own
    // region and its parent's).
    let mut exact: Vec<Option<Rat>> = vec![None; loops.len()];
    let mut area = |i: usize| -> Rat {
        exact[i]
            .get_or_insert_with(|| signed_area(loops[i].0))
            .clone()
    };
    (0..loops.len())
        .map(|i| {
            region[i].sign().is_none() && {
                let mut sum = area(i);
                for &c in &children[i] {
                    sum += area(c);
                }
                sum.is_zero()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::level::Level;
    use num_traits::Zero;
    use proptest::prelude::*;

    proptest! {
        /// The enclosures change no answer: each region is zero exactly
        /// when the exact sum of its loops' areas is. Squares and
        /// collapsed loops (out and back) on a small grid, their corners
        /// vertices (doubles) or crossings a third of the way along an
        /// edge (not doubles: loose enclosures), a child the reverse of its
        /// parent (a zero region) now and then, at scale 1 and at both ends
        /// of the range in the frame such a mesh takes.
        #[test]
        fn zero_regions_are_the_exact_ones(
            shapes in prop::collection::vec((0i32..8, 0i32..8, 0i32..4, 0usize..4, any::<bool>()), 1..12),
            parents in prop::collection::vec(prop::option::weighted(0.6, 0usize..12), 12),
            shift in prop_oneof![Just(0i32), -1040i32..-1000, 1000i32..1020],
        ) {
            let s = |v: f64| crate::exact::scale::times_pow2(v, shift);
            let level = Level::new(Rat::zero());
            let at = |x: i32, y: i32, crossing: bool| {
                let (x, y) = (f64::from(x), f64::from(y));
                if crossing {
                    // (x + 1/3, y + 1/3) at z = 0.
                    LoopPoint::on_edge([s(x), s(y), s(-1.0)], [s(x + 1.0), s(y + 1.0), s(2.0)], &level)
                } else {
                    LoopPoint::of_vertex([s(x), s(y), 0.0])
                }
            };
            let mut loops: Vec<Vec<LoopPoint>> = Vec::new();
            let mut parent: Vec<Option<usize>> = Vec::new();
            for (i, &(x, y, d, kind, crossing)) in shapes.iter().enumerate() {
                let square = vec![at(x, y, crossing), at(x + d, y, crossing), at(x + d, y + d, crossing), at(x, y + d, crossing)];
                // A parent comes before its child (a forest).
                let (points, p) = match kind {
                    1 if i > 0 => (loops[i - 1].iter().rev().cloned().collect(), Some(i - 1)),
                    2 => (vec![at(x, y, crossing), at(x + d, y + 1, crossing)], parents[i].filter(|&p| p < i)),
                    _ => (square, parents[i].filter(|&p| p < i)),
                };
                loops.push(points);
                parent.push(p);
            }
            let shapes: Vec<(&[LoopPoint], Option<usize>)> =
                loops.iter().zip(&parent).map(|(l, &p)| (l.as_slice(), p)).collect();
            let frame = Frame::for_points(
                loops.iter().flatten().map(|p| { let [x, y] = p.to_f64(); [x, y, 0.0] }),
            );
            let mut exact: Vec<Rat> = loops.iter().map(|l| signed_area(l)).collect();
            for (i, p) in parent.iter().enumerate() {
                if let Some(p) = *p {
                    let a = signed_area(&loops[i]);
                    exact[p] += a;
                }
            }
            let want: Vec<bool> = exact.iter().map(|a| a.is_zero()).collect();
            prop_assert_eq!(zero_regions(&shapes, frame), want);
        }
    }
}
