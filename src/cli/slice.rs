//! `wmslice slice`: exact level sets at the requested levels, written as a
//! summary, JSON, or a rendered format.

use super::args::{Format, SliceArgs};
use super::input::{load_input, Input};
use super::{emit, slice_error, usage, ExitCode, Failure, Tag};
use anyhow::anyhow;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::naive::naive_slice;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::output::summary::summary;
use wmslice::{LevelSet, Slicer};

pub fn parse_levels(a: &SliceArgs) -> Result<Vec<Rat>, Failure> {
    let mut levels = Vec::new();
    for z in &a.at {
        levels.push(parse_rational(z).map_err(|e| usage(format!("--at {z}: {e}")))?);
    }
    if let Some(f) = &a.levels_file {
        let text = std::fs::read_to_string(f)
            .map_err(|e| anyhow!("cannot read {}: {e}", f.display()))
            .tag(ExitCode::Input)?;
        for (i, line) in text.lines().enumerate() {
            let t = line.split('#').next().unwrap_or("").trim();
            if t.is_empty() {
                continue;
            }
            levels.push(
                parse_rational(t).map_err(|e| usage(format!("{}:{}: {e}", f.display(), i + 1)))?,
            );
        }
    }
    if levels.is_empty() {
        return Err(usage("no levels: give --at Z or --levels-file FILE".into()));
    }
    Ok(levels)
}

/// Runs `slice`.
pub fn run(a: SliceArgs) -> Result<(), Failure> {
    let levels = parse_levels(&a)?;
    let input = load_input(&a.mesh, a.snap.as_deref())?;
    if !a.quiet {
        for n in &input.notes {
            eprintln!("note: {n}");
        }
    }
    if a.naive {
        return slice_naive(&a, &input, &levels);
    }
    let unit = input
        .unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()));
    let slicer = Slicer::with_unit(&input.mesh, unit).map_err(slice_error)?;
    let sets: Vec<LevelSet> = levels
        .iter()
        .map(|c| slicer.slice_at(c))
        .collect::<Result<_, _>>()
        .map_err(slice_error)?;
    if let Some(path) = &a.certificate {
        super::certificate::write(path, &a, &input, &levels, &sets)?;
    }
    let text = match a.format {
        Format::Svg | Format::Html | Format::Cli | Format::CliBinary => {
            return super::render::write(&a, &input, &sets);
        }
        Format::Json => {
            let ex = if a.exact {
                Exactness::WithExact
            } else {
                Exactness::Rounded
            };
            to_json(
                &MeshHeader::new(&input.mesh, input.unit.as_ref()),
                &sets,
                ex,
            )
        }
        Format::Summary => sets.iter().map(summary).collect::<Vec<_>>().join("\n"),
    };
    emit(a.output.as_deref(), &text)
}

fn slice_naive(a: &SliceArgs, input: &Input, levels: &[Rat]) -> Result<(), Failure> {
    if a.format != Format::Summary {
        return Err(usage("--naive only prints a summary".into()));
    }
    let unit = input
        .unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()));
    let mut text = String::new();
    for c in levels {
        let n = naive_slice(&input.mesh, &(c / &unit));
        let area = n.filled_area() * &unit * &unit;
        text.push_str(&format!(
            "level z = {} (NAIVE strong-Morse slicer: wrong at degenerate levels)\n  {} segments ({} zero-length, {} duplicated)\n  {} filled contours, area {} (~{}), {} open polylines\n",
            rat_to_string(c),
            n.segments.len(),
            n.zero_length,
            n.duplicates,
            n.loops.len(),
            rat_to_string(&area),
            rat_to_f64(&area),
            n.open
        ));
    }
    emit(a.output.as_deref(), text.trim_end())
}
