//! Input: exact level sets from the slicer. Output: the [`Level`] Python
//! class (wrapped by `wmslice.LevelSet`): each family of loops as one
//! `(N, 2)` float64 ndarray of the nearest doubles of the exact points with
//! the loops' start offsets (rounded on the slicing threads: no Python
//! object per point), the other parts as small tuples, the exact values on
//! demand, the JSON text of SPEC 9 byte-equal to the command line's, and
//! pickling (an exact binary encoding, `codec`).

use crate::codec;
use crate::core::MeshCore;

use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyList, PyTuple};
use rayon::prelude::*;
use std::sync::{Arc, Mutex};
use wmslice::exact::rational::{rat_to_f64, Rat};
use wmslice::exact::Sign;
use wmslice::levelset::{LevelSet, Loop};
use wmslice::output::atomic::AtomicFile;
use wmslice::output::json::{level_text, Exactness, JsonWriter, LevelText, MeshHeader};
use wmslice::segment::CutPoint;

/// Where a level's JSON header comes from.
#[derive(Clone)]
pub enum HeaderSrc {
    /// The mesh it was sliced from (the header is made on first use).
    Mesh(Arc<MeshCore>),
    /// A header carried with the level (unpickled).
    Fixed(Arc<MeshHeader>),
}

impl HeaderSrc {
    /// The header.
    pub fn get(&self) -> &MeshHeader {
        match self {
            HeaderSrc::Mesh(m) => m.header(),
            HeaderSrc::Fixed(h) => h,
        }
    }
}

/// One family of loops rounded: points `(x, y)` interleaved, loop `i` at
/// rows `starts[i]..starts[i + 1]`, and each loop's rounded area.
pub struct Rounded {
    xy: Vec<f64>,
    starts: Vec<i64>,
    areas: Vec<f64>,
}

/// A loop's area as the JSON writes it: with `exact`, the nearest double of
/// the exact area; else the certified rounding from its rounded points
/// (`rounded`: [`Loop::rounded_area`]). An area beyond the doubles is
/// `f64::MAX` of its (exact) sign.
pub fn loop_area(l: &Loop, exact: bool, rounded: &[[f64; 2]]) -> f64 {
    let a = if exact {
        rat_to_f64(&l.area())
    } else {
        l.rounded_area(rounded)
    };
    if a.is_finite() {
        a
    } else if l.orientation == Sign::Negative {
        f64::MIN
    } else {
        f64::MAX
    }
}

/// Rounds a family (on the calling thread: the slicing workers call it).
pub fn round_family(loops: &[Loop], exact: bool) -> Rounded {
    let n: usize = loops.iter().map(|l| l.points.len()).sum();
    let mut xy = Vec::with_capacity(2 * n);
    let mut starts = Vec::with_capacity(loops.len() + 1);
    let mut areas = Vec::with_capacity(loops.len());
    let mut points = Vec::new();
    starts.push(0);
    for l in loops {
        points.clear();
        points.extend(l.points.iter().map(|p| p.to_f64()));
        xy.extend(points.iter().flatten());
        starts.push((xy.len() / 2) as i64);
        areas.push(loop_area(l, exact, &points));
    }
    Rounded { xy, starts, areas }
}

/// Every family of a level, rounded.
pub struct RoundedLevel {
    contours: Option<Rounded>,
    below: Option<Rounded>,
    above: Option<Rounded>,
    boundaries: Vec<Option<Rounded>>,
}

/// Whether L- and L+ are S_O's loops (no vertex on the plane).
fn shared(ls: &LevelSet) -> bool {
    Arc::ptr_eq(&ls.contours, &ls.below) && Arc::ptr_eq(&ls.contours, &ls.above)
}

/// Rounds every family of a level (what the slicing workers do).
pub fn round_level(ls: &LevelSet, exact: bool) -> RoundedLevel {
    let split = !shared(ls);
    RoundedLevel {
        contours: Some(round_family(&ls.contours, exact)),
        below: split.then(|| round_family(&ls.below, exact)),
        above: split.then(|| round_family(&ls.above, exact)),
        boundaries: ls
            .regions
            .iter()
            .map(|r| Some(round_family(&r.boundary, exact)))
            .collect(),
    }
}

