//! Input: a validated mesh and an exact level. Output: the complete
//! [`LevelSet`] of SPEC sections 3 to 6: contours S_O, face regions F with
//! their boundaries dF, ridges and valleys S_NO, extremal points P, saddles,
//! and the one-sided limits L- and L+, every loop nested.
//!
//! Everything here is exact; points and areas are exact rationals in the
//! mesh's units. Rounding happens only in `output`.

pub mod check;
mod limits;
pub mod ridges;

use crate::chain::{chain_loops, ChainError};
use crate::classify::{
    edges::classify_edges, faces::face_regions, vertices::extremum_kind, EdgeClass, ExtremumKind,
    Facing, RidgeKind, Side, Signs,
};
use crate::exact::area::{rounded_area, signed_area, total_signed_area};
use crate::exact::crossing::{Crossings, EdgeGridEnds};
use crate::exact::filter::{signed_area_filtered, FilteredPoint};
use crate::exact::frame::Frame;
use crate::exact::grid::MeshGrid;
use crate::exact::point::{LoopPoint, Scale};
use crate::exact::rational::{rat_div, rat_to_f64, Rat};
use crate::exact::{Level, Point2, Sign};
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::validate::{accept, Report};
use crate::mesh::Mesh;
use crate::nest::{nest, Family, Role};
use crate::segment::{edge_segments, face_segment, Carrier, CutPoint, Segment, Via};
use num_traits::One;
use rustc_hash::FxHashMap as HashMap;
use std::sync::Arc;

/// A closed, oriented loop with exact points.
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// The mesh element each point lies on, in order (first not repeated).
    pub cuts: Vec<CutPoint>,
    /// Exact points, in the mesh's units (held as integers when they
    /// fit; [`LoopPoint::exact`] gives reduced rationals).
    pub points: Vec<LoopPoint>,
    /// The exact sign of the signed area: positive when counter-clockwise
    /// (for L- and L+, at `c -/+ epsilon`: see `collapsed`).
    pub orientation: Sign,
    /// Outer or hole, from the nesting depth in its family.
    pub role: Role,
    /// Index of the smallest enclosing loop of the same family.
    pub parent: Option<usize>,
    /// L-, L+ only: the loop has collapsed in the limit (SPEC section 6):
    /// it runs only along ridges or valleys, or around an extremum, so
    /// the material (or void) it bounds on one side has zero area at the
    /// level. Its orientation and role are those at `c -/+ epsilon`.
    pub collapsed: bool,
    /// L-, L+ at a level with a vertex on the plane: the edges the loop
    /// crosses at `c -/+ epsilon`, in order (its structure; `cuts` are
    /// their limits, merged). Empty otherwise.
    pub crossings: Vec<EdgeId>,
}

impl Loop {
    /// The exact signed area (positive when counter-clockwise). Computed
    /// on each call, in time near-linear in the size of the result.
    pub fn area(&self) -> Rat {
        signed_area(&self.points)
    }

    /// The signed area as a double: from the nearest doubles of the points
    /// (`rounded`, as [`LoopPoint::to_f64`] gives them), within the
    /// certified bound of [`rounded_area`] (about `n u d (4m + 3d)` for
    /// `n` points, loop size `d`, distance `m` from the origin) and of the
    /// exact sign; where that bound cannot show the sign, the nearest
    /// double of the exact area, and `f64::MAX` of its sign when it lies
    /// beyond the doubles (JSON has no infinity). A function of the exact
    /// loop alone.
    pub fn rounded_area(&self, rounded: &[[f64; 2]]) -> f64 {
        let r = rounded_area(rounded).unwrap_or_else(|| rat_to_f64(&self.area()));
        if r.is_finite() {
            r
        } else if r < 0.0 {
            f64::MIN
        } else {
            f64::MAX
        }
    }
}

/// The exact total signed area of a family of loops (the area they
/// enclose, holes counted negative).
pub fn total_area(loops: &[Loop]) -> Rat {
    total_signed_area(loops.iter().map(|l| l.points.as_slice()))
}

