//! `wmslice slice`: exact level sets at the requested levels, written as a
//! summary, JSON, or a rendered format.

use super::args::{Format, SliceArgs};
use super::input::{load_input, read_stdin, Input};
use super::paths::{refuse_overwriting, Named};
use super::progress::{progress, step};
use super::{emit, slice_error, usage, worker_pool, ExitCode, Failure, Tag};
use anyhow::anyhow;
use std::io::{ErrorKind, Write};
use std::path::Path;
use std::time::{Duration, Instant};
use wmslice::critical::{
    self,
    fit::{fit_layers, mid_planes},
};
use wmslice::exact::crossing::{path_counts, NumberPath};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::layers::{
    height_range, plan_levels, slice_plan_then, LayerPlan, SweepError, SweepPlan,
};
use wmslice::naive::naive_slice;
use wmslice::output::atomic::AtomicFile;
use wmslice::output::json::{level_text, to_json, Exactness, JsonWriter, MeshHeader};
use wmslice::output::summary::summary;
use wmslice::{LevelSet, Slicer};

pub fn parse_levels(a: &SliceArgs) -> Result<Vec<Rat>, Failure> {
    let mut levels = Vec::new();
    for z in &a.at {
        levels.push(parse_rational(z).map_err(|e| usage(format!("--at {z}: {e}")))?);
    }
    if let Some(f) = &a.levels_file {
        // `-` is standard input (`seq 0 0.2 10 | wmslice slice part.stl
        // --levels-file -`), unless the mesh comes from there.
        let stdin = f.as_os_str() == "-";
        if stdin && a.mesh == "-" {
            return Err(usage(
                "the mesh and --levels-file cannot both be standard input".into(),
            ));
        }
        let text = if stdin {
            read_stdin().and_then(|b| {
                String::from_utf8(b).map_err(|e| std::io::Error::new(ErrorKind::InvalidData, e))
            })
        } else {
            std::fs::read_to_string(f)
        }
        .map_err(|e| match stdin {
            true => anyhow!("cannot read the levels from standard input: {e}"),
            false => anyhow!("cannot read {}: {e}", f.display()),
        })
        .tag(ExitCode::Input)?;
        let given = levels.len();
        for (i, line) in text.lines().enumerate() {
            let t = line.split('#').next().unwrap_or("").trim();
            if t.is_empty() {
                continue;
            }
            levels.push(
                parse_rational(t).map_err(|e| usage(format!("{}:{}: {e}", f.display(), i + 1)))?,
            );
        }
        // An empty file is a mistake (a wrong path, a failed export), not
        // a plan: refused even beside --at.
        if levels.len() == given {
            return Err(usage(format!(
                "{} holds no level (one per line, as 0.6, 3/5 or -1e-3; # comments)",
                f.display()
            )));
        }
    }
    Ok(levels)
}

/// The uniform layer plan of the arguments, if any.
fn parse_uniform(a: &SliceArgs) -> Result<Option<LayerPlan>, Failure> {
    let exact = |flag: &str, v: &Option<String>| -> Result<Option<Rat>, Failure> {
        v.as_deref()
            .map(|t| parse_rational(t).map_err(|e| usage(format!("{flag} {t}: {e}"))))
            .transpose()
    };
    Ok(match exact("--layer-height", &a.layer_height)? {
        None => None,
        Some(height) => Some(LayerPlan {
            height,
            first: exact("--first", &a.first)?,
            last: exact("--last", &a.last)?,
        }),
    })
}

/// Where streamed output goes.
enum Sink {
    Stdout(std::io::BufWriter<std::io::Stdout>),
    File(std::io::BufWriter<AtomicFile>),
}

impl Sink {
    fn open(path: Option<&std::path::Path>) -> Result<Sink, Failure> {
        Ok(match path {
            None => Sink::Stdout(std::io::BufWriter::new(std::io::stdout())),
            Some(p) => Sink::File(std::io::BufWriter::new(
                AtomicFile::create(p)
                    .map_err(|e| anyhow!("cannot write {}: {e}", p.display()))
                    .tag(ExitCode::Output)?,
            )),
        })
    }

    /// Flushes, and renames the file into place.
    fn close(self) -> std::io::Result<()> {
        match self {
            Sink::Stdout(mut w) => w.flush(),
            Sink::File(w) => w.into_inner().map_err(|e| e.into_error())?.commit(),
        }
    }
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::Stdout(w) => w.write(buf),
            Sink::File(w) => w.write(buf),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::Stdout(w) => w.flush(),
            Sink::File(w) => w.flush(),
        }
    }
}

fn output_error(e: std::io::Error) -> Failure {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        // `wmslice ... | head`: the reader has what it wanted.
        std::process::exit(0);
    }
    Failure {
        code: ExitCode::Output,
        error: anyhow!("cannot write the output: {e}"),
    }
}

