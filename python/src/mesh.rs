//! Input: numpy arrays (vertices `(n, 3)` float64 or float32, faces `(m, 3)`
//! of any integer type), a mesh file or a built-in dataset name. Output:
//! the [`Mesh`] Python class (wrapped by `wmslice.Mesh`): validated once,
//! then sliced at one level, at many (the threaded plane sweep), or at
//! uniform layers, each level rounded on the slicing threads.

use crate::core::{CoreError, MeshCore};
use crate::errors::InternalError;
use crate::errors::{invalid_mesh, load_error, report_error, slice_error, snap_error, sweep_error};
use crate::level::{round_level, HeaderSrc, Level, RoundedLevel};
use crate::values::{exact, levels as levels_of};
use numpy::ndarray::Array2;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::sync::Arc;
use wmslice::critical::{self, fit::PlanReport};
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::ids::FaceId;
use wmslice::layers::{height_range, plan_levels, slice_levels_then, LayerPlan};
use wmslice::levelset::LevelSet;
use wmslice::mesh::io::{load_bytes_exact, load_exact, ExactPositions, LoadError, LoadReport};
use wmslice::mesh::prepare::{prepare_exact_with, PrepareError, Prepared, Repairs};
use wmslice::mesh::validate::{Severity, Tally};
use wmslice::output::critical::critical_json;
use wmslice::{datasets as builtin, Mesh as RawMesh};

/// A validated mesh, ready to slice.
#[pyclass(frozen, module = "wmslice._native")]
pub struct Mesh {
    pub core: Arc<MeshCore>,
}

/// The exception for a mesh that cannot be made ready.
fn core_error(py: Python<'_>, e: CoreError) -> PyErr {
    match e {
        CoreError::Snap(s) => snap_error(py, s),
        CoreError::Invalid(r) => report_error(py, &r),
        CoreError::Internal(e) => slice_error(py, e),
    }
}

/// Validates and prepares a mesh without the GIL.
pub fn ready(py: Python<'_>, mesh: RawMesh, snap: Option<Rat>, repairs: Repairs) -> PyResult<Mesh> {
    let core = py
        .detach(move || MeshCore::new(mesh, snap.as_ref(), repairs))
        .map_err(|e| core_error(py, e))?;
    Ok(Mesh {
        core: Arc::new(core),
    })
}

fn snap_of(snap: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Rat>> {
    snap.filter(|s| !s.is_none())
        .map(|s| exact("snap grid", s))
        .transpose()
}

/// Vertices as `[f64; 3]` rows from a float64 or float32 array (other
/// dtypes go through `numpy.asarray(..., float64)`).
fn positions(obj: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 3]>> {
    let py = obj.py();
    fn rows<T: Copy + numpy::Element>(
        a: &Bound<'_, numpy::PyArray2<T>>,
        f: impl Fn(T) -> f64,
    ) -> PyResult<Vec<[f64; 3]>> {
        let a = a.readonly();
        let v = a.as_array();
        if v.ncols() != 3 {
            return Err(PyValueError::new_err(format!(
                "vertices must have shape (n, 3), got (n, {})",
                v.ncols()
            )));
        }
        Ok(v.rows()
            .into_iter()
            .map(|r| [f(r[0]), f(r[1]), f(r[2])])
            .collect())
    }
    if let Ok(a) = obj.cast::<PyArray2<f64>>() {
        return rows(a, |x| x);
    }
    if let Ok(a) = obj.cast::<PyArray2<f32>>() {
        return rows(a, f64::from);
    }
    let np = py.import("numpy")?;
    let arr = np.call_method1("asarray", (obj,))?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "vertices must be a float array, got dtype kind {kind:?}"
        )));
    }
    let nd: usize = arr.getattr("ndim")?.extract()?;
    if nd != 2 {
        return Err(PyValueError::new_err(format!(
            "vertices must have shape (n, 3), got {nd} dimensions"
        )));
    }
    let size: usize = arr.getattr("dtype")?.getattr("itemsize")?.extract()?;
    if kind == "f" && size > 8 {
        return Err(PyTypeError::new_err(
            "vertices wider than float64 would be rounded: convert them yourself",
        ));
    }
    // Integers up to 2^53 and every float16/32/64 convert exactly;
    // larger integers would be rounded, so they are refused.
    if kind != "f" {
        let big = arr
            .call_method0("__abs__")?
            .call_method0("max")
            .ok()
            .map(|m| m.extract::<f64>().unwrap_or(0.0) > 9007199254740992.0)
            .unwrap_or(false);
        if big {
            return Err(PyValueError::new_err(
                "integer vertices beyond 2^53 are not exact as doubles",
            ));
        }
    }
    let f = np.call_method1("asarray", (arr, "float64"))?;
    rows(f.cast::<PyArray2<f64>>()?, |x| x)
}

