//! Shared by the slab fuzz targets: bytes -> a closed slab mesh and a few
//! extra levels (`wmslice::datasets::slab`), and a panic hook that prints
//! the case being checked as a ready-to-paste regression test for
//! `tests/fuzz_regressions.rs`, whatever panicked.

use std::cell::RefCell;
use wmslice::datasets::slab::{levels_from_bytes, Slab};
use wmslice::exact::rational::{rat_to_string, Rat};

thread_local! {
    static CASE: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Chains a hook before libfuzzer-sys's (which prints and aborts).
pub fn install_panic_hook() {
    let next = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        CASE.with(|c| {
            eprintln!("\n==== failing case; as a test in tests/fuzz_regressions.rs:\n#[test]\nfn fuzz_regression_N() {{\n    check({});\n}}\n====", c.borrow());
        });
        next(info);
    }));
}

/// The slab and extra levels of `data`; remembers them for the hook.
pub fn case(data: &[u8]) -> (Slab, Vec<Rat>) {
    let (slab, rest) = Slab::split_bytes(data);
    let extra = levels_from_bytes(&slab.mesh(), rest);
    CASE.with(|c| {
        let mut s = c.borrow_mut();
        s.clear();
        s.push_str(&slab.pasteable());
        s.push_str(", &[");
        for (i, l) in extra.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            s.push('"');
            s.push_str(&rat_to_string(l));
            s.push('"');
        }
        s.push(']');
    });
    (slab, extra)
}
