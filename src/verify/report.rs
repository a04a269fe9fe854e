//! Input: what the verifier found. Output: typed [`Violation`]s (where:
//! level, family, loop, point; what: a [`Problem`]) and the [`Report`] with
//! its one-line summary.

use super::doc::On;
use crate::exact::Sign;
use std::fmt;

/// The part of a result a violation concerns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Family {
    /// The `mesh` header.
    Header,
    /// The level itself (its `z`).
    Level,
    /// S_O (`contours`).
    Contours,
    /// F (`faces`): a face region.
    Regions,
    /// dF: a boundary loop of a region (`faces[i].boundary`).
    Boundary,
    /// S_NO (`ridges`).
    Ridges,
    /// P (`points`).
    Points,
    /// `saddles`.
    Saddles,
    /// L- (`below`).
    Below,
    /// L+ (`above`).
    Above,
}

impl Family {
    fn name(self) -> &'static str {
        match self {
            Family::Header => "mesh header",
            Family::Level => "level",
            Family::Contours => "S_O loop",
            Family::Regions => "F region",
            Family::Boundary => "dF of region",
            Family::Ridges => "S_NO ridge",
            Family::Points => "P point",
            Family::Saddles => "saddle",
            Family::Below => "L- loop",
            Family::Above => "L+ loop",
        }
    }
}

/// Where a violation is: every index is a position in the result file.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Place {
    /// Index in `levels`, with its `z` text.
    pub level: Option<(usize, String)>,
    /// Which family.
    pub family: Family,
    /// Index in the family's list (loop, region, ridge, point, saddle).
    pub item: Option<usize>,
    /// For dF: the boundary loop within the region.
    pub sub: Option<usize>,
    /// The point (or segment starting at it) within the loop or polyline.
    pub point: Option<usize>,
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((i, z)) = &self.level {
            write!(f, "level {i} (z = {z}): ")?;
        }
        f.write_str(self.family.name())?;
        if let Some(i) = self.item {
            write!(f, " {i}")?;
        }
        if let Some(s) = self.sub {
            write!(f, " loop {s}")?;
        }
        if let Some(p) = self.point {
            write!(f, ", point {p}")?;
        }
        Ok(())
    }
}

impl fmt::Display for On {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            On::Edge(e) => write!(f, "edge e{e}"),
            On::Vertex(v) => write!(f, "vertex v{v}"),
        }
    }
}

fn sign(s: Sign) -> &'static str {
    match s {
        Sign::Negative => "below",
        Sign::Zero => "on the plane",
        Sign::Positive => "above",
    }
}

/// Another loop of the same family, for crossing reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Other {
    /// The other loop's index (for dF: within the same region).
    pub item: usize,
    /// The segment of the other loop (starting at this point index).
    pub point: usize,
}

impl fmt::Display for Other {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "loop {} segment {}", self.item, self.point)
    }
}

