//! Input: slabs (with extra levels) that once made a slab fuzz target fail
//! (`fuzz/fuzz_targets/slice_invariants.rs`, `slice_oracle.rs`), and every
//! seed of their corpora. Output: the same checks the targets run, one
//! named test per case: SPEC section 7's invariants, exact crossing points
//! and the volume identity at every vertex height, midpoint and extra level
//! (`wmslice::datasets::slab::check_slab`), and with the `cgal-oracle`
//! feature agreement with CGAL at the same levels
//! (`wmslice::oracle::compare::compare_slab`).
//!
//! A failing fuzz run prints the case as a ready `fuzz_regression_N` test
//! (`check(Slab { .. }, &["p/q", ..])`) to paste here.

use wmslice::datasets::slab::{check_slab, levels_from_bytes, Slab};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::Rat;

/// The fuzz targets' checks on one slab and extra levels (`"p/q"`).
fn check(slab: Slab, extra: &[&str]) {
    let extra: Vec<Rat> = extra
        .iter()
        .map(|s| parse_rational(s).expect("a rational level"))
        .collect();
    check_rat(&slab, &extra);
}

fn check_rat(slab: &Slab, extra: &[Rat]) {
    if let Err(e) = check_slab(slab, extra) {
        panic!("{e}");
    }
    #[cfg(feature = "cgal-oracle")]
    {
        use wmslice::oracle::compare::{compare_slab, Coverage};
        if let Err(e) = compare_slab(slab, extra, &mut Coverage::default()) {
            panic!("{e}");
        }
    }
}

#[test]
fn every_slab_fuzz_seed_passes() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/fuzz/corpus/seeds");
    let mut seen = 0;
    for target in ["slice_invariants", "slice_oracle"] {
        let dir = std::path::Path::new(root).join(target);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        for f in files {
            let data = std::fs::read(&f).unwrap();
            let (slab, rest) = Slab::split_bytes(&data);
            let extra = levels_from_bytes(&slab.mesh(), rest);
            check_rat(&slab, &extra);
            seen += 1;
        }
    }
    assert!(seen >= 10, "only {seen} seeds");
}

/// The hook's output for seed `random_1`, pasted as printed: the helper
/// takes it as is.
#[test]
fn a_pasted_case_runs() {
    check(
        Slab {
            nx: 4,
            ny: 2,
            bot: vec![-2, -2, -2, -2, -2, -2, -2, -2, -2, -2, -2, -2, -2, -2, -2],
            thick: vec![1, 2, 1, 2, 1, 1, 2, 2, 2, 2, 1, 1, 1, 1, 1],
            diag: vec![false, false, false, true, true, true, false, true],
            rot: 0,
        },
        &[
            "-25579680400934054547/11978930560069354790",
            "-50848/18199",
            "-120242/55337",
            "-35672/13073",
        ],
    );
}
