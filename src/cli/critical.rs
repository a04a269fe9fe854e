//! `wmslice critical`: the critical heights of a mesh, its Reeb graph, and
//! (with `--layer-height`) a layer plan that honours the flats or an audit
//! of the uniform plan; text, JSON or SVG.

use super::args::{CriticalArgs, CriticalFormat};
use super::input::load_input;
use super::paths::{refuse_overwriting, Named};
use super::progress::step;
use super::{emit, slice_error, usage, worker_pool, ExitCode, Failure};
use std::path::Path;
use wmslice::critical::fit::PlanReport;
use wmslice::critical::{self, CriticalReport};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::Rat;
use wmslice::layers::height_range;
use wmslice::output::critical::{critical_json, critical_text};
use wmslice::output::reeb_svg::reeb_svg;
use wmslice::Slicer;

fn parse(flag: &str, v: Option<&str>) -> Result<Option<Rat>, Failure> {
    v.map(|t| parse_rational(t).map_err(|e| usage(format!("{flag} {t}: {e}"))))
        .transpose()
}

/// The plan the arguments ask for, if any.
fn plan(
    a: &CriticalArgs,
    report: &CriticalReport,
    z_min: &Rat,
) -> Result<Option<PlanReport>, Failure> {
    let Some(height) = parse("--layer-height", a.layer_height.as_deref())? else {
        return Ok(None);
    };
    let plan = if a.fit_critical {
        PlanReport::fitted(report, &height)
    } else {
        let two = Rat::from_integer(2.into());
        let first = parse("--first", a.first.as_deref())?.unwrap_or_else(|| z_min + &height / two);
        PlanReport::uniform(report, &height, &first)
    };
    plan.map(Some).map_err(|e| usage(e.to_string()))
}

/// Runs `critical`.
pub fn run(a: CriticalArgs) -> Result<(), Failure> {
    if let Some(path) = a.output.as_deref() {
        let mesh = Named {
            role: "the mesh",
            path: Path::new(&a.mesh),
        };
        refuse_overwriting(&[mesh], &[Named { role: "-o", path }])?;
    }
    let (_, pool) = worker_pool(a.threads)?;
    let reading = step("reading and welding the mesh", false);
    let input = pool.install(|| load_input(&a.mesh, a.snap.as_deref(), a.repairs.repairs()));
    reading.finish_and_clear();
    let input = input?;
    for n in &input.notes {
        eprintln!("note: {n}");
    }
    let unit = input
        .unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()));
    let analysing = step(
        "validating the mesh and finding its critical heights",
        false,
    );
    let (slicer, header) = pool.install(|| {
        rayon::join(
            || Slicer::with_unit(&input.mesh, unit.clone()),
            || input.header(),
        )
    });
    let report = slicer.map_err(slice_error).and_then(|slicer| {
        critical::analyze(&slicer).map_err(|e| Failure {
            code: ExitCode::Internal,
            error: e.into(),
        })
    });
    analysing.finish_and_clear();
    let report = report?;
    let (z_min, _) = height_range(&input.mesh, &unit);
    let plan = plan(&a, &report, &z_min)?;
    let text = match a.format {
        CriticalFormat::Text => critical_text(&report, plan.as_ref()),
        CriticalFormat::Json => critical_json(&header, &report, plan.as_ref()),
        CriticalFormat::Svg => reeb_svg(&report.reeb, &format!("Reeb graph of {}", a.mesh)),
    };
    emit(a.output.as_deref(), &text)
}
