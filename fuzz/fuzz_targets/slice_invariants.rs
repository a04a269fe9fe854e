//! Input: arbitrary bytes -> a small closed slab with many ties
//! (`Slab::split_bytes`) and up to 4 extra exact levels from the remaining
//! bytes (`levels_from_bytes`). Output: nothing; panics on a bug: at every
//! vertex height, every midpoint and every extra level the level set
//! satisfies SPEC section 7's invariants 1-4, every crossing point equals
//! the big-rational reference (fast `i128` path included), and Simpson's
//! rule gives the exact volume (`wmslice::datasets::slab::check_slab`).
//! A failure prints the case as a regression test to paste.
#![no_main]

use libfuzzer_sys::fuzz_target;
use wmslice::datasets::slab::check_slab;

#[path = "slab_common.rs"]
mod slab_common;

fuzz_target!(init: slab_common::install_panic_hook(), |data: &[u8]| {
    let (slab, extra) = slab_common::case(data);
    if let Err(e) = check_slab(&slab, &extra) {
        panic!("slice invariant violated: {e}\n{slab:?}");
    }
});
