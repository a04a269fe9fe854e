//! `wmslice demo`: built-in datasets at their degenerate levels, with what a
//! naive slicer would have done.

use super::args::DemoArgs;
use super::{slice_error, usage, Failure};
use crate::say;
use wmslice::datasets;
use wmslice::exact::rational::{rat_to_string, Rat};
use wmslice::naive::naive_slice;
use wmslice::output::summary::summary;
use wmslice::Slicer;

/// The demo's degenerate levels: one of each kind of degeneracy.
const DEMO: [(&str, i64, &str); 8] = [
    (
        "double_torus",
        2,
        "a monkey saddle (m = 3): three holes touch one outer loop",
    ),
    (
        "upright_torus",
        1,
        "an ordinary saddle at the top of the hole",
    ),
    ("saddle8", 2, "an 8-branch saddle (m = 4)"),
    (
        "lying_torus",
        2,
        "the top vertex ring: one closed ridge, no contour",
    ),
    (
        "cylinder",
        2,
        "the top cap: one up-facing region, no contour",
    ),
    (
        "internal_torus",
        2,
        "the cavity's top ring: a ridge inside the material",
    ),
    ("grid", 2, "a network of ridges around nine pits"),
    ("octahedron", 0, "a square of transversal in-plane edges"),
];

/// Runs `demo`.
pub fn run(_args: DemoArgs) -> Result<(), Failure> {
    say!("wmslice demo: exact level sets of built-in datasets at degenerate levels\n");
    for (name, z, what) in DEMO {
        let d = datasets::by_name(name).ok_or_else(|| usage(format!("missing dataset {name}")))?;
        let mesh = d.build();
        let slicer = Slicer::new(&mesh).map_err(slice_error)?;
        let c = Rat::from_integer(z.into());
        let ls = slicer.slice_at(&c).map_err(slice_error)?;
        say!("== {name} at z = {z}: {what}");
        say!("{}", summary(&ls));
        let n = naive_slice(&mesh, &c);
        say!(
            "  naive slicer : {} segments ({} zero-length, {} duplicated), {} filled contours of area {}\n",
            n.segments.len(),
            n.zero_length,
            n.duplicates,
            n.loops.len(),
            rat_to_string(&n.filled_area())
        );
    }
    say!("Slice any of them yourself: wmslice slice double_torus --at 2 --format json --exact");
    Ok(())
}