/// Faces as vertex-id triples from any integer array; an index that no
/// `u32` holds (negative, or too large) is an [`InvalidMesh`] naming the
/// face and corner.
fn faces(obj: &Bound<'_, PyAny>, vertices: usize) -> PyResult<Vec<[u32; 3]>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let arr = np.call_method1("asarray", (obj,))?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "faces must be an integer array, got dtype kind {kind:?}"
        )));
    }
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "faces must have shape (m, 3), got {shape:?}"
        )));
    }
    let convert = |rows: &mut dyn Iterator<Item = [i128; 3]>| -> PyResult<Vec<[u32; 3]>> {
        let mut out = Vec::with_capacity(shape[0]);
        let mut bad = Vec::new();
        for (f, r) in rows.enumerate() {
            let mut t = [0u32; 3];
            for c in 0..3 {
                match u32::try_from(r[c]) {
                    Ok(v) if v != u32::MAX => t[c] = v,
                    _ => bad.push((f, c, r[c])),
                }
            }
            out.push(t);
        }
        if bad.is_empty() {
            return Ok(out);
        }
        let defects = bad
            .iter()
            .take(wmslice::mesh::validate::MAX_LISTED_DEFECTS)
            .map(|&(f, c, i)| {
                (
                    serde_json::json!({"kind": "index_out_of_range", "face": f, "corner": c,
                        "index": i.to_string(), "vertices": vertices}),
                    format!("face f{f} corner {c} refers to vertex {i}, but there are only {vertices} vertices"),
                    Severity::Error,
                )
            })
            .collect();
        let unlisted = bad
            .len()
            .saturating_sub(wmslice::mesh::validate::MAX_LISTED_DEFECTS);
        Err(invalid_mesh(py, defects, unlisted, Tally::Exact))
    };
    macro_rules! typed {
        ($t:ty) => {
            if let Ok(a) = arr.cast::<PyArray2<$t>>() {
                let a = a.readonly();
                let v = a.as_array();
                let mut it = v
                    .rows()
                    .into_iter()
                    .map(|r| [r[0] as i128, r[1] as i128, r[2] as i128]);
                return convert(&mut it);
            }
        };
    }
    typed!(i64);
    typed!(i32);
    typed!(u32);
    typed!(u64);
    typed!(i16);
    typed!(u16);
    typed!(i8);
    typed!(u8);
    let a = np.call_method1("asarray", (arr, "int64"))?;
    let a = a.cast::<PyArray2<i64>>()?.readonly();
    let v = a.as_array();
    let mut it = v
        .rows()
        .into_iter()
        .map(|r| [r[0] as i128, r[1] as i128, r[2] as i128]);
    convert(&mut it)
}