/// The exact sign of a polygon's area: filtered, exact when the filter
/// cannot tell.
fn orientation_of(filtered: &[FilteredPoint<'_>], points: &[LoopPoint]) -> Sign {
    signed_area_filtered(filtered)
        .sign
        .unwrap_or_else(|| Sign::of_rat(&signed_area(points)))
}

/// A face region F with its boundary loops dF.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceRegion {
    /// Facing.
    pub facing: Facing,
    /// Its faces, ascending.
    pub faces: Vec<FaceId>,
    /// Exact unsigned area.
    pub area: Rat,
    /// Boundary loops in the direction the faces induce, nested within the
    /// region.
    pub boundary: Vec<Loop>,
}

/// A maximal S_NO polyline.
#[derive(Clone, Debug, PartialEq)]
pub struct Ridge {
    /// Ridge or valley.
    pub kind: RidgeKind,
    /// Closed cycle or open polyline.
    pub closed: bool,
    /// Vertices in order.
    pub vertices: Vec<VertexId>,
    /// Their exact points.
    pub points: Vec<Point2>,
}

/// An isolated extremal vertex P.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtremalPoint {
    /// The vertex.
    pub vertex: VertexId,
    /// Min or max.
    pub kind: ExtremumKind,
    /// Its exact point.
    pub point: Point2,
}

/// A saddle vertex with its `2m` S_O branches (`m >= 2`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Saddle {
    /// The vertex.
    pub vertex: VertexId,
    /// Number of S_O branches `2m`.
    pub branches: u32,
}

/// The weak-Morse level set of a mesh at one exact level.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelSet {
    /// The exact level, in the mesh's units.
    pub level: Rat,
    /// S_O: oriented contours, material on the left. Shared with `below`
    /// and `above` when no vertex lies on the plane (they are then the
    /// same loops; `Arc::ptr_eq` tells).
    pub contours: Arc<Vec<Loop>>,
    /// F with dF.
    pub regions: Vec<FaceRegion>,
    /// S_NO.
    pub ridges: Vec<Ridge>,
    /// P.
    pub extrema: Vec<ExtremalPoint>,
    /// Saddles.
    pub saddles: Vec<Saddle>,
    /// L-: the contour just below the level.
    pub below: Arc<Vec<Loop>>,
    /// L+: the contour just above the level.
    pub above: Arc<Vec<Loop>>,
}

/// Why slicing failed.
#[derive(Debug, thiserror::Error)]
pub enum SliceError {
    /// The mesh is not accepted (SPEC section 1); the report names every
    /// defect, its measures (volume, bounding box) in the mesh's units
    /// times the slicer's unit (a snapped mesh's file units).
    #[error("the mesh is not accepted for slicing (SPEC 1: closed, oriented, manifold, no fold, self-intersection or degenerate face):\n{0}")]
    InvalidMesh(Box<Report>),
    /// Chaining failed: an internal error.
    #[error(transparent)]
    Chain(#[from] ChainError),
    /// An exact invariant of SPEC section 7 failed: an internal error.
    #[error("invariant violated at level {level}: {what} (internal error, please report)")]
    Invariant {
        /// The level, as `p/q`.
        level: String,
        /// What failed.
        what: String,
    },
}

/// Slices one validated mesh at exact levels.
///
/// ```
/// use wmslice::{datasets, exact::parse_rational, Slicer};
/// let mesh = datasets::by_name("unit_cube").unwrap().build();
/// let slicer = Slicer::new(&mesh).unwrap();
/// let ls = slicer.slice_at(&parse_rational("1/2").unwrap()).unwrap();
/// assert_eq!(ls.contours.len(), 1);
/// assert_eq!(ls.contours[0].area(), parse_rational("1").unwrap());
/// // At the top face: one up-facing region, no contour.
/// let top = slicer.slice_at(&parse_rational("1").unwrap()).unwrap();
/// assert!(top.contours.is_empty());
/// assert_eq!(top.regions.len(), 1);
/// ```
pub struct Slicer<'m> {
    mesh: &'m Mesh,
    topo: Topology,
    unit: Rat,
    /// The positions on one binary grid, when they fit (fast crossings).
    grid: Option<MeshGrid>,
    /// Off that grid: which vertices may end an edge of the per-edge
    /// integer crossing (`None`: all may).
    ends: Option<EdgeGridEnds>,
    /// The power of two the filters scale by (the identity unless the
    /// mesh lies at the ends of the double range).
    frame: Frame,
}

