//! Input: arbitrary bytes, taken as a result document (SPEC 9 JSON) that
//! claims to slice the built-in `peg_cube` (flats facing up and down, a
//! shoulder, holes). Output: nothing; panics only on a bug. `verify` reads
//! results other programs wrote, through its own streaming JSON reader:
//! whatever the text, it returns a report or a named error, never panics.
//! The seeds are the command line's own results (`--exact`), which verify
//! clean; mutations of them reach every check. And the reader accepts
//! JSON only: what it parses, serde_json parses too (but for numbers
//! beyond a double's range, which it keeps as text, and nesting deeper
//! than serde_json's limit).
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
    if wmslice::verify::json::parse(text).is_ok() {
        if let Err(e) = serde_json::from_str::<serde_json::Value>(text) {
            let why = e.to_string();
            assert!(
                why.contains("number out of range") || why.contains("recursion limit"),
                "the reader took what serde_json refuses ({why}): {text:?}"
            );
        }
    }
});