/// How many worker threads: all cores by default; from 1 to
/// [`wmslice::layers::max_threads`].
pub(crate) fn thread_count(threads: Option<usize>) -> PyResult<usize> {
    match threads {
        Some(0) => Err(PyValueError::new_err("threads must be at least 1")),
        Some(t) => wmslice::layers::thread_count(t)
            .map_err(|e| PyValueError::new_err(format!("threads={e}"))),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

impl Mesh {
    /// Slices ascending distinct levels on `threads` workers, each level
    /// rounded on its worker.
    fn sweep(
        &self,
        py: Python<'_>,
        levels: Vec<Rat>,
        exact_out: bool,
        threads: usize,
    ) -> PyResult<Vec<Level>> {
        let core = Arc::clone(&self.core);
        let done = py.detach(move || {
            let finish = |_: usize, ls: LevelSet| {
                let r = round_level(&ls, exact_out);
                (ls, r)
            };
            let mut out: Vec<(LevelSet, RoundedLevel)> = Vec::with_capacity(levels.len());
            slice_levels_then(core.slicer(), &levels, threads, &finish, |_, x| {
                out.push(x);
                Ok::<(), std::io::Error>(())
            })
            .map(|()| out)
        });
        let done = done.map_err(|e| sweep_error(py, e))?;
        Ok(done
            .into_iter()
            .map(|(ls, r)| {
                Level::new(
                    ls,
                    HeaderSrc::Mesh(Arc::clone(&self.core)),
                    exact_out,
                    Some(r),
                )
            })
            .collect())
    }
}

/// Sorted, distinct levels (the order the command line slices and writes).
fn ascending(mut levels: Vec<Rat>) -> PyResult<Vec<Rat>> {
    levels.sort_unstable();
    levels.dedup();
    if levels.is_empty() {
        return Err(PyValueError::new_err("no levels"));
    }
    Ok(levels)
}

#[pymethods]
impl Mesh {
    /// A mesh from `(n, 3)` vertices and `(m, 3)` faces (counter-clockwise
    /// seen from outside), its vertices at exactly one point merged when
    /// `weld` (exact; vertices renumbered in first-seen order), snapped to
    /// the grid `snap` when given, faces that use one vertex twice removed
    /// when `drop_collapsed` (SPEC 1's lenient mode; later faces are
    /// renumbered), degenerate faces removed by edge flips, then validated
    /// (`InvalidMesh` names every defect).
    #[new]
    #[pyo3(signature = (vertices, faces, snap=None, drop_collapsed=false, weld=false))]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        snap: Option<&Bound<'_, PyAny>>,
        drop_collapsed: bool,
        weld: bool,
    ) -> PyResult<Self> {
        let q = snap_of(snap)?;
        let positions = positions(vertices)?;
        let faces = self::faces(faces, positions.len())?;
        let mesh = RawMesh::from_raw(positions, faces);
        ready(py, mesh, q, Repairs::from_flags(weld, drop_collapsed))
    }

    /// How many vertices `weld` merged into an earlier one at the same
    /// point; None when not asked for.
    #[getter]
    fn welded(&self) -> Option<usize> {
        self.core.welded
    }

    /// The faces `drop_collapsed` removed, by their ids as given; None
    /// when not asked for.
    #[getter]
    fn dropped(&self) -> Option<Vec<u32>> {
        self.core
            .dropped
            .as_ref()
            .map(|d| d.iter().map(|f| f.0).collect())
    }

    /// Vertex count (as sliced: after snapping merged vertices).
    #[getter]
    fn num_vertices(&self) -> usize {
        self.core.mesh().num_vertices()
    }

    /// Face count.
    #[getter]
    fn num_faces(&self) -> usize {
        self.core.mesh().num_faces()
    }

    /// The vertices as sliced, `(n, 3)` float64: exact unless snapped to a
    /// grid whose multiples are not doubles (then the nearest doubles).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let m = self.core.mesh();
        let unit = self.core.unit();
        let one = unit == &Rat::from_integer(1.into());
        let xyz: Vec<f64> = m
            .positions
            .iter()
            .flat_map(|p| {
                p.map(|x| {
                    if one {
                        x
                    } else {
                        rat_to_f64(&(wmslice::exact::rational::rat_from_f64(x) * unit))
                    }
                })
            })
            .collect();
        let a = Array2::from_shape_vec((m.num_vertices(), 3), xyz)
            .unwrap_or_else(|_| Array2::zeros((0, 3)));
        PyArray2::from_owned_array(py, a)
    }

    /// The faces as sliced (after edge flips), `(m, 3)` uint32.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u32>> {
        let m = self.core.mesh();
        let ids: Vec<u32> = m.faces.iter().flat_map(|t| t.map(|v| v.0)).collect();
        let a = Array2::from_shape_vec((m.num_faces(), 3), ids)
            .unwrap_or_else(|_| Array2::zeros((0, 3)));
        PyArray2::from_owned_array(py, a)
    }

    /// The snap grid as `"p/q"`, or None.
    #[getter]
    fn snap(&self) -> Option<String> {
        self.core.grid().map(rat_to_string)
    }

    /// What snapping did: `{grid, moved, largest_move, merged}`, or None.
    #[getter]
    fn snap_report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(s) = &self.core.snap else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("grid", s.grid.clone())?;
        d.set_item("moved", s.moved)?;
        d.set_item("largest_move", s.max_move.clone())?;
        d.set_item("merged", s.merged)?;
        Ok(Some(d))
    }

    /// The edge flips that removed degenerate faces: dicts with `face`,
    /// `beyond`, `edge`, `apex`, `opposite`.
    #[getter]
    fn flips<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for f in &self.core.flips {
            let d = PyDict::new(py);
            d.set_item("face", f.face.0)?;
            d.set_item("beyond", f.beyond.0)?;
            d.set_item("edge", (f.edge[0].0, f.edge[1].0))?;
            d.set_item("apex", f.apex.0)?;
            d.set_item("opposite", f.opposite.0)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// SHA-256 of the mesh as sliced (the JSON header's).
    #[getter]
    fn sha256(&self, py: Python<'_>) -> String {
        let core = Arc::clone(&self.core);
        py.detach(move || core.header().sha256.clone())
    }

    /// The exact height range `(z_min, z_max)` of the vertices, as Fractions.
    #[getter]
    fn z_range(&self) -> (Rat, Rat) {
        height_range(self.core.mesh(), self.core.unit())
    }

    /// The level set at one exact level.
    #[pyo3(signature = (z, exact=false))]
    fn slice(&self, py: Python<'_>, z: &Bound<'_, PyAny>, exact: bool) -> PyResult<Level> {
        let c = self::exact("level", z)?;
        let core = Arc::clone(&self.core);
        let (ls, r) = py
            .detach(move || {
                let ls = core.slicer().slice_at(&c)?;
                let r = round_level(&ls, exact);
                Ok::<_, wmslice::SliceError>((ls, r))
            })
            .map_err(|e| slice_error(py, e))?;
        Ok(Level::new(
            ls,
            HeaderSrc::Mesh(Arc::clone(&self.core)),
            exact,
            Some(r),
        ))
    }

    /// The level sets at many levels, ascending and distinct (as the
    /// command line slices them), on `threads` workers (default: all
    /// cores); the result does not depend on `threads`.
    #[pyo3(signature = (levels, exact=false, threads=None))]
    fn slice_many(
        &self,
        py: Python<'_>,
        levels: &Bound<'_, PyAny>,
        exact: bool,
        threads: Option<usize>,
    ) -> PyResult<Vec<Level>> {
        let levels = ascending(levels_of(levels)?)?;
        let threads = thread_count(threads)?;
        self.sweep(py, levels, exact, threads)
    }

    /// The exact levels of uniform layers `first + k * layer_height` up to
    /// `last` (defaults: mid-layer above the lowest vertex, the highest
    /// vertex), as the command line's `--layer-height` plans them.
    #[pyo3(signature = (layer_height, first=None, last=None))]
    fn layer_levels(
        &self,
        layer_height: &Bound<'_, PyAny>,
        first: Option<&Bound<'_, PyAny>>,
        last: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Vec<Rat>> {
        let opt = |name: &str, v: Option<&Bound<'_, PyAny>>| {
            v.filter(|v| !v.is_none())
                .map(|v| exact(name, v))
                .transpose()
        };
        let plan = LayerPlan {
            height: exact("layer height", layer_height)?,
            first: opt("first", first)?,
            last: opt("last", last)?,
        };
        let (lo, hi) = height_range(self.core.mesh(), self.core.unit());
        plan_levels(Some(&plan), &[], (&lo, &hi)).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The level sets of uniform layers ([`Mesh::layer_levels`]).
    #[pyo3(signature = (layer_height, first=None, last=None, exact=false, threads=None))]
    fn slice_layers(
        &self,
        py: Python<'_>,
        layer_height: &Bound<'_, PyAny>,
        first: Option<&Bound<'_, PyAny>>,
        last: Option<&Bound<'_, PyAny>>,
        exact: bool,
        threads: Option<usize>,
    ) -> PyResult<Vec<Level>> {
        let levels = self.layer_levels(layer_height, first, last)?;
        let threads = thread_count(threads)?;
        self.sweep(py, levels, exact, threads)
    }

    /// Pickled as the mesh as sliced (exact positions, faces, grid, what
    /// snapping and flipping did); validated again when unpickled.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let m = self.core.mesh();
        let xyz: Vec<f64> = m.positions.iter().flatten().copied().collect();
        let ids: Vec<u32> = m.faces.iter().flat_map(|t| t.map(|v| v.0)).collect();
        let snap = self.core.snap.as_ref().map(|s| {
            (
                rat_to_string(&s.grid),
                s.moved,
                rat_to_string(&s.max_move),
                s.merged,
            )
        });
        let flips: Vec<[u32; 6]> = self
            .core
            .flips
            .iter()
            .map(|f| {
                [
                    f.face.0,
                    f.beyond.0,
                    f.edge[0].0,
                    f.edge[1].0,
                    f.apex.0,
                    f.opposite.0,
                ]
            })
            .collect();
        let restore = py.get_type::<Mesh>().getattr("_restore")?;
        let args = (
            pyo3::types::PyBytes::new(
                py,
                &xyz.iter()
                    .flat_map(|x| x.to_le_bytes())
                    .collect::<Vec<u8>>(),
            ),
            pyo3::types::PyBytes::new(
                py,
                &ids.iter()
                    .flat_map(|x| x.to_le_bytes())
                    .collect::<Vec<u8>>(),
            ),
            snap,
            flips,
            self.dropped(),
            self.core.welded,
        )
            .into_pyobject(py)?
            .into_any();
        Ok((restore, args))
    }

    /// The mesh from [`Mesh::__reduce__`]'s state (`dropped` absent from
    /// pickles made before `drop_collapsed`, `welded` from those made
    /// before `weld`).
    #[staticmethod]
    #[pyo3(signature = (positions, faces, snap, flips, dropped=None, welded=None))]
    fn _restore(
        py: Python<'_>,
        positions: &[u8],
        faces: &[u8],
        snap: Option<(String, usize, String, usize)>,
        flips: Vec<[u32; 6]>,
        dropped: Option<Vec<u32>>,
        welded: Option<usize>,
    ) -> PyResult<Mesh> {
        use wmslice::exact::parse_rational;
        use wmslice::ids::VertexId;
        use wmslice::mesh::flip::Flip;
        use wmslice::mesh::prepare::SnapStats;
        let bad = |what: &str| PyValueError::new_err(format!("not a pickled wmslice mesh: {what}"));
        if positions.len() % 24 != 0 || faces.len() % 12 != 0 {
            return Err(bad("lengths"));
        }
        let f64s: Vec<f64> = positions
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
            .collect();
        let u32s: Vec<u32> = faces
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap_or([0; 4])))
            .collect();
        let pos = f64s.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let tri = u32s.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let stats = match snap {
            None => None,
            Some((grid, moved, max_move, merged)) => Some(SnapStats {
                // A grid is positive (the unit every coordinate is
                // multiplied by, and divided by when levels are mapped).
                grid: parse_rational(&grid)
                    .ok()
                    .filter(|g| *g > Rat::from_integer(0.into()))
                    .ok_or_else(|| bad("grid"))?,
                moved,
                max_move: parse_rational(&max_move).map_err(|_| bad("move"))?,
                merged,
            }),
        };
        let flips = flips
            .into_iter()
            .map(|[face, beyond, a, b, apex, opposite]| Flip {
                face: FaceId(face),
                beyond: FaceId(beyond),
                edge: [VertexId(a), VertexId(b)],
                apex: VertexId(apex),
                opposite: VertexId(opposite),
            })
            .collect();
        let prepared = Prepared {
            unit: stats.as_ref().map(|s| s.grid.clone()),
            mesh: RawMesh::from_raw(pos, tri),
            snap: stats,
            welded,
            dropped: dropped.map(|d| d.into_iter().map(FaceId).collect()),
            flips,
        };
        let core = py
            .detach(move || MeshCore::prepared(prepared))
            .map_err(|e| core_error(py, e))?;
        Ok(Mesh {
            core: Arc::new(core),
        })
    }

    /// The `wmslice-critical` JSON document, as `wmslice critical --format
    /// json` writes it: the critical heights, the Reeb graph and, with a
    /// layer height, the fitted plan (`fit`) or the uniform plan's audit
    /// (first plane `first`, default mid-layer above the lowest vertex).
    #[pyo3(signature = (layer_height=None, fit=false, first=None))]
    fn critical_json(
        &self,
        py: Python<'_>,
        layer_height: Option<&Bound<'_, PyAny>>,
        fit: bool,
        first: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let height = layer_height.map(|h| exact("layer_height", h)).transpose()?;
        let first = first.map(|f| exact("first", f)).transpose()?;
        if height.is_none() && (fit || first.is_some()) {
            return Err(PyValueError::new_err("fit and first need a layer_height"));
        }
        let core = Arc::clone(&self.core);
        py.detach(move || {
            let report = critical::analyze(core.slicer())
                .map_err(|e| InternalError::new_err(e.to_string()))?;
            let plan = match height {
                None => None,
                Some(h) if fit => Some(PlanReport::fitted(&report, &h)),
                Some(h) => {
                    let first = first.unwrap_or_else(|| {
                        height_range(core.mesh(), core.unit()).0 + &h / Rat::from_integer(2.into())
                    });
                    Some(PlanReport::uniform(&report, &h, &first))
                }
            }
            .transpose()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
            Ok(critical_json(core.header(), &report, plan.as_ref()))
        })
    }

    /// The JSON document (SPEC 9) of levels sliced from this mesh; see
    /// `document`.
    #[pyo3(signature = (levels, exact=None, path=None))]
    fn to_json(
        &self,
        py: Python<'_>,
        levels: Vec<Bound<'_, Level>>,
        exact: Option<bool>,
        path: Option<std::path::PathBuf>,
    ) -> PyResult<Option<String>> {
        crate::level::document(py, levels, exact, path)
    }
}

