//! SPEC section 7 on random closed meshes with small integer coordinates:
//! at every vertex height, at midpoints and at random rational levels.

mod common;

use common::slab;
use proptest::prelude::*;
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
