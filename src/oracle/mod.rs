//! Input: a [`Mesh`] and an exact level `c`.
//! Output: the answer of the independent CGAL oracle (`cpp-oracle/`, built
//! only with the `cgal-oracle` feature) as plain Rust types: exact vertex
//! signs, faces in the plane with their facing, the class of every in-plane
//! edge keyed by its sorted vertex pair, extremal vertices, S_O branch
//! counts, and the polylines of `CGAL::Polygon_mesh_slicer` with exact
//! rational points.
//!
//! The oracle works in CGAL's exact kernel (Epeck) and is derived from
//! SPEC.md, not from this crate's code, so agreement is evidence. Calls
//! are serialised by a mutex (CGAL's lazy kernel is not relied on to be
//! thread-safe).
//!
//! [`compare`] compares this answer with the Rust level set element by
//! element (shared by `tests/oracle.rs` and the `slice_oracle` fuzz target).

pub mod compare;

use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::{parse_rational, Rat, Sign};
use crate::ids::{FaceId, VertexId};
use crate::mesh::Mesh;
use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::sync::Mutex;

#[repr(C)]
struct WmoResult {
    num_vertices: usize,
    vertex_sign: *const i8,
    vertex_extremum: *const u8,
    vertex_branches: *const u32,
    num_faces: usize,
    face_in_plane: *const u8,
    num_edges: usize,
    edge_vertices: *const u32,
    edge_class: *const u8,
    num_polylines: usize,
    polyline_start: *const usize,
    num_points: usize,
    point_x: *const *const c_char,
    point_y: *const *const c_char,
    internal: *mut c_void,
}

extern "C" {
    fn wmo_classify(
        xyz: *const f64,
        num_vertices: usize,
        faces: *const u32,
        num_faces: usize,
        level_num: *const c_char,
        level_den: *const c_char,
        result: *mut *mut WmoResult,
        err: *mut c_char,
        err_len: usize,
    ) -> c_int;
    fn wmo_free(result: *mut WmoResult);
    fn wmo_self_intersections(
        xyz: *const f64,
        num_vertices: usize,
        faces: *const u32,
        num_faces: usize,
        does_intersect: *mut c_int,
        pairs: *mut u32,
        max_pairs: usize,
        num_pairs: *mut usize,
        err: *mut c_char,
        err_len: usize,
    ) -> c_int;
}

/// The class of an in-plane edge (both ends on the plane), per SPEC
/// section 3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OracleEdgeClass {
    /// Both faces in F.
    Interior,
    /// S_NO: both opposite vertices below.
    Ridge,
    /// S_NO: both opposite vertices above.
    Valley,
    /// S_O lying on the edge: opposite vertices of opposite signs.
    Transversal,
    /// A boundary edge of F (exactly one face in the plane); `so` when it
    /// is also in S_O.
    Boundary {
        /// Shared with S_O.
        so: bool,
    },
}

impl OracleEdgeClass {
    /// The ridge kind, for S_NO edges.
    pub fn ridge_kind(self) -> Option<RidgeKind> {
        match self {
            OracleEdgeClass::Ridge => Some(RidgeKind::Ridge),
            OracleEdgeClass::Valley => Some(RidgeKind::Valley),
            _ => None,
        }
    }
}

/// An exact point of the plane `z = c`.
pub type ExactXY = (Rat, Rat);

/// The oracle's answer at one level.
#[derive(Clone, Debug, PartialEq)]
pub struct OracleResult {
    /// `sign(z - c)` of every vertex.
    pub signs: Vec<Sign>,
    /// Faces with three vertices on the plane, with their own facing.
    pub in_plane_faces: BTreeMap<FaceId, Facing>,
    /// Every in-plane edge, keyed by its vertex pair (smaller id first).
    pub edges: BTreeMap<(VertexId, VertexId), OracleEdgeClass>,
    /// Extremal vertices P.
    pub extrema: BTreeMap<VertexId, ExtremumKind>,
    /// S_O branch counts of every on-plane vertex (zeros included).
    pub branches: BTreeMap<VertexId, u32>,
    /// `CGAL::Polygon_mesh_slicer`'s polylines (closed ones repeat their
    /// first point), exact.
    pub polylines: Vec<Vec<ExactXY>>,
}