/// Reads a mesh file (STL, OBJ, OFF, PLY, 3MF: every format the command
/// line reads, told by extension and content), merges its vertices at
/// exactly one point when `weld`, snaps it when asked, removes the faces
/// that use one vertex twice when `drop_collapsed`, removes degenerate
/// faces and validates it.
#[pyfunction]
#[pyo3(signature = (path, snap=None, drop_collapsed=false, weld=false))]
pub fn load(
    py: Python<'_>,
    path: std::path::PathBuf,
    snap: Option<&Bound<'_, PyAny>>,
    drop_collapsed: bool,
    weld: bool,
) -> PyResult<Mesh> {
    let shown = path.display().to_string();
    let read = py.detach(|| load_exact(&path));
    prepared(
        py,
        read,
        &shown,
        snap,
        Repairs::from_flags(weld, drop_collapsed),
    )
}

/// As [`load`], for a mesh file's bytes already in memory (the format told
/// by content alone).
#[pyfunction]
#[pyo3(signature = (data, snap=None, drop_collapsed=false, weld=false))]
pub fn load_bytes(
    py: Python<'_>,
    data: &Bound<'_, pyo3::types::PyBytes>,
    snap: Option<&Bound<'_, PyAny>>,
    drop_collapsed: bool,
    weld: bool,
) -> PyResult<Mesh> {
    let bytes = data.as_bytes();
    let read = py.detach(|| load_bytes_exact(bytes, None));
    let repairs = Repairs::from_flags(weld, drop_collapsed);
    prepared(py, read, "<bytes>", snap, repairs)
}

