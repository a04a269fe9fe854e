//! Input: a seeded stream. Output: a slab between two integer height
//! fields over a small rectilinear grid, built to be degenerate at many
//! heights: plateaus (grid points copying a neighbour's height, so whole
//! triangles lie in a plane), ridge and valley lines stamped across the
//! grid, cross-shaped saddles, random cell diagonals; through-holes in
//! some; turned on its side (the axes rotated) in some, so that walls and
//! caps are sliced across too.
//!
//! Closed, oriented and free of self-intersections by construction (see
//! [`super::grid`]): the bottom is a flat plane or a second height field
//! at least one unit below the top at every grid point.

use super::grid::{holes, lines, rotate_axes, GridSlab};
use super::rng::Rng;
use crate::mesh::Mesh;

/// One random height-field slab.
pub(super) fn build(rng: &mut Rng) -> Mesh {
    let nx = rng.size(3, 8);
    let ny = rng.size(3, 8);
    let xs = lines(rng, nx, 0, 1, 2);
    let ys = lines(rng, ny, 0, 1, 2);
    let np = (nx + 1) * (ny + 1);
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    // A small palette, and copies of the left or lower neighbour: plateaus.
    let palette = rng.range(2, 4);
    let mut top = vec![0i64; np];
    for j in 0..=ny {
        for i in 0..=nx {
            top[at(i, j)] = match rng.below(4) {
                2 if i > 0 => top[at(i - 1, j)],
                3 if j > 0 => top[at(i, j - 1)],
                _ => rng.range(0, palette - 1),
            };
        }
    }
    // Stamped features.
    for _ in 0..rng.size(1, 3) {
        let hi = *top.iter().max().unwrap_or(&0);
        let lo = *top.iter().min().unwrap_or(&0);
        match rng.below(4) {
            // A ridge (or valley) along a grid row or column.
            0 | 1 => {
                let v = if rng.below(2) == 0 { hi + 1 } else { lo - 1 };
                if rng.below(2) == 0 {
                    let j = rng.size(0, ny);
                    let (a, b) = (rng.size(0, nx), rng.size(0, nx));
                    for i in a.min(b)..=a.max(b) {
                        top[at(i, j)] = v;
                    }
                } else {
                    let i = rng.size(0, nx);
                    let (a, b) = (rng.size(0, ny), rng.size(0, ny));
                    for j in a.min(b)..=a.max(b) {
                        top[at(i, j)] = v;
                    }
                }
            }
            // A cross-shaped saddle: up along one axis, down along the other.
            2 if nx >= 2 && ny >= 2 => {
                let (i, j) = (rng.size(1, nx - 1), rng.size(1, ny - 1));
                let s = rng.range(lo, hi);
                top[at(i, j)] = s;
                top[at(i - 1, j)] = s + 1;
                top[at(i + 1, j)] = s + 1;
                top[at(i, j - 1)] = s - 1;
                top[at(i, j + 1)] = s - 1;
            }
            // A plateau: a rectangle of grid points at one height.
            _ => {
                let v = rng.range(lo, hi + 1);
                let (i0, j0) = (rng.size(0, nx), rng.size(0, ny));
                let (i1, j1) = ((i0 + rng.size(1, 3)).min(nx), (j0 + rng.size(1, 3)).min(ny));
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        top[at(i, j)] = v;
                    }
                }
            }
        }
    }
    let lo = *top.iter().min().unwrap_or(&0);
    let bot: Vec<i64> = if rng.below(2) == 0 {
        vec![lo - rng.range(1, 2); np]
    } else {
        // A second field below, one or two units under the top, often
        // copying a neighbour's thickness (plateaus underneath too).
        let mut thick = vec![1i64; np];
        for j in 0..=ny {
            for i in 0..=nx {
                thick[at(i, j)] = match rng.below(3) {
                    2 if i > 0 => thick[at(i - 1, j)],
                    _ => rng.range(1, 2),
                };
            }
        }
        top.iter().zip(&thick).map(|(t, d)| t - d).collect()
    };
    let present = if rng.below(2) == 0 {
        let count = rng.size(1, 2);
        holes(rng, nx, ny, count)
    } else {
        vec![true; nx * ny]
    };
    let diag = (0..nx * ny).map(|_| rng.below(2) == 0).collect();
    let slab = GridSlab {
        xs,
        ys,
        present,
        diag,
        top: top.iter().map(|&z| z as f64).collect(),
        bot: bot.iter().map(|&z| z as f64).collect(),
    };
    let mut mesh = slab.mesh();
    let turns = match rng.below(4) {
        0 => 1,
        1 => 2,
        _ => 0,
    };
    rotate_axes(&mut mesh, turns);
    mesh
}