/// What is wrong.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Problem {
    /// A header count differs from the mesh.
    HeaderCount {
        /// `vertices` or `faces`.
        what: &'static str,
        /// As written.
        claimed: u64,
        /// The mesh's.
        actual: usize,
    },
    /// The mesh fingerprint differs: the result is about another mesh.
    MeshHash {
        /// As written.
        claimed: String,
        /// The mesh's.
        actual: String,
    },
    /// The snap grid differs.
    Snap {
        /// As written.
        claimed: Option<String>,
        /// The grid verified against.
        actual: Option<String>,
    },
    /// A text that should be an exact rational is not one.
    BadRational {
        /// Which field.
        what: &'static str,
        /// The text.
        text: String,
    },
    /// An exact rational not in lowest terms or not canonical.
    NotCanonical {
        /// Which field.
        what: &'static str,
        /// The text.
        text: String,
        /// The canonical text.
        canonical: String,
    },
    /// A rounded number is not the double nearest to the exact value.
    NotNearest {
        /// Which field.
        what: &'static str,
        /// The text as written.
        claimed: String,
        /// The nearest double (as Rust prints it).
        nearest: String,
    },
    /// `points`, `exact` and `on` differ in length.
    Lengths {
        /// `points`.
        points: usize,
        /// `exact`.
        exact: usize,
        /// `on`.
        on: usize,
    },
    /// A loop without points.
    EmptyLoop,
    /// An edge id out of range.
    NoSuchEdge(u64),
    /// A vertex id out of range.
    NoSuchVertex(u64),
    /// A face id out of range.
    NoSuchFace(u64),
    /// A point claims an edge the level does not strictly cross.
    EdgeNotCrossed {
        /// The edge.
        edge: u64,
        /// Its ends' sides.
        signs: [Sign; 2],
    },
    /// A point claims a vertex that is not on the plane.
    VertexOffPlane {
        /// The vertex.
        vertex: u64,
        /// Its side.
        sign: Sign,
    },
    /// The exact point is not the point of the element it claims.
    WrongPoint {
        /// The element.
        on: On,
        /// As written.
        claimed: String,
        /// The exact point of the element at this level.
        actual: String,
    },
    /// A segment that is no piece of the family at this level.
    NotAPiece {
        /// Start element.
        from: On,
        /// End element.
        to: On,
    },
    /// A segment that runs against the direction the mesh orientation gives.
    Reversed {
        /// Start element.
        from: On,
        /// End element.
        to: On,
    },
    /// Every segment of the loop runs against the orientation: the loop is
    /// reversed (its reversed pieces are not listed one by one).
    LoopReversed {
        /// Its number of segments.
        segments: usize,
    },
    /// A piece used more than once.
    Repeated {
        /// Start element.
        from: On,
        /// End element.
        to: On,
    },
    /// A piece of the family that no loop contains.
    Missing {
        /// Start element.
        from: On,
        /// End element.
        to: On,
    },
    /// `area_exact` is not the exact signed area of the exact points.
    WrongArea {
        /// As written.
        claimed: String,
        /// The shoelace area.
        actual: String,
    },
    /// The signed area's sign disagrees with the role.
    Orientation {
        /// The role as written.
        role: String,
        /// The exact signed area.
        area: String,
        /// For dF: the region's facing.
        facing: Option<&'static str>,
    },
    /// A role other than `outer` or `hole`.
    BadRole(String),
    /// The role disagrees with the exact nesting depth.
    WrongRole {
        /// As written.
        claimed: String,
        /// From exact containment.
        expected: &'static str,
        /// Number of loops of the family containing this one.
        depth: usize,
    },
    /// The parent disagrees with exact containment.
    WrongParent {
        /// As written.
        claimed: Option<u64>,
        /// The smallest containing loop.
        expected: Option<usize>,
    },
    /// Every segment of the loop runs back along another loop: no point
    /// of it can be tested for containment.
    NoInteriorSegment,
    /// L-, L+: the loop is not the limit of a loop of the contour at
    /// `c -/+ epsilon` (the pieces chained through edges).
    NotALimitLoop,
    /// L-, L+: a loop of the contour at `c -/+ epsilon` is missing.
    LimitLoopMissing {
        /// The first element of its limit.
        first: On,
        /// The number of points of its limit.
        points: usize,
    },
    /// L-, L+: the pieces of the perturbed face walk do not chain through
    /// edges (two leave one edge, or one leads nowhere).
    LimitNotChained(u64),
    /// L-, L+: the role disagrees with the sign of the area at
    /// `c -/+ epsilon` (the first non-zero term in `epsilon`).
    LimitOrientation {
        /// The role as written.
        role: String,
        /// The sign of the area for small `epsilon > 0`.
        sign: Sign,
    },
    /// L-, L+: `collapsed` disagrees with the limit areas of the regions
    /// the loop bounds.
    WrongCollapsed {
        /// As written.
        claimed: bool,
    },
    /// Two segments of the family cross.
    Crossing(Other),
    /// Two segments touch at a point that is not a mesh element they share.
    Touching(Other),
    /// Two segments overlap along a stretch.
    Overlap(Other),
    /// Two passes through one mesh element cross there.
    CrossingAt {
        /// The shared element.
        at: On,
        /// The other pass (loop and point index).
        other: Other,
    },
    /// A face in F that does not lie in the plane.
    FaceNotInPlane(u64),
    /// A face listed twice in F.
    FaceRepeated(u64),
    /// An in-plane face missing from F.
    FaceMissing(u64),
    /// Two regions share an in-plane edge: they are one region.
    RegionsJoined {
        /// The shared edge.
        edge: u64,
        /// The other region.
        other: usize,
    },
    /// A region whose faces are not connected across in-plane edges.
    Disconnected {
        /// Faces reachable from the first.
        reached: usize,
        /// Faces listed.
        faces: usize,
    },
    /// A facing other than up, down, flat.
    BadFacing(String),
    /// The facing disagrees with the exact orientation of the faces.
    WrongFacing {
        /// As written.
        claimed: String,
        /// From orient2d.
        expected: &'static str,
    },
    /// A region with both up and down faces.
    MixedFacing,
    /// The region's area is wrong.
    WrongRegionArea {
        /// As written.
        claimed: String,
        /// Exact.
        actual: String,
    },
    /// The boundary loops' signed areas do not add up to the region's
    /// signed area.
    BoundarySum {
        /// Sum of the boundary loops' exact areas.
        sum: String,
        /// `+area` (up), `-area` (down) or 0 (flat).
        expected: String,
    },
    /// A kind other than ridge/valley or min/max.
    BadKind(String),
    /// A polyline with fewer vertices than its kind needs.
    TooShort,
    /// `points` and `vertices` differ in length.
    PointCount {
        /// `points`.
        points: usize,
        /// `vertices`.
        vertices: usize,
    },
    /// Two consecutive vertices are not joined by a mesh edge.
    NotAnEdge(u64, u64),
    /// The edge is not an S_NO edge at this level.
    NotRidgeEdge {
        /// The edge.
        edge: u64,
        /// What it is.
        is: &'static str,
    },
    /// The edge is S_NO of the other kind.
    WrongRidgeKind {
        /// The edge.
        edge: u64,
        /// As written.
        claimed: String,
        /// From the opposite vertices' signs.
        expected: &'static str,
    },
    /// An S_NO edge in two polylines (or twice in one).
    RidgeEdgeRepeated(u64),
    /// An S_NO edge in no polyline.
    RidgeEdgeMissing {
        /// The edge.
        edge: u64,
        /// Its kind.
        kind: &'static str,
    },
    /// An open polyline ends at a vertex where it could go on.
    NotMaximal(u64),
    /// A polyline runs through a junction (more than two S_NO edges, or a
    /// change of kind) instead of ending there.
    ThroughJunction(u64),
    /// A vertex in P that is not an extremum.
    NotExtremum(u64),
    /// An extremum of the other kind.
    WrongExtremum {
        /// The vertex.
        vertex: u64,
        /// As written.
        claimed: String,
        /// From its neighbours' signs.
        expected: &'static str,
    },
    /// A vertex listed twice in P (or twice in saddles).
    VertexRepeated(u64),
    /// An extremum missing from P.
    ExtremumMissing {
        /// The vertex.
        vertex: u64,
        /// Its kind.
        kind: &'static str,
    },
    /// An extremal vertex that also appears in another family.
    ExtremumElsewhere(u64),
    /// A saddle entry for a vertex with fewer than four S_O branches.
    NotSaddle {
        /// The vertex.
        vertex: u64,
        /// Its S_O branches.
        branches: usize,
    },
    /// A wrong branch count.
    WrongBranches {
        /// The vertex.
        vertex: u64,
        /// As written.
        claimed: u64,
        /// S_O pieces ending at the vertex.
        actual: usize,
    },
    /// A saddle missing from `saddles`.
    SaddleMissing {
        /// The vertex.
        vertex: u64,
        /// Its S_O branches.
        branches: usize,
    },
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use Problem as P;
        match self {
            P::HeaderCount { what, claimed, actual } => {
                write!(f, "claims {claimed} {what}, the mesh has {actual}")
            }
            P::MeshHash { claimed, actual } => write!(
                f,
                "sha256 {claimed} is not the mesh's {actual}: the result is about another mesh"
            ),
            P::Snap { claimed, actual } => write!(
                f,
                "snap grid {} differs from the grid verified against, {}",
                claimed.as_deref().unwrap_or("null"),
                actual.as_deref().unwrap_or("null")
            ),
            P::BadRational { what, text } => write!(f, "{what} {text:?} is not an exact rational"),
            P::NotCanonical { what, text, canonical } => {
                write!(f, "{what} {text:?} is not in lowest terms (write {canonical:?})")
            }
            P::NotNearest { what, claimed, nearest } => write!(
                f,
                "{what} {claimed} is not the double nearest to the exact value ({nearest})"
            ),
            P::Lengths { points, exact, on } => write!(
                f,
                "points, exact and on differ in length ({points}, {exact}, {on})"
            ),
            P::EmptyLoop => f.write_str("empty loop"),
            P::NoSuchEdge(e) => write!(f, "edge e{e} does not exist"),
            P::NoSuchVertex(v) => write!(f, "vertex v{v} does not exist"),
            P::NoSuchFace(x) => write!(f, "face f{x} does not exist"),
            P::EdgeNotCrossed { edge, signs } => write!(
                f,
                "edge e{edge} is not strictly crossed at this level (its ends are {} and {})",
                sign(signs[0]),
                sign(signs[1])
            ),
            P::VertexOffPlane { vertex, sign: s } => {
                write!(f, "vertex v{vertex} is not on the plane (it is {})", sign(*s))
            }
            P::WrongPoint { on, claimed, actual } => write!(
                f,
                "exact point {claimed} is not the point of {on} at this level, {actual}"
            ),
            P::NotAPiece { from, to } => {
                write!(f, "segment {from} -> {to} is not a piece of this family at this level")
            }
            P::Reversed { from, to } => write!(
                f,
                "segment {from} -> {to} runs against the orientation (material must be on its left)"
            ),
            P::LoopReversed { segments } => write!(
                f,
                "runs backwards: all its {segments} segments run against the orientation (material must be on its left)"
            ),
            P::Repeated { from, to } => write!(f, "segment {from} -> {to} is used more than once"),
            P::Missing { from, to } => {
                write!(f, "piece {from} -> {to} of this family is in no loop")
            }
            P::WrongArea { claimed, actual } => {
                write!(f, "area_exact {claimed} is not the exact signed area {actual}")
            }
            P::Orientation { role, area, facing } => match facing {
                Some(fc) => write!(
                    f,
                    "{role} boundary loop of a {fc} region has signed area {area}: wrong orientation"
                ),
                None => write!(
                    f,
                    "{role} loop has signed area {area}: outer loops must be > 0, holes < 0"
                ),
            },
            P::BadRole(r) => write!(f, "role {r:?} is neither outer nor hole"),
            P::WrongRole { claimed, expected, depth } => write!(
                f,
                "role {claimed} but exact containment puts it inside {depth} loops: {expected}"
            ),
            P::WrongParent { claimed, expected } => write!(
                f,
                "parent {} but the smallest loop containing it is {}",
                claimed.map_or("null".into(), |p| p.to_string()),
                expected.map_or("none".into(), |p| p.to_string())
            ),
            P::NoInteriorSegment => f.write_str(
                "every segment runs back along another loop: containment cannot be decided",
            ),
            P::NotALimitLoop => f.write_str(
                "is not the limit of a loop of the contour at c -/+ epsilon (pieces chained through edges)",
            ),
            P::LimitLoopMissing { first, points } => write!(
                f,
                "the limit loop of {points} points through {first} is missing"
            ),
            P::LimitNotChained(e) => write!(
                f,
                "the perturbed face walk does not chain through edge e{e}"
            ),
            P::LimitOrientation { role, sign } => write!(
                f,
                "{role} loop has a {} area at c -/+ epsilon: outer loops must be > 0, holes < 0",
                match sign {
                    Sign::Positive => "positive",
                    Sign::Negative => "negative",
                    Sign::Zero => "zero",
                }
            ),
            P::WrongCollapsed { claimed } => write!(
                f,
                "collapsed is {claimed}, but {}",
                if *claimed {
                    "every region the loop bounds has a non-zero limit area"
                } else {
                    "a region the loop bounds has limit area 0"
                }
            ),
            P::Crossing(o) => write!(f, "crosses {o}"),
            P::Touching(o) => write!(f, "touches {o} at a point that is no shared mesh element"),
            P::Overlap(o) => write!(f, "overlaps {o} along a stretch"),
            P::CrossingAt { at, other } => write!(f, "crosses the pass of {other} through {at}"),
            P::FaceNotInPlane(x) => write!(f, "face f{x} does not lie in the plane"),
            P::FaceRepeated(x) => write!(f, "face f{x} is listed more than once in F"),
            P::FaceMissing(x) => write!(f, "face f{x} lies in the plane but is in no region"),
            P::RegionsJoined { edge, other } => write!(
                f,
                "shares in-plane edge e{edge} with region {other}: they are one region"
            ),
            P::Disconnected { reached, faces } => write!(
                f,
                "is not connected: {reached} of its {faces} faces are reachable across in-plane edges"
            ),
            P::BadFacing(x) => write!(f, "facing {x:?} is not up, down or flat"),
            P::WrongFacing { claimed, expected } => {
                write!(f, "facing {claimed} but its faces are {expected} (exact orient2d)")
            }
            P::MixedFacing => f.write_str("has both up and down faces"),
            P::WrongRegionArea { claimed, actual } => {
                write!(f, "area {claimed} is not the exact area {actual}")
            }
            P::BoundarySum { sum, expected } => write!(
                f,
                "boundary loops add up to signed area {sum}, expected {expected}"
            ),
            P::BadKind(k) => write!(f, "kind {k:?} is not valid here"),
            P::TooShort => f.write_str("has too few vertices"),
            P::PointCount { points, vertices } => {
                write!(f, "has {points} points for {vertices} vertices")
            }
            P::NotAnEdge(a, b) => write!(f, "vertices v{a} and v{b} are not joined by an edge"),
            P::NotRidgeEdge { edge, is } => {
                write!(f, "edge e{edge} is not a ridge or valley at this level: it is {is}")
            }
            P::WrongRidgeKind { edge, claimed, expected } => {
                write!(f, "edge e{edge} is a {expected}, not a {claimed}")
            }
            P::RidgeEdgeRepeated(e) => write!(f, "edge e{e} is in more than one polyline"),
            P::RidgeEdgeMissing { edge, kind } => {
                write!(f, "{kind} edge e{edge} is in no polyline")
            }
            P::NotMaximal(v) => write!(
                f,
                "ends at vertex v{v}, which is no junction: the polyline is not maximal"
            ),
            P::ThroughJunction(v) => write!(f, "runs through junction vertex v{v}"),
            P::NotExtremum(v) => write!(f, "vertex v{v} is not an isolated extremum on the plane"),
            P::WrongExtremum { vertex, claimed, expected } => {
                write!(f, "vertex v{vertex} is a {expected}, not a {claimed}")
            }
            P::VertexRepeated(v) => write!(f, "vertex v{v} is listed more than once"),
            P::ExtremumMissing { vertex, kind } => {
                write!(f, "vertex v{vertex} is an isolated {kind} on the plane but not in P")
            }
            P::ExtremumElsewhere(v) => write!(
                f,
                "extremal vertex v{v} appears here; it belongs to P and nothing else"
            ),
            P::NotSaddle { vertex, branches } => write!(
                f,
                "vertex v{vertex} has {branches} S_O branches: not a saddle"
            ),
            P::WrongBranches { vertex, claimed, actual } => write!(
                f,
                "vertex v{vertex} claims {claimed} branches, S_O has {actual} pieces ending there"
            ),
            P::SaddleMissing { vertex, branches } => write!(
                f,
                "vertex v{vertex} has {branches} S_O branches but is not listed as a saddle"
            ),
        }
    }
}

