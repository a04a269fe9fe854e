//! Input: every built-in dataset at every distinct vertex height and the
//! midpoints between consecutive ones, and 1000 random closed slabs with
//! integer coordinates (many ties) at the same kinds of levels, and the
//! meshes with the coordinate patterns of real files (`bench/meshgen.rs`:
//! `f32` noise near zero, decimal OBJ, an `f64` part with flats) at their
//! vertex heights, midpoints, decimal levels and levels whose crossings
//! tie between two doubles.
//! Output: a pass when the Rust level set agrees element by element with the
//! independent CGAL oracle (`wmslice::oracle`, feature `cgal-oracle`): vertex
//! signs, faces in the plane (and facing), the class of every in-plane edge,
//! extremal vertices, S_O branch counts and saddles, and the exact contour
//! segments of `CGAL::Polygon_mesh_slicer`. A disagreement prints the
//! (shrunk) mesh as pasteable Rust and both answers.
//!
//! The comparison itself (and how CGAL 5.5's unoriented polylines are
//! matched against Rust's S_O, S_NO, dF and P) lives in
//! `wmslice::oracle::compare`, shared with the `slice_oracle` fuzz target.
#![cfg(feature = "cgal-oracle")]

mod common;

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)]
mod meshgen;

use common::Slab;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use wmslice::classify::{Facing, RidgeKind};
use wmslice::datasets::slab::heights_and_midpoints;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::Rat;
use wmslice::oracle::compare::{compare_answers, compare_levels, Coverage};
use wmslice::oracle::{oracle_classify, OracleEdgeClass};
use wmslice::{LevelSet, Mesh, Slicer};

/// Compares at every distinct vertex height and midpoint; the report of
/// the first failing level.
fn compare_all_levels(mesh: &Mesh, cov: &mut Coverage) -> Result<(), String> {
    compare_levels(mesh, &heights_and_midpoints(mesh), cov)
}

#[test]
fn oracle_rejects_bad_input() {
    let open = Mesh::from_raw(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    );
    assert!(oracle_classify(&open, &Rat::from_integer(0.into())).is_err());
    let out_of_range = Mesh::from_raw(vec![[0.0, 0.0, 0.0]], vec![[0, 1, 2]]);
    assert!(oracle_classify(&out_of_range, &Rat::from_integer(0.into())).is_err());
}

#[test]
fn oracle_answers_the_unit_cube_exactly() {
    let mesh = wmslice::datasets::by_name("unit_cube").unwrap().build();
    // A level that is not a double: 1/3.
    let third = Rat::new(1.into(), 3.into());
    let o = oracle_classify(&mesh, &third).unwrap();
    assert!(o.edges.is_empty() && o.in_plane_faces.is_empty() && o.extrema.is_empty());
    assert_eq!(o.polylines.len(), 1);
    let pl = &o.polylines[0];
    assert_eq!(
        pl.first(),
        pl.last(),
        "closed polylines repeat their first point"
    );
    // The top face: one up region, its boundary reported by CGAL, no S_O.
    let top = oracle_classify(&mesh, &Rat::from_integer(1.into())).unwrap();
    assert!(!top.in_plane_faces.is_empty());
    assert!(top.in_plane_faces.values().all(|&f| f == Facing::Up));
    assert!(top.edges.values().all(|c| matches!(
        c,
        OracleEdgeClass::Interior | OracleEdgeClass::Boundary { so: false }
    )));
    assert!(top.branches.values().all(|&b| b == 0));
}

