//! Input: arbitrary bytes. Output: nothing; panics only on a bug: loading
//! them as StlBinary must not panic, and a mesh that loads and validates must
//! pass the topology invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;
use wmslice::mesh::io::MeshFormat;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    common::check(data, MeshFormat::StlBinary);
});