/// Which family of loops.
#[derive(Clone, Copy)]
enum Family {
    Contours,
    Below,
    Above,
    Boundary(usize),
}

impl Family {
    fn parse(name: &str, region: Option<usize>) -> PyResult<Family> {
        Ok(match (name, region) {
            ("contours", None) => Family::Contours,
            ("below", None) => Family::Below,
            ("above", None) => Family::Above,
            ("boundary", Some(r)) => Family::Boundary(r),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "no family {name:?} (contours, below, above, or boundary with a region)"
                )))
            }
        })
    }
}

/// One exact level set, with where its header comes from.
#[pyclass(frozen, module = "wmslice._native")]
pub struct Level {
    pub inner: Arc<LevelSet>,
    pub header: HeaderSrc,
    /// Sliced with exact output (areas the nearest doubles of the exact
    /// areas; exact values offered).
    pub exact: bool,
    rounded: Mutex<Option<RoundedLevel>>,
}

impl Level {
    /// A level, with its families already rounded (or `None`: rounded when
    /// asked for).
    pub fn new(
        inner: LevelSet,
        header: HeaderSrc,
        exact: bool,
        rounded: Option<RoundedLevel>,
    ) -> Self {
        Level {
            inner: Arc::new(inner),
            header,
            exact,
            rounded: Mutex::new(rounded),
        }
    }

    fn loops(&self, family: Family) -> PyResult<&[Loop]> {
        let ls = &self.inner;
        Ok(match family {
            Family::Contours => &ls.contours,
            Family::Below => &ls.below,
            Family::Above => &ls.above,
            Family::Boundary(r) => {
                &ls.regions
                    .get(r)
                    .ok_or_else(|| PyIndexError::new_err(format!("no region {r}")))?
                    .boundary
            }
        })
    }

    /// The family rounded: taken from the workers' result the first time,
    /// else rounded now.
    fn take_rounded(&self, family: Family) -> PyResult<Rounded> {
        let taken = self.rounded.lock().ok().and_then(|mut g| {
            let r = g.as_mut()?;
            match family {
                Family::Contours => r.contours.take(),
                Family::Below => r.below.take(),
                Family::Above => r.above.take(),
                Family::Boundary(i) => r.boundaries.get_mut(i)?.take(),
            }
        });
        match taken {
            Some(r) => Ok(r),
            None => Ok(round_family(self.loops(family)?, self.exact)),
        }
    }

    /// `(points (N, 2), starts (k + 1), areas (k), roles, parents, collapsed)`.
    fn family_tuple<'py>(&self, py: Python<'py>, family: Family) -> PyResult<Bound<'py, PyTuple>> {
        let r = self.take_rounded(family)?;
        let loops = self.loops(family)?;
        let rows = r.xy.len() / 2;
        let xy = Array2::from_shape_vec((rows, 2), r.xy)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let points = PyArray2::from_owned_array(py, xy);
        let starts = PyArray1::from_vec(py, r.starts);
        let areas = PyArray1::from_vec(py, r.areas);
        let roles: Vec<&str> = loops.iter().map(|l| role_name(l)).collect();
        let parents: Vec<Option<usize>> = loops.iter().map(|l| l.parent).collect();
        let collapsed: Vec<bool> = loops.iter().map(|l| l.collapsed).collect();
        (points, starts, areas, roles, parents, collapsed).into_pyobject(py)
    }
}

fn role_name(l: &Loop) -> &'static str {
    match l.role {
        wmslice::nest::Role::Outer => "outer",
        wmslice::nest::Role::Hole => "hole",
    }
}

/// The name `serde` gives a unit enum (as the JSON writes it).
fn name<T: serde::Serialize>(v: &T) -> String {
    match serde_json::to_value(v) {
        Ok(serde_json::Value::String(s)) => s,
        _ => String::new(),
    }
}

