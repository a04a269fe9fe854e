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
