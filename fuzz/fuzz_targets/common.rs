//! Input: fuzz bytes and a format. Output: nothing; panics on a bug. The
//! same steps as `tests/io_fuzz_regressions.rs`: load (must not panic),
//! validate, and check the topology invariants of an accepted mesh.

use wmslice::mesh::io::{load_bytes, MeshFormat};
use wmslice::mesh::topology::check_invariants;
use wmslice::mesh::validate::validate;

pub fn check(data: &[u8], format: MeshFormat) {
    let Ok((mesh, _report)) = load_bytes(data, Some(format)) else {
        return;
    };
    let report = validate(&mesh);
    if report.is_accepted() {
        if let Some(topo) = &report.topology {
            if let Err(e) = check_invariants(&mesh, topo) {
                panic!("accepted mesh breaks a topology invariant: {e}");
            }
        }
    }
}
