//! What the held-out examples share: a file read and prepared as the
//! command line prepares it, and levels picked evenly.

use wmslice::exact::Rat;
use wmslice::mesh::prepare::{prepare_exact_with, Repairs};
use wmslice::Mesh;

/// The file's name, for one line of output.
pub fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The mesh as sliced: read, welded when asked, snapped to `snap` when
/// given, collapsed faces dropped when asked, degenerate faces flipped
/// away. `Err` is the line to print (`unread` or `unsnapped`, the name,
/// why).
pub fn load(path: &str, snap: Option<&Rat>, repairs: Repairs) -> Result<Mesh, String> {
    let name = file_name(path);
    let (mesh, _, exact) = wmslice::mesh::io::load_exact(std::path::Path::new(path))
        .map_err(|e| format!("unread    {name}: {e}"))?;
    prepare_exact_with(mesh, &exact, snap, repairs)
        .map(|p| p.mesh)
        .map_err(|e| format!("unsnapped {name}: {e}"))
}

/// At most `n` of `all`, evenly picked, first and last included.
pub fn evenly(all: &[Rat], n: usize) -> Vec<Rat> {
    let n = n.min(all.len());
    (0..n)
        .map(|i| all[i * (all.len() - 1) / (n - 1).max(1)].clone())
        .collect()
}