fn sweep_error(e: SweepError<std::io::Error>) -> Failure {
    match e {
        SweepError::Slice { source, .. } => slice_error(source),
        SweepError::Sink(io) => output_error(io),
        SweepError::Threads(_) => Failure {
            code: ExitCode::Internal,
            error: e.into(),
        },
    }
}

/// Runs `slice`.
pub fn run(a: SliceArgs) -> Result<(), Failure> {
    let mesh = Path::new(&a.mesh);
    let mut inputs = vec![Named {
        role: "the mesh",
        path: mesh,
    }];
    inputs.extend(a.levels_file.as_deref().map(|path| Named {
        role: "--levels-file",
        path,
    }));
    let outputs: Vec<Named> = [("-o", &a.output), ("--certificate", &a.certificate)]
        .into_iter()
        .filter_map(|(role, p)| {
            Some(Named {
                role,
                path: p.as_deref()?,
            })
        })
        .collect();
    refuse_overwriting(&inputs, &outputs)?;
    let explicit = parse_levels(&a)?;
    let uniform = parse_uniform(&a)?;
    // Before reading what may be a large mesh.
    if explicit.is_empty() && uniform.is_none() {
        return Err(usage(wmslice::layers::PlanError::Empty.to_string()));
    }
    // Welding and validation run on the workers too.
    let (threads, pool) = worker_pool(a.threads)?;
    let mut steps = Steps::start();
    let loading = step("reading and welding the mesh", a.quiet);
    let input = pool.install(|| load_input(&a.mesh, a.snap.as_deref(), a.repairs.repairs()));
    loading.finish_and_clear();
    let input = input?;
    steps.mark("reading");
    if !a.quiet {
        for n in &input.notes {
            eprintln!("note: {n}");
        }
    }
    let unit = input
        .unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()));
    let (lo, hi) = height_range(&input.mesh, &unit);
    // A fitted plan needs the critical heights, so the slicer, first.
    let planned = if a.fit_critical {
        None
    } else {
        Some(
            plan_levels(uniform.as_ref(), &explicit, (&lo, &hi))
                .map_err(|e| usage(e.to_string()))?,
        )
    };
    if a.naive {
        if a.certificate.is_some() {
            return Err(usage(
                "--certificate does not certify the --naive slicer".into(),
            ));
        }
        return slice_naive(&a, &input, planned.as_deref().unwrap_or(&[]));
    }
    let validating = step("validating the mesh and building its topology", a.quiet);
    // The header's fingerprint is hashed, and the faces filed under the
    // levels, beside validation.
    let levels: Vec<Rat>;
    let (slicer, (header, plan)) = match planned {
        Some(planned) => {
            levels = planned;
            let (slicer, rest) = pool.install(|| {
                rayon::join(
                    || Slicer::with_unit(&input.mesh, unit.clone()),
                    || header_and_plan(&input, &unit, &levels),
                )
            });
            (slicer.map_err(slice_error)?, rest)
        }
        None => {
            let slicer = pool
                .install(|| Slicer::with_unit(&input.mesh, unit.clone()))
                .map_err(slice_error)?;
            levels = fitted_levels(&slicer, uniform.as_ref(), &explicit, (&lo, &hi))?;
            let rest = pool.install(|| header_and_plan(&input, &unit, &levels));
            (slicer, rest)
        }
    };
    validating.finish_and_clear();
    steps.mark("validation");
    let bar = progress(levels.len(), a.quiet);
    let ex = if a.exact {
        Exactness::WithExact
    } else {
        Exactness::Rounded
    };
    let streamed = matches!(a.format, Format::Json | Format::Summary) && a.certificate.is_none();
    if streamed {
        let sink = Sink::open(a.output.as_deref())?;
        let sink = match a.format {
            Format::Json => {
                let mut w = JsonWriter::begin(sink, &header, ex).map_err(output_error)?;
                // Serialized on the workers, written here in order.
                let text = |_: usize, ls: LevelSet| level_text(&ls, ex);
                slice_plan_then(&slicer, &plan, threads, &text, |_, text| {
                    bar.inc(1);
                    w.level_text(&text)
                })
                .map_err(sweep_error)?;
                w.finish().map_err(output_error)?
            }
            _ => {
                let mut sink = sink;
                let text = |_: usize, ls: LevelSet| summary(&ls);
                slice_plan_then(&slicer, &plan, threads, &text, |i, text| {
                    bar.inc(1);
                    let sep = if i == 0 { "" } else { "\n" };
                    writeln!(sink, "{sep}{text}")
                })
                .map_err(sweep_error)?;
                sink
            }
        };
        bar.finish_and_clear();
        steps.mark("levels");
        sink.close().map_err(output_error)?;
        steps.mark("output");
        report_paths(&a);
        steps.report(a.verbose);
        return Ok(());
    }
    let mut sets: Vec<LevelSet> = Vec::with_capacity(levels.len());
    let keep = |_: usize, ls: LevelSet| ls;
    slice_plan_then(&slicer, &plan, threads, &keep, |_, ls| {
        bar.inc(1);
        sets.push(ls);
        Ok::<(), std::io::Error>(())
    })
    .map_err(sweep_error)?;
    bar.finish_and_clear();
    steps.mark("levels");
    report_paths(&a);
    let written = write_sets(&a, &input, &slicer, &header, &levels, &sets, ex);
    steps.mark("output");
    steps.report(a.verbose);
    written
}

