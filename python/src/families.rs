//! The random adversarial families (`wmslice gen --families`) from
//! Python: their names, a mesh for a seed, and its exact answers.

use crate::errors::InternalError;
use crate::mesh::{ready, Mesh};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use wmslice::datasets::families::{all, answers::answers as exact_answers, by_name, Family};
use wmslice::mesh::prepare::Repairs;

fn family(name: &str) -> PyResult<&'static Family> {
    by_name(name).ok_or_else(|| {
        let names: Vec<&str> = all().iter().map(|f| f.name).collect();
        PyValueError::new_err(format!("unknown family {name:?}: {}", names.join(", ")))
    })
}

/// Every family as `(name, what it exercises)`.
#[pyfunction]
pub fn family_names() -> Vec<(&'static str, &'static str)> {
    all().iter().map(|f| (f.name, f.summary)).collect()
}

/// The mesh of `family` for `seed` as its answers slice it: snapped to the
/// family's grid when it has one, validated.
#[pyfunction]
pub fn family_mesh(py: Python<'_>, family: &str, seed: u64) -> PyResult<Mesh> {
    let f = self::family(family)?;
    ready(py, f.generate(seed), f.snap(), Repairs::default())
}

/// The answers file of `wmslice gen --random SEED --family NAME --answers
/// FILE` (JSON text), verified before it is returned.
#[pyfunction]
pub fn family_answers(py: Python<'_>, family: &str, seed: u64) -> PyResult<String> {
    let f = self::family(family)?;
    py.detach(move || {
        exact_answers(f.generate(seed), f.snap().as_ref())
            .map(|a| a.to_json(f, seed))
            .map_err(|e| InternalError::new_err(e.to_string()))
    })
}
