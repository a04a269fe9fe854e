//! Input: a [`Mesh`] as loaded. Output: a [`Report`]: counts, genus,
//! bounding box, exact volume and every [`Defect`] with the element ids it
//! concerns, and the [`Topology`] when the mesh is structurally sound.
//!
//! A mesh is accepted for slicing (SPEC section 1) when it has no defect of
//! [`Severity::Error`]: closed, every edge in exactly two faces with
//! opposite directions, every vertex link one cycle, no fold, no
//! self-intersection, finite coordinates, indices in range, no repeated
//! vertex in a face, no duplicate face, no degenerate face (three collinear
//! vertices: those an edge flip removes are removed before, by
//! [`crate::mesh::flip`], so one left is named with the reason it could not
//! be flipped), exact signed volume > 0, and every shell facing the way
//! its place among the others demands ([`crate::mesh::shells`]). Unused
//! vertices are reported as warnings, and so, in a mesh that is not
//! closed, are vertices at the point of another. Every test is exact.
//!
//! Folds and self-intersections are decided for closed, oriented, manifold
//! meshes with finite coordinates (the others are rejected already), by
//! [`crate::mesh::intersect`]. A fold is the one self-intersection of two
//! faces on an edge that proper triangles can have; it is reported as
//! [`Defect::Fold`], by its edge, and never again as a
//! [`Defect::SelfIntersection`], which names every other pair.
//! [`accept`] gives the slicer the same verdict, without computing the
//! exact volume of a mesh that a certified floating-point sum shows to be
//! positive.

use crate::exact::predicates::{is_degenerate_triangle, Sign};
use crate::exact::rational::{rat_to_string, Rat};
use crate::exact::volume::{signed_volume, volume_sign_filter};
use crate::ids::{FaceId, VertexId};
use crate::mesh::flip::{diagnose, Unflippable};
pub use crate::mesh::intersect::Tally;
use crate::mesh::intersect::{face_pairs, EdgeOverlap};
pub use crate::mesh::shells::ShellFacing;
use crate::mesh::shells::{misnested_shells, shells};
use crate::mesh::topology::{Topology, TopologyIssue, NO_FACE};
use crate::mesh::weld::coordinate_key;
use crate::mesh::Mesh;
use crate::par;
use num_traits::Signed;
use rayon::prelude::*;
use std::collections::HashMap;
use std::fmt;

/// At most this many defects are listed; the rest are counted.
pub const MAX_LISTED_DEFECTS: usize = 1000;

/// The search for self-intersections stops counting pairs of faces that
/// meet beyond a shared vertex or with none shared when it has found this
/// many ([`Tally::AtLeast`]); the listed ones are the same. A fuzzed
/// 13 574-face PLY file (a soup of faces spanning the `f32` range) has 8.8
/// million such pairs, and took 29 s to count.
pub const MAX_COUNTED_PAIRS: usize = 10 * MAX_LISTED_DEFECTS;

/// Whether a defect blocks slicing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// The slicer rejects the mesh.
    Error,
    /// Reported; the mesh stays sliceable.
    Warning,
}

/// How a duplicate face runs against the first face on its three
/// vertices (their cyclic orders compared: exact, no geometry).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Turn {
    /// The same way round: one face written twice.
    Same,
    /// The other way round: two bodies touch along it (files that hold
    /// several bodies, e.g. a multibody CAD export), or the surface folds
    /// back into a sheet there.
    Reversed,
}

impl Turn {
    /// How face `b` runs against face `a`, both on the same three vertices
    /// (so `b[0]` is one of `a`'s): the same way when `b[1]` follows
    /// `b[0]` in `a` too.
    fn of(a: [VertexId; 3], b: [VertexId; 3]) -> Turn {
        let i = a.iter().position(|&v| v == b[0]).unwrap_or(0);
        if a[(i + 1) % 3] == b[1] {
            Turn::Same
        } else {
            Turn::Reversed
        }
    }
}

