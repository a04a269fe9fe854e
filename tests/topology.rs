//! The edge table and fans satisfy their structural invariants on every
//! dataset and on random closed meshes; fans follow the surface orientation.

mod common;

use common::slab;
use proptest::prelude::*;
use wmslice::datasets;
use wmslice::mesh::topology::{check_invariants, Topology};
use wmslice::VertexId;

#[test]
fn every_dataset_has_sound_tables() {
    for d in datasets::all() {
        let mesh = d.build();
        let (topo, issues) = Topology::build(&mesh);
        assert!(issues.is_empty(), "{}: {issues:?}", d.name);
        check_invariants(&mesh, &topo).unwrap_or_else(|e| panic!("{}: {e}", d.name));
    }
}

#[test]
fn the_fan_of_an_octahedron_apex_is_counter_clockwise_from_outside() {
    let mesh = datasets::by_name("octahedron").unwrap().build();
    let (topo, _) = Topology::build(&mesh);
    // The top vertex: the one with the largest z.
    let top = (0..mesh.num_vertices())
        .max_by(|&a, &b| mesh.positions[a][2].total_cmp(&mesh.positions[b][2]))
        .unwrap();
    let fan = topo.fan(VertexId::from_idx(top));
    assert_eq!(fan.len(), 4);
    // Seen from above (outside), consecutive neighbours turn counter-clockwise.
    for k in 0..4 {
        let a = mesh.pos(fan[k].neighbour);
        let b = mesh.pos(fan[(k + 1) % 4].neighbour);
        let c = mesh.positions[top];
        let cross = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
        assert!(cross > 0.0, "fan turns clockwise at {k}");
    }
}

proptest! {
    #[test]
    fn random_closed_meshes_have_sound_tables(s in slab()) {
        let mesh = s.mesh();
        let (topo, issues) = Topology::build(&mesh);
        prop_assert!(issues.is_empty());
        prop_assert_eq!(check_invariants(&mesh, &topo), Ok(()));
    }
}

#[test]
fn a_vertex_of_thousands_of_faces_has_sound_tables() {
    // A double cone of 3000 faces around each apex, the ring numbered
    // out of order (a vertex's edges are found by their other end).
    let n = 3000u32;
    let ring = |i: u32| 2 + (i * 7 + 3) % n;
    let mut positions = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    positions.extend((0..n).map(|k| {
        let i = (0..n).position(|i| ring(i) == 2 + k).unwrap() as f64;
        let t = std::f64::consts::TAU * i / f64::from(n);
        [t.cos(), t.sin(), 0.0]
    }));
    let mut faces = Vec::new();
    for i in 0..n {
        let (a, b) = (ring(i), ring((i + 1) % n));
        faces.push([0, a, b]);
        faces.push([1, b, a]);
    }
    let mesh = wmslice::Mesh::from_raw(positions, faces);
    let (topo, issues) = Topology::build(&mesh);
    assert!(issues.is_empty(), "{issues:?}");
    check_invariants(&mesh, &topo).unwrap();
    assert_eq!(topo.fan(VertexId(0)).len(), n as usize);
    for (f, tri) in mesh.faces.iter().enumerate() {
        for c in 0..3 {
            let e = topo.edge(topo.face_edges[f][c]);
            let mut ends = [tri[c], tri[(c + 1) % 3]];
            ends.sort_unstable();
            assert_eq!(e.v, ends, "face {f} corner {c}");
        }
    }
}
