//! How the cost grows with triangles and with layers: builds the
//! benchmark shapes of `bench/compare` (`bench/meshgen.rs`: on one small
//! grid, `torus` and `steps`; with real coordinate patterns, `torus0`,
//! `knot`, `steps64` and `plate64`) in memory at
//! 0.1 M to 10 M triangles, times validation + topology and the layer sweep,
//! and prints a Markdown table with the cost per triangle and per output
//! point:
//!
//! ```sh
//! cargo run --release --example scaling                 # 0.1M..10M x 100 layers, 1M x 10..1000
//! cargo run --release --example scaling -- --max 2000000 --threads 2
//! ```
//!
//! One run per row (the largest take seconds); nothing is written out.

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)] // the criterion benches use the rest
mod meshgen;

use std::time::Instant;
use wmslice::exact::rational::{rat_from_f64, Rat};
use wmslice::layers::{plan_levels, slice_levels, LayerPlan};
use wmslice::Slicer;

const SIZES: [usize; 7] = [
    100_000, 200_000, 500_000, 1_000_000, 2_000_000, 5_000_000, 10_000_000,
];
const LAYER_COUNTS: [usize; 4] = [10, 100, 1000, 4000];

/// The plan `bench/compare` uses: `layers` levels over the shape's height.
fn plan(shape: &str, lo: f64, hi: f64, layers: usize) -> (Rat, Rat) {
    if shape.starts_with("steps") {
        let h = Rat::new(125.into(), layers.into());
        return (h.clone(), h);
    }
    let span = hi - lo;
    let h = Rat::new(
        ((span / layers as f64 * 10000.0) as i64).into(),
        10000.into(),
    );
    let first = Rat::new(((lo * 1000.0).ceil() as i64).into(), 1000.into())
        + &h / Rat::from_integer(2.into());
    (first, h)
}

struct Row {
    shape: &'static str,
    triangles: usize,
    layers: usize,
    build_s: f64,
    slice_s: f64,
    points: usize,
}

fn measure(
    shape: &'static str,
    b: &meshgen::Builder,
    layers: usize,
    threads: usize,
) -> Result<Row, Box<dyn std::error::Error>> {
    let mesh = b.to_mesh();
    let t = Instant::now();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let slicer = pool.install(|| Slicer::new(&mesh))?;
    let build_s = t.elapsed().as_secs_f64();
    let (lo, hi) = b.z_range();
    let (first, height) = plan(shape, lo, hi, layers);
    let last = &first + &height * Rat::from_integer((layers - 1).into());
    let range = (rat_from_f64(lo), rat_from_f64(hi));
    let plan = LayerPlan {
        height,
        first: Some(first),
        last: Some(last),
    };
    let levels = plan_levels(Some(&plan), &[], (&range.0, &range.1))?;
    let mut points = 0usize;
    let t = Instant::now();
    slice_levels(&slicer, &levels, threads, |_, ls| {
        points += ls.contours.iter().map(|l| l.points.len()).sum::<usize>();
        Ok::<(), std::convert::Infallible>(())
    })?;
    Ok(Row {
        shape,
        triangles: mesh.num_faces(),
        layers: levels.len(),
        build_s,
        slice_s: t.elapsed().as_secs_f64(),
        points,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let (mut max, mut threads) = (10_000_000usize, 1usize);
    while let Some(a) = args.next() {
        let mut value = || -> Result<usize, Box<dyn std::error::Error>> {
            Ok(args.next().ok_or(format!("{a} needs a value"))?.parse()?)
        };
        match a.as_str() {
            "--max" => max = value()?,
            "--threads" => threads = value()?,
            _ => return Err(format!("unexpected argument {a} (--max N, --threads N)").into()),
        }
    }
    println!("| shape | triangles | layers | build s | slice s | contour points | build ns/triangle | slice ns/(triangle x layer) | slice ns/point |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    let print = |r: &Row| {
        let per = |s: f64, n: f64| s * 1e9 / n;
        println!(
            "| {} | {} | {} | {:.3} | {:.3} | {} | {:.0} | {:.2} | {:.0} |",
            r.shape,
            r.triangles,
            r.layers,
            r.build_s,
            r.slice_s,
            r.points,
            per(r.build_s, r.triangles as f64),
            per(r.slice_s, (r.triangles * r.layers) as f64),
            per(r.slice_s, r.points.max(1) as f64),
        );
    };
    // The two shapes on one small grid, then the classes with real
    // coordinate patterns (bench/meshgen.rs).
    for shape in ["torus", "steps", "torus0", "knot", "steps64", "plate64"] {
        for &n in SIZES.iter().filter(|&&n| n <= max) {
            let b = match shape {
                "torus" => meshgen::torus_of(n),
                "steps" => meshgen::steps_of(n),
                "torus0" => meshgen::torus_origin_of(n),
                "knot" => meshgen::knot_of(n),
                "steps64" => meshgen::steps_f64_of(n),
                _ => meshgen::plate_of(n),
            };
            print(&measure(shape, &b, 100, threads)?);
            if n == 1_000_000 {
                for layers in LAYER_COUNTS.into_iter().filter(|&l| l != 100) {
                    print(&measure(shape, &b, layers, threads)?);
                }
            }
        }
    }
    Ok(())
}