impl<'m> Slicer<'m> {
    /// Validates the mesh and builds its topology. The coordinates are
    /// taken exactly as stored.
    pub fn new(mesh: &'m Mesh) -> Result<Self, SliceError> {
        Self::with_unit(mesh, Rat::one())
    }

    /// As [`Slicer::new`], for a mesh whose stored coordinates are integers
    /// on the grid `unit` (a snapped mesh): the true coordinate is
    /// `stored * unit`, exactly.
    pub fn with_unit(mesh: &'m Mesh, unit: Rat) -> Result<Self, SliceError> {
        // The grid (a pass over the coordinates) beside validation.
        let parallel = mesh.num_faces() >= crate::par::MIN_LEN;
        let (accepted, (grid, ends)) = crate::par::join(
            parallel,
            || accept(mesh),
            || {
                let p = &mesh.positions;
                (MeshGrid::new(p), EdgeGridEnds::new(p))
            },
        );
        // A snapped mesh is stored in grid steps: the report's measures in
        // the file's units.
        let topo = accepted.map_err(|r| SliceError::InvalidMesh(Box::new(r.in_units(&unit))))?;
        Ok(Slicer {
            mesh,
            topo,
            unit,
            grid,
            ends,
            frame: Frame::for_points(mesh.positions.iter().copied()),
        })
    }

    /// The mesh's topology.
    pub fn topology(&self) -> &Topology {
        &self.topo
    }

    /// The mesh being sliced.
    pub fn mesh(&self) -> &Mesh {
        self.mesh
    }

    /// The grid unit: a stored coordinate times `unit` is the true one.
    pub fn unit(&self) -> &Rat {
        &self.unit
    }

    /// The complete level set at the exact level `c` (in the mesh's units).
    pub fn slice_at(&self, c: &Rat) -> Result<LevelSet, SliceError> {
        let grid_level = self.grid_level(c);
        let active: Vec<FaceId> = (0..self.mesh.num_faces())
            .map(FaceId::from_idx)
            .filter(|&f| touches(self.mesh, f, &grid_level))
            .collect();
        self.slice_active(c, &grid_level, &active)
    }

    /// The level `c` in the stored (grid) units.
    pub(crate) fn grid_level(&self, c: &Rat) -> Arc<Level> {
        Arc::new(Level::new(rat_div(c, &self.unit)))
    }

    /// The level set at `c` (`level` is `c` in grid units) from the faces
    /// that touch or cross the plane, ascending. Every element of the level
    /// set belongs to such a face, so the result equals [`Slicer::slice_at`];
    /// the layer sweep supplies `active` without scanning the mesh.
    pub(crate) fn slice_active(
        &self,
        c: &Rat,
        grid_level: &Arc<Level>,
        active: &[FaceId],
    ) -> Result<LevelSet, SliceError> {
        let mut ls = LevelBuilder::new(self, grid_level, active)
            .build(c)
            .map_err(|e| match e {
                // Name the level the caller asked for; the numbers in `what`
                // are the grid's.
                SliceError::Invariant { what, .. } if !self.unit.is_one() => {
                    SliceError::Invariant {
                        level: crate::exact::rational::rat_to_string(c),
                        what: format!("{what} (in units of the snapping grid)"),
                    }
                }
                e => e,
            })?;
        if !self.unit.is_one() {
            let u = &self.unit;
            // The signs are unchanged (u^2 > 0). The unit is split into
            // integer parts once, not per point.
            let unit = Scale::new(u);
            let scale = |l: &mut Loop| {
                for p in &mut l.points {
                    *p = p.scaled_by(&unit);
                }
            };
            let shared = Arc::ptr_eq(&ls.contours, &ls.below);
            Arc::make_mut(&mut ls.contours).iter_mut().for_each(scale);
            if shared {
                ls.below = Arc::clone(&ls.contours);
                ls.above = Arc::clone(&ls.contours);
            } else {
                Arc::make_mut(&mut ls.below).iter_mut().for_each(scale);
                Arc::make_mut(&mut ls.above).iter_mut().for_each(scale);
            }
            // Areas scale by u^2 (a big product: only for a level with
            // regions).
            if !ls.regions.is_empty() {
                let u2 = u * u;
                for r in &mut ls.regions {
                    r.area *= &u2;
                    r.boundary.iter_mut().for_each(scale);
                }
            }
            for r in &mut ls.ridges {
                r.points.iter_mut().for_each(|p| *p = p.scaled(u));
            }
            for e in &mut ls.extrema {
                e.point = e.point.scaled(u);
            }
        }
        Ok(ls)
    }
}

