//! The critical values of a mesh file, checked against the slow path.
//!
//! `cargo run --release --example critical_check -- FILE [SNAP]` loads the
//! mesh as the command line does (snapped to the grid `SNAP` if given; a
//! 3MF part placed off the doubles needs one), runs
//! [`wmslice::critical::analyze`] and the independent
//! [`wmslice::critical::brute_force::classify_all`] (the full level set at
//! every distinct vertex height: quadratic, so skipped above
//! [`SLOW_LIMIT`] faces), and exits 1 unless they agree. Prints the times
//! of validation, of the analysis and of the slow path.

use std::time::Instant;
use wmslice::critical::{analyze, brute_force};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::Rat;
use wmslice::mesh::io::load_exact;
use wmslice::mesh::prepare::prepare_exact;
use wmslice::Slicer;

/// Above this many faces only the analysis runs (and is timed).
const SLOW_LIMIT: usize = 100_000;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: critical_check FILE [SNAP]");
        std::process::exit(2);
    };
    // Read and prepared as the command line does: a 3MF vertex whose
    // placed position is not a double is snapped from its exact position.
    let (mesh, _, exact) = match load_exact(std::path::Path::new(path)) {
        Ok(read) => read,
        Err(e) => {
            println!("{path}: unread: {e}");
            std::process::exit(2);
        }
    };
    let q = args.get(1).map(|q| parse_rational(q).expect("a grid"));
    let p = match prepare_exact(mesh, &exact, q.as_ref()) {
        Ok(p) => p,
        Err(e) => {
            println!("{path}: refused: {e}");
            return;
        }
    };
    let unit = p
        .unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()));
    let t = Instant::now();
    let slicer = match Slicer::with_unit(&p.mesh, unit) {
        Ok(s) => s,
        Err(e) => {
            println!("{path}: refused: {e}");
            return;
        }
    };
    let t_validate = t.elapsed();
    let t = Instant::now();
    let fast = analyze(&slicer).expect("no internal error");
    let t_fast = t.elapsed();
    let faces = p.mesh.num_faces();
    let head = format!(
        "{path}: {faces} faces, {} critical heights, {} nodes, {} arcs, genus {} (validation {:.3} s, analysis {:.3} s)",
        fast.levels.len(),
        fast.reeb.nodes.len(),
        fast.reeb.arcs.len(),
        fast.genus,
        t_validate.as_secs_f64(),
        t_fast.as_secs_f64(),
    );
    if faces > SLOW_LIMIT {
        println!("{head}: slow path skipped (over {SLOW_LIMIT} faces)");
        return;
    }
    let t = Instant::now();
    let slow = brute_force::classify_all(&slicer).expect("slices");
    let t_slow = t.elapsed();
    let ok = fast.levels == slow;
    println!(
        "{head}: {} (slow path {:.3} s)",
        if ok { "agree" } else { "DIFFER" },
        t_slow.as_secs_f64()
    );
    if !ok {
        std::process::exit(1);
    }
}
