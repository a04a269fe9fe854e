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

/// `fuzz/fuzz_targets/adversarial.rs` on two of its own seeds (bytes
/// `JhQEAAQAAAQABAQABAAAAAAAAAAAAAAAAAAPA+T9` and `...PAxwC`, base64): a
/// 2 x 1 slab with heights 0..3 scaled by `2^-540` and by `2^540`. Every
/// loop's exact area is a small multiple of `2^-1080` (nearer to 0 than
/// to any other double, so its rounded area is 0, README), or of `2^1080`
/// (beyond `f64::MAX`: rounded to infinity); the invariant check once
/// called both the wrong sign. The target's check: accepted, then every
/// SPEC 7 invariant at every vertex height and midpoint.
#[test]
fn adversarial_loops_whose_area_rounds_to_zero_or_infinity() {
    for e in [-540, 540] {
        slab_2x1_scaled(2f64.powi(e));
    }
}

fn slab_2x1_scaled(s: f64) {
    use wmslice::datasets::slab::heights_and_midpoints;
    use wmslice::levelset::check::check_level_invariants;
    // Vertex i: x = (i mod 12) / 4, y = i / 12 - 2, z = i mod 4, times s.
    let positions: Vec<[f64; 3]> = (0..24)
        .map(|i: i32| {
            [
                f64::from((i % 12) / 4),
                f64::from(i / 12 - 2),
                f64::from(i % 4),
            ]
            .map(|v| v * s)
        })
        .collect();
    let faces: Vec<[u32; 3]> = vec![
        [12, 13, 17],
        [0, 5, 1],
        [12, 17, 16],
        [0, 4, 5],
        [13, 14, 18],
        [1, 6, 2],
        [13, 18, 17],
        [1, 5, 6],
        [14, 15, 19],
        [2, 7, 3],
        [14, 19, 18],
        [2, 6, 7],
        [16, 17, 21],
        [4, 9, 5],
        [16, 21, 20],
        [4, 8, 9],
        [17, 18, 21],
        [5, 9, 6],
        [18, 22, 21],
        [6, 9, 10],
        [18, 19, 22],
        [6, 10, 7],
        [19, 23, 22],
        [7, 10, 11],
        [0, 1, 13],
        [0, 13, 12],
        [1, 2, 14],
        [1, 14, 13],
        [2, 3, 15],
        [2, 15, 14],
        [3, 7, 19],
        [3, 19, 15],
        [7, 11, 23],
        [7, 23, 19],
        [11, 10, 22],
        [11, 22, 23],
        [10, 9, 21],
        [10, 21, 22],
        [9, 8, 20],
        [9, 20, 21],
        [8, 4, 16],
        [8, 16, 20],
        [4, 0, 12],
        [4, 12, 16],
    ];
    let mesh = wmslice::Mesh::from_raw(positions, faces);
    assert_eq!(mesh.pos(wmslice::VertexId(1)), [0.0, -2.0 * s, s]);
    let slicer = wmslice::Slicer::new(&mesh).expect("a closed slab, accepted");
    let levels = heights_and_midpoints(&mesh);
    assert!(levels.len() >= 7);
    for c in levels.iter().take(40) {
        let ls = slicer.slice_at(c).expect("sliced");
        if let Err(e) = check_level_invariants(&mesh, slicer.topology(), &ls) {
            panic!("scale {s:e}, at {c}: {e}");
        }
    }
}
