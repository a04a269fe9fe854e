//! `wmslice._native`: the extension module of the Python package `wmslice`
//! (the Python classes in `python/wmslice/` wrap it).
//!
//! Input: numpy arrays, file paths and Python numbers. Output: exact level
//! sets whose points come out as `float64` ndarrays built straight from the
//! slicer's results (rounded to the nearest double on the slicing threads,
//! no Python object per point), the same JSON the command line writes, and
//! typed Python exceptions. Every library error maps to an exception; the
//! GIL is released while a mesh is validated, sliced or written.

mod batch;
mod codec;
mod core;
mod errors;
mod families;
mod level;
mod mesh;
mod values;

use pyo3::prelude::*;

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InvalidMesh", py.get_type::<errors::InvalidMesh>())?;
    m.add("InternalError", py.get_type::<errors::InternalError>())?;
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<level::Level>()?;
    m.add_function(wrap_pyfunction!(mesh::load, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::load_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::dataset, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::datasets, m)?)?;
    m.add_function(wrap_pyfunction!(level::document, m)?)?;
    m.add_function(wrap_pyfunction!(values::exact_value, m)?)?;
    m.add_function(wrap_pyfunction!(batch::slice_part, m)?)?;
    m.add_function(wrap_pyfunction!(batch::join_shards, m)?)?;
    m.add_function(wrap_pyfunction!(families::family_names, m)?)?;
    m.add_function(wrap_pyfunction!(families::family_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(families::family_answers, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
