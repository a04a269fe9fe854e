//! Input: arbitrary bytes, taken as a result document (SPEC 9 JSON) that
//! claims to slice the built-in `peg_cube` (flats facing up and down, a
//! shoulder, holes). Output: nothing; panics only on a bug. `verify` reads
//! results other programs wrote, through its own streaming JSON reader:
//! whatever the text, it returns a report or a named error, never panics.
//! The seeds are the command line's own results (plain and `--exact`),
//! which verify clean; mutations of them reach every check.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use wmslice::verify::Verifier;
use wmslice::Mesh;

fuzz_target!(|data: &[u8]| {
    static MESH: OnceLock<Mesh> = OnceLock::new();
    let mesh = MESH.get_or_init(|| {
        wmslice::datasets::by_name("peg_cube")
            .expect("a built-in dataset")
            .build()
    });
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let verifier = Verifier::new(mesh, None).expect("peg_cube is valid");
    let _ = verifier.verify(text);
});