/// A mesh file as read, snapped and repaired as asked, validated; errors
/// name the file as `shown`.
fn prepared(
    py: Python<'_>,
    read: Result<(wmslice::Mesh, LoadReport, ExactPositions), LoadError>,
    shown: &str,
    snap: Option<&Bound<'_, PyAny>>,
    repairs: Repairs,
) -> PyResult<Mesh> {
    let q = snap_of(snap)?;
    let (mesh, _, exact) = read.map_err(|e| load_error(shown, e))?;
    // A 3MF vertex whose transformed position is not a double is placed
    // only by the grid; without one it is the file's error.
    let p = py
        .detach(|| prepare_exact_with(mesh, &exact, q.as_ref(), repairs))
        .map_err(|e| match e {
            PrepareError::NotDoubles(e) => load_error(shown, e),
            PrepareError::Snap(e) => snap_error(py, e),
        })?;
    let core = py
        .detach(move || MeshCore::prepared(p))
        .map_err(|e| core_error(py, e))?;
    Ok(Mesh {
        core: Arc::new(core),
    })
}

/// A built-in dataset (the paper's meshes, built exactly), by name.
#[pyfunction]
#[pyo3(signature = (name, snap=None))]
pub fn dataset(py: Python<'_>, name: &str, snap: Option<&Bound<'_, PyAny>>) -> PyResult<Mesh> {
    let q = snap_of(snap)?;
    let d = builtin::by_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "no built-in dataset {name:?}; wmslice.datasets() lists them"
        ))
    })?;
    ready(py, d.build(), q, Repairs::default())
}

/// The built-in datasets: `(name, summary, degenerate levels as Fractions)`.
#[pyfunction]
pub fn datasets() -> Vec<(&'static str, &'static str, Vec<Rat>)> {
    builtin::all()
        .iter()
        .map(|d| {
            (
                d.name,
                d.summary,
                d.degenerate_levels
                    .iter()
                    .map(|&(p, q)| Rat::new(p.into(), q.into()))
                    .collect(),
            )
        })
        .collect()
}
