//! Input: arbitrary bytes -> the same slabs and extra levels as
//! `slice_invariants`. Output: nothing; panics when the Rust level set and
//! the independent CGAL oracle disagree at any vertex height, midpoint or
//! extra level (`wmslice::oracle::compare::compare_slab`, the comparison
//! of `tests/oracle.rs`). Needs `--features cgal-oracle`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use wmslice::oracle::compare::{compare_slab, Coverage};

#[path = "slab_common.rs"]
mod slab_common;

fuzz_target!(init: slab_common::install_panic_hook(), |data: &[u8]| {
    let (slab, extra) = slab_common::case(data);
    if let Err(e) = compare_slab(&slab, &extra, &mut Coverage::default()) {
        panic!("Rust and CGAL disagree: {e}\n{slab:?}");
    }
});