impl fmt::Display for Turn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Turn::Same => "the same way round (one face written twice)",
            Turn::Reversed => {
                "turned the other way (two bodies touching along it, as a multibody file holds them, or a sheet)"
            }
        })
    }
}

/// One defect of a mesh, naming the elements involved.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Defect {
    /// The mesh has no face.
    #[error("the mesh has no faces")]
    Empty,
    /// A face refers to a vertex that does not exist.
    #[error("face {face} corner {corner} refers to vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// The face.
        face: FaceId,
        /// Corner 0, 1 or 2.
        corner: u8,
        /// The bad index.
        index: u32,
        /// The number of vertices.
        vertices: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: VertexId,
    },
    /// A face uses one vertex twice.
    #[error("face {face} repeats a vertex")]
    RepeatedVertex {
        /// The face.
        face: FaceId,
    },
    /// The same three vertices form two faces.
    #[error("face {face} duplicates face {first}, {turn}")]
    DuplicateFace {
        /// The later face.
        face: FaceId,
        /// The first face with these vertices.
        first: FaceId,
        /// Whether it runs the same way round as `first`.
        turn: Turn,
    },
    /// An edge with only one face: the mesh is not closed.
    #[error("open edge {a}-{b}: only face {face} uses it")]
    OpenEdge {
        /// Endpoint.
        a: VertexId,
        /// Endpoint.
        b: VertexId,
        /// The single face.
        face: FaceId,
    },
    /// An edge shared by more than two faces.
    #[error("non-manifold edge {a}-{b} is shared by {} faces: {}", faces.len(), list(faces))]
    NonManifoldEdge {
        /// Endpoint.
        a: VertexId,
        /// Endpoint.
        b: VertexId,
        /// Every face on the edge.
        faces: Vec<FaceId>,
    },
    /// A face whose three edges all run the same way as its neighbours'.
    #[error("face {face} is flipped: all its edges run the same way as its neighbours'")]
    FlippedFace {
        /// The face.
        face: FaceId,
    },
    /// Two faces traverse an edge in the same direction.
    #[error(
        "edge {a}-{b} is traversed the same way by faces {}: inconsistent orientation",
        list(faces)
    )]
    InconsistentEdge {
        /// Endpoint.
        a: VertexId,
        /// Endpoint.
        b: VertexId,
        /// The two faces.
        faces: Vec<FaceId>,
    },
    /// The faces around a vertex form several cycles (a pinch point).
    #[error("bowtie vertex {vertex}: its faces form {cycles} separate fans")]
    BowtieVertex {
        /// The vertex.
        vertex: VertexId,
        /// Number of fans.
        cycles: usize,
    },
    /// Two faces on one edge lie in one plane on the same side of it
    /// (zero-thickness fold), decided with exact orient3d and orient2d.
    #[error("faces {} fold onto each other along edge {a}-{b}", list(faces))]
    Fold {
        /// Endpoint.
        a: VertexId,
        /// Endpoint.
        b: VertexId,
        /// The two faces.
        faces: Vec<FaceId>,
    },
    /// Two faces meet anywhere but in the vertices and edges they share
    /// (touching counts), decided exactly; `a < b`. Two faces on an edge
    /// that fold onto each other are a [`Defect::Fold`] instead.
    #[error("faces {a} and {b} intersect: they meet outside the vertices and edges they share")]
    SelfIntersection {
        /// The face with the smaller id.
        a: FaceId,
        /// The other face.
        b: FaceId,
    },
    /// The exact signed volume is not positive: the mesh is inside out.
    #[error(
        "signed volume {volume} is not positive: faces must be counter-clockwise seen from outside"
    )]
    NotOutward {
        /// The exact signed volume.
        volume: String,
    },
    /// A shell (a connected component of the surface) whose orientation
    /// disagrees with where it lies, so that the faces bound no solid: an
    /// outward shell inside the material (a solid in a solid, counted
    /// twice), or an inward one outside it (a cavity in empty space).
    /// Decided exactly ([`crate::mesh::shells`]).
    #[error(
        "the shell of face {face} faces {facing}, but the winding number of the other shells around it is \
         {winding}: a shell facing outward must lie outside the material (0), a cavity's shell facing inward \
         inside it (1)"
    )]
    MisnestedShell {
        /// The shell's lowest face id.
        face: FaceId,
        /// Which way the shell faces (the sign of its own exact volume).
        facing: ShellFacing,
        /// The winding number of the other shells around it.
        winding: i64,
    },
    /// A face whose three vertices are collinear (zero area), left after
    /// the repair by edge flips ([`crate::mesh::flip::repair_degenerate`]),
    /// with the reason no flip removed it.
    #[error("face {face} is degenerate (its vertices are collinear): {why}")]
    DegenerateFace {
        /// The face.
        face: FaceId,
        /// Why no edge flip removed it.
        why: Unflippable,
    },
    /// A used vertex at exactly the point of an earlier used vertex, in a
    /// mesh that is not a closed manifold: the likely cause of its open
    /// edges (an indexed file with seams, say). Listed as a note; such a
    /// mesh is refused for its other defects. Indexed formats are taken as
    /// given; `--weld` ([`crate::mesh::prepare::CoincidentVertices::Weld`])
    /// merges equal coordinates, and so does `--snap`.
    #[error("vertex {vertex} lies exactly where vertex {first} does: faces across them do not connect (--weld merges vertices with equal coordinates, exactly; --snap also does)")]
    CoincidentVertex {
        /// The later vertex.
        vertex: VertexId,
        /// The first vertex at that point.
        first: VertexId,
    },
    /// A vertex no face uses (accepted and ignored).
    #[error("vertex {vertex} is not used by any face")]
    UnusedVertex {
        /// The vertex.
        vertex: VertexId,
    },
}

