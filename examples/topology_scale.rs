//! Measures topology build time, table size, validation and a layer sweep
//! on large closed meshes: `cargo run --release --example topology_scale --
//! 500 100` (grid side n, about 4 n^2 triangles; number of layers).

use std::time::Instant;
use wmslice::exact::rational::Rat;
use wmslice::layers::slice_levels;
use wmslice::mesh::topology::Topology;
use wmslice::mesh::validate::validate;
use wmslice::{Mesh, Slicer};

/// A closed slab over an n x n grid with a wavy integer top.
fn slab(n: usize) -> Mesh {
    let idx = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let m = ((n + 1) * (n + 1)) as u32;
    let mut pos = Vec::new();
    for layer in 0..2 {
        for j in 0..=n {
            for i in 0..=n {
                let z = if layer == 0 {
                    0.0
                } else {
                    10.0 + ((i * 7 + j * 3) % 5) as f64
                };
                pos.push([i as f64, j as f64, z]);
            }
        }
    }
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            faces.extend([
                [m + a, m + b, m + c],
                [m + a, m + c, m + d],
                [a, c, b],
                [a, d, c],
            ]);
        }
    }
    let mut ring = Vec::new();
    ring.extend((0..n).map(|i| (i, 0)));
    ring.extend((0..n).map(|j| (n, j)));
    ring.extend((1..=n).rev().map(|i| (i, n)));
    ring.extend((1..=n).rev().map(|j| (0, j)));
    for k in 0..ring.len() {
        let (p, q) = (ring[k], ring[(k + 1) % ring.len()]);
        let (bp, bq) = (idx(p.0, p.1), idx(q.0, q.1));
        faces.extend([[bp, bq, m + bq], [bp, m + bq, m + bp]]);
    }
    Mesh::from_raw(pos, faces)
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(500);
    let mesh = slab(n);
    let t = Instant::now();
    let (topo, issues) = Topology::build(&mesh);
    let build = t.elapsed();
    let t = Instant::now();
    let report = validate(&mesh);
    let full = t.elapsed();
    println!(
        "{} triangles: topology {:.3} s, {:.1} bytes/triangle, issues {}; full validation {:.3} s, accepted {}",
        mesh.num_faces(),
        build.as_secs_f64(),
        topo.heap_bytes() as f64 / mesh.num_faces() as f64,
        issues.len(),
        full.as_secs_f64(),
        report.is_accepted()
    );
    let layers: i64 = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let slicer = Slicer::new(&mesh).expect("valid mesh");
    // Planes from 0 to 15 (the wavy top spans 10..14), some at vertex heights.
    let levels: Vec<Rat> = (1..=layers)
        .map(|k| Rat::new((15 * k).into(), layers.into()))
        .collect();
    let t = Instant::now();
    let mut points = 0usize;
    slice_levels::<std::convert::Infallible, _>(&slicer, &levels, 1, |_, ls| {
        points += ls.contours.iter().map(|l| l.points.len()).sum::<usize>();
        Ok(())
    })
    .expect("slice");
    println!(
        "{layers} layers, one thread: {:.3} s, {points} contour points",
        t.elapsed().as_secs_f64()
    );
}
