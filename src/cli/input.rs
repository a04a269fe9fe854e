//! Input: a mesh argument (a file or a built-in dataset name) and an
//! optional snap grid. Output: the mesh to slice, with notes for the user.
//!
//! Every command that loads a mesh (check, slice, verify) takes it through
//! the same steps: read, snap when asked, then remove degenerate faces by
//! edge flips (SPEC 1; `wmslice::mesh::flip`), so that the mesh hash in a
//! result and the one `verify` computes are those of the mesh as sliced.

use super::{ExitCode, Failure, Tag};
use anyhow::anyhow;
use std::path::Path;
use wmslice::datasets;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, rat_to_string, Rat};
use wmslice::mesh::flip::{repair_degenerate, Flip};
use wmslice::mesh::io::{load_bytes, MeshFormat};
use wmslice::mesh::snap::snap;
use wmslice::Mesh;

/// A mesh as given on the command line: a file, or a built-in dataset.
pub struct Input {
    /// The mesh (in grid units when snapped).
    pub mesh: Mesh,
    /// The snap grid, if any.
    pub unit: Option<Rat>,
    /// What loading did, for the user.
    pub notes: Vec<String>,
    /// The bytes of the input file (empty for a built-in dataset).
    pub file_bytes: Vec<u8>,
    /// The edge flips that removed degenerate faces, in the order made.
    pub flips: Vec<Flip>,
}

/// At most this many flips are listed in the note; the rest are counted.
const LISTED_FLIPS: usize = 10;

/// Removes the degenerate faces edge flips can remove, with a note.
fn repaired(mut input: Input) -> Input {
    let (mesh, flips) = {
        let r = repair_degenerate(&input.mesh);
        if r.flips.is_empty() {
            return input;
        }
        (r.mesh.into_owned(), r.flips)
    };
    let mut listed: Vec<String> = flips
        .iter()
        .take(LISTED_FLIPS)
        .map(|f| f.to_string())
        .collect();
    if flips.len() > LISTED_FLIPS {
        listed.push(format!("and {} more", flips.len() - LISTED_FLIPS));
    }
    input.notes.push(format!(
        "flipped {} degenerate faces (a vertex inside the opposite edge; the surface does not move): {}",
        flips.len(),
        listed.join(", ")
    ));
    input.mesh = mesh;
    input.flips = flips;
    input
}

pub fn load_input(spec: &str, snap_arg: Option<&str>) -> Result<Input, Failure> {
    load_unrepaired(spec, snap_arg).map(repaired)
}

fn load_unrepaired(spec: &str, snap_arg: Option<&str>) -> Result<Input, Failure> {
    let path = Path::new(spec);
    let mut notes = Vec::new();
    let mut file_bytes = Vec::new();
    let mesh = if path.exists() {
        file_bytes = wmslice::mesh::io::read_file(path)
            .map_err(|e| anyhow!("cannot read {spec}: {e}"))
            .tag(ExitCode::Input)?;
        let hint = path
            .extension()
            .and_then(|e| e.to_str())
            .and_then(MeshFormat::from_extension);
        let (mesh, report) = load_bytes(&file_bytes, hint).tag(ExitCode::Input)?;
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
            file_bytes,
            flips: Vec::new(),
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
                file_bytes,
                flips: Vec::new(),
            })
        }
    }
}
