//! `wmslice check`: validation report, text or JSON; exit 0 only for a
//! mesh the slicer accepts.

use super::args::CheckArgs;
use super::input::load_input;
use super::progress::step;
use super::{ExitCode, Failure};
use crate::say;
use anyhow::anyhow;
use serde_json::Value;
use wmslice::mesh::snap::SnapError;
use wmslice::mesh::validate::{validate, Severity, Tally};

/// Runs `check`.
pub fn run(a: CheckArgs) -> Result<(), Failure> {
    // Spinners on a terminal only (a 10 M-face scan takes seconds to
    // read and validate), cleared before the report.
    let reading = step("reading and welding the mesh", false);
    let input = load_input(&a.mesh, a.snap.as_deref(), a.repairs.repairs());
    reading.finish_and_clear();
    let input = match input {
        Ok(input) => input,
        Err(f) => {
            if a.json {
                refusal_json(&a.mesh, &f)?;
            }
            return Err(f);
        }
    };
    let validating = step("validating the mesh", false);
    let report = validate(&input.mesh);
    validating.finish_and_clear();
    // A snapped mesh is stored in grid steps; report its measures in the
    // file's units.
    let report = match &input.unit {
        Some(unit) => report.in_units(unit),
        None => report,
    };
    if a.json {
        let defects = report.defects.iter().map(|d| {
            let v = serde_json::to_value(d).unwrap_or_default();
            listed(v, d.severity(), d.to_string())
        });
        let doc = document(
            &a.mesh,
            report.is_accepted(),
            serde_json::to_value(&report.stats).unwrap_or_default(),
            defects.collect(),
            (report.unlisted, report.tally),
            &input.notes,
        );
        say!("{}", serde_json::to_string_pretty(&doc).unwrap_or_default());
    } else {
        for n in &input.notes {
            say!("note: {n}");
        }
        say!("{report}");
    }
    if report.is_accepted() {
        Ok(())
    } else {
        let first = report
            .errors()
            .next()
            .map(|d| d.to_string())
            .unwrap_or_default();
        Err(Failure {
            code: ExitCode::InvalidMesh,
            error: anyhow!("{} is rejected for slicing: {first}", a.mesh),
        })
    }
}

/// With `--json`, a mesh that snapping refuses (a non-finite coordinate,
/// one too far from the origin for the grid, a grid that collapses every
/// face) is reported as JSON too: not accepted, its one defect as the
/// Python package lists it, no measures. Input and argument errors stay
/// on standard error only.
fn refusal_json(mesh: &str, f: &Failure) -> Result<(), Failure> {
    let Some(defect) = f
        .error
        .downcast_ref::<SnapError>()
        .and_then(SnapError::defect_json)
    else {
        return Ok(());
    };
    let defect = listed(defect, Severity::Error, f.error.to_string());
    let doc = document(
        mesh,
        false,
        Value::Null,
        vec![defect],
        (0, Tally::Exact),
        &[],
    );
    say!("{}", serde_json::to_string_pretty(&doc).unwrap_or_default());
    Ok(())
}

/// A defect's JSON with its severity and message added.
fn listed(mut defect: Value, severity: Severity, message: String) -> Value {
    if let Some(o) = defect.as_object_mut() {
        o.insert(
            "severity".into(),
            serde_json::to_value(severity).unwrap_or_default(),
        );
        o.insert("message".into(), message.into());
    }
    defect
}

/// `check --json`'s document: whether the mesh is accepted, its measures
/// (null when snapping refused it before they were taken), the listed
/// defects, how many more there are and whether that count is exact,
/// and the notes on reading it.
fn document(
    mesh: &str,
    accepted: bool,
    stats: Value,
    defects: Vec<Value>,
    (unlisted, tally): (usize, Tally),
    notes: &[String],
) -> Value {
    serde_json::json!({
        "mesh": mesh,
        "accepted": accepted,
        "stats": stats,
        "defects": defects,
        "unlisted_defects": unlisted,
        "unlisted_count": tally,
        "notes": notes,
    })
}
