//! SPEC section 7 on random closed meshes with small integer coordinates:
//! at every vertex height, at midpoints and at random rational levels.

mod common;

use common::slab;
use proptest::prelude::*;
use wmslice::datasets::slab::{check_edge_points, heights_and_midpoints};
use wmslice::exact::rational::Rat;
use wmslice::exact::{Level, Sign};
use wmslice::levelset::check::{
    check_level_invariants, check_volume_identity, same_structure, vertex_heights,
};
use wmslice::mesh::validate::validate;
use wmslice::Slicer;

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn slabs_are_valid_and_every_level_satisfies_the_invariants(s in slab()) {
        let mesh = s.mesh();
        let report = validate(&mesh);
        prop_assert!(report.is_accepted(), "{report}");
        let slicer = Slicer::new(&mesh).unwrap();
        let zs = vertex_heights(&mesh);
        let two = Rat::from_integer(2.into());
        let mut levels = zs.clone();
        for w in zs.windows(2) {
            levels.push((&w[0] + &w[1]) / &two);
        }
        for c in &levels {
            let ls = slicer.slice_at(c).map_err(|e| TestCaseError::fail(e.to_string()))?;
            if let Err(e) = check_level_invariants(&mesh, slicer.topology(), &ls) {
                return Err(TestCaseError::fail(format!("level {c}: {e}\n{s:?}")));
            }
        }
    }

    /// A mesh whose coordinates span more than one 62-bit grid (x scaled
    /// by 2^40, y by 2^-40) takes the per-edge crossing path: its level
    /// sets keep the invariants, its crossings are the reference ones,
    /// and its loops pass through the same mesh elements as the unscaled
    /// mesh's (which takes the grid path).
    #[test]
    fn meshes_off_one_grid_slice_like_meshes_on_it(s in slab()) {
        let mesh = s.mesh();
        let mut wide = mesh.clone();
        for p in &mut wide.positions {
            p[0] *= 2f64.powi(40);
            p[1] *= 2f64.powi(-40);
        }
        prop_assert!(wmslice::exact::grid::MeshGrid::new(&mesh.positions).is_some());
        prop_assert!(wmslice::exact::grid::MeshGrid::new(&wide.positions).is_none());
        let (on, off) = (Slicer::new(&mesh).unwrap(), Slicer::new(&wide).unwrap());
        for c in heights_and_midpoints(&mesh) {
            let (a, b) = (on.slice_at(&c).unwrap(), off.slice_at(&c).unwrap());
            if let Err(e) = check_level_invariants(&wide, off.topology(), &b)
                .and_then(|()| check_edge_points(&off, &b))
            {
                return Err(TestCaseError::fail(format!("level {c}: {e}\n{s:?}")));
            }
            for (x, y) in [(&a.contours, &b.contours), (&a.below, &b.below), (&a.above, &b.above)] {
                let cuts = |f: &[wmslice::levelset::Loop]| f.iter().map(|l| l.cuts.clone()).collect::<Vec<_>>();
                prop_assert_eq!(cuts(x), cuts(y), "level {}", c);
            }
        }
    }

    #[test]
    fn simpson_on_exact_cross_sections_gives_the_exact_volume(s in slab()) {
        let mesh = s.mesh();
        let slicer = Slicer::new(&mesh).unwrap();
        let volume = validate(&mesh).volume;
        if let Err(e) = check_volume_identity(&slicer, &volume) {
            return Err(TestCaseError::fail(format!("{e}\n{s:?}")));
        }
    }

    #[test]
    fn contours_change_only_at_vertex_heights(s in slab(), t1 in 1i64..1000, t2 in 1i64..1000) {
        let mesh = s.mesh();
        let slicer = Slicer::new(&mesh).unwrap();
        let zs = vertex_heights(&mesh);
        for w in zs.windows(2) {
            let at = |t: i64| &w[0] + (&w[1] - &w[0]) * Rat::new(t.into(), 1001.into());
            let a = slicer.slice_at(&at(t1)).unwrap();
            let b = slicer.slice_at(&at(t2)).unwrap();
            prop_assert!(same_structure(&a, &b), "between {} and {}", w[0], w[1]);
            prop_assert!(a.regions.is_empty() && a.ridges.is_empty() && a.extrema.is_empty() && a.saddles.is_empty());
        }
    }

    #[test]
    fn float_bracketed_sign_equals_the_rational_comparison(
        p in -10_000i64..10_000, q in 1i64..10_000, h in -2_000_000i64..2_000_000, e in 0u32..12
    ) {
        let c = Rat::new(p.into(), q.into());
        let hf = h as f64 / f64::from(1u32 << e);
        let exact = Rat::from_float(hf).unwrap();
        let want = match exact.cmp(&c) {
            std::cmp::Ordering::Less => Sign::Negative,
            std::cmp::Ordering::Equal => Sign::Zero,
            std::cmp::Ordering::Greater => Sign::Positive,
        };
        prop_assert_eq!(Level::new(c).sign_of(hf), want);
    }
}