fn list(faces: &[FaceId]) -> String {
    faces
        .iter()
        .map(|f| f.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

impl Defect {
    /// Whether this defect blocks slicing.
    pub fn severity(&self) -> Severity {
        match self {
            Defect::UnusedVertex { .. } | Defect::CoincidentVertex { .. } => Severity::Warning,
            _ => Severity::Error,
        }
    }
}

/// Counts and exact measures of a mesh.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Number of vertices (as stored).
    pub vertices: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of undirected edges; `None` (not counted) when a face
    /// repeats a vertex or names one that does not exist.
    pub edges: Option<usize>,
    /// Connected components (of faces across shared edges); `None` as for
    /// `edges`.
    pub components: Option<usize>,
    /// V - E + F over the used vertices; `None` as for `edges`.
    pub euler_characteristic: Option<i64>,
    /// `(2 C - chi) / 2` for a closed orientable surface, else `None`.
    pub genus: Option<i64>,
    /// Exact coordinates as stored: `[min, max]` per axis (the nearest
    /// doubles in the mesh's units after [`Report::in_units`]).
    pub bounding_box: Option<[[f64; 3]; 2]>,
    /// Exact signed volume, as `"p/q"`; `None` when a face names a vertex
    /// that does not exist.
    pub volume: Option<String>,
}

/// The result of validation.
#[derive(Clone, Debug)]
pub struct Report {
    /// Counts and measures.
    pub stats: Stats,
    /// Listed defects: at most [`MAX_LISTED_DEFECTS`] errors and as many
    /// warnings (so that warnings never hide an error).
    pub defects: Vec<Defect>,
    /// Defects found beyond the listed ones.
    pub unlisted: usize,
    /// Of those, the errors.
    pub unlisted_errors: usize,
    /// Whether the two counts are exact or lower bounds (the search for
    /// self-intersections stopped at [`MAX_COUNTED_PAIRS`]).
    pub tally: Tally,
    /// The exact signed volume (zero when a face names a vertex that does
    /// not exist: see `stats.volume`).
    pub volume: Rat,
    /// The tables, when indices are in range and faces are proper triangles.
    pub topology: Option<Topology>,
}

impl Report {
    /// Whether the slicer accepts the mesh (no error-severity defect).
    pub fn is_accepted(&self) -> bool {
        self.unlisted_errors == 0
            && self
                .defects
                .iter()
                .all(|d| d.severity() == Severity::Warning)
    }

    /// The measures of a mesh stored in grid units (snapped: true
    /// coordinate = stored value * `unit`) in the mesh's own units: the
    /// volume exactly (times `unit^3`), the bounding box as the nearest
    /// doubles of the exact corners.
    pub fn in_units(mut self, unit: &Rat) -> Self {
        let scale = |x: f64| {
            Rat::from_float(x).map_or(x, |r| crate::exact::rational::rat_to_f64(&(r * unit)))
        };
        if let Some(bb) = &mut self.stats.bounding_box {
            for corner in bb.iter_mut() {
                *corner = corner.map(scale);
            }
        }
        self.volume = &self.volume * unit * unit * unit;
        if self.stats.volume.is_some() {
            self.stats.volume = Some(rat_to_string(&self.volume));
        }
        self
    }

    /// The blocking defects.
    pub fn errors(&self) -> impl Iterator<Item = &Defect> {
        self.defects
            .iter()
            .filter(|d| d.severity() == Severity::Error)
    }
}

/// The defects found, each severity listed up to [`MAX_LISTED_DEFECTS`]
/// and counted beyond.
#[derive(Default)]
struct Sink {
    defects: Vec<Defect>,
    listed_errors: usize,
    unlisted: usize,
    unlisted_errors: usize,
    tally: Tally,
}

impl Sink {
    fn push(&mut self, d: Defect) {
        let error = d.severity() == Severity::Error;
        let listed = if error {
            self.listed_errors
        } else {
            self.defects.len() - self.listed_errors
        };
        if listed < MAX_LISTED_DEFECTS {
            self.listed_errors += usize::from(error);
            self.defects.push(d);
        } else {
            self.unlisted += 1;
            self.unlisted_errors += usize::from(error);
        }
    }

    /// `n` errors found beyond the listed ones (or at least `n`).
    fn count_unlisted_errors(&mut self, n: usize, tally: Tally) {
        self.unlisted += n;
        self.unlisted_errors += n;
        if tally == Tally::AtLeast {
            self.tally = tally;
        }
    }
}

/// Validates a mesh: every defect of SPEC section 1, exactly.
pub fn validate(mesh: &Mesh) -> Report {
    validate_with(mesh, VolumeNeed::Exact).0
}

/// Validates a mesh for slicing: its topology when it is accepted, else the
/// whole [`Report`] (as [`validate`] makes it). The verdict is
/// [`validate`]'s, exactly; an accepted mesh is decided faster, as its
/// exact volume is not computed when a floating-point sum with a certified
/// error bound shows it positive ([`volume_sign_filter`]).
pub fn accept(mesh: &Mesh) -> Result<Topology, Box<Report>> {
    let (mut report, volume_computed) = validate_with(mesh, VolumeNeed::Sign);
    if report.is_accepted() {
        return Ok(report.topology.take().unwrap_or_default());
    }
    if !volume_computed {
        report.volume = signed_volume(mesh);
        report.stats.volume = Some(rat_to_string(&report.volume));
    }
    Err(Box::new(report))
}

/// What validation must know of the signed volume.
#[derive(Clone, Copy, PartialEq, Eq)]
enum VolumeNeed {
    /// Its exact value, for the report.
    Exact,
    /// Whether it is positive (exact only when a filter cannot tell).
    Sign,
}

/// The report, and whether its volume was computed (else the volume is
/// positive, and the report's value is a placeholder zero).
fn validate_with(mesh: &Mesh, need: VolumeNeed) -> (Report, bool) {
    let mut sink = Sink::default();
    let nv = mesh.num_vertices();
    if mesh.faces.is_empty() {
        sink.push(Defect::Empty);
    }
    for (v, p) in mesh.positions.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            sink.push(Defect::NonFiniteCoordinate {
                vertex: VertexId::from_idx(v),
            });
        }
    }
    let mut structural = true;
    let mut in_range = true;
    for (f, tri) in mesh.faces.iter().enumerate() {
        let face = FaceId::from_idx(f);
        for (c, v) in tri.iter().enumerate() {
            if v.idx() >= nv {
                structural = false;
                in_range = false;
                sink.push(Defect::IndexOutOfRange {
                    face,
                    corner: c as u8,
                    index: v.0,
                    vertices: nv,
                });
            }
        }
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            structural = false;
            sink.push(Defect::RepeatedVertex { face });
        }
    }

    let bounding_box = mesh.bounding_box();
    let mut stats = Stats {
        vertices: nv,
        faces: mesh.num_faces(),
        edges: None,
        components: None,
        euler_characteristic: None,
        genus: None,
        bounding_box,
        volume: None,
    };
    if !structural {
        // Without proper triangles there are no edge tables to count; the
        // volume needs only the indices in range (a face repeating a
        // vertex adds zero to it).
        let volume = if in_range {
            signed_volume(mesh)
        } else {
            Rat::default()
        };
        stats.volume = in_range.then(|| rat_to_string(&volume));
        let report = Report {
            stats,
            defects: sink.defects,
            unlisted: sink.unlisted,
            unlisted_errors: sink.unlisted_errors,
            tally: sink.tally,
            volume,
            topology: None,
        };
        return (report, true);
    }

    // Independent passes, on the caller's rayon pool (one thread: one
    // after the other); defects are reported in the same order either way.
    let parallel = mesh.num_faces() >= par::MIN_LEN;
    let finite = mesh
        .positions
        .iter()
        .all(|p| p.iter().all(|x| x.is_finite()));
    // The geometric passes decide signs only, the same in a frame where
    // no predicate scales its coordinates itself (as each would, call by
    // call, for a mesh whose coordinates lie near `1e-300` or `1e300`).
    let framed = mesh.in_predicate_frame();
    // The topology's build is the longest chain; the passes that do not
    // need it run beside it.
    let ((volume, degenerate), (topo, issues)) = par::join(
        parallel,
        || {
            par::join(
                parallel,
                || match need {
                    VolumeNeed::Sign if volume_sign_filter(mesh) == Some(Sign::Positive) => None,
                    _ => Some(signed_volume(mesh)),
                },
                || {
                    if finite {
                        degenerate_faces(&framed)
                    } else {
                        Vec::new()
                    }
                },
            )
        },
        || Topology::build(mesh),
    );
    let volume_computed = volume.is_some();
    let volume = volume.unwrap_or_default();
    stats.volume = Some(rat_to_string(&volume));
    for d in duplicate_faces(mesh, &topo, &issues) {
        sink.push(d);
    }
    let closed_manifold = issues.is_empty();
    report_topology_issues(mesh, issues, &mut sink);

    let mut used = vec![false; nv];
    for tri in &mesh.faces {
        for v in tri {
            used[v.idx()] = true;
        }
    }
    for (v, &u) in used.iter().enumerate() {
        if !u {
            sink.push(Defect::UnusedVertex {
                vertex: VertexId::from_idx(v),
            });
        }
    }
    if !closed_manifold {
        for (vertex, first) in coincident_vertices(mesh, &used) {
            sink.push(Defect::CoincidentVertex { vertex, first });
        }
    }
    // The component count (a serial union-find) beside the fold check
    // (parallel over edges) and the self-intersection test.
    let geometric = finite && closed_manifold;
    let (shells, (edge_defects, apart)) = par::join(
        parallel,
        || shells(mesh, &topo),
        || {
            if geometric {
                let (edges, apart) =
                    face_pairs(&framed, &topo, MAX_LISTED_DEFECTS, MAX_COUNTED_PAIRS);
                (edges, Some(apart))
            } else {
                (Vec::new(), None)
            }
        },
    );
    let degenerate = diagnose(&framed, &degenerate)
        .into_iter()
        .map(|(face, why)| Defect::DegenerateFace { face, why });
    for d in degenerate {
        sink.push(d);
    }
    let folded = edge_defects
        .iter()
        .any(|(_, kind)| matches!(kind, EdgeOverlap::Fold));
    let mut intersecting = Vec::new();
    for (e, kind) in edge_defects {
        let edge = topo.edge(e);
        let mut faces = edge.faces;
        faces.sort_unstable();
        match kind {
            EdgeOverlap::Fold => sink.push(Defect::Fold {
                a: edge.v[0],
                b: edge.v[1],
                faces: faces.to_vec(),
            }),
            EdgeOverlap::Collinear => intersecting.push((faces[0], faces[1])),
            EdgeOverlap::Proper => {}
        }
    }
    // Shells may be told apart by where they lie only when they are
    // disjoint closed surfaces: no fold, no face pair that meets.
    let disjoint = geometric
        && intersecting.is_empty()
        && !folded
        && apart
            .as_ref()
            .is_some_and(|a| a.pairs.is_empty() && a.unlisted == 0);
    if let Some(apart) = apart {
        // Both lists are ascending; the first MAX_LISTED_DEFECTS of their
        // union are among the listed ones of each.
        intersecting.extend(apart.pairs);
        intersecting.sort_unstable();
        sink.count_unlisted_errors(apart.unlisted, apart.tally);
    }
    for (a, b) in intersecting {
        sink.push(Defect::SelfIntersection { a, b });
    }
    if disjoint {
        for m in misnested_shells(&framed, &shells) {
            sink.push(Defect::MisnestedShell {
                face: m.face,
                facing: m.facing,
                winding: m.winding,
            });
        }
    }
    if volume_computed
        && closed_manifold
        && finite
        && !mesh.faces.is_empty()
        && !volume.is_positive()
    {
        sink.push(Defect::NotOutward {
            volume: rat_to_string(&volume),
        });
    }

    let used_count = used.iter().filter(|&&u| u).count() as i64;
    let edges = topo.num_edges();
    let euler = used_count - edges as i64 + stats.faces as i64;
    let components = shells.len();
    stats.edges = Some(edges);
    stats.euler_characteristic = Some(euler);
    stats.components = Some(components);
    if closed_manifold {
        stats.genus = Some((2 * components as i64 - euler) / 2);
    }
    let report = Report {
        stats,
        defects: sink.defects,
        unlisted: sink.unlisted,
        unlisted_errors: sink.unlisted_errors,
        tally: sink.tally,
        volume,
        topology: closed_manifold.then_some(topo),
    };
    (report, volume_computed)
}

