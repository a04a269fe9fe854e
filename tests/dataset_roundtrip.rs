//! Every dataset through every writer and back through its reader: the same
//! welded mesh (same faces as coordinate triples, same orientation) and the
//! same exact volume.

use wmslice::datasets;
use wmslice::mesh::io::{load, MeshFormat};
use wmslice::mesh::validate::validate;
use wmslice::Mesh;

/// Faces as coordinate triples, each rotated to start at its smallest
/// corner (orientation kept), sorted: independent of vertex numbering.
fn canonical(m: &Mesh) -> Vec<[[u64; 3]; 3]> {
    let mut v: Vec<[[u64; 3]; 3]> = m
        .faces
        .iter()
        .map(|t| {
            let c = t.map(|v| m.pos(v).map(|x| (x + 0.0).to_bits()));
            let k = (0..3).min_by_key(|&k| c[k]).unwrap();
            [c[k], c[(k + 1) % 3], c[(k + 2) % 3]]
        })
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn every_dataset_round_trips_through_every_format() {
    let dir = tempfile::tempdir().unwrap();
    for d in datasets::all() {
        let mesh = d.build();
        let want = canonical(&mesh);
        let volume = validate(&mesh).volume;
        for format in MeshFormat::ALL {
            let path = dir
                .path()
                .join(format!("{}-{format:?}.{}", d.name, format.extension()));
            mesh.save_as(&path, format)
                .unwrap_or_else(|e| panic!("{} {format:?}: {e}", d.name));
            let (back, report) =
                load(&path).unwrap_or_else(|e| panic!("{} {format:?}: {e}", d.name));
            assert_eq!(report.format, format, "{}: detected format", d.name);
            assert_eq!(
                back.num_vertices(),
                mesh.num_vertices(),
                "{} {format:?}: welded vertex count",
                d.name
            );
            assert_eq!(
                canonical(&back),
                want,
                "{} {format:?}: faces differ",
                d.name
            );
            assert_eq!(
                validate(&back).volume,
                volume,
                "{} {format:?}: volume",
                d.name
            );
        }
    }
}
