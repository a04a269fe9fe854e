//! Input: arbitrary bytes, taken as a pickled level of the Python package
//! (`python/src/codec.rs`, compiled in here as it is: it needs no Python).
//! Output: nothing; panics only on a bug. A pickle is bytes from anywhere:
//! whatever they hold, decoding returns a level or a named error, never
//! panics, and a level it returns is one every method can use:
//!
//! - its JSON text, rounded and exact, is JSON (serde_json reads it);
//! - encoding it and decoding that gives the same bytes again;
//! - each point's nearest doubles (the integer fast path of a sliced
//!   point) are those of its exact value, and each loop's rounded area
//!   (the certified float filter) has its exact area's sign (a zero, the
//!   sign of its sign bit), on whatever integers and powers of two the
//!   bytes hold, far beyond a grid.
//!
//! The seeds are levels the package pickled (`Level.__reduce__`).
#![no_main]

use std::cmp::Ordering;

use libfuzzer_sys::fuzz_target;
use wmslice::exact::rational::rat_to_f64;
use wmslice::exact::Sign;
use wmslice::levelset::{LevelSet, Loop};
use wmslice::output::json::{level_text, Exactness};

#[path = "../../python/src/codec.rs"]
mod codec;

fuzz_target!(|data: &[u8]| {
    let Ok((ls, header, exact)) = codec::decode(data) else {
        return;
    };
    let bytes = codec::encode(&ls, &header, exact);
    let (again, header2, exact2) = codec::decode(&bytes).expect("encode's bytes decode");
    assert_eq!(
        codec::encode(&again, &header2, exact2),
        bytes,
        "a decoded level encodes to other bytes"
    );
    for ex in [Exactness::Rounded, Exactness::WithExact] {
        let text = level_text(&ls, ex).to_bytes();
        if let Err(e) = serde_json::from_slice::<serde_json::Value>(&text) {
            panic!("a decoded level's {ex:?} text is not JSON ({e})");
        }
    }
    for l in families(&ls) {
        let rounded: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
        for (p, r) in l.points.iter().zip(&rounded) {
            let e = p.exact();
            let nearest = [rat_to_f64(&e.x), rat_to_f64(&e.y)];
            assert!(
                nearest
                    .iter()
                    .zip(r)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{p:?}: nearest doubles {r:?}, of the exact value {nearest:?}"
            );
        }
        // A zero carries its sign: an area that rounds to zero is `+0` or
        // `-0` as the exact area is positive or negative.
        let area = l.area();
        let fast = l.rounded_area(&rounded);
        let sign = match (fast.partial_cmp(&0.0), fast.is_sign_negative()) {
            (Some(Ordering::Greater), _) | (Some(Ordering::Equal), false) => Sign::Positive,
            (Some(Ordering::Less), _) | (Some(Ordering::Equal), true) => Sign::Negative,
            (None, _) => panic!("rounded area {fast} of a loop of exact area {area}"),
        };
        let exact_sign = Sign::of_rat(&area);
        assert!(
            sign == exact_sign || (exact_sign == Sign::Zero && fast == 0.0),
            "rounded area {fast:e} of a loop of exact area {area}"
        );
    }
});

/// Every loop of a level: S_O, L-, L+ and the regions' boundaries.
fn families(ls: &LevelSet) -> impl Iterator<Item = &Loop> {
    ls.contours
        .iter()
        .chain(ls.below.iter())
        .chain(ls.above.iter())
        .chain(ls.regions.iter().flat_map(|r| r.boundary.iter()))
}
