//! Times the stages of slicing one mesh file with the same layer plan as
//! `wmslice slice`, and prints them as one JSON line (used by
//! `bench/compare` for the "slicing only" column):
//!
//! ```sh
//! cargo run --release --example bench_slice -- MESH.stl --layer-height H \
//!     [--first Z0] [--last Z1] [--threads N] [--repeat R] [--snap Q]
//! ```
//!
//! `load_s`: read, parse and weld the file (with `--snap`, also snap it
//! to the grid `Q` and flip away degenerate faces, as `wmslice slice
//! --snap` does); `build_s`: validation and
//! topology (`Slicer::new`, on `--threads` workers); `slice_s`:
//! `layers::slice_levels` alone (the median of `R` runs, default 1),
//! results dropped after counting, nothing written out.

use std::time::Instant;
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_from_f64, Rat};
use wmslice::layers::{plan_levels, slice_levels, LayerPlan};
use wmslice::Slicer;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut mesh_path = None;
    let (mut height, mut first, mut last) = (None, None, None);
    let (mut threads, mut repeat) = (1usize, 1usize);
    let mut snap = None;
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--layer-height" => height = Some(parse_rational(&value()?)?),
            "--first" => first = Some(parse_rational(&value()?)?),
            "--last" => last = Some(parse_rational(&value()?)?),
            "--threads" => threads = value()?.parse()?,
            "--repeat" => repeat = value()?.parse::<usize>()?.max(1),
            "--snap" => snap = Some(parse_rational(&value()?)?),
            _ if mesh_path.is_none() => mesh_path = Some(a),
            _ => return Err(format!("unexpected argument {a}").into()),
        }
    }
    let usage = "usage: bench_slice MESH --layer-height H [--first Z0] [--last Z1] [--threads N] [--repeat R] [--snap Q]";
    let mesh_path = mesh_path.ok_or(usage)?;
    let height = height.ok_or(usage)?;

    let t = Instant::now();
    let (mesh, _report) = wmslice::mesh::io::load(std::path::Path::new(&mesh_path))?;
    // In grid units when snapped: true coordinate = stored * unit.
    let prepared = wmslice::mesh::prepare::prepare(mesh, snap.as_ref())?;
    let (mesh, unit) = (
        prepared.mesh,
        prepared.unit.unwrap_or_else(|| Rat::from_integer(1.into())),
    );
    let load_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    // Validation uses the same number of threads as the slicing.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let slicer = pool.install(|| Slicer::with_unit(&mesh, unit.clone()))?;
    let build_s = t.elapsed().as_secs_f64();

    let zs = mesh.positions.iter().map(|p| p[2]);
    let lo = rat_from_f64(zs.clone().fold(f64::INFINITY, f64::min)) * &unit;
    let hi = rat_from_f64(zs.fold(f64::NEG_INFINITY, f64::max)) * &unit;
    let plan = LayerPlan {
        height,
        first,
        last,
    };
    let levels: Vec<Rat> = plan_levels(Some(&plan), &[], (&lo, &hi))?;

    let mut times = Vec::with_capacity(repeat);
    let (mut loops, mut points) = (0usize, 0usize);
    for _ in 0..repeat {
        (loops, points) = (0, 0);
        let t = Instant::now();
        slice_levels(&slicer, &levels, threads, |_, ls| {
            loops += ls.contours.len();
            points += ls.contours.iter().map(|l| l.points.len()).sum::<usize>();
            Ok::<(), std::convert::Infallible>(())
        })?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{{\"triangles\": {}, \"levels\": {}, \"threads\": {threads}, \"load_s\": {load_s:.6}, \"build_s\": {build_s:.6}, \"slice_s\": {:.6}, \"contours\": {loops}, \"points\": {points}}}",
        mesh.num_faces(),
        levels.len(),
        times[times.len() / 2]
    );
    Ok(())
}