/// Why the oracle gave no answer.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OracleError {
    /// The input was rejected or CGAL failed; `code` is a `WMO_ERR_*`
    /// constant of `oracle.h`.
    #[error("CGAL oracle error {code}: {message}")]
    Failed {
        /// The C error code.
        code: i32,
        /// The C++ side's message.
        message: String,
    },
    /// The answer could not be read back (an internal error).
    #[error("CGAL oracle returned a malformed answer: {0}")]
    Malformed(String),
}

static LOCK: Mutex<()> = Mutex::new(());

/// Runs the CGAL oracle on `mesh` at the exact level `level`.
pub fn oracle_classify(mesh: &Mesh, level: &Rat) -> Result<OracleResult, OracleError> {
    let xyz: Vec<f64> = mesh.positions.iter().flatten().copied().collect();
    let faces: Vec<u32> = mesh.faces.iter().flat_map(|f| f.map(|v| v.0)).collect();
    let malformed = |s: &str| OracleError::Malformed(s.to_string());
    let num = CString::new(level.numer().to_string()).map_err(|_| malformed("numerator"))?;
    let den = CString::new(level.denom().to_string()).map_err(|_| malformed("denominator"))?;
    let mut err = vec![0 as c_char; 1024];
    let mut raw: *mut WmoResult = std::ptr::null_mut();
    let guard = LOCK.lock().unwrap_or_else(|p| p.into_inner());
    // SAFETY: every pointer is valid for the lengths passed; the shim
    // writes only `raw` and at most `err.len()` bytes of `err`.
    let code = unsafe {
        wmo_classify(
            xyz.as_ptr(),
            mesh.num_vertices(),
            faces.as_ptr(),
            mesh.num_faces(),
            num.as_ptr(),
            den.as_ptr(),
            &mut raw,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    drop(guard);
    if code != 0 || raw.is_null() {
        // SAFETY: the shim NUL-terminates `err` within its length.
        let message = unsafe { CStr::from_ptr(err.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        return Err(OracleError::Failed { code, message });
    }
    // SAFETY: `raw` is a live result of `wmo_classify`; it is read here and
    // freed exactly once below.
    let out = unsafe { read_result(&*raw) };
    // SAFETY: as above.
    unsafe { wmo_free(raw) };
    out
}

/// CGAL's self-intersection verdict on a closed, oriented 2-manifold mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OracleSelfIntersections {
    /// `CGAL::Polygon_mesh_processing::does_self_intersect`.
    pub does_intersect: bool,
    /// The pairs `self_intersections` reports, smaller id first, ascending;
    /// a degenerate face `f` comes as `(f, f)`. CGAL counts a fold (two
    /// faces on an edge, coplanar, on one side of it) as an intersecting
    /// pair, where this crate names it a [`crate::mesh::validate::Defect::Fold`].
    pub pairs: Vec<(FaceId, FaceId)>,
}

/// Runs CGAL's exact self-intersection test (Epeck; see `oracle.h` for the
/// notion it decides) on `mesh`.
pub fn oracle_self_intersections(mesh: &Mesh) -> Result<OracleSelfIntersections, OracleError> {
    let xyz: Vec<f64> = mesh.positions.iter().flatten().copied().collect();
    let faces: Vec<u32> = mesh.faces.iter().flat_map(|f| f.map(|v| v.0)).collect();
    let mut err = vec![0 as c_char; 1024];
    let mut capacity = 64usize;
    loop {
        let mut pairs = vec![0u32; 2 * capacity];
        let (mut does, mut count): (c_int, usize) = (0, 0);
        let guard = LOCK.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: every pointer is valid for the lengths passed; the shim
        // writes at most `2 * capacity` ids to `pairs`, `does`, `count`
        // and at most `err.len()` bytes of `err`.
        let code = unsafe {
            wmo_self_intersections(
                xyz.as_ptr(),
                mesh.num_vertices(),
                faces.as_ptr(),
                mesh.num_faces(),
                &mut does,
                pairs.as_mut_ptr(),
                capacity,
                &mut count,
                err.as_mut_ptr(),
                err.len(),
            )
        };
        drop(guard);
        if code != 0 {
            // SAFETY: the shim NUL-terminates `err` within its length.
            let message = unsafe { CStr::from_ptr(err.as_ptr()) }
                .to_string_lossy()
                .into_owned();
            return Err(OracleError::Failed { code, message });
        }
        if count > capacity {
            capacity = count;
            continue;
        }
        let pairs = pairs[..2 * count]
            .chunks_exact(2)
            .map(|p| (FaceId(p[0]), FaceId(p[1])))
            .collect();
        return Ok(OracleSelfIntersections {
            does_intersect: does != 0,
            pairs,
        });
    }
}

/// Copies a C result into Rust types.
///
/// # Safety
/// `r` must be a live result of `wmo_classify`.
unsafe fn read_result(r: &WmoResult) -> Result<OracleResult, OracleError> {
    unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
        if n == 0 {
            &[]
        } else {
            std::slice::from_raw_parts(p, n)
        }
    }
    let bad = |s: String| OracleError::Malformed(s);
    let nv = r.num_vertices;
    let signs: Vec<Sign> = slice(r.vertex_sign, nv)
        .iter()
        .map(|&s| match s {
            -1 => Ok(Sign::Negative),
            0 => Ok(Sign::Zero),
            1 => Ok(Sign::Positive),
            x => Err(bad(format!("sign {x}"))),
        })
        .collect::<Result<_, _>>()?;
    let mut in_plane_faces = BTreeMap::new();
    for (f, &k) in slice(r.face_in_plane, r.num_faces).iter().enumerate() {
        let facing = match k {
            0 => continue,
            1 => Facing::Up,
            2 => Facing::Down,
            3 => Facing::Flat,
            x => return Err(bad(format!("facing {x}"))),
        };
        in_plane_faces.insert(FaceId::from_idx(f), facing);
    }
    let ev = slice(r.edge_vertices, 2 * r.num_edges);
    let mut edges = BTreeMap::new();
    for (i, &k) in slice(r.edge_class, r.num_edges).iter().enumerate() {
        let class = match k {
            0 => OracleEdgeClass::Interior,
            1 => OracleEdgeClass::Ridge,
            2 => OracleEdgeClass::Valley,
            3 => OracleEdgeClass::Transversal,
            4 => OracleEdgeClass::Boundary { so: false },
            5 => OracleEdgeClass::Boundary { so: true },
            x => return Err(bad(format!("edge class {x}"))),
        };
        edges.insert((VertexId(ev[2 * i]), VertexId(ev[2 * i + 1])), class);
    }
    let mut extrema = BTreeMap::new();
    for (v, &k) in slice(r.vertex_extremum, nv).iter().enumerate() {
        match k {
            0 => {}
            1 => {
                extrema.insert(VertexId::from_idx(v), ExtremumKind::Min);
            }
            2 => {
                extrema.insert(VertexId::from_idx(v), ExtremumKind::Max);
            }
            x => return Err(bad(format!("extremum {x}"))),
        }
    }
    let branches = slice(r.vertex_branches, nv)
        .iter()
        .enumerate()
        .filter(|&(v, _)| signs[v] == Sign::Zero)
        .map(|(v, &b)| (VertexId::from_idx(v), b))
        .collect();
    let px = slice(r.point_x, r.num_points);
    let py = slice(r.point_y, r.num_points);
    let text = |p: *const c_char| -> Result<Rat, OracleError> {
        let s = CStr::from_ptr(p).to_string_lossy();
        parse_rational(&s).map_err(|e| bad(format!("point {s}: {e}")))
    };
    let starts = slice(r.polyline_start, r.num_polylines + 1);
    let mut polylines = Vec::with_capacity(r.num_polylines);
    for w in starts.windows(2) {
        if w[0] > w[1] || w[1] > r.num_points {
            return Err(bad(format!("polyline range {}..{}", w[0], w[1])));
        }
        let pl = (w[0]..w[1])
            .map(|i| Ok((text(px[i])?, text(py[i])?)))
            .collect::<Result<Vec<_>, OracleError>>()?;
        polylines.push(pl);
    }
    Ok(OracleResult {
        signs,
        in_plane_faces,
        edges,
        extrema,
        branches,
        polylines,
    })
}