/// Whether face `f` touches or crosses the plane (min <= c <= max), exactly.
pub(crate) fn touches(mesh: &Mesh, f: FaceId, level: &Level) -> bool {
    let s = mesh.faces[f.idx()].map(|v| level.sign_of(mesh.positions[v.idx()][2]));
    s.contains(&Sign::Zero) || (s.contains(&Sign::Positive) && s.contains(&Sign::Negative))
}

struct LevelBuilder<'a> {
    mesh: &'a Mesh,
    topo: &'a Topology,
    /// Builds the exact points (on the mesh's grid when it fits).
    points: Crossings<'a>,
    level: &'a Level,
    signs: Signs<'a>,
    active: &'a [FaceId],
}

impl<'a> LevelBuilder<'a> {
    fn new(slicer: &'a Slicer<'a>, level: &'a Arc<Level>, active: &'a [FaceId]) -> Self {
        LevelBuilder {
            mesh: slicer.mesh,
            topo: &slicer.topo,
            points: Crossings::new(
                slicer.grid.as_ref(),
                slicer.ends.as_ref(),
                level,
                slicer.frame,
            ),
            level,
            signs: Signs::new(slicer.mesh, level),
            active,
        }
    }

    fn vertex_point(&self, v: VertexId) -> Point2 {
        Point2::of_vertex(self.mesh.pos(v))
    }

    /// The vertices carrying cut point `c` (an edge's ends: one lookup in
    /// the edge table).
    fn carrier(&self, c: CutPoint) -> Carrier {
        match c {
            CutPoint::AtVertex(v) => [v; 2],
            CutPoint::OnEdge(e) => self.topo.edge(e).v,
        }
    }

    /// The exact point of cut point `c`, carried by `[a, b]`.
    fn cut_point(&self, c: CutPoint, [a, b]: Carrier) -> LoopPoint {
        match c {
            CutPoint::AtVertex(v) => self.points.vertex(v, self.mesh.pos(v)),
            CutPoint::OnEdge(_) => self
                .points
                .crossing(a, b, self.mesh.pos(a), self.mesh.pos(b)),
        }
    }

