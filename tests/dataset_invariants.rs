//! SPEC section 7 on every built-in dataset: invariants 1-4 at every vertex
//! height and between them, and the exact volume identity (6).

use wmslice::datasets;
use wmslice::exact::rational::Rat;
use wmslice::levelset::check::{check_level_invariants, check_volume_identity, vertex_heights};
use wmslice::mesh::validate::validate;
use wmslice::Slicer;

#[test]
fn every_dataset_satisfies_the_invariants_at_every_height() {
    for d in datasets::all() {
        let mesh = d.build();
        let slicer = Slicer::new(&mesh).unwrap_or_else(|e| panic!("{}: {e}", d.name));
        let zs = vertex_heights(&mesh);
        let two = Rat::from_integer(2.into());
        let mids: Vec<Rat> = zs.windows(2).map(|w| (&w[0] + &w[1]) / &two).collect();
        for c in zs.iter().chain(&mids) {
            let ls = slicer
                .slice_at(c)
                .unwrap_or_else(|e| panic!("{} at {c}: {e}", d.name));
            if let Err(e) = check_level_invariants(&mesh, slicer.topology(), &ls) {
                panic!("{} at {c}: {e}", d.name);
            }
        }
        check_volume_identity(&slicer, &validate(&mesh).volume)
            .unwrap_or_else(|e| panic!("{}: {e}", d.name));
    }
}
