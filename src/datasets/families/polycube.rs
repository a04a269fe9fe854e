//! Input: a seeded stream. Output: a polycube on a non-uniform integer
//! grid: a block with boxes carved out (closed cavities, notches that
//! leave overhangs, tunnels) and boxes added on top. Its horizontal faces
//! are flat regions at the grid heights, up or down facing, often with
//! holes, several per level, next to cavity ceilings and floors.
//!
//! Every step keeps the voxel set well-composed and face-connected (a
//! step that would not is undone), so the boundary is a closed 2-manifold
//! that cannot self-intersect (see [`super::voxels`]); a cavity is carved
//! only where every cell around it is solid, so at least one wall of
//! solid surrounds it.

use super::grid::lines;
use super::rng::Rng;
use super::voxels::Voxels;
use crate::mesh::Mesh;

/// A random box inside the grid: corner and extent per axis.
fn random_box(rng: &mut Rng, n: [usize; 3], max: usize) -> ([usize; 3], [usize; 3]) {
    let mut lo = [0; 3];
    let mut hi = [0; 3];
    for d in 0..3 {
        let w = rng.size(1, max.min(n[d]));
        lo[d] = rng.size(0, n[d] - w);
        hi[d] = lo[d] + w;
    }
    (lo, hi)
}

/// Carves a closed cavity (a box whose one-cell neighbourhood is solid),
/// if a random try finds room. Returns whether it did.
fn carve_cavity(rng: &mut Rng, v: &mut Voxels) -> bool {
    let n = v.n;
    if n.iter().any(|&x| x < 3) {
        return false;
    }
    let mut lo = [0; 3];
    let mut hi = [0; 3];
    for d in 0..3 {
        let w = rng.size(1, 2.min(n[d] - 2));
        lo[d] = rng.size(1, n[d] - 1 - w);
        hi[d] = lo[d] + w;
    }
    for k in lo[2] - 1..=hi[2] {
        for j in lo[1] - 1..=hi[1] {
            for i in lo[0] - 1..=hi[0] {
                if !v.get([i as i64, j as i64, k as i64]) {
                    return false;
                }
            }
        }
    }
    v.fill(lo, hi, false);
    true
}

/// One random polycube.
pub(super) fn build(rng: &mut Rng) -> Mesh {
    let n = [rng.size(4, 7), rng.size(4, 7), rng.size(4, 6)];
    let mut v = Voxels::new(n);
    let base_top = rng.size(2, n[2] - 1);
    let fx = rng.size(n[0] - 1, n[0]);
    let fy = rng.size(n[1] - 1, n[1]);
    v.fill([0, 0, 0], [fx, fy, base_top], true);
    carve_cavity(rng, &mut v);
    for _ in 0..rng.size(3, 8) {
        let before = v.clone();
        match rng.below(5) {
            0 => {
                carve_cavity(rng, &mut v);
            }
            // A notch or a tunnel: empty cells with solid above them.
            1 | 2 => {
                let (mut lo, mut hi) = random_box(rng, n, 3);
                if rng.below(3) == 0 {
                    let d = rng.size(0, 1);
                    lo[d] = 0;
                    hi[d] = n[d];
                }
                v.fill(lo, hi, false);
            }
            // A box added on top of (or beside) what is there.
            _ => {
                let (mut lo, mut hi) = random_box(rng, n, 3);
                let h = hi[2] - lo[2];
                lo[2] = rng.size(base_top.saturating_sub(1), n[2] - 1);
                hi[2] = (lo[2] + h).min(n[2]);
                v.fill(lo, hi, true);
            }
        }
        if !(v.is_well_composed() && v.is_connected()) {
            v = before;
        }
    }
    let xs = lines(rng, n[0], 0, 1, 3);
    let ys = lines(rng, n[1], 0, 1, 3);
    let zs = lines(rng, n[2], 0, 1, 2);
    v.mesh(&xs, &ys, &zs)
}