    /// The level set; `c` is the level in the caller's units (the
    /// builder's level is in grid units).
    fn build(self, c: &Rat) -> Result<LevelSet, SliceError> {
        let mesh = self.mesh;
        let topo = self.topo;
        let signs = &self.signs;

        // One pass over the faces touching the plane, each vertex sign
        // taken once per face: F's faces (three zeros), in-plane edge
        // candidates, vertices on the plane, and the S_O segments of
        // crossed faces (faces of F have no segment: no + and -). Each
        // segment's start carrier comes with it, so no edge is looked up
        // again.
        let mut in_plane: Vec<FaceId> = Vec::new();
        let mut candidates: Vec<EdgeId> = Vec::new();
        let mut on_plane: Vec<VertexId> = Vec::new();
        // A crossed face has one segment: room for all, so no level
        // grows these step by step.
        let mut segments: Vec<Segment> = Vec::with_capacity(self.active.len());
        let mut carriers: Vec<Carrier> = Vec::with_capacity(self.active.len());
        for &f in self.active {
            let tri = mesh.faces[f.idx()];
            let s = tri.map(|v| signs.of(v));
            if s.contains(&Sign::Zero) {
                if s.iter().all(|&x| x == Sign::Zero) {
                    in_plane.push(f);
                }
                // Every face around an on-plane vertex or edge touches the
                // plane, so each is taken once: from its first fan face,
                // from its first face.
                for c in 0..3 {
                    if s[c] == Sign::Zero {
                        let v = tri[c];
                        if topo.fan(v).first().is_some_and(|e| e.face == f) {
                            on_plane.push(v);
                        }
                        if s[(c + 1) % 3] == Sign::Zero {
                            let e = topo.face_edges[f.idx()][c];
                            if topo.edge(e).faces[0] == f {
                                candidates.push(e);
                            }
                        }
                    }
                }
            }
            if let Some((seg, [start, _])) = face_segment(topo, f, tri, s) {
                segments.push(seg);
                carriers.push(start);
            }
        }
        let mut region_of = HashMap::default();
        let regions = face_regions(mesh, topo, signs, &in_plane, &mut region_of);
        candidates.sort_unstable();
        on_plane.sort_unstable();
        let edges = classify_edges(topo, signs, &candidates, &regions, &region_of);

        // S_O: the crossed faces' segments, then transversal edges and
        // shared dF edges.
        for s in edge_segments(&edges) {
            carriers.push(self.carrier(s.from));
            segments.push(s);
        }
        let contours = Arc::new(self.loops_with(&segments, Some(&carriers))?);

        // Saddles: on-plane vertices with 2m >= 4 S_O branches.
        let mut branches: HashMap<VertexId, u32> = HashMap::default();
        for s in &segments {
            for c in [s.from, s.to] {
                if let CutPoint::AtVertex(v) = c {
                    *branches.entry(v).or_default() += 1;
                }
            }
        }
        let mut saddles: Vec<Saddle> = branches
            .into_iter()
            .filter(|&(_, b)| b >= 4)
            .map(|(vertex, branches)| Saddle { vertex, branches })
            .collect();
        saddles.sort_unstable_by_key(|s| s.vertex);

        // dF: each region's boundary, chained by the same vertex rule.
        let mut face_regions_out = Vec::with_capacity(regions.len());
        for r in regions {
            let segs: Vec<Segment> = r
                .boundary
                .iter()
                .map(|b| Segment {
                    from: CutPoint::AtVertex(b.from),
                    to: CutPoint::AtVertex(b.to),
                    via: Via::Edge(b.edge),
                })
                .collect();
            let boundary = self.loops(&segs)?;
            face_regions_out.push(FaceRegion {
                facing: r.facing,
                faces: r.faces,
                area: r.area,
                boundary,
            });
        }

        // S_NO.
        let sno: Vec<(EdgeId, [VertexId; 2], RidgeKind)> = edges
            .iter()
            .filter_map(|e| match e.class {
                EdgeClass::Extremal(kind) => Some((e.edge, topo.edge(e.edge).v, kind)),
                _ => None,
            })
            .collect();
        let ridges = ridges::join_ridges(&sno)
            .into_iter()
            .map(|p| Ridge {
                kind: p.kind,
                closed: p.closed,
                points: p.vertices.iter().map(|&v| self.vertex_point(v)).collect(),
                vertices: p.vertices,
            })
            .collect();

        // P.
        let extrema = on_plane
            .iter()
            .copied()
            .filter_map(|v| {
                extremum_kind(topo, signs, v).map(|kind| ExtremalPoint {
                    vertex: v,
                    kind,
                    point: self.vertex_point(v),
                })
            })
            .collect();

        // With no vertex on the plane, perturbing zero signs changes
        // nothing: L- and L+ are S_O, segment for segment.
        let (below, above) = if on_plane.is_empty() {
            (Arc::clone(&contours), Arc::clone(&contours))
        } else {
            (
                Arc::new(self.one_sided(Side::Below)?),
                Arc::new(self.one_sided(Side::Above)?),
            )
        };

        let ls = LevelSet {
            level: c.clone(),
            contours,
            regions: face_regions_out,
            ridges,
            extrema,
            saddles,
            below,
            above,
        };
        check_orientation(&ls)?;
        Ok(ls)
    }

    fn loops(&self, segments: &[Segment]) -> Result<Vec<Loop>, SliceError> {
        self.loops_with(segments, None)
    }