/// Faces with the same three vertices as an earlier face, in face order.
///
/// Only faces the topology flags are looked at. Two faces on the same
/// three vertices share each of their edges; such an edge is either used
/// twice in one direction (a bad edge, whose issue lists both faces) or has
/// exactly these two faces, with the same opposite vertex.
fn duplicate_faces(mesh: &Mesh, topo: &Topology, issues: &[TopologyIssue]) -> Vec<Defect> {
    let mut candidates: Vec<FaceId> = topo
        .edges
        .par_iter()
        .with_min_len(par::MIN_LEN)
        .filter(|e| e.opposite[0] == e.opposite[1])
        .flat_map_iter(|e| e.faces)
        .collect();
    for issue in issues {
        if let TopologyIssue::BadEdge {
            forward, backward, ..
        } = issue
        {
            candidates.extend(forward.iter().chain(backward));
        }
    }
    candidates.retain(|&f| f != NO_FACE);
    candidates.sort_unstable();
    candidates.dedup();
    duplicates_among(mesh, &candidates)
}

/// Faces of `faces` (ascending) with the same three vertices as an earlier
/// one of them.
fn duplicates_among(mesh: &Mesh, faces: &[FaceId]) -> Vec<Defect> {
    let mut seen: HashMap<[VertexId; 3], FaceId, ahash::RandomState> =
        HashMap::with_capacity_and_hasher(faces.len(), ahash::RandomState::new());
    let mut found = Vec::new();
    for &face in faces {
        let mut key = mesh.faces[face.idx()];
        key.sort_unstable();
        match seen.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => found.push(Defect::DuplicateFace {
                face,
                first: *e.get(),
                turn: Turn::of(mesh.faces[e.get().idx()], mesh.faces[face.idx()]),
            }),
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(face);
            }
        }
    }
    found
}