#[test]
fn every_dataset_agrees_with_cgal_at_every_vertex_height_and_midpoint() {
    let mut failures = Vec::new();
    let mut cov = Coverage::default();
    for d in wmslice::datasets::all() {
        if let Err(e) = compare_all_levels(&d.build(), &mut cov) {
            failures.push(format!("dataset {}: {e}", d.name));
        }
    }
    println!(
        "compared {} levels of {} datasets with the CGAL oracle: {cov:?}",
        cov.levels,
        wmslice::datasets::all().len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(cov.saddles_by_branches.contains_key(&6) && cov.saddles_by_branches.contains_key(&8));
}

#[test]
fn real_coordinate_patterns_agree_with_cgal() {
    // Small versions of `bench/compare`'s torus0, knot and steps64: their
    // crossings take the per-edge, certified and wide number paths, and
    // steps64's flats put faces in the plane with off-grid x and y.
    let meshes = [
        ("torus0", meshgen::torus_origin(24, 8)),
        ("knot", meshgen::knot(24, 6)),
        ("steps64", meshgen::steps_f64(4)),
    ];
    let mut failures = Vec::new();
    let mut cov = Coverage::default();
    for (name, b) in &meshes {
        let mesh = b.to_mesh();
        let mut levels = heights_and_midpoints(&mesh);
        let (lo, hi) = (levels[0].clone(), levels[levels.len() - 1].clone());
        // Decimal levels as a user types them, and simple fractions of the
        // stepped part's 1.25 steps (ties between two doubles).
        let decimals = (-300..=300).map(|k| Rat::new(k.into(), 10.into()));
        let ties = ["1/3", "3/8", "7/8", "21/8"].map(|c| parse_rational(c).unwrap());
        levels.extend(decimals.chain(ties).filter(|c| *c > lo && *c < hi));
        if let Err(e) = compare_levels(&mesh, &levels, &mut cov) {
            failures.push(format!("{name}: {e}"));
        }
    }
    println!(
        "compared {} levels with the CGAL oracle: {cov:?}",
        cov.levels
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(cov.in_plane_faces > 0 && cov.extrema > 0, "{cov:?}");
}

/// Runs `cases` random meshes from `strategy` through the comparison with
/// a fixed seed (WMSLICE_ORACLE_SEED=<u64> explores others); proptest
/// shrinks a failure to a minimal case. Returns what was covered.
fn run_random<S: Strategy>(what: &str, strategy: S, to_mesh: impl Fn(&S::Value) -> Mesh) -> Coverage
where
    S::Value: std::fmt::Debug,
{
    let cases = 1000;
    let seed: u64 = std::env::var("WMSLICE_ORACLE_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_c6a1);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let cov = std::cell::RefCell::new(Coverage::default());
    let meshes = std::cell::Cell::new(0usize);
    let result = runner.run(&strategy, |v| {
        meshes.set(meshes.get() + 1);
        compare_all_levels(&to_mesh(&v), &mut cov.borrow_mut())
            .map_err(|e| TestCaseError::fail(format!("{e}\ngenerated from: {v:?}")))
    });
    let cov = cov.into_inner();
    println!(
        "compared {} levels of {} {what} (seed {seed}) with the CGAL oracle: {cov:?}",
        cov.levels,
        meshes.get()
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    cov
}

#[test]
fn random_slabs_agree_with_cgal() {
    let cov = run_random("random slabs", common::slab(), Slab::mesh);
    // The random meshes must exercise every class, or the run proves little.
    for class in [
        "Interior",
        "Ridge",
        "Valley",
        "Transversal",
        "Boundary { so: false }",
        "Boundary { so: true }",
    ] {
        assert!(
            cov.edges.get(class).copied().unwrap_or(0) > 0,
            "no {class} edge was compared"
        );
    }
    assert!(cov.extrema > 0 && cov.in_plane_faces > 0 && !cov.saddles_by_branches.is_empty());
}

/// Slabs under the integer shear `z += a x + b y` (orientation-preserving,
/// determinant 1): tilted walls and caps put oblique lines of vertices and
/// faces into one plane.
fn sheared((s, a, b): &(Slab, i32, i32)) -> Mesh {
    let mut m = s.mesh();
    for p in &mut m.positions {
        p[2] += f64::from(*a) * p[0] + f64::from(*b) * p[1];
    }
    m
}

#[test]
fn random_sheared_slabs_agree_with_cgal() {
    let cov = run_random(
        "sheared slabs",
        (common::slab(), -2i32..=2, -2i32..=2),
        sheared,
    );
    assert!(cov.in_plane_faces > 0 && !cov.saddles_by_branches.is_empty());
}

/// The comparison itself must notice a wrong answer: corrupt correct Rust
/// level sets in several ways and expect a disagreement each time.
#[test]
fn the_comparison_detects_corrupted_answers() {
    let cases = [
        ("octahedron", 0),
        ("unit_cube", 1),
        ("grid", 2),
        ("grid", 1),
        ("double_torus", 2),
        ("lying_torus", 2),
    ];
    let mut detected = 0;
    for (name, z) in cases {
        let mesh = wmslice::datasets::by_name(name).unwrap().build();
        let c = Rat::from_integer(z.into());
        let slicer = Slicer::new(&mesh).unwrap();
        let ls = slicer.slice_at(&c).unwrap();
        let oracle = oracle_classify(&mesh, &c).unwrap();
        assert_eq!(
            compare_answers(&mesh, &c, &ls, &oracle),
            Vec::<String>::new()
        );
        let mut mutants: Vec<(&str, LevelSet)> = Vec::new();
        if !ls.contours.is_empty() {
            let mut m = ls.clone();
            std::sync::Arc::make_mut(&mut m.contours).pop();
            mutants.push(("a contour loop dropped", m));
            let mut m = ls.clone();
            let p = &mut std::sync::Arc::make_mut(&mut m.contours)[0].points[0];
            let mut moved = p.exact().into_owned();
            moved.x += Rat::new(1.into(), 1024.into());
            *p = moved.into();
            mutants.push(("a contour point moved", m));
        }
        if !ls.saddles.is_empty() {
            let mut m = ls.clone();
            m.saddles[0].branches += 2;
            mutants.push(("a saddle's branch count changed", m));
        }
        if !ls.regions.is_empty() {
            let mut m = ls.clone();
            m.regions[0].facing = match m.regions[0].facing {
                Facing::Up => Facing::Down,
                _ => Facing::Up,
            };
            mutants.push(("a region's facing flipped", m));
            let mut m = ls.clone();
            m.regions[0].faces.pop();
            mutants.push(("a region face dropped", m));
        }
        if !ls.extrema.is_empty() {
            let mut m = ls.clone();
            m.extrema.pop();
            mutants.push(("an extremum dropped", m));
        }
        if !ls.ridges.is_empty() {
            let mut m = ls.clone();
            m.ridges[0].kind = match m.ridges[0].kind {
                RidgeKind::Ridge => RidgeKind::Valley,
                RidgeKind::Valley => RidgeKind::Ridge,
            };
            mutants.push(("a ridge kind swapped", m));
        }
        for (what, m) in mutants {
            assert!(
                !compare_answers(&mesh, &c, &m, &oracle).is_empty(),
                "{name} at {z}: {what} went unnoticed"
            );
            detected += 1;
        }
    }
    assert!(detected >= 10, "only {detected} corruptions tried");
}
