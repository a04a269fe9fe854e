//! Input: fuzz bytes and a format. Output: nothing; panics on a bug
//! (`tests/io_fuzz_regressions.rs` replays saved inputs through this same
//! file): load (must not panic),
//! snap what a 3MF transform leaves off the doubles, as read and with
//! every combination of the repairs (coincident vertices welded, collapsed
//! faces removed): validate, and check the topology invariants of an
//! accepted mesh.

use wmslice::exact::rational::Rat;
use wmslice::mesh::io::{load_bytes_exact, MeshFormat};
use wmslice::mesh::prepare::{prepare_exact_with, CoincidentVertices, CollapsedFaces, Repairs};
use wmslice::mesh::topology::check_invariants;
use wmslice::mesh::validate::validate;

pub fn check(data: &[u8], format: MeshFormat) {
    let Ok((mesh, _report, exact)) = load_bytes_exact(data, Some(format)) else {
        return;
    };
    // A 3MF vertex whose transformed position is not a double is placed
    // by a grid (1/1024) from its exact image; without one, refused.
    let grid = Rat::new(1.into(), 1024.into());
    let q = (!exact.is_empty()).then_some(&grid);
    // As read, welded (`--weld`), with the faces that use one vertex twice
    // removed (`--drop-collapsed`), and both.
    let modes = [CoincidentVertices::Keep, CoincidentVertices::Weld].map(|coincident| {
        [CollapsedFaces::Refuse, CollapsedFaces::Drop].map(|collapsed| Repairs {
            coincident,
            collapsed,
        })
    });
    for mode in modes.into_iter().flatten() {
        let Ok(prepared) = prepare_exact_with(mesh.clone(), &exact, q, mode) else {
            return;
        };
        let mesh = prepared.mesh;
        let report = validate(&mesh);
        if report.is_accepted() {
            if let Some(topo) = &report.topology {
                if let Err(e) = check_invariants(&mesh, topo) {
                    panic!("accepted mesh ({mode:?}) breaks a topology invariant: {e}");
                }
            }
        }
    }
}
