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
//! one point. A loop is collapsed when its limit encloses no material on
//! one side: every piece of it runs along a ridge or valley edge (S_NO) or
//! shrinks to a point, so the region it bounds with its neighbours has
//! zero area in the limit (around an extremum, along a ridge and back, on
//! both sides of a closed ridge ring).

use super::{LevelBuilder, Loop, SliceError};
use crate::chain::chain_loops;
use crate::classify::Side;
use crate::exact::perturbed::{orientation, EpsPoint, Motion, Towards};
use crate::exact::point::LoopPoint;
use crate::exact::Sign;
use crate::ids::{EdgeId, VertexId};
use crate::nest::{nest, Family};
use crate::segment::{face_segment, Carrier, CutPoint, Segment, Via};

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
        let moving: Vec<Vec<EpsPoint<'_>>> = chained
            .iter()
            .map(|c| {
                c.crossings
                    .iter()
                    .zip(&c.run_of)
                    .map(|(&(_, [a, b]), &r)| {
                        let motion = Motion {
                            a: self.mesh.pos(a),
                            b: self.mesh.pos(b),
                            towards,
                        };
                        EpsPoint::new(&c.points[r as usize], motion)
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
        let mut loops = Vec::with_capacity(chained.len());
        for ((c, sign), n) in chained.into_iter().zip(signs).zip(nesting) {
            let collapsed = self.is_collapsed(&c, &segments);
            loops.push(Loop {
                cuts: c.cuts,
                points: c.points,
                orientation: sign,
                role: n.role,
                parent: n.parent,
                collapsed,
                crossings: c.crossings.into_iter().map(|(e, _)| e).collect(),
            });
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
    /// across their edge has its third vertex on the same side.
    fn is_collapsed(&self, c: &Chained, segments: &[Segment]) -> bool {
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
