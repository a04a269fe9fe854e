//! `wmslice gen`: list or write the built-in datasets, list the random
//! families, or write a random mesh of one family with its answers.

use super::args::GenArgs;
use super::paths::{refuse_overwriting, Named};
use super::{emit, usage, ExitCode, Failure, Tag};
use crate::say;
use wmslice::datasets;
use wmslice::datasets::families::{self, answers::AnswerError};
use wmslice::mesh::io::MeshFormat;

/// Runs `gen`.
pub fn run(a: GenArgs) -> Result<(), Failure> {
    if a.list {
        for d in datasets::all() {
            say!("{:<20} {}", d.name, d.summary);
        }
        return Ok(());
    }
    if a.families {
        for f in families::all() {
            say!("{:<14} {}", f.name, f.summary);
        }
        return Ok(());
    }
    let out = a.output.ok_or_else(|| usage("missing -o FILE".into()))?;
    // The format by extension, before any work (a random family's
    // answers take seconds): a name the writer does not know is a bad
    // argument, not a failed write.
    let format = out
        .extension()
        .and_then(|e| e.to_str())
        .and_then(MeshFormat::from_extension)
        .ok_or_else(|| {
            usage(format!(
                "cannot tell the output format of {} from its extension \
                 (stl, obj, off, ply or 3mf)",
                out.display()
            ))
        })?;
    if let Some(path) = a.answers.as_deref() {
        let outputs = [
            Named {
                role: "-o",
                path: &out,
            },
            Named {
                role: "--answers",
                path,
            },
        ];
        refuse_overwriting(&[], &outputs)?;
    }
    if let Some(seed) = a.random {
        let name = a.family.unwrap_or_default();
        let f = families::by_name(&name).ok_or_else(|| {
            usage(format!(
                "unknown family {name} (see `wmslice gen --families`)"
            ))
        })?;
        let mesh = f.generate(seed);
        // The answers first: nothing is written when they fail.
        let answers = match &a.answers {
            Some(path) => {
                let answers =
                    families::answers::answers(mesh.clone(), f.snap().as_ref()).map_err(|e| {
                        let code = match e {
                            AnswerError::Snap(_) => ExitCode::InvalidMesh,
                            _ => ExitCode::Internal,
                        };
                        Failure {
                            code,
                            error: e.into(),
                        }
                    })?;
                Some((path, answers.to_json(f, seed)))
            }
            None => None,
        };
        mesh.save_as(&out, format).tag(ExitCode::Output)?;
        eprintln!("wrote {} seed {seed} to {}", f.name, out.display());
        if let Some((path, text)) = answers {
            emit(Some(path), &text)?;
            eprintln!("wrote its answers to {}", path.display());
        }
        return Ok(());
    }
    let name = a.name.unwrap_or_default();
    let d = datasets::by_name(&name)
        .ok_or_else(|| usage(format!("unknown dataset {name} (see `wmslice gen --list`)")))?;
    d.build().save_as(&out, format).tag(ExitCode::Output)?;
    eprintln!("wrote {} to {}", d.name, out.display());
    Ok(())
}
