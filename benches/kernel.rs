//! Criterion benches of the kernel stages on mid-size meshes, the same
//! shapes as `bench/compare`'s (`bench/meshgen.rs`, exact `f32` coordinates):
//!
//! - `torus_100k`: a tilted torus of about 100 000 triangles: topology
//!   build, `Slicer::new` (validation and topology), one layer
//!   (`Slicer::slice_at`, which scans every face), and a 1000-layer sweep
//!   over its height (no plane meets a vertex ring);
//! - `steps_50k`: the CAD-like stepped part (about 50 000 triangles, flats
//!   at every `k * 1.25`): one layer at a flat, and a 1000-layer sweep
//!   (`layers::slice_levels`, one thread, levels `k * 0.125`, so every
//!   tenth level lies on the flats);
//! - `critical_100k`: `critical::analyze` (critical heights and the Reeb
//!   graph) on three coordinate patterns of about 100 000 triangles: the
//!   torus centred at the origin in `f32` (nearly every height shared by a
//!   mirrored pair of vertices), the knot with six-decimal coordinates, and
//!   the stepped part (large flats).
//!
//! ```sh
//! cargo bench --bench kernel                  # about two minutes
//! cargo bench --bench kernel -- torus_100k    # one group
//! ```

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)] // the STL writer is for the example
mod meshgen;

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::Duration;
use wmslice::exact::rational::{rat_from_f64, Rat};
use wmslice::layers::slice_levels;
use wmslice::mesh::topology::Topology;
use wmslice::{Mesh, Slicer};

/// `n` levels evenly spread strictly inside the mesh's height range.
fn spread_levels(mesh: &Mesh, n: usize) -> Vec<Rat> {
    let zs = mesh.positions.iter().map(|p| p[2]);
    let lo = rat_from_f64(zs.clone().fold(f64::INFINITY, f64::min));
    let hi = rat_from_f64(zs.fold(f64::NEG_INFINITY, f64::max));
    let step = (&hi - &lo) / Rat::from_integer((n as i64).into());
    let half = &step / Rat::from_integer(2.into());
    (0..n)
        .map(|k| &lo + &half + &step * Rat::from_integer((k as i64).into()))
        .collect()
}

/// Levels `k / 8` for `k = 1..=n` (exact, on the steps' flats every tenth).
fn eighths(n: i64) -> Vec<Rat> {
    (1..=n).map(|k| Rat::new(k.into(), 8.into())).collect()
}

/// Slices every level on one thread, returns the number of contour points.
fn sweep(slicer: &Slicer<'_>, levels: &[Rat]) -> usize {
    let mut points = 0usize;
    slice_levels(slicer, levels, 1, |_, ls| {
        points += ls.contours.iter().map(|l| l.points.len()).sum::<usize>();
        Ok::<(), std::convert::Infallible>(())
    })
    .expect("sweep");
    points
}

fn torus(c: &mut Criterion) {
    let mesh = meshgen::torus_of(100_000).to_mesh();
    let slicer = Slicer::new(&mesh).expect("the torus is a valid closed mesh");
    let mid = spread_levels(&mesh, 1).remove(0);

    let mut g = c.benchmark_group("torus_100k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    g.bench_function("topology_build", |b| {
        b.iter(|| black_box(Topology::build(black_box(&mesh))))
    });
    g.bench_function("slicer_new", |b| {
        b.iter(|| black_box(Slicer::new(black_box(&mesh)).expect("valid")))
    });
    g.bench_function("one_layer", |b| {
        b.iter(|| black_box(slicer.slice_at(black_box(&mid)).expect("slice")))
    });
    let levels = spread_levels(&mesh, 1000);
    g.bench_function("sweep_1000_layers", |b| {
        b.iter(|| black_box(sweep(&slicer, &levels)))
    });
    g.finish();
}

fn steps(c: &mut Criterion) {
    let mesh = meshgen::steps_of(50_000).to_mesh();
    let slicer = Slicer::new(&mesh).expect("the stepped part is a valid closed mesh");
    let flat = Rat::new(5.into(), 4.into());
    let levels = eighths(1000);

    let mut g = c.benchmark_group("steps_50k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(3));
    g.bench_function("one_layer_at_a_flat", |b| {
        b.iter(|| black_box(slicer.slice_at(black_box(&flat)).expect("slice")))
    });
    g.bench_function("sweep_1000_layers", |b| {
        b.iter(|| black_box(sweep(&slicer, &levels)))
    });
    g.finish();
}

fn critical(c: &mut Criterion) {
    let meshes = [
        (
            "torus_origin_f32",
            meshgen::torus_origin_of(100_000).to_mesh(),
        ),
        (
            "knot_decimal",
            meshgen::knot_of(100_000).rounded_to_decimals(6).to_mesh(),
        ),
        ("steps", meshgen::steps_of(100_000).to_mesh()),
    ];
    let mut g = c.benchmark_group("critical_100k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(3));
    for (name, mesh) in &meshes {
        let slicer = Slicer::new(mesh).expect("a valid closed mesh");
        g.bench_function(*name, |b| {
            b.iter(|| black_box(wmslice::critical::analyze(black_box(&slicer)).expect("analysis")))
        });
    }
    g.finish();
}

criterion_group!(benches, torus, steps, critical);
criterion_main!(benches);
