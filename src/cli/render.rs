//! Input: the sliced level sets and the `slice` arguments. Output: the
//! rendered formats of `slice --format svg|html|cli|cli-binary`, written
//! atomically (a temporary file in the target directory, then a rename).
//!
//! Every rendered format lists the levels in ascending exact order, equal
//! levels once. `svg`: one file per level into the directory `-o DIR`
//! (created as needed), named `layer-0003_z=3_5.svg`, after which the
//! directory's level files of an earlier run are removed (other files are
//! left alone); with a single level,
//! `-o FILE` is the file itself (unless it is an existing directory or ends
//! in `/`), and without `-o` the SVG goes to stdout. `html`: one file (or
//! stdout). `cli`, `cli-binary`: one file (or stdout); `--side` picks L-
//! (default), L+ or S_O, `--with-ridges` adds S_NO as open polylines.
//! Everything is rendered before the first file is written, so a rendering
//! failure writes nothing.

use super::args::{Format, LoopSide, SliceArgs};
use super::input::Input;
use super::{emit, usage, ExitCode, Failure, Tag};
use anyhow::anyhow;
use std::path::{Path, PathBuf};
use wmslice::critical::CriticalReport;
use wmslice::output::atomic::write_atomic;
use wmslice::output::cli_layers::{self, CliOptions, Encoding, LoopChoice};
use wmslice::output::html::{critical_marks, viewer, ViewerLayer, ViewerOptions};
use wmslice::output::svg::{is_level_file_name, level_file_name, level_svg, Scene, SvgOptions};
use wmslice::LevelSet;

/// The name of what is sliced: a file's stem, or the dataset name.
fn part_name(spec: &str) -> String {
    let p = Path::new(spec);
    if p.exists() {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| spec.to_string())
    } else {
        spec.to_string()
    }
}

/// The level sets in ascending exact order, equal levels once.
fn ascending(sets: &[LevelSet]) -> Vec<&LevelSet> {
    let mut v: Vec<&LevelSet> = sets.iter().collect();
    v.sort_by(|a, b| a.level.cmp(&b.level));
    v.dedup_by(|a, b| a.level == b.level);
    v
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    write_atomic(path, bytes)
        .map_err(|e| anyhow!("cannot write {}: {e}", path.display()))
        .tag(ExitCode::Output)
}

fn write_stdout_bytes(bytes: &[u8]) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r
            .map_err(|e| anyhow!("cannot write to stdout: {e}"))
            .tag(ExitCode::Output),
    }
}

/// Today's date for `$$DATE`, or the one `SOURCE_DATE_EPOCH` fixes
/// (reproducible builds).
fn today() -> String {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| i64::try_from(d.as_secs()).unwrap_or(0))
                .unwrap_or(0)
        });
    cli_layers::date_ddmmyy(secs)
}

/// Writes the rendered format chosen in `a`.
pub fn write(
    a: &SliceArgs,
    input: &Input,
    sets: &[LevelSet],
    critical: Option<&CriticalReport>,
) -> Result<(), Failure> {
    let scene = Scene::new(&input.mesh, input.unit.as_ref());
    let name = part_name(&a.mesh);
    let levels = ascending(sets);
    match a.format {
        Format::Svg => write_svgs(a, &scene, &name, &levels),
        Format::Html => {
            let (critical, unlisted_marks) = critical.map(critical_marks).unwrap_or_default();
            let layers: Vec<ViewerLayer> = levels
                .iter()
                .map(|ls| ViewerLayer {
                    heading: name.clone(),
                    note: String::new(),
                    level: ls,
                    scene: &scene,
                })
                .collect();
            let page = viewer(
                &layers,
                &ViewerOptions {
                    title: format!("wmslice: {name}"),
                    arrows: a.arrows,
                    critical,
                    unlisted_marks,
                },
            );
            emit(a.output.as_deref(), &page)?;
            note(a, || {
                a.output.as_ref().map(|p| {
                    format!(
                        "wrote the viewer of {} levels to {}",
                        levels.len(),
                        p.display()
                    )
                })
            });
            Ok(())
        }
        Format::Cli | Format::CliBinary => {
            let opts = CliOptions {
                encoding: if a.format == Format::Cli {
                    Encoding::Ascii
                } else {
                    Encoding::Binary
                },
                side: match a.side {
                    LoopSide::Below => LoopChoice::Below,
                    LoopSide::Above => LoopChoice::Above,
                    LoopSide::Contour => LoopChoice::Contour,
                },
                with_ridges: a.with_ridges,
                label: name.clone(),
                date: today(),
            };
            let file = cli_layers::from_level_sets(levels, scene.bounds(), &opts);
            if opts.encoding == Encoding::Binary {
                cli_layers::check_binary(&file).tag(ExitCode::Output)?;
            }
            let bytes = cli_layers::write(&file);
            match &a.output {
                Some(p) => {
                    write_file(p, &bytes)?;
                    note(a, || {
                        Some(format!(
                            "wrote {} layers to {}",
                            file.layers.len(),
                            p.display()
                        ))
                    });
                    Ok(())
                }
                None => write_stdout_bytes(&bytes),
            }
        }
        Format::Summary | Format::Json => Err(Failure {
            code: ExitCode::Internal,
            error: anyhow!("render::write called for {:?} (internal error)", a.format),
        }),
    }
}