fn exactness(exact: bool) -> Exactness {
    if exact {
        Exactness::WithExact
    } else {
        Exactness::Rounded
    }
}

fn points_array<'py>(
    py: Python<'py>,
    pts: impl Iterator<Item = [f64; 2]>,
) -> Bound<'py, PyArray2<f64>> {
    let xy: Vec<f64> = pts.flatten().collect();
    let rows = xy.len() / 2;
    // `rows * 2` values: the shape fits.
    let a = Array2::from_shape_vec((rows, 2), xy).unwrap_or_else(|_| Array2::zeros((0, 2)));
    PyArray2::from_owned_array(py, a)
}

#[pymethods]
impl Level {
    /// The exact level, as a Fraction.
    #[getter]
    fn z(&self) -> Rat {
        self.inner.level.clone()
    }

    /// Whether the level was sliced with exact output.
    #[getter]
    fn exact(&self) -> bool {
        self.exact
    }

    /// Whether L- and L+ are S_O's loops (no vertex on the plane).
    fn shared(&self) -> bool {
        shared(&self.inner)
    }

    /// A family of loops (`contours`, `below`, `above`; `boundary` with a
    /// region index): `(points (N, 2) float64, starts (k + 1) int64, areas
    /// (k) float64, roles, parents, collapsed)`.
    #[pyo3(signature = (name, region=None))]
    fn family<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        region: Option<usize>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        self.family_tuple(py, Family::parse(name, region)?)
    }

    /// F: `(facing, faces (uint32 ndarray), exact area (Fraction))` per region.
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for r in &self.inner.regions {
            let faces: Vec<u32> = r.faces.iter().map(|f| f.0).collect();
            out.append((
                name(&r.facing),
                PyArray1::from_vec(py, faces),
                r.area.clone(),
            ))?;
        }
        Ok(out)
    }

    /// S_NO: `(kind, closed, vertices (uint32), points (k, 2) float64)`.
    fn ridges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for r in &self.inner.ridges {
            let vertices: Vec<u32> = r.vertices.iter().map(|v| v.0).collect();
            out.append((
                name(&r.kind),
                r.closed,
                PyArray1::from_vec(py, vertices),
                points_array(py, r.points.iter().map(|p| p.to_f64())),
            ))?;
        }
        Ok(out)
    }

    /// P: `(vertex, kind, x, y)` with the nearest doubles.
    fn extrema(&self) -> Vec<(u32, String, f64, f64)> {
        self.inner
            .extrema
            .iter()
            .map(|e| {
                let [x, y] = e.point.to_f64();
                (e.vertex.0, name(&e.kind), x, y)
            })
            .collect()
    }

    /// Saddles: `(vertex, branches)`.
    fn saddles(&self) -> Vec<(u32, u32)> {
        self.inner
            .saddles
            .iter()
            .map(|s| (s.vertex.0, s.branches))
            .collect()
    }

    /// One loop's exact values: its points as `(Fraction, Fraction)`, the
    /// mesh element each lies on as `('edge' | 'vertex', id)`, and its exact
    /// signed area.
    #[pyo3(signature = (name, index, region=None))]
    #[allow(clippy::type_complexity)]
    fn loop_exact(
        &self,
        name: &str,
        index: usize,
        region: Option<usize>,
    ) -> PyResult<(Vec<(Rat, Rat)>, Vec<(&'static str, u32)>, Rat)> {
        let loops = self.loops(Family::parse(name, region)?)?;
        let l = loops
            .get(index)
            .ok_or_else(|| PyIndexError::new_err(format!("no loop {index}")))?;
        let points = l
            .points
            .iter()
            .map(|p| {
                let e = p.exact();
                (e.x.clone(), e.y.clone())
            })
            .collect();
        let on = l
            .cuts
            .iter()
            .map(|c| match c {
                CutPoint::OnEdge(e) => ("edge", e.0),
                CutPoint::AtVertex(v) => ("vertex", v.0),
            })
            .collect();
        Ok((points, on, l.area()))
    }

    /// The level's JSON object (SPEC 9) as bytes; `exact` defaults to how
    /// the level was sliced.
    #[pyo3(signature = (exact=None))]
    fn text<'py>(&self, py: Python<'py>, exact: Option<bool>) -> Bound<'py, PyBytes> {
        let ex = exactness(exact.unwrap_or(self.exact));
        let inner = Arc::clone(&self.inner);
        let bytes = py.detach(move || level_text(&inner, ex).to_bytes());
        PyBytes::new(py, &bytes)
    }

    /// The header's fields: `(vertices, faces, sha256, snap)`.
    fn header(&self, py: Python<'_>) -> (usize, usize, String, Option<String>) {
        let src = self.header.clone();
        let h = py.detach(move || src.get().clone());
        (h.vertices, h.faces, h.sha256, h.snap)
    }

    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let inner = Arc::clone(&self.inner);
        let src = self.header.clone();
        let exact = self.exact;
        let bytes = py.detach(move || codec::encode(&inner, src.get(), exact));
        let restore = py.get_type::<Level>().getattr("_from_bytes")?;
        Ok((restore, (PyBytes::new(py, &bytes),)))
    }

    /// A level from [`Level::__reduce__`]'s bytes.
    #[staticmethod]
    fn _from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Level> {
        let data = data.to_vec();
        let (ls, header, exact) = py
            .detach(move || codec::decode(&data))
            .map_err(|e| PyValueError::new_err(format!("not a pickled wmslice level: {e}")))?;
        Ok(Level::new(
            ls,
            HeaderSrc::Fixed(Arc::new(header)),
            exact,
            None,
        ))
    }
}

