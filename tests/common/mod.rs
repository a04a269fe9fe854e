//! Closed random meshes with small integer coordinates (ties everywhere),
//! shared by the property tests.
#![allow(dead_code)]

use proptest::prelude::*;
use wmslice::Mesh;

/// A slab between two height fields over an `nx` x `ny` grid: bottom
/// heights `bot`, top heights `top = bot + thick` (> bot), each cell split
/// along the diagonal `diag`. Closed, oriented outward, genus 0. The axes
/// are then rotated cyclically `rot` times (orientation-preserving), so
/// walls and caps lie in every direction.
#[derive(Clone, Debug)]
pub struct Slab {
    pub nx: usize,
    pub ny: usize,
    pub bot: Vec<i32>,
    pub thick: Vec<i32>,
    pub diag: Vec<bool>,
    pub rot: u8,
}

impl Slab {
    pub fn mesh(&self) -> Mesh {
        let (nx, ny) = (self.nx, self.ny);
        let idx = |i: usize, j: usize| j * (nx + 1) + i;
        let n = (nx + 1) * (ny + 1);
        let mut pos = Vec::with_capacity(2 * n);
        for layer in 0..2 {
            for j in 0..=ny {
                for i in 0..=nx {
                    let k = idx(i, j);
                    let z = if layer == 0 {
                        self.bot[k]
                    } else {
                        self.bot[k] + self.thick[k]
                    };
                    pos.push([i as f64, j as f64, z as f64]);
                }
            }
        }
        let b = |i, j| idx(i, j) as u32;
        let t = |i, j| (n + idx(i, j)) as u32;
        let mut faces = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let d = self.diag[j * nx + i];
                let (p00, p10, p11, p01) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
                let quads: [[(usize, usize); 3]; 2] = if d {
                    [[p00, p10, p11], [p00, p11, p01]]
                } else {
                    [[p00, p10, p01], [p10, p11, p01]]
                };
                for q in quads {
                    faces.push([t(q[0].0, q[0].1), t(q[1].0, q[1].1), t(q[2].0, q[2].1)]);
                    faces.push([b(q[0].0, q[0].1), b(q[2].0, q[2].1), b(q[1].0, q[1].1)]);
                }
            }
        }
        // Boundary ring counter-clockwise seen from above.
        let mut ring = Vec::new();
        for i in 0..nx {
            ring.push((i, 0));
        }
        for j in 0..ny {
            ring.push((nx, j));
        }
        for i in (1..=nx).rev() {
            ring.push((i, ny));
        }
        for j in (1..=ny).rev() {
            ring.push((0, j));
        }
        for k in 0..ring.len() {
            let p = ring[k];
            let q = ring[(k + 1) % ring.len()];
            faces.push([b(p.0, p.1), b(q.0, q.1), t(q.0, q.1)]);
            faces.push([b(p.0, p.1), t(q.0, q.1), t(p.0, p.1)]);
        }
        for _ in 0..self.rot % 3 {
            for p in &mut pos {
                *p = [p[2], p[0], p[1]];
            }
        }
        Mesh::from_raw(pos, faces)
    }
}

/// Random slabs: up to 4 x 4 cells, heights in a small range.
pub fn slab() -> impl Strategy<Value = Slab> {
    (1usize..=4, 1usize..=4).prop_flat_map(|(nx, ny)| {
        let n = (nx + 1) * (ny + 1);
        (
            proptest::collection::vec(-2i32..=2, n),
            proptest::collection::vec(1i32..=3, n),
            proptest::collection::vec(any::<bool>(), nx * ny),
            0u8..3,
        )
            .prop_map(move |(bot, thick, diag, rot)| Slab {
                nx,
                ny,
                bot,
                thick,
                diag,
                rot,
            })
    })
}
