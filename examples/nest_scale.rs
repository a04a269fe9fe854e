//! Measures nesting on many small loops side by side and on nested rings:
//! `cargo run --release --example nest_scale -- 10000`.

use std::time::Instant;
use wmslice::exact::point::LoopPoint;
use wmslice::nest::nest_points;

fn square(x: i64, y: i64, s: i64) -> Vec<LoopPoint> {
    let p = |x: i64, y: i64| LoopPoint::from_integers(x.into(), y.into(), 1, 0).unwrap();
    vec![p(x, y), p(x + s, y), p(x + s, y + s), p(x, y + s)]
}

fn main() {
    let n: i64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    for k in [n / 4, n] {
        let side = (k as f64).sqrt().ceil() as i64;
        let loops: Vec<Vec<LoopPoint>> = (0..k)
            .map(|i| square(3 * (i % side), 3 * (i / side), 2))
            .collect();
        let t = Instant::now();
        let nested = nest_points(&loops);
        println!(
            "{k} side-by-side squares: {:.3} s ({} outer)",
            t.elapsed().as_secs_f64(),
            nested.iter().filter(|n| n.parent.is_none()).count()
        );
    }
}
