//! Compares this crate with the CGAL oracle on mesh files you did not make
//! (never committed: fetch them, e.g. trimesh's `models/`, manifold's
//! `test/models/`):
//!
//! ```sh
//! cargo run --release --features cgal-oracle --example heldout_oracle -- \
//!     [--weld] [--drop-collapsed] [--snap Q] [--levels N] MESH...
//! ```
//!
//! For each file, the mesh as sliced (read, welded with `--weld`, snapped
//! to `Q` when given, collapsed faces dropped with `--drop-collapsed`,
//! degenerate faces flipped away): validation's self-intersection verdict
//! and face pairs against CGAL's
//! ([`wmslice::oracle::compare::compare_self_intersections`]; skipped when
//! the topology has issues), then, when the slicer accepts the mesh, the
//! whole level set against CGAL's at `N` (default 40) of its vertex heights
//! and midpoints between them, evenly picked
//! ([`wmslice::oracle::compare::compare_levels`]). One line per file; exits
//! with 1 when they disagree anywhere.

#[path = "support/heldout.rs"]
mod heldout;

use wmslice::datasets::slab::heights_and_midpoints;
use wmslice::oracle::compare::{compare_levels, compare_self_intersections, Coverage};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = heldout::Args::parse("heldout_oracle", 40)?;
    let mut disagreed = 0;
    for (name, mesh) in heldout::meshes(&args) {
        let intersections = match compare_self_intersections(&mesh) {
            Ok(None) => "topology has issues".to_string(),
            Ok(Some(true)) => "both find self-intersections".to_string(),
            Ok(Some(false)) => "neither finds self-intersections".to_string(),
            Err(e) => {
                disagreed += 1;
                println!("DISAGREE  {name}: self-intersections: {}", first_lines(&e));
                continue;
            }
        };
        if wmslice::Slicer::new(&mesh).is_err() {
            println!("refused   {name}: {intersections}");
            continue;
        }
        let picked = heldout::evenly(&heights_and_midpoints(&mesh), args.levels);
        let n = picked.len();
        let mut cov = Coverage::default();
        match compare_levels(&mesh, &picked, &mut cov) {
            Ok(()) => println!("agree     {name}: {intersections}; {n} levels"),
            Err(e) => {
                disagreed += 1;
                println!("DISAGREE  {name}: levels: {}", first_lines(&e));
            }
        }
    }
    if disagreed > 0 {
        eprintln!("{disagreed} of {} files disagree", args.paths.len());
        std::process::exit(1);
    }
    Ok(())
}

/// The first lines of a report (the rest is the mesh as pasteable Rust).
fn first_lines(report: &str) -> String {
    report.lines().take(8).collect::<Vec<_>>().join("\n    ")
}
