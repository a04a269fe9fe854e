//! Closed random meshes with small integer coordinates (ties everywhere),
//! shared by the property tests. The slab itself lives in the library
//! (`wmslice::datasets::slab`, also used by the fuzz targets); the proptest
//! strategy stays here.
#![allow(dead_code)]

use proptest::prelude::*;
pub use wmslice::datasets::slab::Slab;

/// Random slabs: up to 4 x 4 cells, heights in a small range.
pub fn slab() -> impl Strategy<Value = Slab> {
    (1usize..=4, 1usize..=4).prop_flat_map(|(nx, ny)| {
        let n = (nx + 1) * (ny + 1);
        (
            proptest::collection::vec(-2i32..=2, n),
            proptest::collection::vec(1i32..=3, n),
            proptest::collection::vec(any::<bool>(), nx * ny),
            0u8..3,
        )
            .prop_map(move |(bot, thick, diag, rot)| Slab {
                nx,
                ny,
                bot,
                thick,
                diag,
                rot,
            })
    })
}
