//! Input: 47 x 47 sixteen-sided pillars with a vertex ring at mid height
//! (about 200k triangles), sliced at a regular level, at the ring (every
//! contour runs along in-plane edges through vertices on the plane), at the
//! top caps (2209 face regions) and at ten layers. Output: slicing and
//! verification times: `cargo run --release --example verify_scale`.

use std::time::Instant;
use wmslice::exact::parse_rational;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::verify::verify;
use wmslice::{Mesh, Slicer};

/// `k` x `k` closed `n`-gon prisms of height 10 with a vertex ring at 5.
fn pillars(k: usize, n: usize) -> Mesh {
    let mut pos = Vec::new();
    let mut faces = Vec::new();
    let zs = [0.0, 5.0, 10.0];
    for i in 0..k {
        for j in 0..k {
            let base = pos.len() as u32;
            let (cx, cy) = (3.0 * i as f64, 3.0 * j as f64);
            for z in zs {
                for m in 0..n {
                    let a = std::f64::consts::TAU * m as f64 / n as f64;
                    pos.push([cx + a.cos(), cy + a.sin(), z]);
                }
            }
            let v = |ring: usize, m: usize| base + (ring * n + m % n) as u32;
            for ring in 0..zs.len() - 1 {
                for m in 0..n {
                    faces.push([v(ring, m), v(ring, m + 1), v(ring + 1, m + 1)]);
                    faces.push([v(ring, m), v(ring + 1, m + 1), v(ring + 1, m)]);
                }
            }
            let top = zs.len() - 1;
            for m in 1..n - 1 {
                faces.push([v(top, 0), v(top, m), v(top, m + 1)]);
                faces.push([v(0, 0), v(0, m + 1), v(0, m)]);
            }
        }
    }
    Mesh::from_raw(pos, faces)
}

fn verify_time_on_a_200k_triangle_mesh() {
    let mesh = pillars(47, 16);
    println!(
        "{} triangles, {} vertices",
        mesh.num_faces(),
        mesh.num_vertices()
    );
    let slicer = Slicer::new(&mesh).unwrap();
    for z in ["2.5", "5", "10"] {
        let t = Instant::now();
        let ls = slicer.slice_at(&parse_rational(z).unwrap()).unwrap();
        let slice_time = t.elapsed();
        let text = to_json(&MeshHeader::new(&mesh, None), &[ls], Exactness::WithExact);
        let t = Instant::now();
        let report = verify(&mesh, None, &text).unwrap();
        let verify_time = t.elapsed();
        assert!(report.passed(), "{}", report.summary());
        println!(
            "z = {z}: slice {slice_time:?}, verify {verify_time:?} ({} bytes of JSON): {}",
            text.len(),
            report.summary()
        );
    }
}

fn verify_time_on_many_layers() {
    let mesh = pillars(47, 16);
    let slicer = Slicer::new(&mesh).unwrap();
    // Ten layers 1 apart, off the vertex heights: 30 families of 2209 loops.
    let levels: Vec<_> = (0..10)
        .map(|i| wmslice::exact::Rat::new((2 * i + 1).into(), 2.into()))
        .collect();
    let t = Instant::now();
    let sets: Vec<_> = levels.iter().map(|c| slicer.slice_at(c).unwrap()).collect();
    let slice_time = t.elapsed();
    let text = to_json(&MeshHeader::new(&mesh, None), &sets, Exactness::WithExact);
    let t = Instant::now();
    let report = verify(&mesh, None, &text).unwrap();
    let verify_time = t.elapsed();
    assert!(report.passed(), "{}", report.summary());
    println!(
        "10 layers: slice {slice_time:?}, verify {verify_time:?} ({} bytes): {}",
        text.len(),
        report.summary()
    );
}

fn main() {
    verify_time_on_a_200k_triangle_mesh();
    verify_time_on_many_layers();
}
