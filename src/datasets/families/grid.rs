//! Input: a rectilinear grid of cells (some left out as holes), a diagonal
//! per cell, and a top and a bottom height per grid point. Output: the
//! closed slab between the two height fields, walled along the domain's
//! boundary; and the voxel checks the polycube families share.
//!
//! Why the slab cannot self-intersect: the top and the bottom are
//! piecewise linear over the same triangulation with `top > bottom` at
//! every used grid point, hence over every triangle; the walls stand
//! vertically over distinct boundary edges of a planar domain, which meet
//! only at shared grid points, where the walls share their vertical edge.
//! The domain is a 2-manifold with boundary when no two left-out cells
//! (or a left-out cell and the outside) touch at a corner only; the
//! callers keep their holes apart (see [`holes`]).

use super::rng::Rng;
use crate::datasets::build::Builder;
use crate::mesh::Mesh;
use std::collections::BTreeSet;

/// A slab over a rectilinear grid.
#[derive(Clone, Debug)]
pub(super) struct GridSlab {
    /// Grid line positions along x (strictly increasing), `nx + 1` of them.
    pub xs: Vec<f64>,
    /// Grid line positions along y, `ny + 1`.
    pub ys: Vec<f64>,
    /// Whether cell `(i, j)` (index `j * nx + i`) is part of the domain.
    pub present: Vec<bool>,
    /// Cell diagonal: `(i, j)-(i+1, j+1)` when set, else `(i+1, j)-(i, j+1)`.
    pub diag: Vec<bool>,
    /// Top height of grid point `(i, j)` (index `j * (nx + 1) + i`).
    pub top: Vec<f64>,
    /// Bottom height, `< top` at every point a present cell uses.
    pub bot: Vec<f64>,
}

impl GridSlab {
    pub fn nx(&self) -> usize {
        self.xs.len() - 1
    }

    pub fn ny(&self) -> usize {
        self.ys.len() - 1
    }

    /// Index of grid point `(i, j)`.
    pub fn at(&self, i: usize, j: usize) -> usize {
        j * (self.nx() + 1) + i
    }

    /// The union-jack triangulation: cell `(i, j)` takes the diagonal
    /// through `(i, j)` when `i + j` is even, so every grid point with
    /// `i + j` even has all eight neighbours in its link (room for a
    /// saddle with up to eight branches).
    pub fn union_jack(nx: usize, ny: usize) -> Vec<bool> {
        (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i + j) % 2 == 0))
            .collect()
    }

    /// The closed, outward-oriented mesh.
    pub fn mesh(&self) -> Mesh {
        let (nx, ny) = (self.nx(), self.ny());
        debug_assert_eq!(self.present.len(), nx * ny);
        debug_assert_eq!(self.diag.len(), nx * ny);
        let mut tris: Vec<[usize; 3]> = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let c = j * nx + i;
                if !self.present[c] {
                    continue;
                }
                let (p00, p10, p11, p01) = (
                    self.at(i, j),
                    self.at(i + 1, j),
                    self.at(i + 1, j + 1),
                    self.at(i, j + 1),
                );
                if self.diag[c] {
                    tris.push([p00, p10, p11]);
                    tris.push([p00, p11, p01]);
                } else {
                    tris.push([p00, p10, p01]);
                    tris.push([p10, p11, p01]);
                }
            }
        }
        let mut b = Builder::new();
        let point = |k: usize, z: f64| {
            let (i, j) = (k % (nx + 1), k / (nx + 1));
            [self.xs[i], self.ys[j], z]
        };
        let mut up = vec![u32::MAX; (nx + 1) * (ny + 1)];
        let mut down = vec![u32::MAX; (nx + 1) * (ny + 1)];
        for t in &tris {
            for &k in t {
                if up[k] == u32::MAX {
                    debug_assert!(self.top[k] > self.bot[k]);
                    up[k] = b.vertex(point(k, self.top[k]));
                    down[k] = b.vertex(point(k, self.bot[k]));
                }
            }
        }
        for t in &tris {
            b.tri(up[t[0]], up[t[1]], up[t[2]]);
            b.tri(down[t[0]], down[t[2]], down[t[1]]);
        }
        // Directed boundary edges have the domain on their left; the wall
        // under each faces right, outward.
        let directed: BTreeSet<(usize, usize)> = tris
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .collect();
        for &(p, q) in &directed {
            if !directed.contains(&(q, p)) {
                b.quad(down[p], down[q], up[q], up[p]);
            }
        }
        b.finish()
    }
}

/// Up to `count` rectangular holes of cells, each at least one cell away
/// from the grid's border and two cells (so no shared grid point) from
/// every other hole: the domain stays a 2-manifold, its holes become
/// through-holes of the slab. Returns the `present` mask.
pub(super) fn holes(rng: &mut Rng, nx: usize, ny: usize, count: usize) -> Vec<bool> {
    let mut present = vec![true; nx * ny];
    let mut placed: Vec<[usize; 4]> = Vec::new();
    if nx < 3 || ny < 3 {
        return present;
    }
    for _ in 0..count {
        let w = rng.size(1, (nx - 2).min(2));
        let h = rng.size(1, (ny - 2).min(2));
        let i0 = rng.size(1, nx - 1 - w);
        let j0 = rng.size(1, ny - 1 - h);
        let r = [i0, j0, i0 + w, j0 + h];
        // Apart: a gap of at least one full cell between the rectangles.
        let apart = |o: &[usize; 4]| r[2] < o[0] || o[2] < r[0] || r[3] < o[1] || o[3] < r[1];
        if placed.iter().all(apart) {
            for j in r[1]..r[3] {
                for i in r[0]..r[2] {
                    present[j * nx + i] = false;
                }
            }
            placed.push(r);
        }
    }
    present
}

/// Grid line positions: `start`, then `n` steps drawn from `lo..=hi`.
pub(super) fn lines(rng: &mut Rng, n: usize, start: i64, lo: i64, hi: i64) -> Vec<f64> {
    let mut out = vec![start as f64];
    let mut x = start;
    for _ in 0..n {
        x += rng.range(lo, hi);
        out.push(x as f64);
    }
    out
}

/// Turns a mesh on its side: the axes rotated cyclically `times` times,
/// `(x, y, z) -> (z, x, y)` each (a rotation, so the orientation stays
/// outward).
pub(super) fn rotate_axes(mesh: &mut Mesh, times: usize) {
    for _ in 0..times % 3 {
        for p in &mut mesh.positions {
            *p = [p[2], p[0], p[1]];
        }
    }
}