/// One violation: where, and what.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Violation {
    /// Where.
    pub place: Place,
    /// What.
    pub problem: Problem,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.place, self.problem)
    }
}

/// What was checked, for the summary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Checked {
    /// Levels.
    pub levels: usize,
    /// Loops of every family (S_O, dF, L-, L+).
    pub loops: usize,
    /// Loop points.
    pub points: usize,
    /// Face regions.
    pub regions: usize,
    /// Ridge polylines.
    pub ridges: usize,
    /// Extremal points.
    pub extrema: usize,
    /// Saddles.
    pub saddles: usize,
}

/// The verdict on a result.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Report {
    /// What was checked.
    pub checked: Checked,
    /// Every violation, in file order.
    pub violations: Vec<Violation>,
}

impl Report {
    /// Whether the result passed every check.
    pub fn passed(&self) -> bool {
        self.violations.is_empty()
    }

    /// One line: the verdict and what was checked.
    pub fn summary(&self) -> String {
        let c = &self.checked;
        let what = format!(
            "{} levels, {} loops, {} points, {} regions, {} ridges, {} extrema, {} saddles",
            c.levels, c.loops, c.points, c.regions, c.ridges, c.extrema, c.saddles
        );
        if self.passed() {
            format!("verified: {what}; SPEC 7 invariants 1-4 hold exactly")
        } else {
            format!(
                "verification FAILED: {} violations in {what}",
                self.violations.len()
            )
        }
    }
}
