//! Read and write times of every mesh format on a large grid:
//! `cargo run --release --example io_scale`.

use wmslice::mesh::io::{load_bytes, write_mesh, MeshFormat, SaveOptions};
use wmslice::Mesh;

/// A grid surface of `2 n^2` triangles with dyadic coordinates.
fn grid(n: u32) -> Mesh {
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            positions.push([
                f64::from(i) * 0.25,
                f64::from(j) * 0.5,
                f64::from((i ^ j) & 7),
            ]);
        }
    }
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_raw(positions, faces)
}

fn main() {
    let mesh = grid(700);
    for format in MeshFormat::ALL {
        let t = std::time::Instant::now();
        let mut bytes = Vec::new();
        write_mesh(&mesh, format, SaveOptions::default(), &mut bytes).unwrap();
        let written = t.elapsed();
        let t = std::time::Instant::now();
        let (read, _) = load_bytes(&bytes, None).unwrap();
        println!(
            "{format}: {} faces, {} bytes, write {written:?}, read {:?}",
            read.num_faces(),
            bytes.len(),
            t.elapsed()
        );
        assert_eq!(read.num_faces(), mesh.num_faces());
    }
}
