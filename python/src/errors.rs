//! Input: the library's typed errors. Output: Python exceptions:
//! [`InvalidMesh`] (a `ValueError`) naming every defect by element id,
//! `ValueError` for a bad level or argument, `OSError` for a file that
//! cannot be read or written, [`InternalError`] (a `RuntimeError`) for a
//! broken invariant, which is a bug.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyList;
use wmslice::layers::SweepError;
use wmslice::mesh::io::LoadError;
use wmslice::mesh::snap::SnapError;
use wmslice::mesh::validate::{Report, Severity, Tally};
use wmslice::SliceError;

pyo3::create_exception!(
    wmslice,
    InvalidMesh,
    PyValueError,
    "The mesh is not accepted for slicing (SPEC 1). `.defects` lists every \
     defect as a dict with its `kind`, the element ids it concerns, its \
     `severity` and `message`; `.unlisted` counts defects beyond the list \
     (a lower bound when `.unlisted_count` is \"at_least\": the search for \
     self-intersections stops counting at 10 000 pairs of faces)."
);
pyo3::create_exception!(
    wmslice,
    InternalError,
    PyRuntimeError,
    "A broken invariant on a mesh validation accepted: a bug, please report."
);

/// At most this many defects are named in the message; `.defects` has all
/// that validation listed.
const IN_MESSAGE: usize = 10;

/// An [`InvalidMesh`] with its message and `.defects` (JSON objects, each
/// with `message` and `severity` added).
pub fn invalid_mesh(
    py: Python<'_>,
    defects: Vec<(serde_json::Value, String, Severity)>,
    unlisted: usize,
    tally: Tally,
) -> PyErr {
    let errors: Vec<&str> = defects
        .iter()
        .filter(|d| d.2 == Severity::Error)
        .map(|d| d.1.as_str())
        .collect();
    let count = errors.len() + unlisted;
    let at_least = match tally {
        Tally::Exact => "",
        Tally::AtLeast => "at least ",
    };
    let mut message = format!(
        "invalid mesh ({at_least}{count} blocking defect{}): {}",
        if count == 1 { "" } else { "s" },
        errors
            .iter()
            .take(IN_MESSAGE)
            .copied()
            .collect::<Vec<_>>()
            .join("; ")
    );
    if count > IN_MESSAGE {
        message.push_str(&format!(
            "; and {at_least}{} more (see .defects)",
            count - IN_MESSAGE
        ));
    }
    let err = InvalidMesh::new_err(message);
    let attach = || -> PyResult<()> {
        let json = py.import("json")?;
        let list = PyList::empty(py);
        for (mut value, text, severity) in defects {
            if let Some(o) = value.as_object_mut() {
                o.insert("message".into(), text.into());
                o.insert(
                    "severity".into(),
                    match severity {
                        Severity::Error => "error",
                        Severity::Warning => "warning",
                    }
                    .into(),
                );
            }
            list.append(json.call_method1("loads", (value.to_string(),))?)?;
        }
        let v = err.value(py);
        v.setattr("defects", list)?;
        v.setattr("unlisted", unlisted)?;
        v.setattr(
            "unlisted_count",
            match tally {
                Tally::Exact => "exact",
                Tally::AtLeast => "at_least",
            },
        )?;
        Ok(())
    };
    match attach() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The exception for a validation report.
pub fn report_error(py: Python<'_>, report: &Report) -> PyErr {
    let defects = report
        .defects
        .iter()
        .map(|d| {
            (
                serde_json::to_value(d).unwrap_or_default(),
                d.to_string(),
                d.severity(),
            )
        })
        .collect();
    invalid_mesh(py, defects, report.unlisted, report.tally)
}

/// The exception for a slicing error.
pub fn slice_error(py: Python<'_>, e: SliceError) -> PyErr {
    match e {
        SliceError::InvalidMesh(report) => report_error(py, &report),
        other => InternalError::new_err(other.to_string()),
    }
}

/// The exception for a failed sweep.
pub fn sweep_error<E: std::error::Error + 'static>(py: Python<'_>, e: SweepError<E>) -> PyErr {
    match e {
        SweepError::Slice { source, .. } => slice_error(py, source),
        SweepError::Sink(e) => PyOSError::new_err(e.to_string()),
        SweepError::Threads(t) => PyRuntimeError::new_err(format!("cannot start threads: {t}")),
    }
}

/// The exception for a snapping error: a bad grid is a `ValueError`; a
/// mesh snapping refuses is an [`InvalidMesh`] naming the vertex.
pub fn snap_error(py: Python<'_>, e: SnapError) -> PyErr {
    let text = e.to_string();
    match e.defect_json() {
        Some(value) => invalid_mesh(py, vec![(value, text, Severity::Error)], 0, Tally::Exact),
        None => PyValueError::new_err(text),
    }
}

/// The exception for a file that cannot be loaded: `OSError` (with the
/// errno, so a missing file is `FileNotFoundError`) when it cannot be
/// read, `ValueError` when it cannot be parsed.
pub fn load_error(path: &str, e: LoadError) -> PyErr {
    match e {
        LoadError::Io { source, .. } => io_error(path, &source),
        other => PyValueError::new_err(format!("{path}: {other}")),
    }
}

/// An `OSError` (the subclass its errno selects) naming the file.
pub fn io_error(path: &str, e: &std::io::Error) -> PyErr {
    match e.raw_os_error() {
        Some(errno) => PyOSError::new_err((errno, e.to_string(), path.to_owned())),
        None => PyOSError::new_err(format!("{path}: {e}")),
    }
}