fn note(a: &SliceArgs, text: impl FnOnce() -> Option<String>) {
    if !a.quiet {
        if let Some(t) = text() {
            eprintln!("note: {t}");
        }
    }
}

fn write_svgs(
    a: &SliceArgs,
    scene: &Scene,
    name: &str,
    levels: &[&LevelSet],
) -> Result<(), Failure> {
    let opts = SvgOptions { arrows: a.arrows };
    let out = a.output.as_deref();
    let into_dir = |p: &Path| p.is_dir() || p.as_os_str().to_string_lossy().ends_with('/');
    if levels.len() == 1 {
        let svg = level_svg(levels[0], scene, name, &opts);
        return match out {
            None => emit(None, &svg),
            Some(p) if into_dir(p) => {
                let f = p.join(level_file_name(0, &levels[0].level));
                write_file(&f, svg.as_bytes())?;
                note(a, || Some(format!("wrote {}", f.display())));
                remove_earlier_levels(a, p, &[f])
            }
            Some(p) => {
                write_file(p, svg.as_bytes())?;
                note(a, || Some(format!("wrote {}", p.display())));
                Ok(())
            }
        };
    }
    let dir = out.ok_or_else(|| {
        usage(format!(
            "--format svg writes one file per level: give -o DIR for these {} levels",
            levels.len()
        ))
    })?;
    if dir.exists() && !dir.is_dir() {
        return Err(Failure {
            code: ExitCode::Output,
            error: anyhow!(
                "{} is a file; -o must be a directory for {} SVG files",
                dir.display(),
                levels.len()
            ),
        });
    }
    let files: Vec<(PathBuf, String)> = levels
        .iter()
        .enumerate()
        .map(|(i, ls)| {
            (
                dir.join(level_file_name(i, &ls.level)),
                level_svg(ls, scene, name, &opts),
            )
        })
        .collect();
    for (path, svg) in &files {
        write_file(path, svg.as_bytes())?;
    }
    note(a, || {
        Some(format!(
            "wrote {} SVG files to {}",
            files.len(),
            dir.display()
        ))
    });
    let written: Vec<PathBuf> = files.into_iter().map(|(p, _)| p).collect();
    remove_earlier_levels(a, dir, &written)
}

/// Removes the level SVGs in `dir` that this run did not write (an
/// earlier run's levels, named as [`level_file_name`] names them), so the
/// directory holds this run's levels and no others; files of any other
/// name are left alone. Done after every new file is in place.
fn remove_earlier_levels(a: &SliceArgs, dir: &Path, written: &[PathBuf]) -> Result<(), Failure> {
    let cannot = |e: std::io::Error| anyhow!("cannot tidy {}: {e}", dir.display());
    let mut removed = 0usize;
    for entry in std::fs::read_dir(dir)
        .map_err(cannot)
        .tag(ExitCode::Output)?
    {
        let path = entry.map_err(cannot).tag(ExitCode::Output)?.path();
        let ours = path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(is_level_file_name);
        let new = written.iter().any(|w| w.file_name() == path.file_name());
        if ours && path.is_file() && !new {
            std::fs::remove_file(&path)
                .map_err(|e| anyhow!("cannot remove {}: {e}", path.display()))
                .tag(ExitCode::Output)?;
            removed += 1;
        }
    }
    if removed > 0 {
        note(a, || {
            Some(format!(
                "removed {removed} level SVG files of an earlier run from {}",
                dir.display()
            ))
        });
    }
    Ok(())
}