/// Each used vertex at exactly the point of an earlier used one (`-0` and
/// `+0` are one coordinate), with that first vertex.
fn coincident_vertices(mesh: &Mesh, used: &[bool]) -> Vec<(VertexId, VertexId)> {
    let key = |p: [f64; 3]| p.map(coordinate_key);
    let mut first: rustc_hash::FxHashMap<[u64; 3], VertexId> = Default::default();
    let mut out = Vec::new();
    for (i, p) in mesh.positions.iter().enumerate() {
        if !used[i] {
            continue;
        }
        let v = VertexId::from_idx(i);
        match first.entry(key(*p)) {
            std::collections::hash_map::Entry::Occupied(e) => out.push((v, *e.get())),
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(v);
            }
        }
    }
    out
}

fn report_topology_issues(mesh: &Mesh, issues: Vec<TopologyIssue>, sink: &mut Sink) {
    // A face whose three edges are all inconsistent is named as flipped.
    let mut inconsistent: Vec<([VertexId; 2], Vec<FaceId>)> = Vec::new();
    let mut per_face: HashMap<FaceId, u8> = HashMap::new();
    for issue in issues {
        match issue {
            TopologyIssue::BadEdge {
                v,
                forward,
                backward,
            } => {
                let all: Vec<FaceId> = forward.iter().chain(&backward).copied().collect();
                match (forward.len(), backward.len()) {
                    (1, 0) | (0, 1) => sink.push(Defect::OpenEdge {
                        a: v[0],
                        b: v[1],
                        face: all[0],
                    }),
                    (2, 0) | (0, 2) => {
                        for f in &all {
                            *per_face.entry(*f).or_default() += 1;
                        }
                        inconsistent.push((v, all));
                    }
                    _ => sink.push(Defect::NonManifoldEdge {
                        a: v[0],
                        b: v[1],
                        faces: all,
                    }),
                }
            }
            TopologyIssue::Bowtie { vertex, cycles } => {
                sink.push(Defect::BowtieVertex { vertex, cycles })
            }
        }
    }
    let mut flipped: Vec<FaceId> = per_face
        .iter()
        .filter(|(_, &n)| n == 3)
        .map(|(&f, _)| f)
        .collect();
    flipped.sort_unstable();
    for &face in &flipped {
        sink.push(Defect::FlippedFace { face });
    }
    let _ = mesh;
    for (v, faces) in inconsistent {
        if faces.iter().any(|f| flipped.binary_search(f).is_ok()) {
            continue;
        }
        sink.push(Defect::InconsistentEdge {
            a: v[0],
            b: v[1],
            faces,
        });
    }
}

