//! `wmslice demo`: built-in datasets at their degenerate levels, with what a
//! naive slicer would have done.
//!
//! Input: `-o FILE` (default `wmslice-demo.html`). Output: a summary per
//! level on stdout, and the HTML viewer of the same levels written to FILE
//! (atomically; directories created as needed).

use super::args::DemoArgs;
use super::{slice_error, usage, ExitCode, Failure, Tag};
use crate::say;
use anyhow::anyhow;
use wmslice::datasets;
use wmslice::exact::rational::{rat_to_string, Rat};
use wmslice::naive::naive_slice;
use wmslice::output::atomic::write_atomic;
use wmslice::output::html::{viewer, ViewerLayer, ViewerOptions};
use wmslice::output::summary::summary;
use wmslice::output::svg::Scene;
use wmslice::{LevelSet, Mesh, Slicer};

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
pub fn run(args: DemoArgs) -> Result<(), Failure> {
    say!("wmslice demo: exact level sets of built-in datasets at degenerate levels\n");
    let mut shown: Vec<(&str, &str, Mesh, LevelSet)> = Vec::new();
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
        shown.push((name, what, mesh, ls));
    }
    let scenes: Vec<Scene> = shown.iter().map(|s| Scene::new(&s.2, None)).collect();
    let layers: Vec<ViewerLayer> = shown
        .iter()
        .zip(&scenes)
        .map(|((name, what, _, ls), scene)| ViewerLayer {
            heading: (*name).to_string(),
            note: (*what).to_string(),
            level: ls,
            scene,
        })
        .collect();
    let page = viewer(
        &layers,
        &ViewerOptions {
            title: "wmslice demo: degenerate levels".into(),
            arrows: false,
            ..Default::default()
        },
    );
    let out = &args.output;
    write_atomic(out, page.as_bytes())
        .map_err(|e| anyhow!("cannot write {}: {e}", out.display()))
        .tag(ExitCode::Output)?;
    say!(
        "Wrote the HTML viewer of these {} levels to {} (open it in a browser; Left/Right step through them).",
        layers.len(),
        out.display()
    );
    say!("Slice any of them yourself: wmslice slice double_torus --at 2 --format json --exact");
    Ok(())
}
