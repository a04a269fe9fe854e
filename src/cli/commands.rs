//! The subcommands: each loads its input, calls the library, and writes.

use super::args::{CheckArgs, Cli, Command, Format, GenArgs, SliceArgs};
use super::{ExitCode, Failure, Tag};
use anyhow::anyhow;
use std::path::Path;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::mesh::snap::snap;
use wmslice::mesh::validate::validate;
use wmslice::naive::naive_slice;
use wmslice::output::atomic::write_atomic;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::output::summary::summary;
use wmslice::{datasets, LevelSet, Mesh, SliceError, Slicer};

/// Prints a line to stdout; a closed pipe (`wmslice ... | head`) ends the
/// output quietly instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {
        write_stdout(&format!($($arg)*))?
    };
}

fn write_stdout(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}") {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        r => r
            .map_err(|e| anyhow!("cannot write to stdout: {e}"))
            .tag(ExitCode::Output),
    }
}

/// Runs one parsed command.
pub fn dispatch(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Demo => demo(),
        Command::Gen(a) => gen(a),
        Command::Check(a) => check(a),
        Command::Slice(a) => slice(a),
    }
}

fn usage(msg: String) -> Failure {
    Failure {
        code: ExitCode::Usage,
        error: anyhow!(msg),
    }
}

/// A mesh as given on the command line: a file, or a built-in dataset.
struct Input {
    mesh: Mesh,
    unit: Option<Rat>,
    notes: Vec<String>,
}

fn load_input(spec: &str, snap_arg: Option<&str>) -> Result<Input, Failure> {
    let path = Path::new(spec);
    let mut notes = Vec::new();
    let mesh = if path.exists() {
        let (mesh, report) = wmslice::mesh::io::load(path).tag(ExitCode::Input)?;
        notes.push(format!("read {} as {}", spec, report.format));
        notes.extend(report.notes.iter().map(|n| n.to_string()));
        mesh
    } else if let Some(d) = datasets::by_name(spec) {
        notes.push(format!("built-in dataset {}", d.name));
        d.build()
    } else {
        return Err(Failure {
            code: ExitCode::Input,
            error: anyhow!("no such file or built-in dataset: {spec} (see `wmslice gen --list`)"),
        });
    };
    match snap_arg {
        None => Ok(Input {
            mesh,
            unit: None,
            notes,
        }),
        Some(q) => {
            let q = parse_rational(q).tag(ExitCode::Usage)?;
            let s = snap(&mesh, &q).tag(ExitCode::InvalidMesh)?;
            notes.push(format!(
                "snapped to grid {}: {} vertices moved, largest coordinate move {} (~{}), {} vertices merged",
                rat_to_string(&q),
                s.moved,
                rat_to_string(&s.max_move),
                rat_to_f64(&s.max_move),
                s.merged
            ));
            Ok(Input {
                mesh: s.mesh,
                unit: Some(s.unit),
                notes,
            })
        }
    }
}

fn gen(a: GenArgs) -> Result<(), Failure> {
    if a.list {
        for d in datasets::all() {
            say!("{:<20} {}", d.name, d.summary);
        }
        return Ok(());
    }
    let name = a.name.unwrap_or_default();
    let d = datasets::by_name(&name)
        .ok_or_else(|| usage(format!("unknown dataset {name} (see `wmslice gen --list`)")))?;
    let out = a.output.ok_or_else(|| usage("missing -o FILE".into()))?;
    d.build().save(&out).tag(ExitCode::Output)?;
    eprintln!("wrote {} to {}", d.name, out.display());
    Ok(())
}

fn check(a: CheckArgs) -> Result<(), Failure> {
    let input = load_input(&a.mesh, a.snap.as_deref())?;
    let report = validate(&input.mesh);
    if a.json {
        let doc = serde_json::json!({
            "mesh": a.mesh,
            "accepted": report.is_accepted(),
            "stats": report.stats,
            "defects": report.defects.iter().map(|d| {
                let mut v = serde_json::to_value(d).unwrap_or_default();
                if let Some(o) = v.as_object_mut() {
                    o.insert("severity".into(), serde_json::to_value(d.severity()).unwrap_or_default());
                    o.insert("message".into(), d.to_string().into());
                }
                v
            }).collect::<Vec<_>>(),
            "unlisted_defects": report.unlisted,
            "notes": input.notes,
        });
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

fn parse_levels(a: &SliceArgs) -> Result<Vec<Rat>, Failure> {
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

fn slice_error(e: SliceError) -> Failure {
    let code = match e {
        SliceError::InvalidMesh(_) => ExitCode::InvalidMesh,
        _ => ExitCode::Internal,
    };
    Failure {
        code,
        error: e.into(),
    }
}

fn emit(out: Option<&Path>, text: &str) -> Result<(), Failure> {
    match out {
        Some(p) => write_atomic(p, text.as_bytes())
            .map_err(|e| anyhow!("cannot write {}: {e}", p.display()))
            .tag(ExitCode::Output),
        None => {
            say!("{text}");
            Ok(())
        }
    }
}

fn slice(a: SliceArgs) -> Result<(), Failure> {
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
    let text = match a.format {
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

/// The demo's degenerate levels: one of each kind of degeneracy.
const DEMO: [(&str, i64, &str); 8] = [
    (
        "double_torus",
        2,
        "a monkey saddle (m = 3): three holes touch one outer loop",
    ),
    (
        "upright_torus",
        1,
        "an ordinary saddle at the top of the hole",
    ),
    ("saddle8", 2, "an 8-branch saddle (m = 4)"),
    (
        "lying_torus",
        2,
        "the top vertex ring: one closed ridge, no contour",
    ),
    (
        "cylinder",
        2,
        "the top cap: one up-facing region, no contour",
    ),
    (
        "internal_torus",
        2,
        "the cavity's top ring: a ridge inside the material",
    ),
    ("grid", 2, "a network of ridges around nine pits"),
    ("octahedron", 0, "a square of transversal in-plane edges"),
];

fn demo() -> Result<(), Failure> {
    say!("wmslice demo: exact level sets of built-in datasets at degenerate levels\n");
    for (name, z, what) in DEMO {
        let d = datasets::by_name(name).ok_or_else(|| usage(format!("missing dataset {name}")))?;
        let mesh = d.build();
        let slicer = Slicer::new(&mesh).map_err(slice_error)?;
        let c = Rat::from_integer(z.into());
        let ls = slicer.slice_at(&c).map_err(slice_error)?;
        say!("== {name} at z = {z}: {what}");
        say!("{}", summary(&ls));
        let n = naive_slice(&mesh, &c);
        say!(
            "  naive slicer : {} segments ({} zero-length, {} duplicated), {} filled contours of area {}\n",
            n.segments.len(),
            n.zero_length,
            n.duplicates,
            n.loops.len(),
            rat_to_string(&n.filled_area())
        );
    }
    say!("Slice any of them yourself: wmslice slice double_torus --at 2 --format json --exact");
    Ok(())
}