    /// An internal error at this level.
    fn invariant(&self, what: String) -> SliceError {
        SliceError::Invariant {
            level: crate::exact::rational::rat_to_string(self.level.value()),
            what,
        }
    }

    /// Chains S_O or dF segments, computes exact points, decides
    /// orientations and nests. `carriers[i]`, when given, carries the
    /// start of `segments[i]`.
    fn loops_with(
        &self,
        segments: &[Segment],
        carriers: Option<&[Carrier]>,
    ) -> Result<Vec<Loop>, SliceError> {
        let chains = chain_loops(self.topo, segments)?;
        let start = |i: usize| {
            let c = segments[i].from;
            let carrier = carriers.map_or_else(|| self.carrier(c), |k| k[i]);
            (c, self.cut_point(c, carrier))
        };
        let shapes: Vec<(Vec<CutPoint>, Vec<LoopPoint>)> = chains
            .iter()
            .map(|ch| ch.iter().map(|&i| start(i)).unzip())
            .collect();
        let mut filtered: Vec<Vec<FilteredPoint<'_>>> = shapes
            .iter()
            .map(|(_, pts)| {
                pts.iter()
                    .map(|p| FilteredPoint::approximate(p, self.points.frame()))
                    .collect()
            })
            .collect();
        let orientations: Vec<Sign> = filtered
            .iter()
            .zip(&shapes)
            .map(|(f, (_, pts))| orientation_of(f, pts))
            .collect();
        let nesting = if shapes.len() < 2 {
            Vec::new()
        } else {
            filtered
                .iter_mut()
                .flatten()
                .for_each(FilteredPoint::enclose);
            let reps = representatives(shapes.iter().map(|(cuts, _)| cuts.as_slice()));
            nest(&Family {
                loops: &filtered,
                orientation: &orientations,
                representative: &reps,
            })
        };
        drop(filtered);
        let mut loops = Vec::with_capacity(shapes.len());
        for (i, (cuts, points)) in shapes.into_iter().enumerate() {
            let orientation = orientations[i];
            let (role, parent) = nesting
                .get(i)
                .map_or((Role::Outer, None), |n| (n.role, n.parent));
            loops.push(Loop {
                cuts,
                points,
                orientation,
                role,
                parent,
                collapsed: false,
                crossings: Vec::new(),
            });
        }
        Ok(loops)
    }
}

/// For each loop of S_O or dF, a point on no other loop of its family: an
/// edge crossing (each edge is crossed once), or a vertex no other loop
/// passes (loops meet only at vertices on the plane, and a segment's
/// interior, in a face or along an edge, holds no vertex).
fn representatives<'c>(loops: impl Iterator<Item = &'c [CutPoint]> + Clone) -> Vec<Option<usize>> {
    let mut count: HashMap<VertexId, u32> = HashMap::default();
    for c in loops.clone().flatten() {
        if let CutPoint::AtVertex(v) = c {
            *count.entry(*v).or_default() += 1;
        }
    }
    loops
        .map(|cuts| {
            cuts.iter().position(|c| match c {
                CutPoint::OnEdge(_) => true,
                CutPoint::AtVertex(v) => count.get(v) == Some(&1),
            })
        })
        .collect()
}

/// SPEC 7.3, checked exactly: outer loops of S_O, L- and L+ have positive
/// area, holes negative.
fn check_orientation(ls: &LevelSet) -> Result<(), SliceError> {
    for (name, family) in [("S_O", &ls.contours), ("L-", &ls.below), ("L+", &ls.above)] {
        for (i, l) in family.iter().enumerate() {
            let ok = match l.role {
                Role::Outer => l.orientation == Sign::Positive,
                Role::Hole => l.orientation == Sign::Negative,
            };
            if !ok {
                return Err(SliceError::Invariant {
                    level: crate::exact::rational::rat_to_string(&ls.level),
                    what: format!(
                        "{name} loop {i} is {:?} but its exact area is {}",
                        l.role,
                        l.area()
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The `2m` of a saddle, as `m`.
impl Saddle {
    /// `m`: 2 for an ordinary saddle, 3 for a monkey saddle.
    pub fn m(&self) -> u32 {
        self.branches / 2
    }
}
