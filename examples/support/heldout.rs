//! What the held-out examples share: their arguments, a file read and
//! prepared as the command line prepares it, and levels picked evenly.

use wmslice::exact::{parse_rational, Rat};
use wmslice::mesh::prepare::{prepare_exact_with, Repairs};
use wmslice::Mesh;

/// `[--weld] [--drop-collapsed] [--snap Q] [--levels N] MESH...`
pub struct Args {
    /// The snap grid, when given.
    pub snap: Option<Rat>,
    /// How many levels to check a mesh at, at most.
    pub levels: usize,
    /// `--weld`, `--drop-collapsed`.
    pub repairs: Repairs,
    /// The mesh files.
    pub paths: Vec<String>,
}

impl Args {
    /// The process's arguments; `levels` unless `--levels` says otherwise.
    /// `Err` is the usage line when no file is given.
    pub fn parse(example: &str, levels: usize) -> Result<Args, Box<dyn std::error::Error>> {
        let mut args = std::env::args().skip(1);
        let mut out = Args {
            snap: None,
            levels,
            repairs: Repairs::default(),
            paths: Vec::new(),
        };
        let (mut weld, mut drop) = (false, false);
        while let Some(a) = args.next() {
            match a.as_str() {
                "--weld" => weld = true,
                "--drop-collapsed" => drop = true,
                "--snap" => out.snap = Some(parse_rational(&args.next().ok_or("--snap needs Q")?)?),
                "--levels" => out.levels = args.next().ok_or("--levels needs N")?.parse()?,
                _ => out.paths.push(a),
            }
        }
        if out.paths.is_empty() {
            return Err(format!(
                "usage: {example} [--weld] [--drop-collapsed] [--snap Q] [--levels N] MESH..."
            )
            .into());
        }
        out.repairs = Repairs::from_flags(weld, drop);
        Ok(out)
    }
}

/// The file's name, for one line of output.
fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// Each file's name and its mesh as sliced: read, welded when asked,
/// snapped to the grid when given, collapsed faces dropped when asked,
/// degenerate faces flipped away. A file that cannot be read or snapped
/// gets its line (`unread` or `unsnapped`, the name, why) and is skipped.
pub fn meshes(args: &Args) -> impl Iterator<Item = (String, Mesh)> + '_ {
    args.paths.iter().filter_map(|path| {
        let name = file_name(path);
        let prepared = wmslice::mesh::io::load_exact(std::path::Path::new(path))
            .map_err(|e| format!("unread    {name}: {e}"))
            .and_then(|(mesh, _, exact)| {
                prepare_exact_with(mesh, &exact, args.snap.as_ref(), args.repairs)
                    .map_err(|e| format!("unsnapped {name}: {e}"))
            });
        match prepared {
            Ok(p) => Some((name, p.mesh)),
            Err(line) => {
                println!("{line}");
                None
            }
        }
    })
}

/// At most `n` of `all`, evenly picked, first and last included.
pub fn evenly(all: &[Rat], n: usize) -> Vec<Rat> {
    let n = n.min(all.len());
    (0..n)
        .map(|i| all[i * (all.len() - 1) / (n - 1).max(1)].clone())
        .collect()
}