/// The JSON document (SPEC 9) of `levels`, in the order given, with the
/// header of the mesh they were sliced from; byte-equal to `wmslice slice
/// ... --format json [--exact]` for the same mesh and levels. The levels'
/// texts are made in parallel, without the GIL. With `path`, the document
/// is written there atomically (temporary file, then rename) and `None` is
/// returned; else it is returned as a str.
#[pyfunction]
#[pyo3(signature = (levels, exact=None, path=None))]
pub fn document(
    py: Python<'_>,
    levels: Vec<Bound<'_, Level>>,
    exact: Option<bool>,
    path: Option<std::path::PathBuf>,
) -> PyResult<Option<String>> {
    let refs: Vec<Arc<LevelSet>> = levels.iter().map(|l| Arc::clone(&l.get().inner)).collect();
    let Some(first) = levels.first() else {
        return Err(PyValueError::new_err("no levels"));
    };
    let src = first.get().header.clone();
    let ex = exactness(exact.unwrap_or_else(|| levels.iter().all(|l| l.get().exact)));
    let texts = move || -> (MeshHeader, Vec<LevelText>) {
        let header = src.get().clone();
        let texts = refs.par_iter().map(|ls| level_text(ls, ex)).collect();
        (header, texts)
    };
    match path {
        None => {
            let text = py.detach(move || -> std::io::Result<String> {
                let (header, texts) = texts();
                let mut w = JsonWriter::begin(Vec::new(), &header, ex)?;
                for t in &texts {
                    w.level_text(t)?;
                }
                Ok(String::from_utf8_lossy(&w.finish()?).into_owned())
            });
            text.map(Some)
                .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))
        }
        Some(p) => {
            let shown = p.display().to_string();
            py.detach(move || -> std::io::Result<()> {
                let (header, texts) = texts();
                let file = std::io::BufWriter::new(AtomicFile::create(&p)?);
                let mut w = JsonWriter::begin(file, &header, ex)?;
                for t in &texts {
                    w.level_text(t)?;
                }
                w.finish()?
                    .into_inner()
                    .map_err(|e| e.into_error())?
                    .commit()
            })
            .map_err(|e| crate::errors::io_error(&shown, &e))?;
            Ok(None)
        }
    }
}
