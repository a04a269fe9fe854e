//! Checks the slicer against itself on mesh files you did not make (never
//! committed: fetch them, e.g. trimesh's `models/`), with no oracle
//! needed:
//!
//! ```sh
//! cargo run --release --example heldout_cross -- \
//!     [--weld] [--drop-collapsed] [--snap Q] [--levels N] MESH...
//! ```
//!
//! For each file, the mesh as sliced (read, welded with `--weld`, snapped
//! to `Q` when given, collapsed faces dropped with `--drop-collapsed`,
//! degenerate faces flipped away), at `N` (default 20) of its vertex
//! heights and the midpoints between them, evenly picked: the z- and
//! x-mirrors, the relabelling, the quarter turn about z, the far
//! translation, the scales to both ends of the double range and the
//! neighbouring regular levels of [`wmslice::datasets::cross_check`] (L+
//! and L- of the mirror swapped, loop for loop; the same loops with the
//! vertices and faces renumbered, with the mesh turned, with it moved by
//! `2^k`, and with it scaled by `2^k` (areas by `4^k`); each limit equal
//! in structure and exact area to the regular contours beside it). One
//! line per file; exits with 1 when a check fails or an accepted mesh
//! fails to slice.

#[path = "support/heldout.rs"]
mod heldout;

use std::time::Instant;
use wmslice::datasets::cross_check::{
    check_all_neighbours, check_mirror, check_transformed, check_x_mirror, Transformed,
};
use wmslice::datasets::slab::heights_and_midpoints;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = heldout::Args::parse("heldout_cross", 20)?;
    let mut failed = 0;
    for (name, mesh) in heldout::meshes(&args) {
        let Ok(slicer) = wmslice::Slicer::new(&mesh) else {
            println!("refused   {name}");
            continue;
        };
        let picked = heldout::evenly(&heights_and_midpoints(&mesh), args.levels);
        let n = picked.len();
        let t = Instant::now();
        let result = check_mirror(&mesh, &picked)
            .and_then(|()| check_x_mirror(&mesh, &picked))
            .map_err(|e| format!("mirror: {e}"))
            .and_then(|()| check_transformed(&slicer, &picked))
            .and_then(|done| {
                check_all_neighbours(&slicer, &picked)
                    .map(|()| done)
                    .map_err(|e| format!("neighbours: {e}"))
            });
        match result {
            Ok(Transformed { moved, scales }) => println!(
                "agree     {name}: {n} levels, mirrors, relabelling, a quarter turn, {}, scaled by {} and neighbours ({:.2} s)",
                match moved {
                    Some(t) => format!("moved by {t:e}"),
                    None => "no exact move".into(),
                },
                scales
                    .iter()
                    .map(|k| format!("2^{k}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                t.elapsed().as_secs_f64()
            ),
            Err(e) => {
                failed += 1;
                println!("FAILED    {name}: {e}");
            }
        }
    }
    if failed > 0 {
        eprintln!("{failed} of {} files failed", args.paths.len());
        std::process::exit(1);
    }
    Ok(())
}
