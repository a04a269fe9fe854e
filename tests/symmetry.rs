//! Exact symmetries keep validation results and the exact volume: axis
//! permutations (with orientation fix-up for odd ones) and integer
//! translations.

mod common;

use common::slab;
use proptest::prelude::*;
use wmslice::mesh::validate::validate;
use wmslice::Mesh;

fn permute(m: &Mesh, perm: [usize; 3], odd: bool, shift: [i32; 3]) -> Mesh {
    let mut out = m.clone();
    for p in &mut out.positions {
        let q = *p;
        *p = [0, 1, 2].map(|k| q[perm[k]] + f64::from(shift[k]));
    }
    if odd {
        for t in &mut out.faces {
            t.swap(1, 2);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, .. ProptestConfig::default() })]
    #[test]
    fn permutations_and_translations_keep_validation_and_volume(
        s in slab(), which in 0usize..6, shift in proptest::array::uniform3(-1000i32..1000)
    ) {
        let perms = [([0, 1, 2], false), ([1, 2, 0], false), ([2, 0, 1], false),
                     ([1, 0, 2], true), ([0, 2, 1], true), ([2, 1, 0], true)];
        let (perm, odd) = perms[which];
        let m = s.mesh();
        let a = validate(&m);
        let b = validate(&permute(&m, perm, odd, shift));
        prop_assert!(a.is_accepted() && b.is_accepted());
        prop_assert_eq!(a.volume, b.volume);
        prop_assert_eq!(a.stats.genus, b.stats.genus);
        prop_assert_eq!(a.defects, b.defects);
        // Without the orientation fix-up an odd permutation turns it inside out.
        if odd {
            let c = validate(&permute(&m, perm, false, shift));
            prop_assert!(!c.is_accepted());
        }
    }
}
