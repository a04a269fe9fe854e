//! Input: Python numbers given as levels, layer heights or snap grids.
//! Output: exact rationals. A `float` is the exact binary value of the
//! double (0.1 is 3602879701896397/36028797018963968, not 1/10); an `int`,
//! a `fractions.Fraction` and a `decimal.Decimal` are taken exactly; a
//! `str` goes through the crate's exact parser (`"0.1"` is 1/10, `"3/5"`
//! works); numpy integers and floats up to 64 bits likewise. Anything else,
//! a bool, NaN or an infinity is a `ValueError`.

use num_bigint::BigInt;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_from_f64, Rat};

fn bad(what: &str, obj: &Bound<'_, PyAny>, why: &str) -> PyErr {
    let shown = obj
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into());
    PyValueError::new_err(format!("{what} {shown}: {why}"))
}

fn of_f64(what: &str, obj: &Bound<'_, PyAny>, x: f64) -> PyResult<Rat> {
    if !x.is_finite() {
        return Err(bad(what, obj, "not a finite number"));
    }
    Ok(rat_from_f64(x))
}

/// The exact value of `obj` (see the module doc); `what` names it in errors.
pub fn exact(what: &str, obj: &Bound<'_, PyAny>) -> PyResult<Rat> {
    let py = obj.py();
    if obj.is_instance_of::<PyBool>() {
        return Err(bad(what, obj, "a bool is not a number here"));
    }
    if obj.is_instance_of::<PyFloat>() {
        return of_f64(what, obj, obj.extract::<f64>()?);
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(Rat::from_integer(obj.extract::<BigInt>()?));
    }
    if obj.is_instance_of::<PyString>() {
        let text: String = obj.extract()?;
        return parse_rational(&text).map_err(|e| bad(what, obj, &e.to_string()));
    }
    let fraction = py.import("fractions")?.getattr("Fraction")?;
    if obj.is_instance(&fraction)? {
        return obj.extract::<Rat>();
    }
    if obj.is_instance(&py.import("decimal")?.getattr("Decimal")?)? {
        // Exact; NaN and infinities are refused by Fraction.
        let f = fraction
            .call1((obj,))
            .map_err(|_| bad(what, obj, "not a finite number"))?;
        return f.extract::<Rat>();
    }
    if obj.is_instance(&py.import("numbers")?.getattr("Integral")?)? {
        let i = obj.call_method0("__index__")?;
        return Ok(Rat::from_integer(i.extract::<BigInt>()?));
    }
    // numpy floating scalars of at most 64 bits convert to a double exactly.
    if let Ok(dtype) = obj.getattr("dtype") {
        let kind: String = dtype.getattr("kind")?.extract()?;
        let size: usize = dtype.getattr("itemsize")?.extract()?;
        if kind == "f" && size <= 8 && obj.getattr("shape")?.len()? == 0 {
            let x: f64 = obj.call_method0("__float__")?.extract()?;
            return of_f64(what, obj, x);
        }
    }
    Err(bad(
        what,
        obj,
        "expected an int, a float (its exact binary value), a str such as '3/5' or '0.2', a Fraction or a Decimal",
    ))
}

/// The exact value of `obj` as a `fractions.Fraction` (how the package
/// reads levels, layer heights and snap grids).
#[pyfunction]
pub fn exact_value(obj: &Bound<'_, PyAny>) -> PyResult<Rat> {
    exact("value", obj)
}

/// Levels from a numpy array (float64, float32 or any integer dtype: no
/// Python object per level) or any iterable of numbers.
pub fn levels(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Rat>> {
    use numpy::{PyArrayDyn, PyArrayMethods};
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        let a = a.readonly();
        return a
            .as_array()
            .iter()
            .map(|&x| of_f64("level", obj, x))
            .collect();
    }
    if let Ok(a) = obj.cast::<PyArrayDyn<f32>>() {
        let a = a.readonly();
        return a
            .as_array()
            .iter()
            .map(|&x| of_f64("level", obj, f64::from(x)))
            .collect();
    }
    if let Ok(a) = obj.cast::<PyArrayDyn<i64>>() {
        let a = a.readonly();
        return Ok(a
            .as_array()
            .iter()
            .map(|&x| Rat::from_integer(x.into()))
            .collect());
    }
    if obj.is_instance_of::<PyString>() {
        return Err(PyValueError::new_err(
            "levels must be a sequence of numbers, not one str",
        ));
    }
    let mut out = Vec::new();
    for item in obj.try_iter()? {
        out.push(exact("level", &item?)?);
    }
    Ok(out)
}