/// Faces of zero area (three collinear vertices), in face order.
fn degenerate_faces(mesh: &Mesh) -> Vec<FaceId> {
    (0..mesh.num_faces())
        .into_par_iter()
        .with_min_len(par::MIN_LEN)
        .filter(|&f| {
            let [a, b, c] = mesh.faces[f].map(|v| mesh.pos(v));
            is_degenerate_triangle(a, b, c)
        })
        .map(FaceId::from_idx)
        .collect()
}

/// A double as the report shows it: the shortest decimal that reads back
/// as it, in exponent form below `1e-5` and from `1e16` on (`1e-300`
/// rather than 300 zeros). Display only: the thresholds pick a notation
/// for the report's text, no decision reads them.
pub(crate) struct Shown(pub(crate) f64);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = self.0.abs();
        if m == 0.0 || !m.is_finite() || (1e-5..1e16).contains(&m) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats;
        writeln!(f, "vertices   {}", s.vertices)?;
        writeln!(f, "faces      {}", s.faces)?;
        let counted = |n: Option<i64>| {
            n.map_or(
                "- (not counted: a face repeats a vertex or names none)".into(),
                |n| n.to_string(),
            )
        };
        let count = |n: Option<usize>| counted(n.map(|n| n as i64));
        writeln!(f, "edges      {}", count(s.edges))?;
        writeln!(f, "components {}", count(s.components))?;
        writeln!(f, "euler      {}", counted(s.euler_characteristic))?;
        match s.genus {
            Some(g) => writeln!(f, "genus      {g}")?,
            None => writeln!(f, "genus      - (not a closed manifold)")?,
        }
        if let Some([lo, hi]) = s.bounding_box {
            let [lo, hi] = [lo, hi].map(|p| p.map(Shown));
            writeln!(
                f,
                "bbox       [{}, {}, {}] .. [{}, {}, {}]",
                lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
            )?;
        }
        match &s.volume {
            Some(v) => writeln!(
                f,
                "volume     {v} (~{})",
                Shown(crate::exact::rational::rat_to_f64(&self.volume))
            )?,
            None => writeln!(
                f,
                "volume     - (not computed: a face names a vertex that does not exist)"
            )?,
        }
        for d in &self.defects {
            let tag = match d.severity() {
                Severity::Error => "error",
                Severity::Warning => "warning",
            };
            writeln!(f, "{tag}: {d}")?;
        }
        let at_least = match self.tally {
            Tally::Exact => "",
            Tally::AtLeast => "at least ",
        };
        match (self.unlisted, self.unlisted_errors) {
            (0, _) => {}
            (n, 0) => writeln!(f, "... and {n} more warnings")?,
            (n, e) if n == e => writeln!(f, "... and {at_least}{n} more errors")?,
            (n, e) => writeln!(
                f,
                "... and {at_least}{n} more defects ({at_least}{e} of them errors)"
            )?,
        }
        if self.tally == Tally::AtLeast {
            writeln!(
                f,
                "(the search for self-intersections stops counting at {MAX_COUNTED_PAIRS} pairs of faces)"
            )?;
        }
        let verdict = if self.is_accepted() {
            "accepted for slicing"
        } else {
            "REJECTED for slicing"
        };
        write!(f, "{verdict}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn extreme_doubles_are_shown_in_exponent_form_and_read_back() {
        let cases = [
            (40.0, "40"),
            (-0.25, "-0.25"),
            (0.0, "0"),
            (1e-300, "1e-300"),
            (-9.205710888e-301, "-9.205710888e-301"),
            (5e-324, "5e-324"),
            (1.7e308, "1.7e308"),
            (1e16, "1e16"),
            (9.5e-6, "9.5e-6"),
        ];
        for (x, shown) in cases {
            let text = Shown(x).to_string();
            assert_eq!(text, shown);
            assert_eq!(text.parse::<f64>().unwrap().to_bits(), (x + 0.0).to_bits());
        }
    }

    proptest! {
        /// Looking only at the faces the topology flags finds what
        /// comparing every face finds: faces on few vertices, often the
        /// same three in either orientation, in meshes with and without
        /// other defects.
        #[test]
        fn flagged_faces_hold_every_duplicate(
            nv in 3u32..9,
            picks in proptest::collection::vec((0u32..9, 0u32..9, 0u32..9), 1..40),
        ) {
            let faces: Vec<[VertexId; 3]> = picks
                .into_iter()
                .map(|(a, b, c)| [a % nv, b % nv, c % nv].map(VertexId))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            let mesh = Mesh { positions: vec![[0.0; 3]; nv as usize], faces };
            let (topo, issues) = Topology::build(&mesh);
            let all: Vec<FaceId> = (0..mesh.num_faces()).map(FaceId::from_idx).collect();
            prop_assert_eq!(
                duplicate_faces(&mesh, &topo, &issues),
                duplicates_among(&mesh, &all)
            );
        }
    }
}
