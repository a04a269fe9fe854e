//! Compares this crate with the CGAL oracle on mesh files you did not make
//! (never committed: fetch them, e.g. trimesh's `models/`, manifold's
//! `test/models/`):
//!
//! ```sh
//! cargo run --release --features cgal-oracle --example heldout_oracle -- \
//!     [--weld] [--snap Q] [--levels N] MESH...
//! ```
//!
//! For each file, the mesh as sliced (read, welded with `--weld`, snapped
//! to `Q` when given, degenerate faces flipped away): validation's self-intersection verdict
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
use wmslice::exact::parse_rational;
use wmslice::mesh::prepare::{CoincidentVertices, Repairs};
use wmslice::oracle::compare::{compare_levels, compare_self_intersections, Coverage};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let (mut snap, mut levels, mut paths) = (None, 40usize, Vec::new());
    let mut repairs = Repairs::default();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--weld" => repairs.coincident = CoincidentVertices::Weld,
            "--snap" => snap = Some(parse_rational(&args.next().ok_or("--snap needs Q")?)?),
            "--levels" => levels = args.next().ok_or("--levels needs N")?.parse()?,
            _ => paths.push(a),
        }
    }
    if paths.is_empty() {
        return Err("usage: heldout_oracle [--weld] [--snap Q] [--levels N] MESH...".into());
    }
    let mut disagreed = 0;
    for path in &paths {
        let name = heldout::file_name(path);
        let mesh = match heldout::load(path, snap.as_ref(), repairs) {
            Ok(mesh) => mesh,
            Err(line) => {
                println!("{line}");
                continue;
            }
        };
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
        let picked = heldout::evenly(&heights_and_midpoints(&mesh), levels);
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
        eprintln!("{disagreed} of {} files disagree", paths.len());
        std::process::exit(1);
    }
    Ok(())
}

/// The first lines of a report (the rest is the mesh as pasteable Rust).
fn first_lines(report: &str) -> String {
    report.lines().take(8).collect::<Vec<_>>().join("\n    ")
}