/// Writes the level sets kept in memory: a rendered format, or the whole
/// JSON or summary text with its certificate.
fn write_sets(
    a: &SliceArgs,
    input: &Input,
    slicer: &Slicer<'_>,
    header: &MeshHeader,
    levels: &[Rat],
    sets: &[LevelSet],
    ex: Exactness,
) -> Result<(), Failure> {
    let text = match a.format {
        Format::Svg | Format::Html | Format::Cli | Format::CliBinary => {
            if a.certificate.is_some() {
                return Err(usage(
                    "--certificate covers --format json or the summary, not rendered formats"
                        .into(),
                ));
            }
            // The viewer lists the critical heights beside the slider.
            let report = match a.format {
                Format::Html => Some(critical::analyze(slicer).map_err(|e| Failure {
                    code: ExitCode::Internal,
                    error: e.into(),
                })?),
                _ => None,
            };
            return super::render::write(a, input, sets, report.as_ref());
        }
        Format::Json => to_json(header, sets, ex),
        Format::Summary => sets.iter().map(summary).collect::<Vec<_>>().join("\n") + "\n",
    };
    emit(a.output.as_deref(), &text)?;
    // After the result, so a failed write leaves no certificate.
    match &a.certificate {
        Some(path) => super::certificate::write(path, a, input, levels, sets, text.as_bytes()),
        None => Ok(()),
    }
}

/// The JSON header's fingerprint and the faces filed under the levels.
fn header_and_plan<'a>(
    input: &'a Input,
    unit: &Rat,
    levels: &'a [Rat],
) -> (MeshHeader, SweepPlan<'a>) {
    rayon::join(
        || input.header(),
        || SweepPlan::new(&input.mesh, unit, levels),
    )
}

/// With `--fit-critical`: the middle of every fitted layer (each layer
/// between H/2 and 3H/2 thick, every flat on a boundary), with the
/// explicit levels.
fn fitted_levels(
    slicer: &Slicer<'_>,
    uniform: Option<&LayerPlan>,
    explicit: &[Rat],
    z_range: (&Rat, &Rat),
) -> Result<Vec<Rat>, Failure> {
    let height = uniform
        .map(|p| p.height.clone())
        .ok_or_else(|| usage("--fit-critical needs --layer-height".into()))?;
    let report = critical::analyze(slicer).map_err(|e| Failure {
        code: ExitCode::Internal,
        error: e.into(),
    })?;
    let layers = fit_layers(&report, &height).map_err(|e| usage(e.to_string()))?;
    let mut levels = explicit.to_vec();
    levels.extend(mid_planes(&layers));
    plan_levels(None, &levels, z_range).map_err(|e| usage(e.to_string()))
}

/// The wall time of each step of a run, printed with `--verbose` so that a
/// slow run can be explained: reading (and welding, snapping), validation
/// (with the topology, the mesh's hash and the faces filed under the
/// levels, and with `--fit-critical` the critical heights), the levels
/// (slicing them, and when streamed their text and its writing), and the
/// output (finishing the file: `fsync` and rename; or, for output kept in
/// memory, writing it whole).
struct Steps {
    last: Instant,
    done: Vec<(&'static str, Duration)>,
}

impl Steps {
    fn start() -> Self {
        Steps {
            last: Instant::now(),
            done: Vec::new(),
        }
    }

    /// Ends step `name` now.
    fn mark(&mut self, name: &'static str) {
        let now = Instant::now();
        self.done.push((name, now - self.last));
        self.last = now;
    }

    fn report(&self, verbose: bool) {
        if verbose {
            let text: Vec<String> = self
                .done
                .iter()
                .map(|(name, t)| format!("{name} {:.3}", t.as_secs_f64()))
                .collect();
            eprintln!("time (s): {}", text.join(", "));
        }
    }
}

/// With `--verbose`: how many loop points took each number path.
fn report_paths(a: &SliceArgs) {
    if a.verbose {
        let counts = path_counts();
        let text: Vec<String> = NumberPath::ALL
            .iter()
            .zip(counts)
            .map(|(p, n)| format!("{} {n}", p.name()))
            .collect();
        eprintln!("number paths (loop points): {}", text.join(", "));
    }
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
    emit(a.output.as_deref(), &text)
}
